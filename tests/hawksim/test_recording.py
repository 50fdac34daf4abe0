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

POS_ATOL = 1e-8
"""m: positions stored as float32 (|x| < 0.1 m here, half an ulp ~4e-9 m)."""

ANGLE_ATOL_DEG = 1e-4
"""deg: plotted attitude angles (float64, from float64 quaternions) vs the constructed ones: trigonometric round-off
only (~1e-13); the round value is a loose bound, so that only a wrong angle definition fails (the old one was off by
180 deg)."""

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
    expected = ["/world/moth", "/world/moth/body", "/world/moth/body/labels", "/world/moth/weight",
                "/world/trajectory", "/world/ruler", "/world/legend"]
    expected += [f"/world/moth/{kind}/{side}" for kind in ("wings", "forces") for side in ("left", "right")]
    expected += [f"/world/moth/wings/{side}/{part}" for side in ("left", "right") for part in ("mesh", "outline")]
    expected += [f"/plots/{name}" for name in (
        "forces/lift", "forces/drag", "forces_nd/L_plus", "forces_nd/D_plus", "moment/pitching",
        "moment_nd/M_plus", "power/aero", "power/joint", "velocity/vx", "velocity/vy", "velocity/vz",
        "attitude/pitch", "attitude/roll", "attitude/yaw")]
    missing = [e for e in expected if e not in chunks]
    assert not missing, missing
    assert not any(e.startswith("/world/uvlm") for e in chunks)

    n = len(result.t)
    steps, quats = temporal_column(chunks, "/world/moth/body", "Transform3D:quaternion")
    np.testing.assert_array_equal(steps, np.arange(n))
    q = np.array([v[0] for v in quats])  # xyzw, stored as float32
    np.testing.assert_allclose(q, result.body_quat[:, [1, 2, 3, 0]], atol=QUAT_ATOL)
    for i, side in enumerate(("left", "right")):
        _, wq = temporal_column(chunks, f"/world/moth/wings/{side}", "Transform3D:quaternion")
        assert len(wq) == n
        x, y, z, w = np.array([v[0] for v in wq], dtype=float).T  # wing frame -> world axes, xyzw
        R = np.stack([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]).transpose(2, 0, 1)
        np.testing.assert_allclose(R, result.wing_R[:, i], atol=WING_R_ATOL)
        _, wt = temporal_column(chunks, f"/world/moth/wings/{side}", "Transform3D:translation")
        np.testing.assert_allclose(np.array([v[0] for v in wt]), result.wing_origin[:, i] - result.body_pos,
                                   atol=POS_ATOL)
        assert len(temporal_column(chunks, f"/world/moth/forces/{side}", "Arrows3D:vectors")[0]) == n

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
    extras[0][1]["pressure"][0, 1, 2] = 672.0  # one outlier panel [Pa] among values of ~5 Pa
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
    p_lim = np.percentile(np.abs([e["pressure"] for _, e in extras]), recording.ROBUST_PERCENTILE)
    rgb = np.array([unpack_rgb(c) for c in colors[0][::4]])
    np.testing.assert_array_equal(rgb, recording.diverging_colors(p[0].reshape(-1), p_lim))
    assert p_lim < 20  # the scale is set by the bulk of the panels, not by the outlier (issue 52)
    assert tuple(rgb[1 * ns + 2]) == (180, 4, 38)  # the outlier clipped to the end colour
    assert len(np.unique(rgb, axis=0)) > nc * ns // 2  # the other panels keep distinct colours
    legend = [rb.column("TextDocument:text").to_pylist()[0][0] for st, rb in chunks["/world/uvlm/legend"]
              if "TextDocument:text" in rb.schema.names][0]
    assert f"+{p_lim:.3g} Pa" in legend and "largest 672 Pa" in legend

    got_steps, strips = temporal_column(chunks, "/world/uvlm/wake/right", "LineStrips3D:strips")
    np.testing.assert_array_equal(got_steps, steps)
    v, g = extras[0][1]["wake"][1]
    _, strength = recording.wake_filaments(v, g)
    g_lim = recording.uvlm_scales(extras)["gamma"][0]
    expected = int((strength >= recording.WAKE_MIN_FRACTION * g_lim).sum())
    assert len(strength) == rows * ns + rows * (ns + 1) and 0 < expected < len(strength)
    assert len(strips[0]) == expected and all(len(p) == 2 for p in strips[0])  # two-point filaments


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
    assert names["/plots/forces_nd"] == "L+, D+ (/ weight) [-]" and names["/plots/moment_nd"] == "M+ [-]"


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
    chunks = read_chunks(path)
    steps, _ = temporal_column(chunks, "/world/uvlm/panels/left", "Mesh3D:vertex_positions")
    np.testing.assert_array_equal(steps, np.arange(0, len(result.t), every))
    # the wake at most WAKE_FRAMES_PER_BEAT times a beat: every other update at 200 steps a beat
    wake, _ = temporal_column(chunks, "/world/uvlm/wake/left", "LineStrips3D:strips")
    gap = result.steps_per_cycle // recording.WAKE_FRAMES_PER_BEAT
    np.testing.assert_array_equal(wake, np.arange(0, len(result.t), max(gap, every)))
    assert len(wake) <= recording.WAKE_FRAMES_PER_BEAT * len(result.t) / result.steps_per_cycle + 1
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
    steps, _ = temporal_column(read_chunks(path), "/world/moth", "Transform3D:translation")
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
    steps, _ = temporal_column(chunks, "/world/moth", "Transform3D:translation")
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


