"""The cycle-mean surrogates against the reference UVLM at fresh held-out kinematics (issue 22, item 3).

For each study speed, ``--samples`` kinematics drawn uniformly in Table 2's box by
:func:`hawksim.surrogate.dataset.sample_kinematics` with ``--seed`` (22 by default: no network was trained on
it; the training sets use seed 0) are run by the UVLM at `hawksim aero`'s default lattice
(:data:`hawksim.backends.resolution.REFERENCE`: 6 x 12 rings, 40 steps per beat, 3 beats, the last averaged; the
same :func:`hawksim.backends.held.run` `hawksim aero` calls, so a label is exactly what `hawksim aero --speed V
--kinematics ...` prints). The labels are computed by :func:`hawksim.surrogate.dataset.generate` into
``--labels`` (a data-set file like any other: resumable, one row per sample with its status), so a rerun only
scores. Scored: the shipped networks (`hawksim predict`'s default), the reference networks (`hawksim predict
--network reference`) and any ``--model NAME=PATH``: per speed and output, mean, 95th percentile and max |error|,
mean signed error and R^2 over the 'ok' samples (a sample whose UVLM diverged or whose averages still change by more
than SETTLE_TOL between its last two wingbeats has no periodic label to match; their counts are given, and the
scores with the unsettled ones included under ``with_unsettled``).

``--fixture PATH --fixture-per-speed K``: writes the first K 'ok' samples of each speed (in index order, no choice
made) with their labels, for tests/hawksim/test_surrogate_reference.py.

    NUMBA_NUM_THREADS=1 nice -n 10 python scripts/studies/surrogate_vs_reference.py --seed 22 --samples 40 \\
        --labels data/uvlm_reference_heldout_s22.sqlite --out results/surrogate/reference_fidelity.json \\
        --fixture results/surrogate/reference_fixture.json --fixture-per-speed 4
"""

from __future__ import annotations

import argparse
import datetime
import json
import shlex
import sys
from pathlib import Path

import numpy as np

from hawksim.backends.network import NETWORKS, OUTPUTS, SHIPPED_SPEEDS, default_for_speed, load_for_speed
from hawksim.backends.resolution import REFERENCE, TRAINING
from hawksim.insect.kinematics import PARAM_NAMES
from hawksim.jsonout import emit
from hawksim.surrogate.dataset import generate, open_dataset

TARGET_ABS = 0.03
"""Issue 22's bound on |predict - aero| in L+ and P+ at held-out kinematics."""
TARGET_R2 = 0.99
"""Issue 22's (and issue 4's) bound on R^2 of L+ and P+."""


def read_labels(path, speed: float, seed: int, n: int) -> dict:
    """Rows 0..n-1 of (speed, seed) of a data-set file: x (m, 7) SI, y (m, 4), idx (m,), status (m,) of the
    non-diverged ones, and the count of diverged ones."""
    conn = open_dataset(path)
    try:
        rows = conn.execute(f"SELECT idx, status, {', '.join(PARAM_NAMES)}, {', '.join(OUTPUTS)} FROM samples "
                            "WHERE CAST(round(speed*1000) AS INTEGER)=? AND seed=? AND idx<? ORDER BY idx",
                            (int(round(speed * 1000)), int(seed), int(n))).fetchall()
    finally:
        conn.close()
    keep = [r for r in rows if r[1] != "diverged"]
    a = np.asarray([r[2:] for r in keep], dtype=float).reshape(-1, len(PARAM_NAMES) + len(OUTPUTS))
    return {"x": a[:, :7], "y": a[:, 7:], "idx": np.asarray([r[0] for r in keep], dtype=int),
            "status": np.asarray([r[1] for r in keep]), "n_diverged": len(rows) - len(keep)}


def error_scores(y: np.ndarray, p: np.ndarray) -> dict:
    """Per output: mean, 95th percentile and max |p - y|, mean signed error, R^2 (y, p: (n, 4))."""
    e = p - y
    ss = np.sum((y - y.mean(axis=0)) ** 2, axis=0)
    r2 = 1.0 - np.sum(e**2, axis=0) / np.where(ss > 0, ss, np.nan)
    out = {}
    for k, name in enumerate(OUTPUTS):
        ae = np.abs(e[:, k])
        out[name] = {"mean_abs": float(ae.mean()), "p95_abs": float(np.percentile(ae, 95)),
                     "max_abs": float(ae.max()), "mean_signed": float(e[:, k].mean()), "r2": float(r2[k]),
                     "n_over_target": int(np.sum(ae > TARGET_ABS))}
    return out


