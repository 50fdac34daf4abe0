"""Where the per-step surrogate's cycle-mean errors come from: per held-out wingbeat |network - UVLM| of L+, D+, M+,
P+ by ascent speed, by beat after the kick and by flight kind (issue 21, item 4; docs/surrogate.md).

    python scripts/studies/step_surrogate_by_speed.py NETWORK.safetensors [...] [--data data/uvlm_flights_0.2.0.sqlite]
        [--out results/surrogate/step_errors_by_speed.json]

Each network is scored on its own held-out flights (its metadata's ``test_flights``), along the recorded UVLM
flights (:func:`hawksim.surrogate.step_train.score`'s cycle means). Prints and writes one JSON object.
"""

import argparse
import json
import sys

import numpy as np

from hawksim.backends.step_network import load
from hawksim.insect.kinematics import Kinematics
from hawksim.jsonout import host_info
from hawksim.surrogate import step_train as T
from hawksim.surrogate.flights import read_flights

SPEED_BINS = ((0.0, 0.5), (0.5, 1.0), (1.0, 1.5), (1.5, 2.0 + 1e-9))
NAMES = ("L_plus", "D_plus", "M_plus", "P_plus")


def beat_errors(net, flights) -> np.ndarray:
    """(n_beats, 7): speed, symmetric, beat after the warm-up, and the signed errors of L+, D+, M+, P+."""
    mirror = np.concatenate([T.MIRROR_F, T.MIRROR_M])
    out = []
    for f in flights:
        x, _ = T.flight_inputs(f, net.lags)
        yl, yr = net.predict(x), net.predict(T.mirror_inputs(x)) * mirror
        r = f.rows
        u_l = r[:, T.column_indices("FLx", "FLy", "FLz", "MLx", "MLy", "MLz")]
        u_r = r[:, T.column_indices("FRx", "FRy", "FRz", "MRx", "MRy", "MRz")]
        geom = T.wing_geometry(Kinematics.from_array(f.kinematics), r[:, T.COLUMN_INDEX["t"]])
        pa = r[:, T.COLUMN_INDEX["power_aero"]]
        cu = T.cycle_means(f, T.flight_loads(f, u_l, u_r, geom), pa)
        cp = T.cycle_means(f, T.flight_loads(f, yl, yr, geom), pa)
        for k in range(len(cu)):
            out.append((f.speed, float(f.symmetric), k, *(cp[k] - cu[k])))
    return np.array(out, float).reshape(-1, 7)


def summary(a: np.ndarray) -> dict:
    def block(s):
        e = np.abs(a[s, 3:])
        return {"beats": int(s.sum()), **{k: float(v) for k, v in zip(NAMES, e.mean(0))}} if s.any() else {}

    return {"all": block(np.ones(len(a), bool)),
            "by_speed": {f"{lo:g}-{min(hi, 2):g}": block((a[:, 0] >= lo) & (a[:, 0] < hi)) for lo, hi in SPEED_BINS},
            "symmetric": block(a[:, 1] == 1), "lateral": block(a[:, 1] == 0),
            "by_beat": {str(k): block(a[:, 2] == k) for k in range(int(a[:, 2].max()) + 1)}}


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("networks", nargs="+")
    ap.add_argument("--data", default="data/uvlm_flights_0.2.0.sqlite")
    ap.add_argument("--out", default="results/surrogate/step_errors_by_speed.json")
    a = ap.parse_args(argv)
    flights = {f.idx: f for f in read_flights(a.data)}
    res = {"host": host_info(), "data": a.data, "networks": {}}
    for path in a.networks:
        net = load(path)
        test = [flights[i] for i in net.meta["test_flights"]]
        res["networks"][path] = {"lags": list(net.lags), "n_flights": net.meta.get("n_flights"),
                                 "command": net.meta.get("command"), **summary(beat_errors(net, test))}
    text = json.dumps(res, indent=1)
    with open(a.out, "w") as fh:
        fh.write(text + "\n")
    print(text)


if __name__ == "__main__":
    sys.exit(main())
