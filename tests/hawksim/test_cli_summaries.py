"""What `hawksim aero`, `predict`, `trim`, `dataset`, `train`, `warmup` and `reproduce` print without ``--json``
(docs/output.md): each its own few lines, and nothing else on stdout; the numbers on those lines are the numbers of
the JSON object of the same run, to the digits printed."""

import json
import re

import pytest

import hawksim.cli as cli
from hawksim.insect.kinematics import TABLE2_BOUNDS_DEG

KIN = "f=28.5,beta=2.47,phi0=-4.5,theta0=15,alpha0=1.8,phi_a=60,alpha_a=65"
TINY = ["--n-chord", "2", "--n-span", "3", "--steps-per-cycle", "20"]
MAX_LINES = 9
"""A summary a person reads in ten seconds: at most this many lines."""
NUMBER = r"(-?\d+(?:\.\d*)?(?:e[-+]?\d+)?)"


def run(monkeypatch, capsys, argv):
    """Run ``hawksim ARGV`` (no --json) in this process; (the JSON object of that same run, as --json would print it;
    stdout; stderr). The object is caught on its way to the printer (hawksim.cli.write_output)."""
    seen = {}
    printer = cli.write_output

    def spy(out, as_json, human=None):
        seen.update(out=json.loads(json.dumps(out)), human=human)
        return printer(out, as_json, human)

    monkeypatch.setattr(cli, "write_output", spy)
    code = cli.main(argv)
    cap = capsys.readouterr()
    assert code == 0, cap.err
    assert seen["human"] is not None, f"hawksim {argv[0]} has no summary of its own"
    return seen["out"], cap.out, cap.err


def only_the_summary(stdout: str, command: str) -> list[str]:
    """The summary's lines, after checking that stdout holds it alone: a first line naming the command, a few
    indented lines, no JSON, no log line."""
    lines = stdout.rstrip("\n").splitlines()
    assert lines[0].startswith(f"hawksim {command}"), lines[0]
    assert 3 <= len(lines) <= MAX_LINES, stdout
    assert all(ln.startswith("  ") for ln in lines[1:]), stdout
    assert "{" not in stdout and "see --json" not in stdout
    return lines


def labelled(lines: list[str], label: str) -> str:
    """The text of the summary line with this label."""
    found = [ln[2:].removeprefix(label).strip() for ln in lines if ln[2:].startswith(label + " ")]
    assert len(found) == 1, (label, lines)
    return found[0]


def printed(text: str, name: str) -> str:
    """The number printed after ``name `` in ``text`` (as written)."""
    m = re.search(re.escape(name) + " " + NUMBER, text)
    assert m is not None, (name, text)
    return m.group(1)


def agrees(shown: str, value: float) -> bool:
    """Whether the number as printed is ``value`` rounded to its last printed digit."""
    mantissa, _, exponent = shown.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    unit = 10.0 ** (int(exponent or 0) - decimals)
    return abs(float(shown) - value) <= 0.51 * unit + 1e-15


def check(text: str, name: str, value: float) -> None:
    shown = printed(text, name)
    assert agrees(shown, value), f"{name} printed {shown}, the JSON says {value}"


def test_agrees_can_fail():
    assert agrees("0.8042", 0.80421) and not agrees("0.8042", 0.8047)
    assert agrees("9.3e-12", 9.26e-12) and not agrees("9.3e-12", 9.4e-12)
    assert agrees("25", 24.99976) and not agrees("25", 24.4)


def test_aero_unsettled_tiny_lattice(monkeypatch, capsys):
    """A coarse 2-beat run at 0.5 m/s: the loads, the power in mW, every beat's L+ and P+, UNSETTLED (the wake's
    start-up still changes the loads by more than 0.1), and that its error is not measured."""
    out, stdout, _ = run(monkeypatch, capsys, ["aero", "--speed", "0.5", "--kinematics", KIN, "--cycles", "2",
                                               "--no-progress", *TINY])
    lines = only_the_summary(stdout, "aero")
    assert lines[0] == ("hawksim aero: body held at 0.5 m/s ascent; UVLM 2 x 3 rings per wing, 20 steps per beat, "
                        "2 beats (last 1 averaged)")
    kin = labelled(lines, "kinematics")
    for k, v in out["kinematics"].items():
        check(kin, k, v)
    check(kin, "chi", out["chi_deg"])
    loads = labelled(lines, "loads")
    for key, name in (("L_plus", "L+"), ("D_plus", "D+"), ("M_plus", "M+"), ("P_plus", "P+")):
        check(loads, name, out[key])
    check(loads, "power", out["power_W"] * 1e3)
    settling = labelled(lines, "settling")
    assert out["status"] == "unsettled" and settling.startswith("UNSETTLED")
    shown = re.search(r"per beat L\+ (.*); P\+ (.*)$", settling)
    for col, key in ((1, "L_plus"), (2, "P_plus")):
        values = shown.group(col).split(", ")
        assert len(values) == len(out["per_cycle"]) == 2
        assert all(agrees(s, c[key]) for s, c in zip(values, out["per_cycle"]))
    assert labelled(lines, "resolution").startswith("not the default (6 x 12 rings, 40 steps): error not measured")
    assert labelled(lines, "wall time") == f"{out['wall_time_s']:.1f} s"


