"""Bad input and failures against the CLI contract (docs/conventions.md; issue 18's trial): a user error exits 2 with
one line naming the input, an environment failure 1, a numerical failure 3 with the step, time and cause; nothing
is left behind. One parametrised case per class of the trial."""

from __future__ import annotations

import os

import pytest

from hawksim.cli import main

KIN = "f=26.1,beta=4.3,phi0=9.4,theta0=-2.8,alpha0=-0.4,phi_a=58.4,alpha_a=48.8"

USER_ERRORS = [
    (["fly", "--speed", "3", "--cycles", "1"], "--speed"),
    (["fly", "--speed", "1", "--cycles", "1e9"], "--cycles"),
    (["fly", "--speed", "1", "--cycles", "1", "--steps-per-cycle", "100000000"], "--steps-per-cycle"),
    (["fly", "--speed", "1", "--cycles", "1", "--perturb", "u=1", "--perturb", "u=2"], "--perturb"),
    (["fly", "--speed", "1", "--cycles", "1", "--rrd", ""], "--rrd"),
    (["fly", "--speed", "1", "--cycles", "1", "--perturb", "x=1"], "--perturb"),
    (["fly", "--speed", "1", "--cycles", "1", "--aero", "uvlm", "--wake-precision", "half"], "--wake-precision"),
    (["fly", "--speed", "1", "--cycles", "1", "--wake-precision", "mixed"], "--wake-precision"),
    (["aero", "--speed", "0", "--kinematics", KIN, "--cycles", "1000000000"], "--cycles"),
    (["aero", "--speed", "0", "--kinematics", KIN, "--n-chord", "1000000"], "--n-chord"),
    (["aero", "--speed", "0", "--kinematics", KIN.replace("f=26.1", "f=nan")], "--kinematics"),
    (["trim", "--speed", "1", "--population", "1000000000"], "--population"),
    (["trim", "--speed", "1", "--population", "1.5"], "--population"),
    (["dataset", "--speed", "1", "--samples", "2", "--out", "{tmp}/d.sqlite", "--seed", "1180591620717411303424"],
     "--seed"),
    (["train", "--data", "{tmp}/none.sqlite", "--out", "{tmp}/m.safetensors", "--speed", "1", "--all-speeds"],
     "--all-speeds"),
    (["reproduce", "--out", "/nonexistent/r"], "--out"),
    (["reproduce", "--out", "{tmp}/a_file"], "--out"),
    (["reproduce", "--out", "{tmp}/full"], "--force"),
]


@pytest.fixture
def tmp(tmp_path):
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "old.json").write_text("{}")
    return tmp_path


def _run(argv, tmp, capsys):
    before = {p.name for p in tmp.iterdir()}
    code = main([a.replace("{tmp}", str(tmp)) for a in argv])
    out, err = capsys.readouterr()
    left = {p.name for p in tmp.iterdir()} - before
    return code, out, err.strip().splitlines(), left


@pytest.mark.parametrize("argv,names", USER_ERRORS, ids=lambda a: " ".join(a) if isinstance(a, list) else a)
def test_user_errors_exit_2_with_one_line_and_leave_nothing(argv, names, tmp, capsys):
    code, out, err, left = _run(argv, tmp, capsys)
    assert code == 2 and out == ""
    assert len(err) == 1 and names in err[0], err
    assert not left
    assert not os.path.exists("/nonexistent")


@pytest.mark.parametrize("content,what", [(b"", "empty"), (b"\x93NUMPY\x01\x00", "not an MJCF"), (None, "directory"),
                                          (b"<mujoco><worldbody></mujoco>", "could not be loaded")])
def test_bad_model_files_are_named(content, what, tmp, capsys):
    path = tmp / "m.xml"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    code, out, err, _ = _run(["fly", "--speed", "1", "--cycles", "1", "--model", str(path)], tmp, capsys)
    assert code == 2 and len(err) == 1 and what in err[0] and "m.xml" in err[0], err


