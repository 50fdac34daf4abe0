"""What `hawksim fly` and `hawksim stability` print for a person, the compact JSON, and `fly --out` read back with
plain numpy (docs/output.md)."""

import json
import zipfile

import numpy as np
import pytest

from hawksim.cli import main

KIN = "f=28.5,beta=2.47,phi0=-4.5,theta0=15,alpha0=1.8,phi_a=60,alpha_a=65"

COMPACT_BYTES_PER_BEAT = 1000
"""Upper bound of the compact JSON's size per wingbeat of a controlled flight [bytes]: one row of ~20 numbers with
their keys (~750 bytes measured), not the gains or the closed-loop spectra (~70 kB before issue 52)."""


def read_npz_without_hawksim(path):
    """The reading code path of a user without hawksim: numpy and json only."""
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays.pop("metadata")))
    return arrays, meta


@pytest.fixture(scope="module")
def controlled(tmp_path_factory):
    """`hawksim fly --speed 1 --cycles 4 --gust ... --json --out` (quasi-steady, LQR per beat) and the same flight in
    memory (hawksim.control.command.fly_command)."""
    import io
    from contextlib import redirect_stdout

    path = tmp_path_factory.mktemp("out") / "flight.npz"
    buf = io.StringIO()
    with redirect_stdout(buf):
        code = main(["fly", "--speed", "1", "--cycles", "4", "--gust", "0,0.5,0@2:1", "--json", "--no-progress",
                     "--out", str(path)])
    assert code == 0
    from hawksim.control.command import fly_command
    from hawksim.control.closed_loop import Gust

    cl = fly_command(1.0, 4, control="lqr", gusts=[Gust(np.array([0.0, 0.5, 0.0]), 2, 1)])
    return json.loads(buf.getvalue()), path, cl


def test_compact_json_has_the_table_not_the_gains(controlled):
    out, path, cl = controlled
    text = json.dumps(out)
    assert len(text) < COMPACT_BYTES_PER_BEAT * 4 + 4000
    ctl = out["control"]
    assert "beats" not in ctl and all("K_long" not in p and "closed_loop_multipliers_long" not in p
                                      for p in ctl["schedule"])
    assert ctl["schedule"][0]["closed_loop_spectral_radius_long"] < 1
    b = out["beats"]
    assert [r["beat"] for r in b] == [1, 2, 3, 4]
    assert {"mean_vertical_speed", "horizontal_speed", "pitch_deg", "roll_deg", "yaw_deg", "speed_error",
            "pitch_error_deg", "commands", "P_plus"} <= b[2].keys()
    assert "state" not in b[0] and "commands_half_stroke" not in b[0]
    assert b[1]["air_velocity"] == [0.0, 0.5, 0.0] and b[2]["air_velocity"] == [0.0, 0.0, 0.0]
    for row, c in zip(b, cl.beats):  # the flight flown again in memory gives the same numbers
        assert row["speed_error"] == pytest.approx(c["speed_error"], abs=1e-9)
        assert row["commands"]["dphi0_deg"] == pytest.approx(c["commands"]["dphi0_deg"], abs=1e-7)
    w = out["worst_beat_errors"]
    assert w["speed_error"] == pytest.approx(max(abs(c["speed_error"]) for c in cl.beats), abs=1e-9)
    assert w["roll_deg"] == pytest.approx(max(abs(r["roll_deg"]) for r in b))
    assert out["floquet"]["open_loop_max"] > 1 > out["floquet"]["closed_loop_max"]
    assert out["wall_time_s"] >= out["timings_s"]["flight_s"] > 0 and out["out"] == str(path)


