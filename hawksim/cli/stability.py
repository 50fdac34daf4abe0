"""`hawksim stability`: stability derivatives at the trim, A_long and A_lat, eigen-analysis; with ``--floquet``
also the periodic orbit of the free body and the Floquet multipliers of its one-wingbeat map, beside the
cycle-averaged A matrices of the same aerodynamic model at the orbit's kinematics."""

from __future__ import annotations

import math
import sys

from hawksim.backends.registry import descriptor, names
from hawksim.cli.args import (INSECT_HELP, UsageError, add_forward_speed_arg, check_forward_condition, insect_arg,
                              parse_kinematics, positive_int_arg, speed_arg)


def _averaged(args, kin, client=None) -> dict:
    if args.aero == "quasi-steady":
        from hawksim.control.linearization import averaged_model
        from hawksim.stability.report import averaged_json
        from hawksim.trim.point import OperatingPoint

        insect = getattr(args, "insect", None)
        fwd = {"forward_speed": args.forward_speed} if args.forward_speed else {}
        point = OperatingPoint(float(args.speed), kin, aero="quasi-steady", body="held", source=args.trim_source or "",
                               **({} if insect is None else {"insect": insect}), **fwd)
        if insect is None:
            return {"speed": args.speed, **fwd, "aero": args.aero,
                    "trim": {"kinematics": kin.to_edge(), **({"source": args.trim_source} if fwd else {})},
                    **averaged_json(averaged_model(point))}
        return {"speed": args.speed, "aero": args.aero, "insect": insect.name,
                "trim": {"kinematics": kin.to_edge(), "source": args.trim_source},
                **averaged_json(averaged_model(point))}
    from hawksim.cli.progress import progress_for
    from hawksim.stability.report import stability_report

    bar = progress_for(args, f"stability V={args.speed:g} (disturbed UVLM runs)", "run", mininterval=0.1)
    out = stability_report(args.speed, kinematics=kin, client=client, progress=bar,
                           **({"forward_speed": args.forward_speed} if args.forward_speed else {}))
    return {"speed": out.pop("speed", args.speed), "aero": args.aero, **out}


