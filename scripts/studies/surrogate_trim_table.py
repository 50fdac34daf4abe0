"""Build the trim table of `hawksim fly --aero surrogate` (hawksim/insects/hawkmoth/data/trim_table_surrogate.json).

The surrogate flight's loads come from the shipped speed-input network, so its trim is that network's own
GA + Nelder-Mead minimum of Eq. 3 at each study speed (seed 0, population 1e5), in the layout of the other trim
tables. Prints ONE JSON object.

    python scripts/studies/surrogate_trim_table.py --out hawksim/insects/hawkmoth/data/trim_table_surrogate.json
"""

import argparse
import math
import sys

from hawksim import __version__
from hawksim.backends.network import load, shipped_path
from hawksim.insect.kinematics import TABLE3_SPEEDS
from hawksim.jsonout import emit
from hawksim.trim.search import GAConfig, trim_on_surrogate


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="hawksim/insects/hawkmoth/data/trim_table_surrogate.json")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    net = load(shipped_path(None))
    rows = []
    for v in TABLE3_SPEEDS:
        r = trim_on_surrogate(net, v, seed=a.seed, cfg=GAConfig())
        rows.append({"speed": v, "kinematics": r.kinematics.to_edge(), "chi": math.degrees(r.kinematics.chi),
                     "surrogate": r.outputs, "fitness": r.fitness, "wall_time_s": r.wall_time_s})
        print(f"{v:g} m/s: {r.outputs}", file=sys.stderr, flush=True)
    out = {"source": "GA + Nelder-Mead minimum of Eq. 3 on the shipped speed-input surrogate",
           "command": " ".join(["python scripts/studies/surrogate_trim_table.py", *sys.argv[1:]]), "seed": a.seed,
           "hawksim_version": __version__, "model": net.meta.get("command"), "rows": rows}
    emit(out, a.out)


if __name__ == "__main__":
    main()