# ---- a recording a reader understands at a glance (issue 52 item 2) ------------------------------------------
def blueprint_components(path: Path, suffix: str) -> dict[str, dict]:
    """Blueprint entity (ending with ``suffix``) -> {component: last value} of the file's blueprint store."""
    reader = RrdReader(path)
    out: dict[str, dict] = {}
    for ch in reader.stream(store=reader.blueprints()[0]).to_chunks():
        if ch.entity_path.endswith(suffix):
            rb = ch.to_record_batch()
            out.setdefault(ch.entity_path, {}).update(
                {c: rb.column(c).to_pylist()[-1] for c in rb.schema.names if ":" in c})
    return out


def series_styles(chunks: dict) -> dict[str, tuple]:
    """Scalars entity -> its colour (r, g, b) from SeriesLines / SeriesPoints (None where it has none)."""
    out = {}
    for e, lst in chunks.items():
        if not any("Scalars:scalars" in rb.schema.names for _, rb in lst):
            continue
        cols = [rb.column(c).to_pylist()[0] for _, rb in lst for c in rb.schema.names
                if c in ("SeriesLines:colors", "SeriesPoints:colors")]
        out[e] = unpack_rgb(cols[0][0]) if cols and cols[0] else None
    return out


def check_distinct_colours(path: Path, chunks: dict) -> dict[str, list]:
    """Every Scalars entity is in exactly one time-series view and has a colour of its own within that view, far
    from the dark background; returns view origin -> its series."""
    ts = [o for c, o, _ in blueprint_views(path) if c == "TimeSeries"]
    by_view: dict[str, list] = {}
    for e, rgb in series_styles(chunks).items():
        views = [o for o in ts if e == o or e.startswith(o + "/")]
        assert len(views) == 1, (e, views)
        assert rgb is not None and max(rgb) >= 120, (e, rgb)  # visible on the viewer's dark background
        by_view.setdefault(views[0], []).append((e, rgb))
    for view, lst in by_view.items():
        colours = [rgb for _, rgb in lst]
        assert len(set(colours)) == len(colours), (view, lst)
    return by_view


def test_blueprint_series_colours_distinct_in_every_view(result, tmp_path):
    path = write_rrd(tmp_path / "flight.rrd", result)
    by_view = check_distinct_colours(path, read_chunks(path))
    assert len(by_view["/plots/forces"]) == 2 and len(by_view["/plots/power"]) == 2
    assert len(by_view["/plots/velocity"]) == 3 and len(by_view["/plots/attitude"]) == 3  # pitch, roll, yaw


def test_3d_view_follows_the_body(result, tmp_path):
    """The 3D view's origin is /world/moth, whose transform is the centre-of-mass position (translation only); the
    body, wings and force arrows hang under it; the eye looks at the origin from 2-4 times the insect's extent, so
    the whole insect (wing tips included) is in frame wherever the moth flies."""
    path = write_rrd(tmp_path / "flight.rrd", result)
    views = blueprint_views(path)
    spatial = [o for c, o, _ in views if c == "3D"]
    assert spatial == ["/world/moth"]
    chunks = read_chunks(path)
    steps, tr = temporal_column(chunks, "/world/moth", "Transform3D:translation")
    np.testing.assert_array_equal(steps, np.arange(len(result.t)))
    np.testing.assert_allclose(np.array([v[0] for v in tr]), result.body_pos, atol=POS_ATOL)
    assert not any(c in rb.schema.names for _, rb in chunks["/world/moth"]
                   for c in ("Transform3D:quaternion", "Transform3D:mat3x3", "Transform3D:rotation_axis_angle"))
    for e in ("body", "wings/left", "wings/right", "forces/left", "forces/right"):
        assert f"/world/moth/{e}" in chunks
    assert not any(e.startswith("/world/wings") or e.startswith("/world/forces") for e in chunks)

    eye = next(iter(blueprint_components(path, "/EyeControls3D").values()))
    target = np.array(eye["EyeControls3D:look_target"][0])
    position = np.array(eye["EyeControls3D:position"][0])
    np.testing.assert_allclose(target, 0.0, atol=1e-12)
    tips = result.wing_origin[:, 0] + result.wing_R[:, 0, :, 1] * HAWKMOTH.R - result.body_pos
    extent = np.linalg.norm(tips, axis=1).max()  # m: the farthest wing tip from the centre of mass
    assert 2.0 * extent <= np.linalg.norm(position - target) <= 4.0 * extent