def cmd_stability(args) -> dict:
    from hawksim.cli.stability_report import render

    args.human = render
    if args.forward_speed:  # forward flight: quasi-steady or UVLM, from given kinematics (issue 51)
        check_forward_condition(args)
    from hawksim.cluster import dask_client
    from hawksim.trim.tables import shipped_trim

    kin = args.kinematics
    insect = getattr(args, "insect", None)
    if insect is not None and args.aero != "quasi-steady":
        raise UsageError(f"--insect takes --aero quasi-steady (the {args.aero} stability analysis is the default "
                         "hawkmoth's)")
    args.trim_source = getattr(args, "kinematics_source", None) or ("given (--kinematics)" if kin is not None
                                                                    else None)
    out_orbit = None
    if args.floquet:
        from hawksim.control.linearization import linearize
        from hawksim.flight.orbit import periodic_orbit
        from hawksim.stability.floquet import floquet_analysis
        from hawksim.stability.report import floquet_json

        from hawksim.flight.orbit import shipped_orbit

        from hawksim.cli.progress import stage_for

        orbit = shipped_orbit(args.speed, args.aero) if kin is None and insect is None else None
        if orbit is None:
            with stage_for(args, "stability: solving the periodic orbit") as st:
                orbit = periodic_orbit(args.speed, args.aero, kinematics=kin, log=st.note, insect=insect,
                                       **({"forward_speed": args.forward_speed} if args.forward_speed else {}))
        if not orbit.converged:
            print(f"hawksim stability: the periodic orbit did not converge (residual {orbit.residual:.2e}); "
                  "the multipliers are of the nearest state found", file=sys.stderr)
        fl = floquet_analysis(linearize(orbit, map="monodromy"))
        if args.kinematics is not None:
            print(f"stability: {solved_note(orbit, args.kinematics)['note']}", file=sys.stderr)
        kin = orbit.kinematics
        args.trim_source = "the insect's periodic orbit (solved here)"
        # issue 20: the control derivatives (B matrices) beside the monodromy: the surrogate's and the UVLM's
        # shipped models (hawksim reproduce --only control_surrogate / control_uvlm) about the shipped orbit, else
        # differenced here (quasi-steady and surrogate: seconds; the UVLM's take minutes: none); in forward flight
        # (issue 51) the quasi-steady one-beat map about the forward orbit, as `fly --control lqr` designs on
        from hawksim.control.schedule import shipped_control_model

        desc = descriptor(args.aero)
        lin = source = None
        if desc.control_model_table is not None and args.kinematics is None and insect is None:
            lin = shipped_control_model(args.speed, args.aero)
            source = f"shipped: hawksim/insects/hawkmoth/data/{desc.control_model_table}"
        if lin is None and desc.linearize_cost == "seconds":
            lin, source = linearize(orbit, map="beat"), "differenced here (hawksim.control.derivatives.linearize)"
        control = None if lin is None else {**lin.to_json(), "source": source, **(
            {"forward_speed": args.forward_speed} if args.forward_speed else {})}
        chart = ("level heading axes (u, v horizontal; the averaged A's eigenvectors are in body-fixed stability "
                 "axes: u_b = u - w_e theta, v_b = v + w_e phi" + (", w_b = w + u_e theta)" if args.forward_speed
                                                                   else ")"))
        out_orbit = {"orbit": orbit_json(orbit, given=args.kinematics), "control_derivatives": control,
                     "floquet": {**floquet_json(fl), "chart": chart}}
        if control is None and args.forward_speed:
            out_orbit["control_derivatives_note"] = (
                f"null: the {args.aero} one-beat control derivatives take minutes per orbit and none is shipped about "
                "a forward orbit (docs/forward_flight.md)")
        if orbit.record is not None:  # a history network: the flight's modes are the augmented map's
            from hawksim.stability.report import history_floquet_json

            out_orbit["floquet"] = {**history_floquet_json(linearize(orbit, map="history")), "chart": chart}
            out_orbit["floquet_record_held"] = {
                **floquet_json(fl), "note": "the one-beat map with the network's record held at the orbit's (the "
                                            "body block of the augmented map): not the flight's dynamics"}
    elif kin is None and insect is not None:  # no shipped trim: the kinematics of its own periodic orbit
        from hawksim.cli.progress import stage_for
        from hawksim.flight.orbit import periodic_orbit

        with stage_for(args, "stability: solving the insect's periodic orbit") as st:
            orbit = periodic_orbit(args.speed, args.aero, log=st.note, insect=insect)
        if not orbit.converged:
            raise ValueError(f"--insect {insect.name}: its periodic orbit at {args.speed:g} m/s did not converge "
                             f"(residual {orbit.residual:.1e}): no kinematics to analyse")
        kin = orbit.kinematics
        args.trim_source = "the insect's periodic orbit (solved here)"
    elif kin is None and args.aero == "quasi-steady":
        kin = shipped_trim(args.speed, "quasi-steady").kinematics
    if not descriptor(args.aero).averaged_system:  # the per-step surrogate: Floquet only (no averaged A)
        if out_orbit is None:
            raise UsageError(f"--aero {args.aero}: only --floquet (the monodromy of the {args.aero}'s orbit); the "
                             "cycle-averaged A matrices are the UVLM's (--aero uvlm) or the quasi-steady model's")
        return {"speed": args.speed, "aero": args.aero, **out_orbit}
    if args.aero == "quasi-steady" or (args.workers == 1 and not args.scheduler):
        out = _averaged(args, kin)
    else:
        with dask_client(args.scheduler, args.workers) as client:
            out = _averaged(args, kin, client)
    start = {"start": args.kinematics_source} if args.forward_speed else {}  # given, or the shipped forward trim
    return {**out, **start, **(out_orbit or {})}


