"""Where in the wingbeat the hawkmoth's lift moves when the step alone is refined (issue 48, item 4): L/W of the third
beat at 40 and 160 steps per beat on the default lattice, Table 3's kinematics at 1 m/s, at the 40 common phases.

    python scripts/studies/step_phase.py --out results/step_phase.json
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from aero.uvlm import UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT
from hawksim.backends.uvlm import UVLMBackend
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import HAWKMOTH, RHO_AIR
from hawksim.jsonout import emit

SPEED = 1.0
STEPS = (40, 160)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    lift = {}
    for spc in STEPS:
        be = UVLMBackend(n_chord=DEFAULT.n_chord, n_span=DEFAULT.n_span, config=UVLMConfig(rho=RHO_AIR))
        r = held_flight(table3_kinematics(SPEED), SPEED, be, cycles=DEFAULT.cycles, steps_per_cycle=spc)
        lift[spc] = r.lift[-spc:] / HAWKMOTH.weight
    stride = STEPS[1] // STEPS[0]
    coarse, fine = lift[STEPS[0]], lift[STEPS[1]][::stride]
    out = {"command": "python " + " ".join(sys.argv), "phase": (np.arange(STEPS[0]) / STEPS[0]).tolist(),
           "lift_40": coarse.tolist(), "lift_160": fine.tolist(), "difference": (fine - coarse).tolist(),
           "L_plus": {str(s): float(v.mean()) for s, v in lift.items()}}
    emit(out, a.out, host=True)


if __name__ == "__main__":
    main()