def test_resolution_error_by_speed_and_lattice():
    from hawksim.cli.loads_report import DEFAULT_ERROR, resolution_error

    default = {"aero": "uvlm", "n_chord": 6, "n_span": 12, "steps_per_cycle": 40, "cycles": 5, "average_cycles": 2}
    assert DEFAULT_ERROR in resolution_error(default, 1.5) and "not at" not in resolution_error(default, 1.5)
    assert "measured at 1-2 m/s, not at 0.5" in resolution_error(default, 0.5)
    assert "no converged limit" in resolution_error(default, 0.0)
    assert resolution_error({**default, "steps_per_cycle": 80}, 1.0).startswith("not the default")
    assert resolution_error({**default, "aero": "quasi-steady"}, 1.0).startswith("quasi-steady")


def test_predict(monkeypatch, capsys):
    out, stdout, _ = run(monkeypatch, capsys, ["predict", "--speed", "1", "--kinematics", KIN])
    lines = only_the_summary(stdout, "predict")
    assert lines[0] == ("hawksim predict: the cycle-mean surrogate at 1 m/s ascent; the reference network (shipped, "
                        "corrected to `hawksim aero`'s default lattice) with the ascent speed as an input")
    loads = labelled(lines, "loads")
    for key, name in (("L_plus", "L+"), ("D_plus", "D+"), ("M_plus", "M+"), ("P_plus", "P+")):
        check(loads, name, out[key])
    check(labelled(lines, "kinematics"), "alpha_a", 65.0)
    assert labelled(lines, "model") == out["model"]


def test_trim_on_a_bound(monkeypatch, capsys):
    """The surrogate's trim at 1 m/s (a small GA): its kinematics, the Table 2 bounds it sits on (checked here
    against the bounds themselves), the balance residual and P+, and the GA's convergence."""
    out, stdout, _ = run(monkeypatch, capsys, ["trim", "--speed", "1", "--population", "2000", "--no-progress"])
    lines = only_the_summary(stdout, "trim")
    kin = labelled(lines, "kinematics")
    for k, v in out["kinematics"].items():
        check(kin, k, v)
    at = [k for k, (lo, hi) in TABLE2_BOUNDS_DEG.items()
          if min(abs(out["kinematics"][k] - lo), abs(out["kinematics"][k] - hi)) < 1e-3]
    bounds = labelled(lines, "bounds")
    assert at, "the 1 m/s minimum-power trim sits on Table 2's bounds (phi_a at 60 deg at least)"
    assert bounds.startswith("ON A BOUND of Table 2: ")
    assert [part.split()[0] for part in bounds.split(": ", 1)[1].split(", ")] == at
    bal = labelled(lines, "balance")
    residual = max(abs(1 - out["L_plus"]), abs(out["D_plus"]), abs(out["M_plus"]))
    check(bal, "residual", residual)
    assert ("balanced, residual" in bal) == (residual <= 0.01)
    check(labelled(lines, "power"), "P+", out["P_plus"])
    search = labelled(lines, "search")
    check(search, "after", out["generations"])
    assert "(converged)" in search and f"Nelder-Mead {out['nm_evaluations']} evaluations" in search


def test_orbit_summary_of_a_shipped_orbit():
    """`trim --free-flight`'s summary (the orbit's JSON, as the command builds it) of the shipped quasi-steady orbit at
    1 m/s; the command itself: test_trim_free_flight."""
    from hawksim.cli.stability import orbit_json
    from hawksim.cli.trim_report import render_trim
    from hawksim.flight.orbit import shipped_orbit

    out = json.loads(json.dumps(orbit_json(shipped_orbit(1.0, "quasi-steady"))))
    lines = only_the_summary(render_trim(out) + "\n", "trim --free-flight")
    check(labelled(lines, "kinematics"), "f", out["kinematics"]["f"])
    res = labelled(lines, "residual")
    assert agrees(res.split()[0], out["residual"]) and res.endswith(": converged") == out["converged"]
    start = labelled(lines, "start")
    check(start, "w", out["initial_state"]["w"])
    check(start, "q", out["initial_state"]["q_deg_s"])
    check(start, "pitch", out["initial_state"]["theta_deg"])
    mean = labelled(lines, "mean")
    v = re.search(r"velocity \((.*)\) m/s \(world, z up\)", mean).group(1).split(", ")
    assert len(v) == 3 and all(agrees(s, x) for s, x in zip(v, out["mean_velocity"])) and "-0.000" not in mean
    check(mean, "P+", out["P_plus"])


