"""`hawksim.flight.recording.write_rrd`: the .rrd file is complete, readable and holds the flight's data."""

from __future__ import annotations

import dataclasses
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rerun.chunk import RrdReader

from hawksim.flight import recording
from hawksim.cli.fly import fly_named
from hawksim.flight.recording import write_rrd
from hawksim.insect.morphology import HAWKMOTH

QUAT_ATOL = 1e-6
"""Body quaternion as stored (float32) vs the flight's float64 one (unit quaternion): float32 rounding, half an ulp
~6e-8; measured 3.0e-8."""

WING_R_ATOL = 1e-5
"""Wing rotation matrices rebuilt from the stored float32 quaternions vs the flight's: products of float32-rounded
components, a few float32 ulps (~1e-7); measured 1.2e-7."""

SCALAR_RTOL = 1e-9
"""Relative: plotted scalars (lift, L+, pitch) vs the flight's values. Stored as float64, so exact in practice;
the round value's source is not recorded; measured: exact (0)."""

SCALAR_ATOL = 1e-15
"""N: absolute floor for lift values near zero (at stroke reversal); measured: exact (0)."""

TIME_ATOL_S = 1e-9
"""s: the time timeline is stored in integer nanoseconds, so truncation of up to 1 ns; measured 1.0e-9 (9.98e-10):
the check also passes on assert_allclose's default rtol = 1e-7 (times up to 0.07 s, i.e. 7e-9 s)."""

MESH_AREA_RTOL = 0.03
"""Relative: area of the recorded wing mesh (N_SPAN x N_CHORD = 21 x 4 quads, straight edges) vs the planform's
wing area: polygonal approximation of the curved edges; the round value's source is not recorded; measured 4.2e-3."""

NORMAL_ATOL = 1e-15
"""m^2: triangle normals' z component (twice the area) may be this far below zero; the mesh lies in z = 0, so only
round-off; measured min 0 (no negative component)."""


@pytest.fixture(scope="module")
def result():
    return fly_named(1.0, 2)


def read_chunks(path: Path) -> dict[str, list]:
    """Entity path -> list of (is_static, record batch) of the file's recording store."""
    out: dict[str, list] = {}
    for ch in RrdReader(path).stream().to_chunks():
        out.setdefault(ch.entity_path, []).append((ch.is_static, ch.to_record_batch()))
    return out


def temporal_column(chunks: dict, entity: str, column: str) -> tuple[np.ndarray, list]:
    """(step indices, values) of a component column over the temporal chunks of an entity, sorted by step."""
    steps, values = [], []
    for static, rb in chunks[entity]:
        if not static and column in rb.schema.names:
            steps += rb.column("step").to_pylist()
            values += rb.column(column).to_pylist()
    order = np.argsort(steps)
    return np.asarray(steps)[order], [values[i] for i in order]


def rerun_cli() -> list[str] | None:
    exe = Path(sys.executable).with_name("rerun")
    if exe.exists():
        return [str(exe)]
    found = shutil.which("rerun")
    return [found] if found else None