def test_a_numerical_blow_up_stops_with_step_time_and_cause(tmp, capsys, monkeypatch):
    """q = 1e9 deg/s at the start: MuJoCo's BADQACC resets the state (it reported a 27 m/s 'ascent' before); now the
    run stops (exit 3), says where and why, and MuJoCo's log goes to stderr, not MUJOCO_LOG.TXT in the cwd."""
    monkeypatch.chdir(tmp)
    code, out, err, left = _run(["fly", "--speed", "1", "--cycles", "2", "--perturb", "q=1e9", "--json",
                                 "--no-progress"], tmp, capsys)
    assert code == 3 and out == ""
    assert len(err) == 1 and "numerical failure" in err[0] and "step 0" in err[0] and "BADQACC" in err[0]
    assert "Nan, Inf or huge value in QACC" in err[0]  # MuJoCo's own words, in the one line
    assert not left  # no MUJOCO_LOG.TXT


def test_an_unreachable_scheduler_fails_fast_and_leaves_no_file(tmp, capsys):
    code, out, err, left = _run(["dataset", "--speed", "1", "--samples", "2", "--out", "{tmp}/d.sqlite",
                                 "--scheduler", "tcp://127.0.0.1:1", "--json", "--no-progress"], tmp, capsys)
    assert code == 1 and out == "" and len(err) == 1 and "tcp://127.0.0.1:1" in err[0]
    assert not left


def test_integers_may_be_written_as_1e5():
    from hawksim.cli import build_parser

    args = build_parser().parse_args(["trim", "--speed", "1", "--population", "1e5"])
    assert args.population == 100_000


def test_a_second_writer_of_one_data_set_is_refused(tmp, capsys):
    """Two `hawksim dataset` runs on one file used to compute the same samples twice; a run now holds an exclusive
    flock on the file while it writes, and a second one exits 2 naming the file (its samples untouched)."""
    import fcntl

    from hawksim.surrogate.dataset import open_dataset

    path = tmp / "d.sqlite"
    open_dataset(path, create=True).close()
    with open(path, "rb") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)  # stands for the first writer
        before = path.read_bytes()
        code = main(["dataset", "--speed", "1", "--samples", "2", "--out", str(path), "--workers", "1", "--json",
                     "--no-progress"])
        err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "another hawksim dataset" in err[0] and "d.sqlite" in err[0]
    assert path.read_bytes() == before


def test_ctrl_c_stops_a_dask_run_quietly(tmp):
    """A terminal's Ctrl-C (SIGINT to the whole process group) during `hawksim dataset` on a LocalCluster: exit 130,
    one line, no worker tracebacks (the workers ignore SIGINT; the parent closes them). Issue 18 counted 4."""
    import signal
    import subprocess
    import sys
    import time

    exe = os.path.join(os.path.dirname(sys.executable), "hawksim")
    p = subprocess.Popen([exe, "dataset", "--speed", "1", "--samples", "400", "--out", str(tmp / "d.sqlite"),
                          "--workers", "2", "--json", "--no-progress"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.time() + 60  # wait for the first stored sample: the cluster is up and computing
    while time.time() < deadline and p.poll() is None:
        if (tmp / "d.sqlite").exists() and os.path.getsize(tmp / "d.sqlite") > 0:
            import sqlite3

            try:
                with sqlite3.connect(tmp / "d.sqlite", timeout=1) as c:
                    if c.execute("SELECT count(*) FROM samples").fetchone()[0] > 0:
                        break
            except sqlite3.Error:
                pass
        time.sleep(0.5)
    os.killpg(p.pid, signal.SIGINT)
    out, err = p.communicate(timeout=120)
    err = err.decode()
    assert p.returncode == 130 and out == b""
    assert "Traceback" not in err and err.strip().splitlines()[-1] == "hawksim: interrupted"
