"""Is a data-set label periodic? The wingbeat-to-wingbeat change of the held-out samples' cycle averages, and
what leaving out the labels that still change does to the shipped networks' held-out R^2. Prints ONE JSON object.

For each study speed, the held-out test samples of that speed's shipped network (the split `hawksim train`
made) are run again by the UVLM at the data set's training resolution for one more wingbeat (4 instead of 3;
wingbeat 3 is the stored label, checked equal to the rerun). Reported per speed:

* quantiles of |beat 3 - beat 2| and |beat 4 - beat 3| of L+, and of the largest of the four outputs' changes,
  and the correlation of the two changes (does a run that still changes at beat 3 keep changing?);
* for thresholds ``--tols``: how many samples have every output's beat 2 -> 3 change within the threshold
  (the criterion of `hawksim.surrogate.dataset.SETTLE_TOL`, which a layout-2 data set applies when it is made), and the
  R^2 of L+ and P+ of the per-speed and speed-input networks on those samples alone, beside all of them.

``--data`` must be the file the shipped networks were trained on (their recorded data hash is checked).
``results/surrogate/label_periodicity.json`` was made at commit be22a4c, whose networks were trained on all 'ok'
samples of the layout-1 data set (no criterion), so it measures the effect of the criterion on the test labels
only; run on the layout-2 data set of the current networks, the criterion is already applied to every sample.

    git show a4a9b6b:data/uvlm_training_0.2.sqlite > old.sqlite     # the layout-1 0.2 set (left the tree)
    python scripts/studies/label_periodicity.py --data old.sqlite \
        --out results/surrogate/label_periodicity.json      # at commit be22a4c
"""

import argparse
import os
import sys

import numpy as np

from hawksim.backends.network import load, shipped_path
from hawksim.jsonout import emit
from hawksim.surrogate.dataset import sample_kinematics
from hawksim.surrogate.train import scores, shipped_held_out


def _beats(args):
    """Per-wingbeat averages (4, 4) of sample (seed, speed, i), or None if the UVLM diverges."""
    from hawksim.backends.held import beat_averages
    from hawksim.backends.resolution import TRAINING

    seed, v, i = args
    try:
        return beat_averages(sample_kinematics(seed, v, int(i)), v, TRAINING, TRAINING.cycles + 1).tolist()
    except FloatingPointError:
        return None


def _r2(y, p) -> dict:
    s = scores(y, p)
    return {k: round(s.r2[k], 4) for k in ("L_plus", "P_plus")}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", default="data/uvlm_training_0.3.sqlite")
    ap.add_argument("--data-seed", type=int, default=0)
    ap.add_argument("--tols", type=float, nargs="+", default=[0.05, 0.1, 0.2])
    ap.add_argument("--n", type=int, help="only the first N held-out samples per speed")
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--out")
    a = ap.parse_args()
    os.environ["NUMBA_NUM_THREADS"] = "1"  # one process per core (set before the workers import numba)
    from multiprocessing import get_context

    try:
        sets = shipped_held_out(a.data)
    except ValueError as e:
        print(f"error: --data {e}", file=sys.stderr)
        sys.exit(2)
    allv = load(shipped_path(None))
    rows = {}
    with get_context("spawn").Pool(a.workers) as pool:
        for v, sur, t, te in sets:
            te = te[:a.n]
            beats = pool.map(_beats, [(a.data_seed, v, i) for i in t.idx[te]], chunksize=4)
            ok = np.array([b is not None for b in beats])
            B = np.array([b for b in beats if b is not None])  # (n, beat, output)
            x, y = t.x[te][ok], t.y[te][ok]
            d23, d34 = np.abs(B[:, 2] - B[:, 1]), np.abs(B[:, 3] - B[:, 2])
            p, q = sur.predict(x, v), allv.predict(x, v)
            row = {"n": int(ok.sum()), "diverged_on_rerun": int((~ok).sum()),
                   "rerun_max_abs_diff": float(np.max(np.abs(B[:, 2] - y))),
                   "L_change_23_quantiles_50_90_99": np.quantile(d23[:, 0], [0.5, 0.9, 0.99]).round(4).tolist(),
                   "L_change_34_quantiles_50_90_99": np.quantile(d34[:, 0], [0.5, 0.9, 0.99]).round(4).tolist(),
                   "max_change_23_quantiles_50_90_99": np.quantile(d23.max(1), [0.5, 0.9, 0.99]).round(4).tolist(),
                   "corr_L_change_23_34": round(float(np.corrcoef(d23[:, 0], d34[:, 0])[0, 1]), 3),
                   "all": {"n": int(len(y)), "per_speed_net_r2": _r2(y, p), "speed_input_net_r2": _r2(y, q)}}
            for tol in a.tols:
                keep = d23.max(1) <= tol
                row[f"settled_{tol:g}"] = {"n": int(keep.sum()), "per_speed_net_r2": _r2(y[keep], p[keep]),
                                           "speed_input_net_r2": _r2(y[keep], q[keep])}
            rows[f"{v:g}"] = row
    emit({"data": a.data, "per_speed": rows}, a.out)


if __name__ == "__main__":
    main()