def test_recording_contents(result, tmp_path):
    path = write_rrd(tmp_path / "flight.rrd", result)
    assert path == tmp_path / "flight.rrd" and path.stat().st_size > 0
    assert [p.name for p in tmp_path.iterdir()] == ["flight.rrd"]  # no temporary file left behind

    reader = RrdReader(path)
    assert len(reader.recordings()) == 1 and len(reader.blueprints()) == 1
    chunks = read_chunks(path)
    expected = ["/world/moth", "/world/moth/body", "/world/trajectory"]
    expected += [f"/world/{kind}/{side}" for kind in ("wings", "forces") for side in ("left", "right")]
    expected += [f"/world/wings/{side}/mesh" for side in ("left", "right")]
    expected += [f"/plots/{name}" for name in (
        "forces/lift", "forces/drag", "forces_nd/L_plus", "forces_nd/D_plus", "moment/pitching",
        "moment_nd/M_plus", "power/aero", "power/joint", "velocity/vx", "velocity/vy", "velocity/vz",
        "attitude/pitch", "attitude/roll")]
    missing = [e for e in expected if e not in chunks]
    assert not missing, missing
    assert not any(e.startswith("/world/uvlm") for e in chunks)

    n = len(result.t)
    steps, quats = temporal_column(chunks, "/world/moth", "Transform3D:quaternion")
    np.testing.assert_array_equal(steps, np.arange(n))
    q = np.array([v[0] for v in quats])  # xyzw, stored as float32
    np.testing.assert_allclose(q, result.body_quat[:, [1, 2, 3, 0]], atol=QUAT_ATOL)
    for i, side in enumerate(("left", "right")):
        _, wq = temporal_column(chunks, f"/world/wings/{side}", "Transform3D:quaternion")
        assert len(wq) == n
        x, y, z, w = np.array([v[0] for v in wq], dtype=float).T  # wing frame -> world, xyzw
        R = np.stack([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]).transpose(2, 0, 1)
        np.testing.assert_allclose(R, result.wing_R[:, i], atol=WING_R_ATOL)
        assert len(temporal_column(chunks, f"/world/forces/{side}", "Arrows3D:vectors")[0]) == n

    lift = result.lift_drag()[0]
    steps, values = temporal_column(chunks, "/plots/forces/lift", "Scalars:scalars")
    np.testing.assert_array_equal(steps, np.arange(n))
    for k in (0, n // 3, n - 1):
        assert values[k][0] == pytest.approx(lift[k], rel=SCALAR_RTOL, abs=SCALAR_ATOL)
    _, lp = temporal_column(chunks, "/plots/forces_nd/L_plus", "Scalars:scalars")
    assert lp[n // 3][0] == pytest.approx(lift[n // 3] / HAWKMOTH.weight, rel=SCALAR_RTOL)
    _, pitch = temporal_column(chunks, "/plots/attitude/pitch", "Scalars:scalars")
    assert pitch[0][0] == pytest.approx(np.rad2deg(result.pitch()[0]), rel=SCALAR_RTOL)

    # time timeline: duration in nanoseconds
    rb = next(rb for static, rb in chunks["/world/moth"] if not static)
    t = np.asarray(rb.column("time").cast("int64").to_pylist()) * 1e-9
    np.testing.assert_allclose(np.sort(t), result.t, atol=TIME_ATOL_S)


def test_cli_verify(result, tmp_path):
    cli = rerun_cli()
    if cli is None:
        pytest.skip("rerun CLI not found")
    path = write_rrd(tmp_path / "flight.rrd", result)
    out = subprocess.run([*cli, "rrd", "verify", str(path)], capture_output=True, text=True, timeout=60,
                         check=False)
    assert out.returncode == 0, out.stderr


def test_wing_mesh_mirrors():
    vl, tl = recording.wing_mesh(HAWKMOTH, "left")
    vr, tr = recording.wing_mesh(HAWKMOTH, "right")
    assert vl.shape == (recording.N_SPAN * (recording.N_CHORD + 1), 3) and tl.max() < len(vl)
    np.testing.assert_allclose(vr, vl * [1, -1, 1])
    assert vl[:, 1].min() == 0 and vl[:, 1].max() == pytest.approx(HAWKMOTH.R)
    area = 0.5 * np.abs(np.cross(vl[tl[:, 1]] - vl[tl[:, 0]], vl[tl[:, 2]] - vl[tl[:, 0]])[:, 2]).sum()
    assert area == pytest.approx(HAWKMOTH.wing_area, rel=MESH_AREA_RTOL)
    # normals along +z on both wings (winding reversed with the mirror)
    for v, t in ((vl, tl), (vr, tr)):
        nz = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])[:, 2]
        assert np.all(nz >= -NORMAL_ATOL)


@pytest.mark.parametrize("make", ["missing_dir", "is_dir", "under_file"])
def test_unwritable_path(result, tmp_path, make):
    if make == "missing_dir":
        path = tmp_path / "nope" / "flight.rrd"
    elif make == "is_dir":
        path = tmp_path / "adir"
        path.mkdir()
    else:
        (tmp_path / "afile").write_text("x")
        path = tmp_path / "afile" / "flight.rrd"
    with pytest.raises(ValueError) as info:
        write_rrd(path, result)
    msg = str(info.value)
    assert str(path) in msg and "\n" not in msg


