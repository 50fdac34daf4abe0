"""`hawksim aero`: one UVLM run with the body held at ascent speed V (cycle-averaged L+, D+, M+, P+)."""

from __future__ import annotations

import math
from dataclasses import replace

from hawksim.backends.resolution import AERO_MODELS, DEFAULT
from hawksim.cli.args import MAX_RINGS, KINEMATICS_HELP, aero_cycles_arg, parse_kinematics, positive_int_arg, speed_arg
from hawksim.cli.progress import progress_for


def cmd_aero(args) -> dict:
    from hawksim.backends.held import run

    res = DEFAULT
    if args.cycles is not None:
        res = replace(res, cycles=args.cycles)
    res = replace(res, aero=args.aero, **{k: v for k, v in (("n_chord", args.n_chord), ("n_span", args.n_span),
                                                            ("steps_per_cycle", args.steps_per_cycle)) if v})
    progress = progress_for(args, "aero")
    r = run(args.kinematics, args.speed, res, progress=progress)
    a = r.averages
    return {
        "L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus, "power_W": a.power_W,
        "wall_time_s": r.wall_time_s,
        "speed": args.speed, "kinematics": args.kinematics.to_edge(), "chi_deg": math.degrees(args.kinematics.chi),
        "resolution": res.to_dict(),
        "per_cycle": [{"L_plus": c.L_plus, "D_plus": c.D_plus, "M_plus": c.M_plus, "P_plus": c.P_plus}
                      for c in r.per_cycle],
    }


def register(sub) -> None:
    p = sub.add_parser("aero", help="one UVLM run with the body held at ascent speed V: cycle-averaged loads")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    p.add_argument("--kinematics", type=parse_kinematics, required=True,
                   help=KINEMATICS_HELP)
    p.add_argument("--cycles", type=aero_cycles_arg,
                   help=f"wingbeats (default {DEFAULT.cycles}; the last {DEFAULT.average_cycles} averaged)")
    p.add_argument("--aero", choices=AERO_MODELS, default=DEFAULT.aero)
    p.add_argument("--n-chord", type=positive_int_arg("n-chord", MAX_RINGS),
                   help=f"chordwise vortex rings per wing ({DEFAULT.n_chord})")
    p.add_argument("--n-span", type=positive_int_arg("n-span", MAX_RINGS),
                   help=f"spanwise vortex rings per wing ({DEFAULT.n_span})")
    p.add_argument("--steps-per-cycle", type=positive_int_arg("steps-per-cycle"),
                   help=f"time steps per wingbeat ({DEFAULT.steps_per_cycle})")
    p.add_argument("--no-progress", action="store_true")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_aero)
