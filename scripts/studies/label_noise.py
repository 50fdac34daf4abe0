"""Label noise of the training data: how much a sample's cycle averages change from one wingbeat to the next.

The data set stores the averages of wingbeat 3 of 3 at the training resolution (`hawksim.backends.resolution.TRAINING`).
Here the same samples (seed 0, indices 0..n-1: the shipped set's first samples) are run for one more wingbeat; the
RMS of (wingbeat 4 - wingbeat 3) / sqrt(2) estimates the noise of one stored label (and 1.4826 MAD / sqrt(2)
the same without the weight of a few near-blow-up runs) (the wake's cycle-to-cycle
variation, largest in hover where the wake stays under the wings).

A second estimate ("realization"): each sample is run again with its flapping frequency changed by a relative
1e-10 (round-off level); the RMS of (label - label') / sqrt(2) over wingbeat 3 is the scatter that the free wake's
sensitivity to round-off alone puts on one stored label (docs/uvlm.md, "Hover is not periodic"). No network can
predict the labels better than these; compare with the surrogates' held-out RMSE. Prints ONE JSON object.

    python scripts/studies/label_noise.py [--n 40] [--speeds 0 0.5 1 1.5 2] [--out results/surrogate/label_noise.json]
"""

import argparse

import numpy as np

from hawksim.backends.averages import OUTPUTS
from hawksim.backends.held import beat_averages
from hawksim.backends.resolution import TRAINING
from hawksim.insect.kinematics import realization
from hawksim.jsonout import emit
from hawksim.surrogate.dataset import sample_kinematics


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.0, 0.5, 1.0, 1.5, 2.0])
    ap.add_argument("--out")
    a = ap.parse_args()
    out = {}
    for v in a.speeds:
        d, dr = [], []
        for i in range(a.n):
            kin = sample_kinematics(0, v, i)
            try:
                c3, c4 = beat_averages(kin, v, TRAINING, TRAINING.cycles + 1)[-2:]
                other = beat_averages(realization(kin), v, TRAINING, TRAINING.cycles)[-1]
            except FloatingPointError:
                continue
            d.append(c4 - c3)
            dr.append(other - c3)
        row = {}
        for name, diff in (("", d), ("realization_", dr)):
            diff = np.asarray(diff)
            diff = diff[np.all(np.isfinite(diff), axis=1) & np.all(np.abs(diff) < 2.0, axis=1)]  # no blow-ups
            rms = np.sqrt(np.mean(diff**2, axis=0)) / np.sqrt(2)
            robust = 1.4826 * np.median(np.abs(diff - np.median(diff, axis=0)), axis=0) / np.sqrt(2)  # MAD
            row.update({f"{name}samples": int(len(diff)), f"{name}label_noise_rms": dict(zip(OUTPUTS, rms.tolist())),
                        f"{name}label_noise_robust": dict(zip(OUTPUTS, robust.tolist()))})
        out[f"{v:g}"] = row
    emit({"resolution": TRAINING.to_dict(), "per_speed": out}, a.out)


if __name__ == "__main__":
    main()
