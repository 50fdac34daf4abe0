"""Step-size study of the stability derivatives (issue 6): the 18 derivatives at one speed for several
disturbance sizes (fraction of U for u, v, w; of 1/T for p, q, r). Prints one JSON object.

    python scripts/derivative_step_study.py --speed 1.0 --out results/stability/step_study_v1.json
"""

import argparse

from hawksim.derivatives import dimensional_derivatives
from hawksim.stability import Scales
from hawksim.trim_table import trim_kinematics
from hawksim.jsonout import emit


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.02, 0.05, 0.1])
    ap.add_argument("--out")
    a = ap.parse_args()
    kin = trim_kinematics(a.speed)
    sc = Scales.of(kin)
    rows = []
    for d in a.sizes:
        r = dimensional_derivatives(kin, a.speed, delta_velocity=d, delta_rate=d)
        rows.append({"size": d, "derivatives_plus": {k: sc.derivative(k, v) for k, v in r.derivatives.items()},
                     "wall_time_s": r.wall_time_s})
    out = {"speed": a.speed, "rows": rows}
    emit(out, a.out)


if __name__ == "__main__":
    main()