def test_failure_leaves_nothing(result, tmp_path, monkeypatch):
    def boom(*args, **kwargs):
        raise RuntimeError("boom")

    monkeypatch.setattr(recording, "_log_flight", boom)
    with pytest.raises(RuntimeError):
        write_rrd(tmp_path / "flight.rrd", result)
    assert list(tmp_path.iterdir()) == []


def synthetic_extras(result, step: int, nc=3, ns=5, rows=4):
    """UVLM-like extras at one step: flat panel lattices in each wing plane and a wake behind."""
    rng = np.random.default_rng(0)
    panels = np.empty((2, nc + 1, ns + 1, 3))
    wake = []
    x = np.linspace(0.25, -0.75, nc + 1) * HAWKMOTH.cbar
    y = np.linspace(0, HAWKMOTH.R, ns + 1)
    for w, sign in enumerate((1.0, -1.0)):
        local = np.stack(np.broadcast_arrays(x[:, None], sign * y[None, :], 0.0 * x[:, None]), -1)
        panels[w] = result.wing_origin[step, w] + local @ result.wing_R[step, w].T
        xw = x[-1] - HAWKMOTH.cbar * np.arange(rows + 1)
        lw = np.stack(np.broadcast_arrays(xw[:, None], sign * y[None, :], 0.0 * xw[:, None]), -1)
        wake.append((result.wing_origin[step, w] + lw @ result.wing_R[step, w].T, rng.normal(size=(rows, ns))))
    pressure = rng.normal(scale=5.0, size=(2, nc, ns))
    return {"panels": panels, "pressure": pressure, "wake": wake}


def unpack_rgb(packed: int) -> tuple[int, int, int]:
    return (packed >> 24) & 255, (packed >> 16) & 255, (packed >> 8) & 255


def test_uvlm_extras(result, tmp_path):
    nc, ns, rows = 3, 5, 4
    steps = (10, 60)
    extras = [(k, synthetic_extras(result, k, nc, ns, rows)) for k in steps]
    res = dataclasses.replace(result, extras=extras)
    chunks = read_chunks(write_rrd(tmp_path / "uvlm.rrd", res))
    for side in ("left", "right"):
        assert f"/world/uvlm/panels/{side}" in chunks and f"/world/uvlm/wake/{side}" in chunks
    assert "/world/uvlm/legend" in chunks

    got_steps, verts = temporal_column(chunks, "/world/uvlm/panels/left", "Mesh3D:vertex_positions")
    np.testing.assert_array_equal(got_steps, steps)
    assert len(verts[0]) == 4 * nc * ns
    # the panel with the largest |pressure| over the recording is at the end of the scale
    _, colors = temporal_column(chunks, "/world/uvlm/panels/left", "Mesh3D:vertex_colors")
    p = extras[0][1]["pressure"]
    p_lim = max(np.abs(e["pressure"]).max() for _, e in extras)
    rgb = np.array([unpack_rgb(c) for c in colors[0][::4]])
    np.testing.assert_array_equal(rgb, recording.diverging_colors(p[0].reshape(-1), p_lim))
    k = np.argmax(np.abs(p[0]))
    if np.abs(p[0]).max() == p_lim:
        assert tuple(rgb[k]) == ((180, 4, 38) if p[0].flat[k] > 0 else (59, 76, 192))

    got_steps, strips = temporal_column(chunks, "/world/uvlm/wake/right", "LineStrips3D:strips")
    np.testing.assert_array_equal(got_steps, steps)
    assert len(strips[0]) == rows * ns + ns + 1  # ring segments + streamwise lines


def test_diverging_colors():
    c = recording.diverging_colors(np.array([-2.0, -1.0, 0.0, 1.0, 5.0]), 1.0)
    assert [tuple(x) for x in c] == [(59, 76, 192), (59, 76, 192), (221, 221, 221), (180, 4, 38), (180, 4, 38)]


# ---- units, views, legends (issue 18 item 5) --------------------------------------------------------------
def blueprint_views(path: Path) -> list[tuple[str, str, str]]:
    """(class, origin, display name) of every view in the file's blueprint."""
    reader = RrdReader(path)
    out = []
    for ch in reader.stream(store=reader.blueprints()[0]).to_chunks():
        rb = ch.to_record_batch()
        if "ViewBlueprint:class_identifier" in rb.schema.names:
            cls = rb.column("ViewBlueprint:class_identifier").to_pylist()[-1][0]
            origin = rb.column("ViewBlueprint:space_origin").to_pylist()[-1][0]
            name = rb.column("ViewBlueprint:display_name").to_pylist()[-1][0]
            out.append((cls, "/" + origin.strip("/"), name))
    return out


