"""Table 3's kinematics (the paper's trims) evaluated by our UVLM at the five ascent speeds, next to the
paper's Table 4 (UVLM values). Prints one JSON object and writes it to --out.

    python scripts/uvlm_table4.py --out results/uvlm_table4.json
"""

import argparse
import json

from hawksim.evaluate import DEFAULT, run
from hawksim.kinematics import TABLE3_SPEEDS, table3_kinematics

TABLE4 = {  # Nguyen et al. (2020) Table 4, UVLM values (ANN in parentheses there)
    "L_plus": (0.97, 0.98, 0.99, 0.99, 0.99), "D_plus": (0, 0, 0, 0, 0),
    "M_plus": (0, -0.01, 0, 0, 0), "P_plus": (0.86, 0.96, 1.09, 1.21, 1.34)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out")
    ap.add_argument("--cycles", type=int, default=4)
    a = ap.parse_args()
    from dataclasses import replace

    res = replace(DEFAULT, cycles=a.cycles, average_cycles=a.cycles - 1)
    rows = []
    for i, v in enumerate(TABLE3_SPEEDS):
        r = run(table3_kinematics(v), v, res)
        rows.append({"speed": v, **{k: getattr(r.averages, k) for k in TABLE4},
                     "paper": {k: TABLE4[k][i] for k in TABLE4},
                     "per_cycle": [[c.L_plus, c.D_plus, c.M_plus, c.P_plus] for c in r.per_cycle],
                     "wall_time_s": r.wall_time_s})
    out = {"resolution": res.to_dict(), "note": "averages over all but the first wingbeat", "rows": rows}
    if a.out:
        with open(a.out, "w") as f:
            json.dump(out, f, indent=1)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
