"""`hawksim fly`: a free flight from the shipped trim of the chosen aerodynamic model (or given kinematics)."""

from __future__ import annotations

from hawksim.backends import FLIGHT_BACKENDS
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE as STEPS_PER_CYCLE
from hawksim.backends.resolution import MIN_STEPS_PER_CYCLE
from hawksim.cli.args import KINEMATICS_HELP, cycles_arg, parse_kinematics, perturbation_arg, speed_arg, writable_file
from hawksim.cli.progress import progress_for


def fly_named(speed: float, cycles: int, aero: str = "quasi-steady", *, kinematics=None, perturb=None,
              model_path=None, steps_per_cycle: int = STEPS_PER_CYCLE, keep_extras_every: int = 0, **kw):
    """`hawksim fly`'s flight: the shipped trim of ``aero`` at ``speed`` (or ``kinematics``), the backend of that
    name, then :func:`hawksim.flight.fly.fly`."""
    from hawksim.backends import flight_backend
    from hawksim.flight.fly import fly
    from hawksim.flight.start import is_lateral, parse_perturbations
    from hawksim.insect.model import load_model
    from hawksim.trim.point import Trim
    from hawksim.trim.tables import shipped_trim

    perturb = parse_perturbations(perturb or {})
    trim = (Trim(float(speed), kinematics, model=aero, source="given") if kinematics is not None
            else shipped_trim(speed, aero))
    backend = flight_backend(aero, kinematics=trim.kinematics, symmetric=not is_lateral(perturb),
                             keep_panels=keep_extras_every > 0)
    return fly(trim, backend, cycles, perturb=perturb, model=load_model(model_path), steps_per_cycle=steps_per_cycle,
               keep_extras_every=keep_extras_every, **kw)


def cmd_fly(args) -> dict:
    progress = progress_for(args, "fly")
    result = fly_named(args.speed, args.cycles, args.aero, perturb=dict(args.perturb or []), model_path=args.model,
                       kinematics=args.kinematics, steps_per_cycle=args.steps_per_cycle,
                       keep_extras_every=args.steps_per_cycle // 10 if args.rrd else 0, progress=progress)
    out = result.summary()
    out["rrd"] = None
    if args.rrd:
        from hawksim.flight.recording import write_rrd

        out["rrd"] = str(write_rrd(args.rrd, result))
    return out


def register(sub) -> None:
    f = sub.add_parser("fly", help="fly the insect from its trim at an ascent speed (MuJoCo, 6-DOF)")
    f.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 (hover) to 2")
    f.add_argument("--cycles", type=cycles_arg, required=True, help="number of wingbeats N")
    f.add_argument("--aero", choices=FLIGHT_BACKENDS, default="quasi-steady",
                   help="aerodynamic model (default quasi-steady)")
    f.add_argument("--rrd", type=writable_file, help="write a Rerun recording to FILE")
    f.add_argument("--perturb", type=perturbation_arg, action="append", metavar="NAME=VALUE",
                   help="initial disturbance: u, v, w [m/s]; p, q, r [deg/s]; theta, phi [deg] (stability axes)")
    f.add_argument("--kinematics", type=parse_kinematics, help="override the trim: " + KINEMATICS_HELP)
    f.add_argument("--model", help="MJCF file (default: the model generated from hawksim.insect.morphology)")
    f.add_argument("--steps-per-cycle", type=int, default=STEPS_PER_CYCLE,
                   help=f"integration steps per wingbeat ({STEPS_PER_CYCLE}; at least {MIN_STEPS_PER_CYCLE})")
    f.add_argument("--no-progress", action="store_true", help="no progress bar")
    f.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    f.set_defaults(func=cmd_fly)
