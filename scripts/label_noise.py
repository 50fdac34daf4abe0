"""Label noise of the training data: how much a sample's cycle averages change from one wingbeat to the next.

The data set stores the averages of wingbeat 3 of 3 at the training resolution (`hawksim.evaluate.TRAINING`).
Here the same samples (seed 0, indices 0..n-1: the shipped set's first samples) are run for one more wingbeat; the
RMS of (wingbeat 4 - wingbeat 3) / sqrt(2) estimates the noise of one stored label (and 1.4826 MAD / sqrt(2)
the same without the weight of a few near-blow-up runs) (the wake's cycle-to-cycle
variation, largest in hover where the wake stays under the wings). No network can predict the labels better than
this; compare with the surrogates' held-out RMSE. Prints ONE JSON object.

    python scripts/label_noise.py [--n 40] [--speeds 0 0.5 1 1.5 2] [--out results/surrogate/label_noise.json]
"""

import argparse
from dataclasses import replace

import numpy as np

from hawksim.dataset import OUTPUTS, sample_kinematics
from hawksim.evaluate import TRAINING, run
from hawksim.jsonout import emit


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.0, 0.5, 1.0, 1.5, 2.0])
    ap.add_argument("--out")
    a = ap.parse_args()
    res = replace(TRAINING, cycles=TRAINING.cycles + 1)
    out = {}
    for v in a.speeds:
        d = []
        for i in range(a.n):
            try:
                r = run(sample_kinematics(0, v, i), v, res)
            except FloatingPointError:
                continue
            c3, c4 = r.per_cycle[-2], r.per_cycle[-1]
            d.append([getattr(c4, k) - getattr(c3, k) for k in OUTPUTS])
        d = np.asarray(d)
        d = d[np.all(np.isfinite(d), axis=1) & np.all(np.abs(d) < 2.0, axis=1)]  # leave out blown-up runs
        rms = np.sqrt(np.mean(d**2, axis=0)) / np.sqrt(2)
        robust = 1.4826 * np.median(np.abs(d - np.median(d, axis=0)), axis=0) / np.sqrt(2)  # MAD -> sigma
        out[f"{v:g}"] = {"samples": int(len(d)), "label_noise_rms": dict(zip(OUTPUTS, rms.tolist())),
                         "label_noise_robust": dict(zip(OUTPUTS, robust.tolist()))}
    emit({"resolution": TRAINING.to_dict(), "per_speed": out}, a.out)


if __name__ == "__main__":
    main()
