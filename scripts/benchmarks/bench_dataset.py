"""Data-set throughput of `hawksim dataset` at the training resolution; prints ONE JSON object.

Generates ``--n`` samples (default 200, seed 12345 so they are not the shipped set's) at each speed given into a
temporary file on a Dask LocalCluster over all cores (what `hawksim dataset` does by default), and projects the
wall time of the paper's data set (5 speeds x 3000 samples) against the 2-hour target of issue 4 from the
steady-state rate (samples arriving after the first one on each worker); the start-up (cluster, imports, numba
cache loading in each worker: once per `hawksim dataset` command, i.e. 5 times for the data set) is reported
and added to the projection.

    python scripts/benchmarks/bench_dataset.py [--n 200] [--speeds 0 2] [--out results/bench_dataset.json]
"""

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from hawksim.backends.resolution import TRAINING
from hawksim.jsonout import emit
from hawksim.surrogate.dataset import generate

PAPER_SAMPLES = 5 * 3000
"""Nguyen et al. (2020), Sec. 2.4: 3000 UVLM samples per ascent speed, five speeds."""
TARGET_H = 2.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.0, 2.0])
    ap.add_argument("--out")
    a = ap.parse_args()
    per_speed = {}
    with tempfile.TemporaryDirectory() as d:
        for v in a.speeds:
            arrivals = []
            t0 = time.perf_counter()
            r = generate(Path(d) / "bench.sqlite", v, a.n, seed=12345, resolution=TRAINING,
                         progress=lambda done, total, log=arrivals: log.append((done, time.perf_counter())))
            wall = time.perf_counter() - t0
            k = min(len(arrivals) - 1, (os.cpu_count() or 1) + 1)  # skip each worker's first sample
            (n0, t1), (n1, t2) = arrivals[k], arrivals[-1]
            steady = (n1 - n0) / (t2 - t1)
            per_speed[f"{v:g}"] = {"samples": r.new, "wall_s": wall, "startup_s": t1 - t0 - n0 / steady,
                                   "steady_samples_per_s": steady, "diverged": r.diverged}
    rate = float(np.mean([p["steady_samples_per_s"] for p in per_speed.values()]))
    startup = float(np.mean([p["startup_s"] for p in per_speed.values()]))
    hours = (PAPER_SAMPLES / rate + 5 * startup) / 3600
    emit({"cpu_count": os.cpu_count(), "resolution": TRAINING.to_dict(), "per_speed": per_speed,
          "samples_per_s": rate, "startup_s": startup, "paper_dataset_samples": PAPER_SAMPLES, "projected_hours": hours,
          "target_hours": TARGET_H, "ratio_to_target": hours / TARGET_H}, a.out, host=True)


if __name__ == "__main__":
    main()
