"""Benchmark of the surrogate against the UVLM it replaces; prints ONE JSON object.

* predict_samples_per_s: batched inference (``Surrogate.predict_torch``, float32, torch's threads = all cores)
  of ``--n`` random kinematics within Table 2's bounds, best of ``--reps`` (target: >= 1e6 samples/s on 2 cores);
  also the float64 numpy path (``Surrogate.predict``) for reference.
* uvlm_eval_s: one UVLM evaluation (the cycle averages the network predicts) at the training resolution the
  network learned and at the default resolution, best of 3 after a warm-up (numba compiled);
* speedup_per_sample: UVLM seconds per evaluation x predictions per second (the paper: "thousands of times").

    python scripts/benchmarks/bench_predict.py [--model FILE] [--n 2000000] [--out results/bench_predict.json]
"""

import argparse
import os
import time

import numpy as np
import torch

from hawksim.backends.held import evaluate
from hawksim.backends.network import load, shipped_path
from hawksim.backends.resolution import DEFAULT, TRAINING
from hawksim.insect.kinematics import bounds_si, table3_kinematics
from hawksim.jsonout import emit


def best_time(fn, reps):
    best = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--model", default=str(shipped_path(1.0)))
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--n", type=int, default=2_000_000)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--out")
    a = ap.parse_args()
    sur = load(a.model)
    lo, hi = bounds_si()
    x = lo + np.random.default_rng(0).random((a.n, 7)) * (hi - lo)
    sur.predict_torch(x[:1000], a.speed)  # warm-up
    t_torch = best_time(lambda: sur.predict_torch(x, a.speed), a.reps)
    n64 = min(a.n, 200_000)
    t_np = best_time(lambda: sur.predict(x[:n64], a.speed), 2)
    kin = table3_kinematics(a.speed)
    evaluate(kin, a.speed, TRAINING)  # compile / load the numba cache
    uvlm = {name: best_time(lambda r=res: evaluate(kin, a.speed, r), 3) for name, res in
            (("training", TRAINING), ("default", DEFAULT))}
    rate = a.n / t_torch
    emit({"model": a.model, "hidden": sur.hidden, "n": a.n, "torch_threads": torch.get_num_threads(),
          "cpu_count": os.cpu_count(), "predict_samples_per_s": rate, "predict_float64_numpy_samples_per_s":
          n64 / t_np, "target_samples_per_s": 1e6, "uvlm_eval_s": uvlm,
          "resolutions": {"training": TRAINING.to_dict(), "default": DEFAULT.to_dict()},
          "speedup_per_sample": {k: v * rate for k, v in uvlm.items()},
          "speedup_single_call": {k: v / best_time(lambda: sur.predict(kin.as_array()[None], a.speed), 20)
                                  for k, v in uvlm.items()}}, a.out, host=True)


if __name__ == "__main__":
    main()
