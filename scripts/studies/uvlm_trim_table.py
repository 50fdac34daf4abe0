"""Build the default trim table (hawksim/insects/hawkmoth/data/trim_table.json) by balancing on the UVLM.

For each ascent speed the starting point is the paper's Table 3 (until the surrogate's GA + Nelder-Mead
optimum is available, issue 5), and f, beta, phi0, alpha0 are adjusted until |L+ - 1|, |D+|, |M+| <= 0.01 by the UVLM
(`hawksim.trim.balance`). Deterministic (no random numbers). Prints one JSON object.

    python scripts/studies/uvlm_trim_table.py --out hawksim/insects/hawkmoth/data/trim_table.json
    python scripts/studies/uvlm_trim_table.py --aero quasi-steady \
        --out hawksim/insects/hawkmoth/data/trim_table_quasi_steady.json
"""

import argparse
import json
import math
import sys
import time

from hawksim import __version__
from hawksim.backends.resolution import Resolution
from hawksim.insect.kinematics import TABLE3_SPEEDS, table3_kinematics
from hawksim.trim.balance import FREE, TRIM_RESOLUTION, balance_on_uvlm

QS_RESOLUTION = Resolution(aero="quasi-steady", steps_per_cycle=200, cycles=2)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="hawksim/insects/hawkmoth/data/trim_table.json")
    ap.add_argument("--speeds", type=float, nargs="+", default=list(TABLE3_SPEEDS))
    ap.add_argument("--aero", choices=("uvlm", "quasi-steady"), default="uvlm")
    a = ap.parse_args()
    res = TRIM_RESOLUTION if a.aero == "uvlm" else QS_RESOLUTION
    rows = []
    for v in a.speeds:
        r = balance_on_uvlm(table3_kinematics(v), v, res)
        av, st = r.averages, r.start.averages
        rows.append({"speed": v, "kinematics": r.kinematics.to_edge(), "chi": math.degrees(r.kinematics.chi),
                     "uvlm": {k: getattr(av, k) for k in ("L_plus", "D_plus", "M_plus", "P_plus")},
                     "start": {"source": "Nguyen et al. (2020) Table 3", "kinematics": r.start.kinematics.to_edge(),
                               "uvlm": {k: getattr(st, k) for k in ("L_plus", "D_plus", "M_plus", "P_plus")}},
                     "converged": r.converged, "evaluations": r.evaluations, "wall_time_s": r.wall_time_s})
        print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    out = {"source": f"{a.aero} balance of Table 3 (f, beta, phi0, alpha0 adjusted)",
           "command": " ".join(["python scripts/studies/uvlm_trim_table.py", *sys.argv[1:]]),
           "seed": None, "hawksim_version": __version__, "free_parameters": list(FREE),
           "resolution": res.to_dict(), "tolerance": 0.01,
           "created": time.strftime("%Y-%m-%d"), "rows": rows}
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