def test_attitude_series_as_the_json_past_90_deg_pitch(result, tmp_path):
    """Issue 52 bug: `fly --perturb q=100 --control none` showed roll jumping to ~175 deg once the pitch passed
    90 deg (Z-Y-X Euler angles), while the JSON says roll 0. The recording plots FlightResult.attitude() (the
    JSON's pitch-first angles, unwrapped): a pure pitch-over from 60 to 300 deg stays a pitch with roll and yaw 0."""
    n = len(result.t)
    pitch = np.deg2rad(np.linspace(60.0, 300.0, n))
    # body -> world for a nose-up pitch about the world's -y (body x up from the heading +x)
    quat = np.stack([np.cos(pitch / 2), 0 * pitch, -np.sin(pitch / 2), 0 * pitch], 1)  # w, x, y, z
    res = dataclasses.replace(result, body_quat=quat)
    chunks = read_chunks(write_rrd(tmp_path / "over.rrd", res))
    got = {k: np.array([v[0] for v in temporal_column(chunks, f"/plots/attitude/{k}", "Scalars:scalars")[1]])
           for k in ("pitch", "roll", "yaw")}
    np.testing.assert_allclose(got["pitch"], np.rad2deg(pitch), atol=ANGLE_ATOL_DEG)
    np.testing.assert_allclose(got["roll"], 0.0, atol=ANGLE_ATOL_DEG)
    np.testing.assert_allclose(got["yaw"], 0.0, atol=ANGLE_ATOL_DEG)
    np.testing.assert_allclose(got["pitch"], np.rad2deg(res.attitude()[:, 0]), rtol=SCALAR_RTOL)


def test_wake_filaments():
    """A uniform sheet of rings: the interior edges cancel, the border carries the rings' circulation; the newest
    row's upstream edges (at the trailing edge) are left out."""
    rows, ns = 3, 4
    x, y = np.meshgrid(-np.arange(rows + 1.0), np.arange(ns + 1.0), indexing="ij")
    v = np.stack([x, y, 0 * x], -1)
    seg, strength = recording.wake_filaments(v, np.full((rows, ns), 2.0))
    assert seg.shape == (rows * ns + rows * (ns + 1), 2, 3)
    mid = seg.mean(1)
    border = (np.isclose(mid[:, 0], -rows)) | np.isclose(mid[:, 1], 0) | np.isclose(mid[:, 1], ns)
    np.testing.assert_allclose(strength[border], 2.0)
    np.testing.assert_allclose(strength[~border], 0.0)
    assert not np.any(np.isclose(mid[:, 0], 0.0) & ~np.isclose(mid[:, 1] % 1, 0))  # no trailing-edge edges


def test_control_errors_in_sensible_units_without_round_off():
    """Issue 52: the Control tab plotted round-off (tick labels like 0.000 000 000 000 3). Tracking errors are
    plotted in mm/s, deg and mm, rounded to 1 um/s, 1e-4 deg and 1 um; commands to 1e-6 of their unit."""
    beats = [{"commands": {"f_hz": 28.53 + 3e-13, "dphi0_deg": -2e-14}, "speed_error": 3e-16,
              "pitch_error_deg": -4e-15, "roll_deg": 0.25, "horizontal_drift_m": 0.0123456}]
    views = {key: name for _, key, _, name in recording.control_views(beats)}
    assert views["speed_error"] == "speed error [mm/s]" and views["horizontal_drift_m"] == "horizontal drift [mm]"
    assert views["f_hz"] == "command f_hz [Hz]"
    assert recording.control_values(beats, "speed_error", "tracking")[0] == 0.0
    assert recording.control_values(beats, "pitch_error_deg", "tracking")[0] == 0.0
    assert recording.control_values(beats, "roll_deg", "tracking")[0] == pytest.approx(0.25, abs=1e-12)
    assert recording.control_values(beats, "horizontal_drift_m", "tracking")[0] == pytest.approx(12.346, abs=1e-9)
    assert recording.control_values(beats, "f_hz", "commands")[0] == pytest.approx(28.53, abs=1e-12)
    assert recording.control_values(beats, "dphi0_deg", "commands")[0] == 0.0


def test_side_colours_stay_off_the_pressure_scale(result, tmp_path):
    """Issue 52 bug: the UVLM recording showed the pressure colours opposite on the left and right wings of a
    symmetric flight: the wings' own fills (orange left, blue right) lay over the pressure panels in the colours of
    the pressure scale's two ends. With panels the wings are outlines only, and the side colours are far from every
    colour of the blue-grey-red scale."""
    scale = recording.diverging_colors(np.linspace(-1, 1, 201), 1.0).astype(float)
    for rgb in recording.SIDE_COLORS.values():
        assert np.linalg.norm(scale - rgb, axis=1).min() > 100
    res = dataclasses.replace(result, extras=[(k, synthetic_extras(result, k)) for k in (0, 5)])
    chunks = read_chunks(write_rrd(tmp_path / "uvlm.rrd", res))
    meshes = [e for e, lst in chunks.items() if any("Mesh3D:vertex_positions" in rb.schema.names for _, rb in lst)]
    assert sorted(meshes) == ["/world/uvlm/panels/left", "/world/uvlm/panels/right"]
    assert "/world/moth/wings/left/outline" in chunks