def test_out_file_read_back_with_numpy_only(controlled):
    out, path, cl = controlled
    a, meta = read_npz_without_hawksim(path)
    assert zipfile.is_zipfile(path)
    r = cl.result
    n = 4 * r.steps_per_cycle
    assert a["t"].shape == (n,) and a["body_pos"].shape == (n, 3) and a["wing_angles"].shape == (n, 2, 3)
    np.testing.assert_allclose(a["t"], r.t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a["body_pos"], r.body_pos, rtol=0, atol=1e-9)
    np.testing.assert_allclose(a["force"], r.force, rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(a["power_joint"], r.power_joint, rtol=1e-7, atol=1e-12)
    assert a["beat_beat"].tolist() == [1, 2, 3, 4]
    np.testing.assert_allclose(a["beat_speed_error"], [c["speed_error"] for c in cl.beats], atol=1e-9)
    assert a["beat_state"].shape == (4, 9) and a["beat_commands_f_hz"].shape == (4,)
    assert a["beat_saturated"].dtype == bool
    # the summary's beat means from the per-step arrays alone: mean vertical speed over beat 2
    spc = meta["steps_per_cycle"]
    z = a["body_pos"][:, 2]
    vz2 = (z[2 * spc] - z[spc]) / (a["t"][2 * spc] - a["t"][spc])
    assert vz2 == pytest.approx(out["beats"][1]["mean_vertical_speed"], rel=1e-9)
    assert meta["format"] == "hawksim-flight-npz/1" and meta["units"]["body_pos"] == "m"
    assert meta["units"]["force"] == "N" and meta["units"]["beat_pitch_error_deg"] == "deg"
    assert meta["units"]["beat_commands_f_hz"] == "Hz" and meta["units"]["wing_angles"] == "rad"
    assert set(meta["units"]) == set(a)  # every array has its unit
    assert meta["command"][:2] == ["hawksim", "fly"] or meta["command"][0] == "hawksim"
    assert "seed" in meta and meta["summary"]["departed_at_beat"] is None


def test_wing_angles_are_the_prescribed_ones():
    """The file's wing angles, read back from the wing frames, are Eq. 1's at each step's time (open loop, fixed
    kinematics; the computed-torque tracking is ~1e-5 deg)."""
    from hawksim.cli.fly import fly_named
    from hawksim.flight.export import wing_angles

    r = fly_named(1.0, 1, "quasi-steady")
    wa = wing_angles(r)
    ang = r.kinematics.angles(r.t).T  # (n, 3)
    for side in range(2):
        np.testing.assert_allclose(wa[:, side], ang, atol=1e-5)


def test_human_summary_of_a_held_flight(capsys):
    assert main(["fly", "--speed", "1", "--cycles", "3", "--no-progress"]) == 0
    text = capsys.readouterr().out
    lines = text.strip().splitlines()
    assert len(lines) <= 12 and "{" not in text
    assert lines[0].startswith("hawksim fly: hawkmoth, quasi-steady aerodynamics, 1 m/s ascent, 3 wingbeats, LQR")
    assert any(line.strip().startswith("verdict    held") for line in lines)
    assert "largest multiplier" in text and "wall time" in text and "m/s" in text


def test_kinematics_start_is_said_on_stderr_and_in_the_summary(capsys):
    """Given kinematics fly from the held-body start, and both stderr and the JSON say so and why; the departure
    message no longer calls it a trim."""
    assert main(["fly", "--speed", "1", "--cycles", "6", "--control", "none", "--kinematics", KIN, "--json",
                 "--no-progress"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert out["start"]["from"] == "trim" and "given kinematics" in out["start"]["note"]
    first = cap.err.strip().splitlines()[0]
    assert first.startswith("fly: starting from the given kinematics") and "--start orbit" in first
    assert "leaves its trim" not in cap.err


def test_steps_per_cycle_without_orbit_is_said(capsys):
    assert main(["fly", "--speed", "1", "--cycles", "1", "--control", "none", "--steps-per-cycle", "400", "--json",
                 "--no-progress"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert "--steps-per-cycle 400 has no periodic orbit" in out["start"]["note"]
    assert "--steps-per-cycle 400" in cap.err.splitlines()[0]


def test_start_orbit_from_given_kinematics_says_f_moved(capsys):
    assert main(["fly", "--speed", "1", "--cycles", "1", "--control", "none", "--start", "orbit", "--kinematics",
                 KIN, "--json", "--no-progress"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert out["start"]["from"] == "orbit" and "f and phi0 are solved" in out["start"]["note"]
    assert "f 28.5 ->" in out["start"]["source"]


@pytest.mark.parametrize("bad", ["/nonexistent/dir/f.npz", "/dev/null", ""])
def test_out_bad_path_exits_2_writes_nothing(bad, capsys, tmp_path):
    assert main(["fly", "--speed", "1", "--cycles", "1", "--out", bad, "--no-progress"]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and len(cap.err.strip().splitlines()) == 1 and "--out" in cap.err


def test_stability_prints_the_multipliers(capsys):
    assert main(["stability", "--speed", "1", "--floquet", "--aero", "quasi-steady", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "entries (see --json)" not in text and "{" not in text
    floquet = text[text.index("Floquet multipliers"):]
    # the shipped quasi-steady 1 m/s orbit's multipliers (hawksim 0.3, `hawksim reproduce --only orbits`)
    assert "longitudinal 1.497+/-0.3848i" in floquet and "|1.546|" in floquet and "UNSTABLE" in floquet
    assert "largest |multiplier| 1.546" in floquet


def test_stability_kinematics_says_it_solved_f(capsys):
    assert main(["stability", "--speed", "1", "--floquet", "--aero", "quasi-steady", "--kinematics", KIN, "--json",
                 "--no-progress"]) == 0
    cap = capsys.readouterr()
    solved = json.loads(cap.out)["orbit"]["kinematics_solved"]
    # the given kinematics are hawksim 0.2's orbit's (28.5 Hz); the sourced hawkmoth's orbit at them flaps at 25.76
    assert solved["f_given"] == pytest.approx(28.5) and solved["f_solved"] == pytest.approx(25.76, abs=0.01)
    line = [s for s in cap.err.splitlines() if s.startswith("stability:")]
    assert len(line) == 1 and "f 28.5 -> 25.764 Hz" in line[0]


def test_stability_uvlm_summary_names_its_model(capsys, monkeypatch):
    """`hawksim stability` with its default UVLM model (the disturbed runs replaced by the quasi-steady report: the
    summary's code path is what is tested) names the model and prints the eigenvalues; it raised KeyError before."""
    from hawksim.stability import report
    from hawksim.stability.floquet import quasi_steady_system

    from hawksim.insect.kinematics import table3_kinematics

    def fake(speed, kinematics=None, client=None, progress=None):
        kin = kinematics if kinematics is not None else table3_kinematics(speed)
        return {"speed": speed, "trim": {"kinematics": kin.to_edge()},
                **report.averaged_json(quasi_steady_system(kin, speed))}

    monkeypatch.setattr(report, "stability_report", fake)
    assert main(["stability", "--speed", "1", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert text.startswith("hawksim stability: uvlm model at 1 m/s") and "longitudinal" in text


def test_fly_summary_suggests_no_floquet_a_backend_cannot_do(capsys):
    """The cycle-mean network has no periodic orbit: the summary says so instead of suggesting a stability command
    that would be refused (the registry's reason)."""
    assert main(["fly", "--speed", "1", "--cycles", "1", "--aero", "surrogate-mean", "--no-progress"]) == 0
    floquet = [line for line in capsys.readouterr().out.splitlines() if line.strip().startswith("Floquet")]
    assert len(floquet) == 1 and "has no periodic orbit" in floquet[0] and "hawksim stability" not in floquet[0]