def meets(sc: dict) -> dict:
    """Whether max |error| <= TARGET_ABS and R^2 >= TARGET_R2 for L+ and P+ (and each part)."""
    lp = ("L_plus", "P_plus")
    return {"max_abs_within": all(sc[k]["max_abs"] <= TARGET_ABS for k in lp),
            "mean_abs_within": all(sc[k]["mean_abs"] <= TARGET_ABS for k in lp),
            "r2_at_least": all(sc[k]["r2"] >= TARGET_R2 for k in lp)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=22, help="seed of the held-out kinematics (never used for training)")
    ap.add_argument("--samples", type=int, default=40, help="held-out kinematics per speed")
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SHIPPED_SPEEDS))
    ap.add_argument("--labels", default="data/uvlm_reference_heldout_s22.sqlite",
                    help="data-set file of the held-out reference labels (computed if missing, resumed if partial)")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--model", action="append", default=[], metavar="NAME=PATH",
                    help="another network to score (per-speed file: only at its speed; speed-input: at all)")
    ap.add_argument("--training-labels", help="also run the same kinematics at the training lattice (TRAINING) into "
                    "this data-set file and score those labels as 'uvlm_training_lattice' (what a perfect fit of the "
                    "shipped networks' data would give)")
    ap.add_argument("--out")
    ap.add_argument("--fixture")
    ap.add_argument("--fixture-per-speed", type=int, default=4)
    a = ap.parse_args()

    extra = dict(m.split("=", 1) for m in a.model)
    t_label = {}
    for v in a.speeds:
        r = generate(a.labels, v, a.samples, seed=a.seed, resolution=REFERENCE, workers=a.workers)
        t_label[f"{v:g}"] = {"new": r.new, "wall_time_s": r.wall_time_s, "samples_per_s": r.samples_per_s}
        if a.training_labels:
            generate(a.training_labels, v, a.samples, seed=a.seed, resolution=TRAINING, workers=a.workers)
    per_speed, fixture = {}, []
    for v in a.speeds:
        lab = read_labels(a.labels, v, a.seed, a.samples)
        ok = lab["status"] == "ok"
        nets = {}
        for fam in NETWORKS:
            try:
                nets[fam] = default_for_speed(v, fam)
            except ValueError:  # a family without a file for this speed
                pass
        for name, path in extra.items():
            try:
                nets[name] = load_for_speed(path, v)
            except ValueError:
                pass
        entry = {"n_ok": int(ok.sum()), "n_unsettled": int((~ok).sum()), "n_diverged": lab["n_diverged"],
                 "labels": t_label[f"{v:g}"], "networks": {}}
        for name, net in nets.items():
            p = net.predict(lab["x"], v)
            sc = error_scores(lab["y"][ok], p[ok])
            entry["networks"][name] = {"command": net.meta.get("command"), "scores": sc, "meets": meets(sc),
                                       "with_unsettled": error_scores(lab["y"], p)}
        if a.training_labels:  # the training lattice's own labels of the same kinematics (where not diverged)
            cheap = read_labels(a.training_labels, v, a.seed, a.samples)
            by_idx = dict(zip(cheap["idx"].tolist(), cheap["y"]))
            both = ok & np.array([int(i) in by_idx for i in lab["idx"]])
            sc = error_scores(lab["y"][both], np.array([by_idx[int(i)] for i in lab["idx"][both]]))
            entry["uvlm_training_lattice"] = {"n": int(both.sum()), "resolution": TRAINING.to_dict(), "scores": sc,
                                              "meets": meets(sc)}
        per_speed[f"{v:g}"] = entry
        for k in np.flatnonzero(ok)[:a.fixture_per_speed]:
            fixture.append({"speed": v, "seed": a.seed, "idx": int(lab["idx"][k]),
                            "kinematics_si": dict(zip(PARAM_NAMES, map(float, lab["x"][k]))),
                            "uvlm": dict(zip(OUTPUTS, map(float, lab["y"][k])))})
        def brief(e, k):
            return f"{k} max {e[k]['max_abs']:.3f} mean {e[k]['mean_abs']:.3f} R2 {e[k]['r2']:.4f}"

        line = "  ".join(f"{n}: {brief(e['scores'], 'L_plus')} | {brief(e['scores'], 'P_plus')}"
                         for n, e in entry["networks"].items())
        print(f"V={v:g} ok {entry['n_ok']}: {line}", file=sys.stderr)

    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    load = Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else None
    command = shlex.join(["python", "scripts/studies/surrogate_vs_reference.py", *sys.argv[1:]])
    res = {"command": command, "date": now, "loadavg": load, "seed": a.seed, "samples_per_speed": a.samples,
           "resolution": REFERENCE.to_dict(), "labels": a.labels, "target_abs": TARGET_ABS, "target_r2": TARGET_R2,
           "per_speed": per_speed}
    if a.fixture:
        with open(a.fixture, "w") as f:
            json.dump({"command": command, "date": now, "seed": a.seed, "resolution": REFERENCE.to_dict(),
                       "note": "first K 'ok' held-out samples per speed in index order; labels by the UVLM at "
                               "`hawksim aero`'s default lattice", "samples": fixture}, f, indent=1)
    emit(res, a.out)


if __name__ == "__main__":
    main()
