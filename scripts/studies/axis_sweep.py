"""L+ and P+ of the current UVLM against the feathering axis's chordwise position (a head start for issue 49,
item 2: the axis is the one parameter the sources leave, to be calibrated to Table 4's L+).

Held body at Table 3's kinematics, 0 / 1 / 2 m/s, 3 beats with the third averaged, at `hawksim aero`'s default
resolution (6 x 12 rings, 40 steps) and at 8 x 16 / 80 (the middle level of docs/validation.md section 4); the
axis at ``Morphology.axis_fraction`` of the local chord behind the leading edge, everything else the default
morphology (so P+ carries today's wing-mass model; L+ of a held body does not depend on it). Resumable (--out).

    python scripts/studies/axis_sweep.py --out results/axis_sweep.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from aero.uvlm import UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.uvlm import UVLMBackend
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.model import load_model
from hawksim.insect.morphology import RHO_AIR, Morphology
from hawksim.jsonout import emit, host_info
from hawksim.paper.reference import PAPER_TABLE4

AXES = (0.0, 0.1, 0.2, 0.25, 0.3, 0.4)
SPEEDS = (0.0, 1.0, 2.0)
RESOLUTIONS = {"6x12/40": (6, 12, 40), "8x16/80": (8, 16, 80)}
TABLE4_SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    path = Path(a.out)
    runs = json.loads(path.read_text())["runs"] if path.exists() else {}
    for rname, (nc, ns, spc) in RESOLUTIONS.items():
        for axis in AXES:
            m = Morphology(axis_fraction=axis)
            model = load_model(morph=m)
            for v in SPEEDS:
                key = f"{rname}|{axis:g}|{v:g}"
                if key in runs:
                    continue
                be = UVLMBackend(m, n_chord=nc, n_span=ns, config=UVLMConfig(rho=RHO_AIR))
                t0 = time.perf_counter()
                try:
                    r = held_flight(table3_kinematics(v), v, be, cycles=3, steps_per_cycle=spc, model=model, morph=m)
                    runs[key] = {"L_plus": r.averages.L_plus, "P_plus": r.averages.P_plus,
                                 "D_plus": r.averages.D_plus, "M_plus": r.averages.M_plus}
                except (FloatingPointError, ValueError) as e:
                    runs[key] = {"error": str(e)}
                runs[key].update(wall_time_s=time.perf_counter() - t0, host=host_info(),
                                 table4_L_plus=PAPER_TABLE4["L_plus"][TABLE4_SPEEDS.index(v)])
                print(key, json.dumps(runs[key]), file=sys.stderr, flush=True)
                tmp = path.with_suffix(".tmp")
                tmp.write_text(json.dumps({"command": "python " + " ".join(sys.argv), "runs": runs}, indent=1))
                tmp.replace(path)
    emit({"command": "python " + " ".join(sys.argv), "runs": runs}, a.out)


if __name__ == "__main__":
    main()