def solved_note(orbit, given) -> dict | None:
    """Where the orbit was solved from given kinematics: its f and phi0 are unknowns of the Newton solve
    (:func:`hawksim.flight.orbit.periodic_orbit`), so they move; the given and solved values (Hz, deg) and one line
    saying so (printed on stderr, kept in the JSON as ``orbit.kinematics_solved``). None without given kinematics."""
    if given is None:
        return None
    g, o = given.to_edge(), orbit.kinematics.to_edge()
    note = (f"the periodic orbit solves f and phi0 from the given kinematics (the other five kept): f {g['f']:.5g} -> "
            f"{o['f']:.5g} Hz, phi0 {g['phi0']:.4g} -> {o['phi0']:.4g} deg; the multipliers are of that orbit")
    return {"note": note, "f_given": g["f"], "f_solved": o["f"], "phi0_given_deg": g["phi0"],
            "phi0_solved_deg": o["phi0"]}


def orbit_json(orbit, given=None) -> dict:
    """The CLI contract's orbit keys (edge units: Hz, deg, deg/s, m/s); a history network's orbit also says how many
    calls its record holds and how much that record changes over the periodic beat (normalized); solved from
    ``given`` kinematics, ``kinematics_solved`` (:func:`solved_note`)."""
    s = orbit.initial_state
    deg = 180 / math.pi
    return {"speed": orbit.speed, "aero": orbit.aero, "kinematics": orbit.kinematics.to_edge(),
            "chi_deg": orbit.kinematics.chi * deg,
            "initial_state": {"u": s.u, "v": s.v, "w": s.w, "p_deg_s": s.p * deg, "q_deg_s": s.q * deg,
                              "r_deg_s": s.r * deg, "phi_deg": s.phi * deg, "theta_deg": s.theta * deg,
                              "psi_deg": s.psi * deg},
            "residual": orbit.residual, "residuals": list(map(float, orbit.residuals)),
            "mean_velocity": list(map(float, orbit.mean_velocity)), "mean_pitch_deg": orbit.mean_pitch * deg,
            "P_plus": orbit.P_plus, "iterations": orbit.iterations, "converged": orbit.converged,
            "floor": orbit.floor, "warm_beats": orbit.warm_beats, "wall_time_s": orbit.wall_time_s} | (
                {} if orbit.record is None else {"record_calls": int(len(orbit.record)),
                                                 "record_change": orbit.record_change}) | (
                {} if given is None else {"kinematics_solved": solved_note(orbit, given)}) | (
                {"forward_speed": orbit.forward_speed} if orbit.forward_speed else {})


def _preload(args) -> tuple[str, ...]:
    """The modules the command imports (hawksim.cli._preload): Dask's only where the UVLM runs go to workers."""
    names = ["hawksim.cluster", "hawksim.trim.tables", "hawksim.stability.report", "hawksim.stability.derivatives",
             "hawksim.stability.system"]
    if args.floquet:
        names += ["hawksim.flight.orbit", "hawksim.stability.floquet"]
    if args.aero == "uvlm" and (args.workers != 1 or args.scheduler):
        names.append("dask.distributed")
    return tuple(names)


def register(sub) -> None:
    p = sub.add_parser("stability", help="stability derivatives, A matrices and modes at the trim; --floquet: "
                                         "free-flight orbit and Floquet multipliers")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    add_forward_speed_arg(p, "; > 0: --aero quasi-steady or uvlm with --kinematics (axes and reference speed: "
                             "docs/forward_flight.md)")
    p.add_argument("--kinematics", type=parse_kinematics, help="use these kinematics instead of the trim table")
    p.add_argument("--aero", choices=names(having="orbits"), default="uvlm", help="aerodynamic model (default uvlm)")
    p.add_argument("--floquet", action="store_true",
                   help="solve the free body's periodic orbit and its monodromy matrix (Floquet multipliers); the "
                        "averaged A matrices are then those of the same model at the orbit's kinematics")
    p.add_argument("--workers", type=positive_int_arg("workers"), default=None,
                   help="single-threaded worker processes for the 14 UVLM runs (default: the machine's cores; "
                        "1: run them in this process)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler to run them on instead")
    p.add_argument("--insect", type=insect_arg, metavar="FILE",
                   help=INSECT_HELP + "; --aero quasi-steady only: the averaged system at the kinematics of its own "
                        "periodic orbit (solved here) unless --kinematics is given, its mass and inertia")
    p.add_argument("--no-progress", action="store_true")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_stability, preload=_preload)
