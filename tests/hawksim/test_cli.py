"""`hawksim fly` against the CLI contract (docs/conventions.md): JSON keys, and bad input -> exit 2, one line."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from hawksim.cli import main

FLY_KEYS = {"speed_target", "cycles", "aero", "mean_vertical_speed", "pitch_change_deg", "max_abs_roll_deg",
            "horizontal_drift", "wall_time_s", "rrd"}
KIN_OK = "f=30,beta=0,phi0=0,theta0=0,alpha0=0,phi_a=45,alpha_a=45"

TWO_BEAT_SPEED_RANGE = (0.5, 1.5)
"""m/s: mean vertical speed of a 2-beat quasi-steady flight started at 1 m/s upward: two beats cannot change it by
more than a few tenths (a plausibility band, not derived or measured)."""


def _hawksim_cmd():
    exe = Path(sys.executable).with_name("hawksim")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "hawksim.cli"]


def test_fly_console_script_json_and_recording(tmp_path):
    rrd = tmp_path / "out.rrd"
    p = subprocess.run([*_hawksim_cmd(), "fly", "--speed", "1", "--cycles", "2", "--rrd", str(rrd), "--json"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)  # exactly one JSON object on stdout
    assert FLY_KEYS <= out.keys()
    assert out["speed_target"] == 1.0 and out["cycles"] == 2 and out["aero"] == "quasi-steady"
    assert out["rrd"] == str(rrd) and rrd.stat().st_size > 10_000
    assert TWO_BEAT_SPEED_RANGE[0] < out["mean_vertical_speed"] < TWO_BEAT_SPEED_RANGE[1]


@pytest.mark.parametrize("args, needle", [
    (["--speed", "-1", "--cycles", "2"], "--speed"),
    (["--speed", "nan", "--cycles", "2"], "--speed"),
    (["--speed", "1", "--cycles", "0"], "--cycles"),
    (["--speed", "1", "--cycles", "2", "--kinematics", KIN_OK.replace("f=30", "f=50")], "f=50"),
    (["--speed", "1", "--cycles", "2", "--kinematics", KIN_OK + ",gamma=3"], "gamma"),
    (["--speed", "1", "--cycles", "2", "--kinematics", KIN_OK.replace("alpha_a=45", "alpha_a=x")], "alpha_a"),
    (["--speed", "1", "--cycles", "2", "--model", "/nonexistent/hawkmoth.xml"], "/nonexistent/hawkmoth.xml"),
    (["--speed", "1", "--cycles", "2", "--perturb", "zz=1"], "zz"),
    (["--speed", "1", "--cycles", "2", "--rrd", "/nonexistent/dir/out.rrd"], "out.rrd"),
    (["--speed", "1", "--cycles", "2", "--aero", "cfd"], "--aero"),
])
def test_bad_input_exits_2_with_one_line(args, needle, capsys):
    assert main(["fly", *args, "--json"]) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    lines = cap.err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0]


def test_corrupt_model_file_exits_2(tmp_path, capsys):
    bad = tmp_path / "corrupt.xml"
    bad.write_text("<mujoco><worldbody><body")
    assert main(["fly", "--speed", "1", "--cycles", "1", "--model", str(bad), "--json"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "corrupt.xml" in err[0]


def test_nothing_written_on_bad_input(tmp_path, capsys):
    rrd = tmp_path / "never.rrd"
    assert main(["fly", "--speed", "1", "--cycles", "0", "--rrd", str(rrd)]) == 2
    assert not rrd.exists() and os.listdir(tmp_path) == []


def test_kinematics_override_and_perturbation_are_used(capsys):
    assert main(["fly", "--speed", "0", "--cycles", "1", "--kinematics", KIN_OK, "--perturb", "q=100",
                 "--perturb", "theta=2", "--json", "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["kinematics"]["f"] == pytest.approx(30) and out["kinematics"]["alpha_a"] == pytest.approx(45)
