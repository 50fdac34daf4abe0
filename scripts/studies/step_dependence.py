"""The loads against the time step at a fixed lattice (issue 48, item 4): shedding rules and the opt-in lumped
near wake (``UVLMConfig.near_wake_zones``), on the heaving plate and on the hawkmoth.

Plate: heave at k = 1, AR 20, 8 x 24 rings, linear-theory wake (aero.plate.PLAIN_CONFIG), 25, 50, 100 steps a period
(25: the wake moves one chordwise panel per step); the first harmonic's amplitude and phase against Theodorsen.
Hawkmoth: `hawksim aero`'s held-body run at Table 3's kinematics, 1 m/s, the default 6 x 12 lattice, 40, 80, 160
steps per beat; L+, P+ of the third beat.

    python scripts/studies/step_dependence.py --out results/step_dependence.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace

import numpy as np

from aero import plate
from aero.unsteady_theory import heave_lift
from aero.uvlm import UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT
from hawksim.backends.uvlm import UVLMBackend
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import RHO_AIR
from hawksim.jsonout import emit

PLATE_VARIANTS = {"travel (default)": {}, "ring": dict(shed_rule="ring"),
                  "ring + 1 lumped zone": dict(shed_rule="ring", near_wake_zones=1),
                  "ring + 2 lumped zones": dict(shed_rule="ring", near_wake_zones=2),
                  "ring + 8 lumped zones": dict(shed_rule="ring", near_wake_zones=8)}
HAWKMOTH_VARIANTS = {"travel (default)": {}, "ring": dict(shed_rule="ring"),
                     "ring + 2 lumped zones": dict(shed_rule="ring", near_wake_zones=2)}
K, ASPECT_RATIO, N_CHORD = 1.0, 20.0, 8
SPEED = 1.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    rows = []
    base = plate.consistent_steps(K, N_CHORD)
    for name, changes in PLATE_VARIANTS.items():
        for mult in (1, 2, 4):
            g = plate.PlateGrid(ASPECT_RATIO, N_CHORD, 24, base * mult)
            t0 = time.perf_counter()
            H = plate.harmonic_response(g, "heave", K, config=replace(plate.PLAIN_CONFIG, **changes)).H
            ref = complex(heave_lift(K))
            rows.append({"case": "plate", "variant": name, "steps_per_cycle": g.steps_per_cycle,
                         "amplitude_ratio": abs(H) / abs(ref), "phase_error_deg": float(np.degrees(np.angle(H / ref))),
                         "wall_time_s": time.perf_counter() - t0})
            print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    for name, changes in HAWKMOTH_VARIANTS.items():
        for spc in (40, 80, 160):
            be = UVLMBackend(n_chord=DEFAULT.n_chord, n_span=DEFAULT.n_span,
                             config=UVLMConfig(rho=RHO_AIR, **changes))
            t0 = time.perf_counter()
            r = held_flight(table3_kinematics(SPEED), SPEED, be, cycles=DEFAULT.cycles, steps_per_cycle=spc)
            rows.append({"case": "hawkmoth", "variant": name, "steps_per_cycle": spc, "L_plus": r.averages.L_plus,
                         "P_plus": r.averages.P_plus, "wall_time_s": time.perf_counter() - t0})
            print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    out = {"command": "python " + " ".join(sys.argv), "rows": rows}
    emit(out, a.out, host=True)


if __name__ == "__main__":
    main()