def series_names(chunks: dict) -> dict[str, str]:
    """Entity -> the series name (SeriesLines or SeriesPoints) of every entity that logs Scalars."""
    out = {}
    for e, lst in chunks.items():
        if not any("Scalars:scalars" in rb.schema.names for _, rb in lst):
            continue
        names = [rb.column(c).to_pylist()[0][0] for _, rb in lst for c in rb.schema.names
                 if c in ("SeriesLines:names", "SeriesPoints:names")]
        out[e] = names[0] if names else None
    return out


def check_units_and_views(path: Path, chunks: dict) -> list:
    views = blueprint_views(path)
    ts = [o for c, o, _ in views if c == "TimeSeries"]
    assert all("[" in n and "]" in n for c, _, n in views if c == "TimeSeries"), views
    series = series_names(chunks)
    assert series
    for e, name in series.items():
        assert name is not None and name.endswith("]") and "[" in name, (e, name)
        assert any(e == o or e.startswith(o + "/") for o in ts), f"{e} is in no time-series view"
    for legend in ("/world/uvlm/legend", "/world/ghost_legend"):
        if legend in chunks:
            assert ("TextDocument", legend) in [(c, o) for c, o, _ in views], f"{legend} is in no text view"
    return views


def test_every_series_in_a_view_with_its_unit(result, tmp_path):
    path = write_rrd(tmp_path / "flight.rrd", result)
    chunks = read_chunks(path)
    views = check_units_and_views(path, chunks)
    assert "/plots/moment_nd/M_plus" in series_names(chunks)
    names = {o: n for c, o, n in views}
    assert names["/plots/forces_nd"] == "L+, D+ [-]" and names["/plots/moment_nd"] == "M+ [-]"


def test_uvlm_legend_in_a_view(result, tmp_path):
    res = dataclasses.replace(result, extras=[(k, synthetic_extras(result, k)) for k in (0, 5, 10)])
    path = write_rrd(tmp_path / "uvlm.rrd", res)
    check_units_and_views(path, read_chunks(path))
    verify(path)


def verify(path: Path) -> None:
    cli = rerun_cli()
    if cli is None:
        pytest.skip("rerun CLI not found")
    out = subprocess.run([*cli, "rrd", "verify", str(path)], capture_output=True, text=True, timeout=60,
                         check=False)
    assert out.returncode == 0, out.stderr


def test_uvlm_extras_every_update(result, tmp_path, monkeypatch):
    """`hawksim fly --aero uvlm --rrd` keeps the UVLM extras at every update (every aero_every steps), and the
    recording logs the panels and wake at each of those steps."""
    from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE, FLY_UVLM
    from hawksim.cli import fly as cli_fly
    from hawksim.cli import main

    every = FLY_STEPS_PER_CYCLE // FLY_UVLM.steps_per_cycle
    seen = {}

    def fake(speed, cycles, aero, **kw):
        seen.update(kw)
        k = kw["keep_extras_every"]
        return dataclasses.replace(result, aero=aero, extras=[(i, synthetic_extras(result, i))
                                                              for i in range(0, len(result.t), k)])

    monkeypatch.setattr(cli_fly, "fly_named", fake)
    path = tmp_path / "uvlm.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "2", "--aero", "uvlm", "--rrd", str(path), "--json",
                 "--no-progress"]) == 0
    assert seen["keep_extras_every"] == every == 5
    steps, _ = temporal_column(read_chunks(path), "/world/uvlm/panels/left", "Mesh3D:vertex_positions")
    np.testing.assert_array_equal(steps, np.arange(0, len(result.t), every))
    verify(path)


