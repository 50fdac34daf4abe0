"""Where the UVLM stands against the paper (issue 48, item 6), nothing tuned: L+ and P+ at Table 3's kinematics
(0, 0.5, 1, 1.5, 2 m/s) against Table 4, and the power law P = a + b V fitted through them against the paper's
0.0702 + 0.0215 V [W], for the current UVLM and hawksim 0.2's (aero.uvlm.LEGACY_0_2), at the default resolution
and at 12 x 24 rings with 80 steps per beat.

    python scripts/studies/uvlm_standing.py --out results/uvlm_standing.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from aero.uvlm import LEGACY_0_2, UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT, Resolution
from hawksim.backends.uvlm import UVLMBackend
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import RHO_AIR
from hawksim.paper.reference import PAPER_POWER_FIT_W, PAPER_TABLE4
from hawksim.jsonout import emit

SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)
MODELS = {"current": {}, "hawksim 0.2": LEGACY_0_2}
RESOLUTIONS = {"default": DEFAULT, "12x24/80": Resolution(n_chord=12, n_span=24, steps_per_cycle=80)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--resolutions", nargs="+", default=list(RESOLUTIONS))
    a = ap.parse_args()
    rows = []
    for rname in a.resolutions:
        res = RESOLUTIONS[rname]
        for mname, changes in MODELS.items():
            for v in SPEEDS:
                be = UVLMBackend(n_chord=res.n_chord, n_span=res.n_span, config=UVLMConfig(rho=RHO_AIR, **changes))
                t0 = time.perf_counter()
                try:
                    r = held_flight(table3_kinematics(v), v, be, cycles=res.cycles, steps_per_cycle=res.steps_per_cycle)
                    avg = r.averages
                    row = {"L_plus": avg.L_plus, "D_plus": avg.D_plus, "M_plus": avg.M_plus, "P_plus": avg.P_plus,
                           "power_W": avg.power_W}
                except FloatingPointError as e:
                    row = {"error": str(e)}
                row.update(resolution=rname, model=mname, speed=v, wall_time_s=time.perf_counter() - t0,
                           paper={k: vals[SPEEDS.index(v)] for k, vals in PAPER_TABLE4.items()})
                rows.append(row)
                print(json.dumps(row), file=sys.stderr, flush=True)
    fits = {}
    for rname in a.resolutions:
        for mname in MODELS:
            pts = [(r["speed"], r["power_W"]) for r in rows
                   if r["resolution"] == rname and r["model"] == mname and "power_W" in r]
            if len(pts) >= 2:
                b, a0 = np.polyfit(*zip(*pts), 1)
                fits[f"{mname} @ {rname}"] = {"intercept_W": a0, "slope_W_per_m_s": b,
                                              "intercept_ratio": a0 / PAPER_POWER_FIT_W[0],
                                              "slope_ratio": b / PAPER_POWER_FIT_W[1]}
    out = {"command": "python " + " ".join(sys.argv), "rows": rows, "power_law": fits,
           "paper_power_law_W": PAPER_POWER_FIT_W}
    emit(out, a.out, host=True)


if __name__ == "__main__":
    main()
