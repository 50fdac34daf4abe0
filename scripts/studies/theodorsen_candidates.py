"""What made the UVLM exceed Theodorsen (issue 48, item 2): each candidate switched on its own, its effect on the
heave and pitch lift's first harmonic against Theodorsen at k = 0.5 and 1.

Plate: AR 20 (24 tip-clustered spanwise rings on the half span), 4, 8 and 16 chordwise rings, prescribed wake,
three periods; the step both at U dt = one chordwise panel (:func:`aero.plate.consistent_steps`) and at 80 steps
per period. The AR-20 result must lie a few per cent BELOW the 2D theory (the 3D deficiency, measured by
scripts/studies/classical_cases.py); the ratios here are against the 2D theory.

    python scripts/studies/theodorsen_candidates.py --out results/classical/theodorsen_candidates.json
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import sys
from dataclasses import replace

import numpy as np

from aero import plate
from aero.unsteady_theory import heave_lift, pitch_lift
from aero.uvlm import LEGACY_0_2

VARIANTS = {
    "hawksim 0.2 (ring shedding, ring jump, first-order dGamma/dt)": dict(LEGACY_0_2),
    "0.2 + wake core 0.001 c (instead of 0.05 c)": dict(LEGACY_0_2, wake_core_chords=1e-3),
    "0.2 + 'travel' shedding": dict(LEGACY_0_2, shed_rule="travel"),
    "0.2 + panel jump (trapezoid)": dict(LEGACY_0_2, potential_jump="panel"),
    "0.2 + second-order dGamma/dt": dict(LEGACY_0_2, time_derivative="bdf2"),
    "travel + panel jump": dict(time_derivative="euler"),
    "travel + panel jump + second-order (new default)": {},
    "new default + wake core 0.001 c": dict(wake_core_chords=1e-3),
    "new default + core growth (hawkmoth setting)": dict(core_growth=True),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    rows = []
    for name, changes in VARIANTS.items():
        cfg = replace(plate.PLAIN_CONFIG, **changes)
        for k in (0.5, 1.0):
            for nc in (4, 8, 16):
                for step in ("consistent", 80):
                    spc = plate.consistent_steps(k, nc) if step == "consistent" else step
                    if nc == 16 and step == 80 and k == 0.5:
                        continue
                    g = plate.PlateGrid(20.0, nc, 24, spc)
                    row = {"variant": name, "changes": changes, "k": k, "n_chord": nc, "steps_per_cycle": spc}
                    for motion, amp, scale, ref in (("heave", 0.02, 0.04, heave_lift), ("pitch", np.radians(1.0),
                                                                                          np.radians(1.0), pitch_lift)):
                        r = plate.run_plate(g, motion, amp, k=k, cycles=3, config=cfg)
                        H = plate.first_harmonic(r, k, spc)[0] / scale
                        th = complex(ref(k))
                        row[motion] = {"amplitude_ratio": abs(H) / abs(th),
                                       "phase_error_deg": float(np.degrees(np.angle(H / th)))}
                    rows.append(row)
                    print(json.dumps(row), file=sys.stderr, flush=True)
    out = {"command": "python " + " ".join(sys.argv), "aspect_ratio": 20.0,
           "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "load_average": os.getloadavg()[0], "rows": rows}
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
