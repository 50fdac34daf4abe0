"""Data-set throughput of `hawksim dataset` at the training resolution; prints ONE JSON object.

Generates ``--n`` samples (default 200, seed 12345 so they are not the shipped set's) at each speed given into a
temporary file on a Dask LocalCluster over all cores (what `hawksim dataset` does by default), and projects the
wall time of the paper's data set (5 speeds x 3000 samples) against the 2-hour target of issue 4. Cluster
start-up and numba cache loading are inside the timing (they are part of a real run).

    python scripts/bench_dataset.py [--n 200] [--speeds 0 2] [--out results/bench_dataset.json]
"""

import argparse
import os
import tempfile
import time
from pathlib import Path

from hawksim.dataset import generate
from hawksim.evaluate import TRAINING
from hawksim.jsonout import emit

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
            t0 = time.perf_counter()
            r = generate(Path(d) / "bench.sqlite", v, a.n, seed=12345, resolution=TRAINING)
            wall = time.perf_counter() - t0
            per_speed[f"{v:g}"] = {"samples": r.new, "wall_s": wall, "samples_per_s": r.new / wall,
                                   "diverged": r.diverged}
    rate = sum(p["samples"] for p in per_speed.values()) / sum(p["wall_s"] for p in per_speed.values())
    hours = PAPER_SAMPLES / rate / 3600
    emit({"cpu_count": os.cpu_count(), "resolution": TRAINING.to_dict(), "per_speed": per_speed,
          "samples_per_s": rate, "paper_dataset_samples": PAPER_SAMPLES, "projected_hours": hours,
          "target_hours": TARGET_H, "ratio_to_target": hours / TARGET_H}, a.out)


if __name__ == "__main__":
    main()
