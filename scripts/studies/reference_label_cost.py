"""Cost of one surrogate label at the training lattice and at `hawksim aero`'s default lattice, side by side.

One process, one numba thread, warm kernels: ``--per-speed`` samples of seed 0 at 0, 1 and 2 m/s evaluated by
:func:`hawksim.surrogate.dataset.evaluate_sample` (what a `hawksim dataset` worker runs) at
:data:`hawksim.backends.resolution.TRAINING` and at :data:`hawksim.backends.resolution.REFERENCE`, alternating
twice so both see the same load; seconds per sample (the evaluation's own wall time, as the data sets' ``wall_s``).

    NUMBA_NUM_THREADS=1 python scripts/studies/reference_label_cost.py --out results/surrogate/reference_label_cost.json
"""

from __future__ import annotations

import argparse
import datetime
import shlex
import sys
from pathlib import Path

import numpy as np

from hawksim.backends.resolution import REFERENCE, TRAINING
from hawksim.jsonout import emit
from hawksim.surrogate.dataset import evaluate_sample


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--per-speed", type=int, default=7)
    ap.add_argument("--out")
    a = ap.parse_args()
    load0 = Path("/proc/loadavg").read_text().split()[:3]
    for res in (TRAINING, REFERENCE):  # compile / warm
        evaluate_sample(0, 1.0, 0, res)
    runs = {"training": [], "reference": []}
    for _ in range(2):
        for name, res in (("training", TRAINING), ("reference", REFERENCE)):
            runs[name] += [evaluate_sample(0, v, i, res).wall_s for v in (0.0, 1.0, 2.0)
                           for i in range(1, 1 + a.per_speed)]
    out = {name: {"s_per_sample": float(np.mean(w)), "min": float(np.min(w)), "max": float(np.max(w)), "n": len(w)}
           for name, w in runs.items()}
    out["ratio"] = out["reference"]["s_per_sample"] / out["training"]["s_per_sample"]
    emit({"command": shlex.join(["python", "scripts/studies/reference_label_cost.py", *sys.argv[1:]]),
          "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
          "loadavg_before": load0, "loadavg_after": Path("/proc/loadavg").read_text().split()[:3],
          "resolutions": {"training": TRAINING.to_dict(), "reference": REFERENCE.to_dict()}, **out}, a.out)


if __name__ == "__main__":
    main()
