"""How much of the per-step surrogate's cycle-mean error a memoryless network cannot remove: twin UVLM flights that
leave the kick in the same body state, with the same kinematics, but different wakes (issue 21, the M+ target).

For each flight spec (:func:`hawksim.surrogate.flights.sample_flight`, family ``orbit``, symmetric flights, speeds
binned near 0, 1 and 2 m/s):

- flight A is the data set's flight (UVLM in the loop; warm-up on the orbit, kicked at t = 2 T);
- flight B gets the same kick one beat earlier too (t = T, its history), and at t = 2 T its body state is *written*
  to A's state after A's kick: from there both fly the same kinematics from the same body state, and differ only
  by the wake shed during the beat before.

A memoryless network sees (almost) the same inputs along the two flights' first beat after the kick (their body
paths part only through the loads' difference), so it predicts nearly the same cycle means for both, and its error
is at least half their difference on one of the two: |A - B| / 2 is a floor of the memoryless error at the data
set's perturbation size. The shipped network's own predictions on both flights are printed beside (how far apart it
puts them, and its error).

    NUMBA_NUM_THREADS=1 python scripts/studies/step_surrogate_memory.py [--seed 7] [--per-bin 4] [--workers 2]
        [--out results/surrogate/step_memory.json]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

BINS = ((0.0, 0.3), (0.85, 1.15), (1.7, 2.0))
BEATS = 4  # 2 warm-up beats, the kick, 2 beats scored
NAMES = ("L_plus", "D_plus", "M_plus", "P_plus")


def _stored(sample):
    from hawksim.surrogate.flights import StoredFlight

    return StoredFlight.from_sample(sample)


def _means(fl, y_left=None, y_right=None):
    """(beats, 4) cycle means of a flight, from its UVLM loads or from given per-row wing loads."""
    from hawksim.surrogate.step_train import flight_cycle_means

    return flight_cycle_means(fl, y_left, y_right)


def _network_means(fl):
    from hawksim.backends.step_network import MIRROR_F, MIRROR_M, load, mirror_inputs, shipped_path
    from hawksim.surrogate.step_train import flight_inputs

    net = load(str(shipped_path()))
    x, _ = flight_inputs(fl, net.lags)
    return _means(fl, net.predict(x), net.predict(mirror_inputs(x)) * np.concatenate([MIRROR_F, MIRROR_M]))


def twins(seed: int, i: int) -> dict:
    from hawksim.surrogate.flights import evaluate_flight, sample_flight

    spec = sample_flight(seed, i)
    log: list = []
    a = evaluate_flight(seed, i, beats=BEATS, kick_log=log)
    after = log[0] + np.asarray(spec.perturbation)
    b = evaluate_flight(seed, i, beats=BEATS, history_kick=np.asarray(spec.perturbation), state_at_kick=after)
    out = {"seed": seed, "idx": i, "speed": spec.speed, "perturbation": list(spec.perturbation),
           "status": [a.status, b.status], "cut": [a.cut, b.cut], "wall_s": a.wall_s + b.wall_s}
    if a.status != "ok" or b.status != "ok" or a.cut or b.cut:
        return out
    fa, fb = _stored(a), _stored(b)
    ua, ub, na, nb = _means(fa), _means(fb), _network_means(fa), _network_means(fb)
    out.update({"uvlm_A": ua.tolist(), "uvlm_B": ub.tolist(), "network_A": na.tolist(), "network_B": nb.tolist()})
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--per-bin", type=int, default=4)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default="results/surrogate/step_memory.json")
    a = ap.parse_args(argv)

    from hawksim.jsonout import host_info
    from hawksim.surrogate.flights import sample_flight

    picks, i = {k: [] for k in range(len(BINS))}, 0
    while any(len(v) < a.per_bin for v in picks.values()) and i < 10_000:
        sp = sample_flight(a.seed, i)
        for k, (lo, hi) in enumerate(BINS):
            if sp.symmetric and lo <= sp.speed <= hi and len(picks[k]) < a.per_bin:
                picks[k].append(i)
        i += 1
    jobs = [(a.seed, j) for k in picks for j in picks[k]]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(a.workers) as ex:
        rows = list(ex.map(twins, *zip(*jobs)))
    summary = {}
    for lo, hi in BINS:
        rs = [r for r in rows if lo <= r["speed"] <= hi and "uvlm_A" in r]
        if not rs:
            continue
        ua, ub = np.array([r["uvlm_A"] for r in rs]), np.array([r["uvlm_B"] for r in rs])
        na, nb = np.array([r["network_A"] for r in rs]), np.array([r["network_B"] for r in rs])
        d_uvlm = np.abs(ua - ub)[:, 0]  # the first beat after the kick
        d_net = np.abs(na - nb)[:, 0]
        err = np.abs(na - ua)[:, 0]
        summary[f"{lo:g}-{hi:g} m/s"] = {
            "n_flights": len(rs),
            "uvlm_history_effect_first_beat_mean": dict(zip(NAMES, d_uvlm.mean(0).tolist())),
            "uvlm_history_effect_first_beat_max": dict(zip(NAMES, d_uvlm.max(0).tolist())),
            "memoryless_floor_first_beat_mean": dict(zip(NAMES, (d_uvlm.mean(0) / 2).tolist())),
            "network_A_minus_B_first_beat_mean": dict(zip(NAMES, d_net.mean(0).tolist())),
            "network_error_flight_A_first_beat_mean": dict(zip(NAMES, err.mean(0).tolist())),
            "uvlm_history_effect_second_beat_mean": dict(zip(NAMES, np.abs(ua - ub)[:, 1].mean(0).tolist())),
        }
    doc = {"host": host_info(), "command": "python scripts/studies/step_surrogate_memory.py " + " ".join(
        sys.argv[1:] if argv is None else argv), "seed": a.seed, "beats": BEATS, "wall_s": time.perf_counter() - t0,
        "summary": summary, "flights": rows}
    from pathlib import Path

    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(doc, indent=1) + "\n")
    print(json.dumps({"summary": summary, "wall_s": doc["wall_s"]}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