@pytest.mark.slow
def test_trim_free_flight(monkeypatch, capsys):
    out, stdout, _ = run(monkeypatch, capsys, ["trim", "--speed", "1", "--free-flight", "--aero", "quasi-steady",
                                               "--no-progress"])
    lines = only_the_summary(stdout, "trim --free-flight")
    assert out["converged"] and labelled(lines, "residual").endswith(
        f"after {out['iterations']} Newton iterations: converged")
    check(labelled(lines, "kinematics"), "phi0", out["kinematics"]["phi0"])


@pytest.fixture(scope="module")
def data_set(tmp_path_factory):
    return tmp_path_factory.mktemp("pipeline") / "d.sqlite"


def test_dataset_then_rerun(monkeypatch, capsys, data_set):
    """30 tiny samples: the file, the new samples and their labels' verdicts; a rerun computes nothing."""
    argv = ["dataset", "--speed", "1", "--samples", "30", "--out", str(data_set), "--workers", "1", "--no-progress",
            *TINY, "--cycles", "3"]
    out, stdout, _ = run(monkeypatch, capsys, argv)
    lines = only_the_summary(stdout, "dataset")
    assert labelled(lines, "file") == f"{data_set}: 30 samples of this speed and seed"
    assert labelled(lines, "this run").startswith(f"{out['new']} new samples in ") and out["new"] == 30
    labels = labelled(lines, "new labels")
    assert labels.startswith(f"{30 - out['diverged_new'] - out['unsettled_new']} ok, {out['diverged_new']} ")
    out, stdout, _ = run(monkeypatch, capsys, argv)
    lines = only_the_summary(stdout, "dataset")
    assert out["new"] == 0 and labelled(lines, "this run") == "nothing new: the file already held them"


def test_dataset_unsettled_said(monkeypatch, capsys, tmp_path):
    """Two-beat labels at the coarse lattice: many still change by more than 0.1, and the summary counts them."""
    out, stdout, _ = run(monkeypatch, capsys, ["dataset", "--speed", "1", "--samples", "8", "--out",
                                               str(tmp_path / "e.sqlite"), "--workers", "1", "--no-progress", *TINY,
                                               "--cycles", "2"])
    labels = labelled(only_the_summary(stdout, "dataset"), "new labels")
    assert out["unsettled_new"] > 0
    assert f"{out['unsettled_new']} UNSETTLED" in labels and "left out of training" in labels


def test_train(monkeypatch, capsys, data_set, tmp_path):
    if not data_set.exists():  # run alone: the same 30 samples as test_dataset_then_rerun's
        from hawksim.backends.resolution import Resolution
        from hawksim.surrogate.dataset import generate

        generate(data_set, 1.0, 30, seed=0, workers=1,
                 resolution=Resolution(n_chord=2, n_span=3, steps_per_cycle=20, cycles=3))
    model = tmp_path / "m.safetensors"
    out, stdout, _ = run(monkeypatch, capsys, ["train", "--data", str(data_set), "--out", str(model), "--hidden", "4",
                                               "--max-iter", "3", "--no-progress"])
    lines = only_the_summary(stdout, "train")
    assert lines[0] == "hawksim train: cycle-mean surrogate for 1 m/s, 4 hidden units, Levenberg-Marquardt"
    assert labelled(lines, "samples") == (f"{out['n_train']} training, {out['n_val']} validation, "
                                          f"{out['n_test']} held out")
    r2, rmse = labelled(lines, "held-out R^2"), labelled(lines, "held-out RMSE")
    for key, name in (("L_plus", "L+"), ("D_plus", "D+"), ("M_plus", "M+"), ("P_plus", "P+")):
        check(r2, name, out["r2"][key])
        check(rmse, name, out["rmse"][key])
    worse = [name for key, name in (("L_plus", "L+"), ("D_plus", "D+"), ("M_plus", "M+"), ("P_plus", "P+"))
             if out["r2"][key] < 0]
    assert ("WORSE than their mean" in r2) == bool(worse)
    assert labelled(lines, "iterations").startswith(f"{out['iterations']} (NOT converged: stopped at --max-iter)")
    assert out["stopped_by"] == "max_iter" and labelled(lines, "written") == str(model) and model.is_file()


