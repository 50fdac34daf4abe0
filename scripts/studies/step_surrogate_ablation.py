"""Which history of the body's motion the per-step surrogate needs (issue 21): the same split, seed and training
budget with no history, lags (0.25, 0.5) and (0.5, 1) wingbeats; held-out per-step R^2 and cycle-mean errors.

    python scripts/studies/step_surrogate_ablation.py --data data/uvlm_flights_0.2.0.sqlite \
        --out results/surrogate/step_ablation.json [--max-flights N] [--epochs 150] [--time-limit 900]

Prints (and writes) one JSON object; cited from docs/surrogate.md ("Per-step surrogate").
"""

import argparse
import json
from pathlib import Path

import torch

from hawksim.jsonout import host_info
from hawksim.surrogate.flights import read_flights
from hawksim.surrogate.step_train import TrainConfig, fit

VARIANTS = {"none": (), "lags_0.25_0.5": (0.25, 0.5), "lags_0.5_1": (0.5, 1.0)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", required=True)
    ap.add_argument("--out")
    ap.add_argument("--max-flights", type=int)
    ap.add_argument("--epochs", type=int, default=150)
    ap.add_argument("--time-limit", type=float, default=900.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--layers", type=int, nargs="+", default=[128, 128, 128])
    ap.add_argument("--weight-decay", type=float, default=0.0)
    ap.add_argument("--ensemble", type=int, default=1)
    ap.add_argument("--only", nargs="*", choices=list(VARIANTS))
    a = ap.parse_args()
    torch.set_num_threads(1)
    out = {"host": host_info(), "data": a.data, "max_flights": a.max_flights, "epochs": a.epochs,
           "time_limit_s": a.time_limit, "seed": a.seed, "variants": {}}
    flights = read_flights(a.data)  # once: the same flights for every variant while a generation may be adding
    if a.max_flights is not None:
        flights = [f for f in flights if f.idx < a.max_flights]
    out["n_flights"] = len(flights)
    for name, lags in VARIANTS.items():
        if a.only and name not in a.only:
            continue
        net, sc = fit(a.data, TrainConfig(hidden=tuple(a.layers), lags=lags, epochs=a.epochs,
                                          max_seconds=a.time_limit, seed=a.seed, weight_decay=a.weight_decay,
                                          ensemble=a.ensemble), flights=flights)
        out["variants"][name] = {"lags": list(lags), "test": sc, "history": net.meta["history"],
                                 "n_train_rows": net.meta["n_train_rows"]}
        print(name, json.dumps(sc["r2"]), json.dumps(sc["cycle_mean_abs_error"]), flush=True)
    text = json.dumps(out, indent=1)
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
