"""Where the hawkmoth's step dependence lives (issue 48, item 4): L+, P+, M+ of `hawksim aero`'s held-body run at
Table 3's kinematics, 1 m/s, the default 6 x 12 lattice, at 40, 80, 160 and 320 steps per beat, with the default
UVLM and with one of its free-wake model terms switched off at a time: the cores' growth with age (``core_growth``),
the free wake itself (``free_wake``: the wake moves with the free stream only), the leading-edge suction
(``le_suction``). Resumable (each run is written to --out as it finishes).

    python scripts/studies/step_ablation.py --out results/step_ablation.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from aero.uvlm import UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT
from hawksim.backends.uvlm import UVLMBackend
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import RHO_AIR
from hawksim.jsonout import emit, host_info

VARIANTS = {"default": {}, "no core growth": {"core_growth": False}, "prescribed wake": {"free_wake": False},
            "no leading-edge suction": {"le_suction": False}}
STEPS = (40, 80, 160, 320)
SPEED = 1.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    path = Path(a.out)
    runs = json.loads(path.read_text())["runs"] if path.exists() else {}
    command = "python " + " ".join(sys.argv)
    for name, changes in VARIANTS.items():
        for spc in STEPS:
            key = f"{name}|{spc}"
            if key in runs:
                continue
            be = UVLMBackend(n_chord=DEFAULT.n_chord, n_span=DEFAULT.n_span, config=UVLMConfig(rho=RHO_AIR, **changes))
            t0 = time.perf_counter()
            r = held_flight(table3_kinematics(SPEED), SPEED, be, cycles=DEFAULT.cycles, steps_per_cycle=spc)
            runs[key] = {"variant": name, "steps_per_cycle": spc, "L_plus": r.averages.L_plus,
                         "P_plus": r.averages.P_plus, "M_plus": r.averages.M_plus,
                         "wall_time_s": time.perf_counter() - t0, "host": host_info()}
            print(key, json.dumps({k: runs[key][k] for k in ("L_plus", "P_plus")}), file=sys.stderr, flush=True)
            tmp = path.with_suffix(".tmp")
            tmp.write_text(json.dumps({"command": command, "speed_m_s": SPEED, "runs": runs}, indent=1))
            tmp.replace(path)
    change = {name: {f"{spc}": runs[f"{name}|{spc}"]["L_plus"] / runs[f"{name}|40"]["L_plus"] - 1.0 for spc in STEPS}
              for name in VARIANTS}
    emit({"command": command, "speed_m_s": SPEED, "L_plus_change_from_40_steps": change, "runs": runs}, a.out)


if __name__ == "__main__":
    main()