# ---- interrupts -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("signame", ["SIGINT", "SIGTERM"])
def test_interrupt_writes_the_steps_flown(tmp_path, monkeypatch, capsys, signame):
    """A signal during the flight: the recording holds the steps flown (up to the step after the signal), it
    verifies, no temporary file is left, the exit status is 130 and stderr says where it stopped."""
    import os
    import signal

    from hawksim.cli import main

    from hawksim.backends.quasi_steady import QuasiSteadyBackend

    at = 150  # mid-beat: the signal comes while Simulator.advance runs the beat's steps
    calls = []
    loads = QuasiSteadyBackend.loads

    def counted(self, state):
        if not calls and round(state.t / state.dt) == at:  # the call for step `at`: steps 0 .. at - 1 are flown
            calls.append(state.t)
            os.kill(os.getpid(), getattr(signal, signame))
        return loads(self, state)

    monkeypatch.setattr(QuasiSteadyBackend, "loads", counted)
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    path = tmp_path / "cut.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "3", "--control", "none", "--rrd", str(path), "--json",
                 "--no-progress"]) == 130
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before  # handlers restored
    assert [p.name for p in tmp_path.iterdir()] == ["cut.rrd"]
    steps, _ = temporal_column(read_chunks(path), "/world/moth", "Transform3D:quaternion")
    assert calls and at <= len(steps) <= at + 2 and np.array_equal(steps, np.arange(len(steps)))
    err = capsys.readouterr()
    assert err.out == "" and "interrupted at step" in err.err and str(path) in err.err
    assert len(err.err.strip().splitlines()) == 1  # the contract's one line
    verify(path)


@pytest.mark.parametrize("signame", ["SIGINT", "SIGTERM"])
def test_interrupt_of_a_controlled_flight_writes_the_beats_flown(tmp_path, monkeypatch, capsys, signame):
    """The default flight (LQR control from the orbit) interrupted by a real signal after beat 2 of 5: exit 130, the
    recording holds the complete beats flown (the beat in which the signal came is finished first) with their
    control commands, it verifies, no temporary file is left and the handlers are restored."""
    import os
    import signal

    from hawksim.cli import fly as cli_fly
    from hawksim.cli import main

    at, spc = 2, 200
    calls = []

    def progress_for(args, desc, unit="step"):
        def hook(k, n):
            calls.append((k, n, unit))
            if k == at:
                os.kill(os.getpid(), getattr(signal, signame))
        return hook

    monkeypatch.setattr(cli_fly, "progress_for", progress_for)
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    path = tmp_path / "cut.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "5", "--rrd", str(path), "--json"]) == 130
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before
    assert calls[0] == (0, 5, "beat") and calls[-1][0] == at  # the hook raised in the call after the signal
    assert [p.name for p in tmp_path.iterdir()] == ["cut.rrd"]
    chunks = read_chunks(path)
    steps, _ = temporal_column(chunks, "/world/moth", "Transform3D:quaternion")
    assert len(steps) == (at + 1) * spc and np.array_equal(steps, np.arange(len(steps)))
    beats, _ = temporal_column(chunks, "/plots/control/commands/f_hz", "Scalars:scalars")
    np.testing.assert_array_equal(beats, np.arange(1, at + 2) * spc)
    err = capsys.readouterr()
    assert err.out == "" and f"interrupted at step {(at + 1) * spc} of {5 * spc}" in err.err and str(path) in err.err
    assert len(err.err.strip().splitlines()) == 1  # the contract's one line: no verdict on a flight cut short
    verify(path)


