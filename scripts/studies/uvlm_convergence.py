"""UVLM convergence study (issue 3): L+, D+, M+, P+ at Table 3's kinematics against the resolution.

For each resolution (chordwise x spanwise rings per wing, steps per wingbeat) the held-body run of
`hawksim aero` (3 wingbeats, last one averaged; per-cycle values show the periodic convergence). Prints one
JSON object and writes it to --out.

    python scripts/studies/uvlm_convergence.py --speed 1.0 --out results/uvlm_convergence.json
"""

import argparse
import json
import time

from hawksim.backends.held import run
from hawksim.backends.resolution import Resolution
from hawksim.insect.kinematics import table3_kinematics
from hawksim.jsonout import emit

LADDER = [(4, 8, 30), (6, 12, 40), (8, 16, 60), (12, 24, 80), (16, 32, 120)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--max-level", type=int, default=len(LADDER))
    ap.add_argument("--out")
    a = ap.parse_args()
    kin = table3_kinematics(a.speed)
    rows = []
    for nc, ns, spc in LADDER[:a.max_level]:
        res = Resolution(n_chord=nc, n_span=ns, steps_per_cycle=spc, cycles=a.cycles)
        t0 = time.perf_counter()
        r = run(kin, a.speed, res)
        rows.append({"n_chord": nc, "n_span": ns, "steps_per_cycle": spc, "wall_time_s": time.perf_counter() - t0,
                     **{k: getattr(r.averages, k) for k in ("L_plus", "D_plus", "M_plus", "P_plus")},
                     "per_cycle": [[c.L_plus, c.D_plus, c.M_plus, c.P_plus] for c in r.per_cycle]})
        print(json.dumps(rows[-1]), flush=True, file=__import__("sys").stderr)
    out = {"speed": a.speed, "kinematics": kin.to_edge(), "cycles": a.cycles, "rows": rows}
    emit(out, a.out)


if __name__ == "__main__":
    main()
