"""Trials behind the reference surrogate's route (docs/surrogate.md, "A surrogate of the reference UVLM").

Scored at the held-out kinematics of scripts/studies/surrogate_vs_reference.py (seed 22, default-lattice labels in
``--heldout``), mean |error| of L+ and P+ per speed over the 'ok' samples:

* ``sizes``: the speed-input correction (H 20, as shipped) trained on the first n samples of each speed of
  ``--data`` (idx < n), for each n of ``--prefix``: does more reference data help?
* ``per_speed``: per-speed corrections (H 10) of the per-speed shipped networks, on idx < ``--per-speed-n``.
* ``fresh``: an 8-100-4 network trained from scratch on the reference labels alone (idx < ``--fresh-n``): route (a)
  with a small data set.
* ``roughness``: the reference UVLM along a random direction (+-1 % of Table 2's ranges) about held-out samples
  0..14 of 1 m/s (numpy seed 5), and sample 3 at the training lattice and at 8 x 16 rings, 50 steps.

    NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1 python -m scripts.studies.reference_route_trials \\
        --out results/surrogate/reference_route_trials.json
"""

from __future__ import annotations

import argparse
import datetime
import shlex
import sys
from pathlib import Path

import numpy as np

from hawksim.backends.network import SHIPPED_SPEEDS, InputDefinition, load, shipped_path
from hawksim.jsonout import emit
from hawksim.surrogate.dataset import read_samples
from hawksim.surrogate.multifidelity import correction_targets, fold
from hawksim.surrogate.train import TrainConfig, train

from scripts.studies.surrogate_vs_reference import error_scores, read_labels


def held_out_errors(predict, heldout, seed=22, n=100) -> dict:
    out = {}
    for v in SHIPPED_SPEEDS:
        lab = read_labels(heldout, v, seed, n)
        ok = lab["status"] == "ok"
        sc = error_scores(lab["y"][ok], predict(lab["x"][ok], v))
        out[f"{v:g}"] = {k: sc[k]["mean_abs"] for k in ("L_plus", "P_plus")}
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default="data/uvlm_reference_0.1.sqlite")
    ap.add_argument("--heldout", default="data/uvlm_reference_heldout_s22.sqlite")
    ap.add_argument("--prefix", type=int, nargs="+", default=[200, 400, 1000])
    ap.add_argument("--per-speed-n", type=int, default=400)
    ap.add_argument("--fresh-n", type=int, default=400)
    ap.add_argument("--parts", nargs="+", default=["sizes", "per_speed", "fresh", "roughness"])
    ap.add_argument("--out")
    a = ap.parse_args()
    import torch

    torch.set_num_threads(1)
    t = read_samples(a.data)
    x_all = np.column_stack([t.x, t.speed])
    groups = np.round(t.speed * 1000).astype(int)
    res = {}
    base = load(shipped_path(None))
    if "sizes" in a.parts:
        res["sizes"] = {}
        for n in a.prefix:
            m = t.idx < n
            r = train(x_all[m], correction_targets(base, x_all[m], t.y[m]), InputDefinition.for_speed(None), seed=0,
                      cfg=TrainConfig(hidden=20), groups=groups[m])
            net = fold(base, r.surrogate)
            res["sizes"][str(n)] = {"n_samples": int(m.sum()), "errors": held_out_errors(net.predict, a.heldout)}
            print(f"sizes n<{n}: {res['sizes'][str(n)]}", file=sys.stderr)
    if "per_speed" in a.parts:
        res["per_speed"] = {"n_per_speed": a.per_speed_n, "errors": {}}
        nets = {}
        for v in SHIPPED_SPEEDS:
            b = load(shipped_path(v))
            tv = read_samples(a.data, speed=v)
            m = tv.idx < a.per_speed_n
            r = train(tv.x[m], correction_targets(b, tv.x[m], tv.y[m]), InputDefinition.for_speed(v), seed=0,
                      cfg=TrainConfig(hidden=10))
            nets[v] = fold(b, r.surrogate)
        res["per_speed"]["errors"] = held_out_errors(lambda x, v: nets[v].predict(x, v), a.heldout)
        print(f"per_speed: {res['per_speed']}", file=sys.stderr)
    if "fresh" in a.parts:
        m = t.idx < a.fresh_n
        r = train(x_all[m], t.y[m], InputDefinition.for_speed(None), seed=0, cfg=TrainConfig(hidden=100),
                  groups=groups[m])
        res["fresh"] = {"n_samples": int(m.sum()), "hidden": 100, "iterations": r.iterations,
                        "errors": held_out_errors(r.surrogate.predict, a.heldout)}
        print(f"fresh: {res['fresh']}", file=sys.stderr)
    if "roughness" in a.parts:
        from hawksim.backends.held import evaluate
        from hawksim.backends.resolution import REFERENCE, TRAINING, Resolution
        from hawksim.insect.kinematics import Kinematics, bounds_si
        from hawksim.surrogate.dataset import sample_kinematics

        lo, hi = bounds_si()
        rng = np.random.default_rng(5)
        rows = []
        for i in range(15):
            x = sample_kinematics(22, 1.0, i).as_array()
            d = rng.normal(size=7)
            dx = 0.01 * (hi - lo) * d / np.linalg.norm(d)
            ys = [evaluate(Kinematics.from_array(np.clip(x + s * dx, lo, hi)), 1.0, REFERENCE) for s in (-1, 0, 1)]
            rows.append({"idx": i, "L_plus": [a_.L_plus for a_ in ys], "P_plus": [a_.P_plus for a_ in ys]})
        second = np.array([[(r[k][0] + r[k][2]) / 2 - r[k][1] for k in ("L_plus", "P_plus")] for r in rows])
        k3 = sample_kinematics(22, 1.0, 3)
        lattices = {name: evaluate(k3, 1.0, rr).L_plus for name, rr in
                    (("training", TRAINING), ("reference", REFERENCE),
                     ("8x16_50", Resolution(n_chord=8, n_span=16, steps_per_cycle=50)))}
        res["roughness"] = {"speed": 1.0, "step": "1 % of Table 2's ranges", "samples": rows,
                            "median_abs_second_difference": np.median(np.abs(second), axis=0).tolist(),
                            "idx3_L_plus_by_lattice": lattices}
        print(f"roughness: {res['roughness']['median_abs_second_difference']} idx3 {lattices}", file=sys.stderr)
    emit({"command": shlex.join(["python", "-m", "scripts.studies.reference_route_trials", *sys.argv[1:]]),
          "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
          "loadavg": Path("/proc/loadavg").read_text().split()[:3], **res}, a.out)


if __name__ == "__main__":
    main()