def test_interrupt_while_writing_leaves_nothing(result, tmp_path, monkeypatch):
    def stop(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(recording, "_log_extras", stop)
    with pytest.raises(KeyboardInterrupt):
        write_rrd(tmp_path / "flight.rrd", result)
    assert list(tmp_path.iterdir()) == []


# ---- the linear prediction's ghost (issue 19 item 7) --------------------------------------------------------
def test_perturbed_flight_ghost(tmp_path, capsys):
    from hawksim.cli import main

    path = tmp_path / "ghost.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "2", "--control", "none", "--perturb", "w=0.01", "--perturb",
                 "phi=0.5", "--rrd", str(path), "--json", "--no-progress"]) == 0
    chunks = read_chunks(path)
    for e in ("/world/ghost", "/world/ghost/body", "/world/ghost/wings/left", "/world/ghost/wings/right/mesh",
              "/world/ghost_trajectory", "/world/ghost_legend"):
        assert e in chunks, e
    for name, _, _ in recording.BEAT_STATES:
        for kind in ("nonlinear", "floquet", "averaged"):
            assert f"/plots/beats/{name}/{kind}" in chunks
    steps, phi = temporal_column(chunks, "/plots/beats/phi/floquet", "Scalars:scalars")
    np.testing.assert_array_equal(steps, [0, 200, 400])
    assert phi[0][0] == pytest.approx(0.5)  # deg, the launch perturbation
    _, w = temporal_column(chunks, "/plots/beats/w/nonlinear", "Scalars:scalars")
    assert len(w) == 2 and w[0][0] == pytest.approx(0.01)
    # the ghost stands GHOST_OFFSET_M beside the nonlinear body (to within the predicted deviation)
    _, tg = temporal_column(chunks, "/world/ghost", "Transform3D:translation")
    _, tm = temporal_column(chunks, "/world/moth", "Transform3D:translation")
    gap = np.array([v[0] for v in tg]) - np.array([v[0] for v in tm])
    np.testing.assert_allclose(gap, np.tile(recording.GHOST_OFFSET_M, (len(gap), 1)), atol=1e-4)
    views = check_units_and_views(path, chunks)
    assert sum(c == "TimeSeries" and o.startswith("/plots/beats/") for c, o, _ in views) == 8
    verify(path)


def test_ghost_skipped_with_a_reason(tmp_path, capsys):
    from hawksim.cli import main

    path = tmp_path / "trim.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "1", "--start", "trim", "--perturb", "w=0.01", "--rrd",
                 str(path), "--json", "--no-progress"]) == 0
    assert "no ghost in the recording" in capsys.readouterr().err
    assert not any(e.startswith("/world/ghost") for e in read_chunks(path))


def test_controlled_flight_records_commands_and_tracking(tmp_path):
    """issue 20 item 6: a controlled flight's commands and tracking errors are series, each in a view with its
    unit, one point per wingbeat."""
    from hawksim.cli import main

    path = tmp_path / "ctl.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "3", "--gust", "0,0.5,0@1:1", "--rrd", str(path), "--json",
                 "--no-progress"]) == 0
    chunks = read_chunks(path)
    check_units_and_views(path, chunks)
    steps, values = temporal_column(chunks, "/plots/control/commands/f_hz", "Scalars:scalars")
    assert len(steps) == 3 and all(15 <= v[0] <= 40 for v in values)  # Table 2's f bounds [Hz]
    assert "/plots/control/tracking/speed_error" in chunks
    verify(path)


def test_half_stroke_commands_are_recorded_at_both_updates(tmp_path):
    """A controller updated per half-stroke (the surrogate's default) records two commands per wingbeat (phases 0
    and 0.5), the tracking errors once per beat."""
    from hawksim.cli import main

    path = tmp_path / "half.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "3", "--aero", "surrogate", "--gust", "0,0.3,0@1:1", "--rrd",
                 str(path), "--json", "--no-progress"]) == 0
    chunks = read_chunks(path)
    check_units_and_views(path, chunks)
    steps, values = temporal_column(chunks, "/plots/control/commands/dphi0_deg", "Scalars:scalars")
    assert len(steps) == 6 and len(set(np.round([v[0] for v in values], 9))) > 2  # six distinct updates
    steps, _ = temporal_column(chunks, "/plots/control/tracking/speed_error", "Scalars:scalars")
    assert len(steps) == 3
    verify(path)


def test_a_link_is_followed_and_a_fifo_refused(result, tmp_path):
    """Issue 53, defect 1: `--rrd link.rrd` replaced the link by a file, `--rrd /dev/null` the device. The link's
    target is written (the link stays); a FIFO (standing in for a device) is refused and stays a FIFO."""
    import stat

    (tmp_path / "flight.rrd").write_bytes(b"old")
    os.symlink("flight.rrd", tmp_path / "link.rrd")
    write_rrd(tmp_path / "link.rrd", result)
    assert (tmp_path / "link.rrd").is_symlink() and (tmp_path / "flight.rrd").stat().st_size > 1000
    os.mkfifo(tmp_path / "fifo.rrd")
    with pytest.raises(ValueError, match="fifo.rrd: it is a FIFO"):
        write_rrd(tmp_path / "fifo.rrd", result)
    assert stat.S_ISFIFO(os.stat(tmp_path / "fifo.rrd").st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fifo.rrd", "flight.rrd", "link.rrd"]
