"""Issue 20's 0.5 m/s lateral gust (beats 5-6) flown with a per-step surrogate that has history inputs, under the
half-stroke LQR designed two ways (docs/control.md, "A history network in the loop"; issue 21).

A record of the trial of 2026-12-02 14:48 UTC, reproducible at commit 046f12e: since 15:30 the shipped network is
the history network, its orbits carry their record and its gains feed the record back (docs/control.md, "The record
in the state"), so on later commits this script's first design is not the record-held one it describes.

A history network's control maps hold its record of past calls at the orbit's (a reduced model,
:class:`hawksim.control.derivatives.Snapshot`). This study flies the gust with those gains and with the gains of
another network's schedule (the shipped memoryless one's), read from a JSON file that this script writes in its
``--dump-gains`` mode. Two processes, because the network is the installed one:

    # in the tree with the memoryless network installed (the shipped one)
    python scripts/studies/control_history_trial.py --dump-gains /tmp/memoryless_gains.json
    # in a scratch worktree with the history network installed as insects/hawkmoth/data/surrogates/uvlm_step.safetensors
    # and its orbit table (scripts/studies/step_surrogate_orbits.py --speeds 0 0.5 1 1.5 2 --no-floquet --table ...)
    NUMBA_NUM_THREADS=1 python scripts/studies/control_history_trial.py --gains /tmp/memoryless_gains.json \
        --out results/control/control_history_trial_gusts.json

Prints (and writes) one JSON object: per design and speed, the peak roll [deg], the first beat from which every
beat is within issue 20's bounds (0.02 m/s, 2 deg of pitch and roll; None: never within 30 beats) and the beats
from the gust's end to it.
"""

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from hawksim.backends.step_network import network_sha256
from hawksim.control.closed_loop import Gust, fly_closed_loop
from hawksim.control.schedule import Schedule
from hawksim.jsonout import host_info

SPEEDS = (0.0, 1.0, 2.0)
GAINS = ("long", "lat", "long_half", "lat_half")


def _schedule(gains: dict | None = None) -> Schedule:
    sch = Schedule(0.0, 2.0, aero="surrogate", rate="half-stroke")
    if gains is not None:
        sch.points = [replace(p, **{k: replace(getattr(p, k), K=np.array(gains[str(p.speed)][k])) for k in GAINS})
                      for p in sch.points]
    return sch


def _gust(sch: Schedule, v: float, beats: int = 30) -> dict:
    b = fly_closed_loop(v, beats, aero="surrogate", schedule=sch, gusts=[Gust(np.array([0.0, 0.5, 0.0]), 5, 2)]).beats
    ok = [abs(x["speed_error"]) <= 0.02 and abs(x["pitch_error_deg"]) <= 2 and abs(x["roll_deg"]) <= 2 for x in b]
    k = next((b[i]["beat"] for i in range(len(ok)) if all(ok[i:])), None)
    return {"peak_roll_deg": max(abs(x["roll_deg"]) for x in b), "in_bounds_from_beat": k,
            "recovered_after_beats": None if k is None else k - 6}


def main():
    ap = argparse.ArgumentParser()
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--dump-gains", help="write the installed network's half-stroke gains (JSON) and stop")
    g.add_argument("--gains", help="a --dump-gains file: also fly with those gains")
    ap.add_argument("--out")
    a = ap.parse_args()
    if a.dump_gains:
        sch = _schedule()
        out = {str(p.speed): {k: getattr(p, k).K.tolist() for k in GAINS} for p in sch.points}
        Path(a.dump_gains).write_text(json.dumps({**out, "network_sha256": network_sha256()}))
        return
    other = json.loads(Path(a.gains).read_text())
    res = {"host": host_info(), "command": "python scripts/studies/control_history_trial.py " + " ".join(sys.argv[1:]),
           "network_sha256": network_sha256(), "gains_network_sha256": other.pop("network_sha256", None),
           "designs": {}}
    for name, sch in (("own reduced model (record held)", _schedule()), ("the --gains network's", _schedule(other))):
        res["designs"][name] = {str(v): _gust(sch, v) for v in SPEEDS}
        print(name, json.dumps(res["designs"][name]), file=sys.stderr, flush=True)
    text = json.dumps(res, indent=1)
    if a.out:
        Path(a.out).write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
