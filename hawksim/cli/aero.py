"""`hawksim aero`: one UVLM run with the body held at ascent speed V (cycle-averaged L+, D+, M+, P+); with
``--forward-speed U`` in forward flight (the air at (-U, 0, -V), the body's own loads counted,
:mod:`hawksim.condition`)."""

from __future__ import annotations

import math
from dataclasses import replace

from hawksim.backends.resolution import AERO_MODELS, DEFAULT
from hawksim.cli.args import (KINEMATICS_HELP, add_forward_speed_arg, add_insect_arg, add_resolution_args,
                              parse_kinematics, resolution_from, speed_arg)
from hawksim.cli.loads_report import render_aero
from hawksim.cli.progress import progress_for


def cmd_aero(args) -> dict:
    """The run's averages with the data set's verdict on them (:func:`hawksim.surrogate.dataset.label_status`):
    ``status`` 'ok' or 'unsettled' (the averaged wingbeat differs from the one before by more than SETTLE_TOL:
    the loads are not periodic yet) and ``peak_force_coefficient``; a run whose peak force is above
    PEAK_FORCE_CEILING (a wake vortex crossing the lattice: loads of 5-2000 times a revolving wing's) is a
    numerical failure (FloatingPointError: exit 3), not a result."""
    from hawksim.backends.held import run
    from hawksim.surrogate.dataset import PEAK_FORCE_CEILING, held_status

    res = replace(resolution_from(args, DEFAULT), aero=args.aero)
    progress = progress_for(args, "aero")
    insect = getattr(args, "insect", None)
    r = run(args.kinematics, args.speed, res, progress=progress, insect=insect, forward_speed=args.forward_speed)
    a = r.averages
    status, peak = held_status(r, res.average_cycles)
    if status == "diverged":
        raise FloatingPointError(
            f"the {res.aero} run's peak force coefficient is {peak:.3g}, above the credible {PEAK_FORCE_CEILING:g} "
            "(a wake vortex crossing the lattice): its loads are not physical; try another --n-chord, --n-span "
            "or --steps-per-cycle" if peak is not None else f"the {res.aero} run's loads are not finite")
    return {
        "L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus, "power_W": a.power_W,
        "status": status, "peak_force_coefficient": peak,
        "wall_time_s": r.wall_time_s,
        "speed": args.speed, "kinematics": args.kinematics.to_edge(), "chi_deg": math.degrees(args.kinematics.chi),
        "resolution": res.to_dict(),
        "per_cycle": [{"L_plus": c.L_plus, "D_plus": c.D_plus, "M_plus": c.M_plus, "P_plus": c.P_plus}
                      for c in r.per_cycle],
    } | ({} if insect is None else {"insect": insect.name}) | (
        {} if not args.forward_speed else {
            "forward_speed": args.forward_speed,
            "body": {k: getattr(r.body_averages, k) for k in ("L_plus", "D_plus", "M_plus")}})


def register(sub) -> None:
    p = sub.add_parser(
        "aero", help="one UVLM run with the body held at ascent speed V: cycle-averaged loads",
        description="One UVLM run with the body held at ascent speed V: cycle-averaged L+, D+, M+, P+. "
                    "The default resolution (6 x 12 rings, 40 steps per beat) is within 1.4 % in L+, 0.4 % in P+ "
                    "and 0.7 % in the lift peak of the limit of the lattice and step refined together at 1-2 m/s "
                    "(1-3 s a run; the refined levels 10 s and 6-8 min); hover has no converged limit. Refine "
                    "--n-chord, --n-span and --steps-per-cycle together (the step alone moves L+ by up to 4.6 % "
                    "from 40 to 160 steps). Measurements: docs/validation.md, sections 3-4.")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    add_forward_speed_arg(p, "; the body's own drag and lift (hawksim.insect.body_aero) count where U > 0")
    p.add_argument("--kinematics", type=parse_kinematics, required=True,
                   help=KINEMATICS_HELP)
    p.add_argument("--aero", choices=AERO_MODELS, default=DEFAULT.aero)
    add_insect_arg(p)
    add_resolution_args(p, DEFAULT)
    p.add_argument("--no-progress", action="store_true")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_aero, human=render_aero)