def test_warmup(monkeypatch, capsys):
    out, stdout, _ = run(monkeypatch, capsys, ["warmup"])
    lines = only_the_summary(stdout, "warmup")
    n = out["compiled"]
    assert lines[0] == ("hawksim warmup: " + (f"compiled {n} numba kernel{'s' if n != 1 else ''} for this CPU" if n
                                              else "nothing to compile: every kernel was already cached for this CPU"))
    assert labelled(lines, "cache") == (out["cache_dir"] or "numba's default cache (NUMBA_CACHE_DIR unset)")
    ran = labelled(lines, "ran")
    check(ran, "a held-body UVLM run", out["stages"]["aero_uvlm_s"])
    check(ran, "a surrogate wingbeat", out["stages"]["fly_surrogate_s"])
    assert labelled(lines, "wall time").startswith(f"{out['wall_time_s']:.1f} s")


@pytest.mark.slow
def test_reproduce_one_part(monkeypatch, capsys, tmp_path):
    out_dir = tmp_path / "r"
    out, stdout, err = run(monkeypatch, capsys, ["reproduce", "--only", "uvlm_table4", "--out", str(out_dir)])
    lines = only_the_summary(stdout, "reproduce")
    assert lines[0] == f"hawksim reproduce: 1 part into {out_dir}/"
    assert labelled(lines, "uvlm_table4") == out["uvlm_table4"] == str(out_dir / "uvlm_table4.json")
    assert labelled(lines, "failed") == "nothing" and "uvlm_table4 ..." in err


def test_reproduce_failures_said():
    """What did not converge or was skipped, in run_all's objects (hawksim.paper.reproduce), on the `failed` line."""
    from hawksim.cli.reproduce_report import render_reproduce

    done = {"orbits": {"uvlm": {"path": "r/orbits/orbit_table_uvlm.json", "converged": {"0": False, "1": True},
                                "residual": {"0": 3e-6, "1": 1e-9}}},
            "trim": "skipped: no shipped surrogate x.safetensors"}
    lines = render_reproduce(done, "r", 125.0).splitlines()
    assert labelled(lines, "orbits") == "r/orbits/orbit_table_uvlm.json (2 speeds)"
    assert labelled(lines, "failed") == ("orbits: uvlm orbit NOT converged at 0 m/s; trim: skipped: no shipped "
                                         "surrogate x.safetensors")
    assert labelled(lines, "wall time") == "2.1 min"


def test_json_is_unchanged_by_the_summary(capsys):
    """--json still prints the one object (the summary is only its rendering)."""
    assert cli.main(["predict", "--speed", "1", "--kinematics", KIN, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"L_plus", "D_plus", "M_plus", "P_plus", "speed", "kinematics", "chi_deg", "model", "network",
            "model_speed"} == set(out)


def test_flights_and_step_network_summaries():
    """`dataset --kind flights` and `train --kind step` (hours of UVLM flights to run for real): their summaries of
    objects with the keys those commands return (hawksim.cli.dataset.cmd_flights, hawksim.cli.train.cmd_train_step)."""
    from hawksim.cli.surrogate_report import render_dataset, render_train

    flights = {"path": "f.sqlite", "kind": "flights", "family": "orbit", "samples": 12, "new": 5, "diverged_new": 2,
               "rows_new": 4000, "seed": 3, "wall_time_s": 61.25}
    lines = only_the_summary(render_dataset(flights) + "\n", "dataset --kind flights")
    assert labelled(lines, "file") == "f.sqlite: 12 flights"
    assert labelled(lines, "this run") == "5 new flights (4000 rows) in 61.2 s"
    assert labelled(lines, "diverged").startswith("2 of the new flights DIVERGED")
    step = {"kind": "step", "n_train": 9000, "n_val": 1000, "n_test": 1200, "test_flights": 4, "r2": {},
            "r2_min": 0.9712, "cycle_mean_abs_error": {"L_plus": 0.0123, "D_plus": 0.0045, "M_plus": 0.0067,
                                                       "P_plus": 0.0089},
            "cycle_mean_max_error": {"L_plus": 0.05, "D_plus": 0.02, "M_plus": 0.03, "P_plus": 0.04},
            "r2_body": {}, "epochs": 40, "out": "s.safetensors", "wall_time_s": 300.0}
    lines = only_the_summary(render_train(step) + "\n", "train --kind step")
    check(labelled(lines, "held-out R^2"), "worst output", 0.9712)
    means = labelled(lines, "cycle means")
    check(means.split("; largest")[0], "L+", 0.0123)
    check(means.split("; largest")[1], "P+", 0.04)
    assert labelled(lines, "written") == "s.safetensors"
