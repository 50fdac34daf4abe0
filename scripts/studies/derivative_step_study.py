"""Step-size and scatter study of the stability derivatives (issue 6): the 18 derivatives at one speed for
several disturbance sizes (fraction of U for u, v, w; of 1/T for p, q, r), each for one or more realizations.

Realization k runs the trim with its flapping frequency changed by a relative k * 1e-10 (round-off level): at
hover and 0.5 m/s the free wake amplifies such changes into several per cent of the cycle averages
(docs/uvlm.md, "Hover is not periodic"), so the spread over realizations is the uncertainty of each derivative;
"determined" marks those whose mean exceeds twice that spread. Prints one JSON object.

    python scripts/studies/derivative_step_study.py --speed 1.0 --out results/stability/step_study_v1.json
    python scripts/studies/derivative_step_study.py --speed 0 --sizes 0.05 --realizations 3 \
        --out results/stability/scatter_v0.json
"""

import argparse
from dataclasses import replace

import numpy as np

from hawksim.insect.kinematics import ROUND_OFF_STEP, realization
from hawksim.jsonout import emit
from hawksim.stability.derivatives import DERIVATIVE_RESOLUTION, dimensional_derivatives
from hawksim.stability.system import Scales
from hawksim.trim.tables import trim_kinematics


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.02, 0.05, 0.1])
    ap.add_argument("--realizations", type=int, default=1)
    ap.add_argument("--cycles", type=int, default=DERIVATIVE_RESOLUTION.cycles,
                    help="wingbeats per run (the disturbance acts over the last --average-cycles)")
    ap.add_argument("--average-cycles", type=int, default=DERIVATIVE_RESOLUTION.average_cycles)
    ap.add_argument("--out")
    a = ap.parse_args()
    res = replace(DERIVATIVE_RESOLUTION, cycles=a.cycles, average_cycles=a.average_cycles)
    kin0 = trim_kinematics(a.speed)
    sc = Scales.of(kin0)
    rows = []
    for d in a.sizes:
        reals, wall = [], 0.0
        for k in range(a.realizations):
            r = dimensional_derivatives(realization(kin0, k), a.speed, res, delta_velocity=d, delta_rate=d)
            reals.append({name: sc.derivative(name, v) for name, v in r.derivatives.items()})
            wall += r.wall_time_s
        row = {"size": d, "derivatives_plus": reals[0], "wall_time_s": wall}
        if a.realizations > 1:
            names = list(reals[0])
            vals = np.array([[re[n] for n in names] for re in reals])
            mean, std = vals.mean(0), vals.std(0, ddof=1)
            row.update({"realizations_plus": reals, "mean_plus": dict(zip(names, mean.tolist())),
                        "std_plus": dict(zip(names, std.tolist())),
                        "determined": [n for n, m, s in zip(names, mean, std) if abs(m) > 2 * s]})
        rows.append(row)
    emit({"speed": a.speed, "resolution": res.to_dict(), "realizations": a.realizations,
          "realization_step": ROUND_OFF_STEP, "rows": rows}, a.out)


if __name__ == "__main__":
    main()
