"""`hawksim fly --forward-speed U` / `--forward-profile`: the forward flight behind the command line (issue 51,
docs/forward_flight.md): its checks (UsageError, exit 2, one line) and the flight, open loop from the periodic orbit
at (U, V), under the per-beat LQR about that one orbit, or under the LQR on the forward-flight schedule."""

from __future__ import annotations

from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE as STEPS_PER_CYCLE
from hawksim.cli.args import UsageError, check_forward_condition


def on_schedule(args) -> bool:
    """Whether the flight flies the forward-flight schedule: ``--control lqr`` with the quasi-steady model and no
    ``--kinematics`` (set by :func:`check_forward_fly`)."""
    return args.control == "lqr" and not args.kinematics_given and args.aero == "quasi-steady"


def check_forward_fly(args) -> None:
    """UsageError (exit 2, one line) for a forward flight that cannot be had (:func:`hawksim.cli.args.
    check_forward_condition`). Two kinds fly: from the shipped forward trims (no ``--kinematics``), open loop from the
    periodic orbit at ``--forward-speed`` or under ``--control lqr`` on the forward-flight schedule (level flight,
    its orbits at :data:`hawksim.control.schedule.FORWARD_SCHEDULE_SPEEDS`: per beat or per half-stroke, with
    ``--forward-profile``, ``--gust`` and ``--sensing-delay``); from given ``--kinematics`` (or with ``--aero
    uvlm``), open loop or under the per-beat LQR about that one orbit (``--gust`` too). Not yet: the constrained LQR,
    a recording, the trim start, another step count, a UVLM forward schedule."""
    args.kinematics_given = args.kinematics is not None
    check_forward_condition(args)
    u = args.forward_speed
    profile = getattr(args, "forward_profile", None)
    asked = [f"--{k.replace('_', '-')}" for k in ("ascent_profile", "rrd") if getattr(args, k, None)]
    if args.control == "clqr":
        asked.append("--control clqr")
    if args.aero != "quasi-steady" and (profile or args.control_rate == "half-stroke"):
        asked.append(f"--aero {args.aero} with --forward-profile or --control-rate half-stroke (the forward-flight "
                     "schedule is quasi-steady; the UVLM flies the per-beat LQR about one orbit)")
    if asked or args.start == "trim" or args.steps_per_cycle != STEPS_PER_CYCLE:
        what = ", ".join(asked) or "--start trim or --steps-per-cycle"
        raise UsageError(f"--forward-speed {u:g} flies open loop or under --control lqr from the periodic orbit only "
                         f"(not yet with {what}; docs/forward_flight.md)")
    scheduled = [f"--{k.replace('_', '-')}" for k in ("forward_profile",) if getattr(args, k, None)]
    if args.control_rate == "half-stroke":
        scheduled.append("--control-rate half-stroke")
    if (scheduled or args.gust) and args.control is None:
        args.control = "lqr"
    if args.gust and args.control != "lqr":
        raise UsageError(f"--gust with --forward-speed flies under --control lqr only (got --control {args.control})")
    if args.sensing_delay is not None and args.control != "lqr":
        raise UsageError(f"--sensing-delay applies to a controlled flight only (--control lqr); this forward flight is "
                         f"open loop (--control {args.control or 'none'})")
    if scheduled and args.control != "lqr":
        raise UsageError(f"{scheduled[0]} with --forward-speed flies under --control lqr only (got --control "
                         f"{args.control})")
    if on_schedule(args):  # (a schedule option has set --control lqr or been refused above)
        from hawksim.control.schedule import FORWARD_SCHEDULE_SPEEDS

        grid = ", ".join(f"{v:g}" for v in FORWARD_SCHEDULE_SPEEDS)
        if args.speed != 0:
            raise UsageError(f"--speed {args.speed:g}: the forward-flight schedule is of level flight (--speed 0)")
        if u not in FORWARD_SCHEDULE_SPEEDS:
            raise UsageError(f"--forward-speed {u:g} under control starts on a schedule orbit ({grid} m/s)")
        bad = [v for v, _ in profile or [] if not (0.0 <= v <= FORWARD_SCHEDULE_SPEEDS[-1])]
        if bad:
            raise UsageError(f"--forward-profile speed {bad[0]:g} m/s: the forward-flight schedule covers "
                             f"0 to {FORWARD_SCHEDULE_SPEEDS[-1]:g} m/s")
    elif scheduled:
        raise UsageError(f"{scheduled[0]} flies the forward-flight schedule from the shipped trims: leave out "
                         "--kinematics (given kinematics fly the per-beat LQR about their one orbit)")


def fly_forward(args, progress) -> dict:
    """The forward flight, open loop or under control (:func:`check_forward_fly`): from the free body's periodic
    orbit at (``--forward-speed``, ``--speed``) solved from ``--kinematics`` (its f and phi0 solved,
    :func:`hawksim.flight.orbit.periodic_orbit`) or, under ``--control lqr`` without ``--kinematics``, from the
    forward-flight schedule's orbit (:class:`hawksim.control.schedule.Schedule` with ``axis="forward"``), flown
    (:func:`hawksim.flight.loop.fly`) with ``--perturb`` added to its launch state; the LQR's hold point moves
    forward at its speed reference."""
    import sys

    from hawksim.cli.fly_report import report
    from hawksim.cli.progress import stage_for
    from hawksim.control.controller import LQR
    from hawksim.control.schedule import Schedule
    from hawksim.flight.loop import fly
    from hawksim.flight.orbit import periodic_orbit
    from hawksim.flight.start import parse_perturbations
    from hawksim.insect.model import load_model

    perturb = parse_perturbations(dict(args.perturb or []))
    model = load_model(args.model) if args.model is not None else None
    u, profile = args.forward_speed, getattr(args, "forward_profile", None)
    delay = args.sensing_delay or 0
    scheduled = on_schedule(args)
    if scheduled:  # the forward-flight schedule over the speeds flown, its orbits solved and linearized here
        speeds = [u] + [v for v, _ in profile or []]
        with stage_for(args, "fly: solving and linearizing the forward-flight schedule's orbits") as st:
            schedule = Schedule(min(speeds), max(speeds), axis="forward", rate=args.control_rate or "beat",
                                delay=delay, model=model, log=st.note)
        controller = LQR(schedule, u, profile=profile)
        orbit = controller.point
    else:
        with stage_for(args, "fly: solving the forward-flight periodic orbit") as st:
            orbit = periodic_orbit(args.speed, args.aero, kinematics=args.kinematics, forward_speed=u,
                                   log=st.note, model=model)
        if not orbit.converged:
            raise FloatingPointError(f"the periodic orbit at {u:g} m/s forward did not converge "
                                     f"(residual {orbit.residual:.2e}); no flight")
        controller = None
        if args.control == "lqr":  # the per-beat LQR about this orbit (a one-point schedule, differenced here)
            with stage_for(args, "fly: linearizing the forward-flight orbit (the LQR's model)"):
                schedule = Schedule.of_orbit(orbit, delay=delay, model=model)
            controller = LQR(schedule, u)
    steps = None
    if progress is not None:
        def steps(k, n):
            progress(k * args.steps_per_cycle, n * args.steps_per_cycle)

    if controller is not None:
        result = fly(orbit, cycles=args.cycles, perturb=perturb, model=model, progress=steps, controller=controller,
                     sensing_delay=delay, gusts=args.gust or ())
    else:
        result = fly(orbit, cycles=args.cycles, perturb=perturb, model=model, progress=steps, keep_extras_every=0)
    out = result.summary()
    if controller is not None:
        out["control"] = {"mode": "lqr", "update_rate": schedule.rate, "delay_beats": delay, "axis": "forward",
                          "profile": [[v, n] for v, n in profile or []],
                          "gusts": [{"velocity": list(map(float, g.velocity)), "start": g.start, "beats": g.beats}
                                    for g in args.gust or ()],
                          "schedule": [p.to_json() for p in schedule.points]}
    o = orbit.kinematics.to_edge()
    if scheduled:
        note = (f"the forward-flight schedule's periodic orbit at {u:g} m/s (from the shipped forward trims; "
                f"{len(schedule.points)} orbits at {', '.join(f'{v:g}' for v in schedule.speeds)} m/s)")
    else:
        g = args.kinematics.to_edge()
        note = (f"periodic orbit of the free body solved from the {'given' if args.kinematics_given else 'shipped'} "
                f"kinematics ({orbit.iterations} Newton iterations, residual {orbit.residual:.1e}): f {g['f']:.4g} -> "
                f"{o['f']:.4g} Hz, phi0 {g['phi0']:.4g} -> {o['phi0']:.4g} deg")
    out["forward_speed"] = u
    out["start"] = {"from": "orbit", "source": result.trim_source, "note": note}
    if out["departed_at_beat"] is not None:
        b = out["beats"][out["departed_at_beat"] - 1]
        print(f"fly: departed at beat {out['departed_at_beat']} of {args.cycles} (horizontal speed "
              f"{b['horizontal_speed']:.3f} m/s, vertical {b['mean_vertical_speed']:.3f} m/s; pitch "
              f"{b['pitch_deg']:.1f} deg): "
              + ("the LQR did not hold it" if controller is not None else
                 "an open-loop flight of this unstable model leaves its periodic orbit"), file=sys.stderr)
    elif controller is not None:
        last = result.beat_log[-min(10, len(result.beat_log)):]
        print(f"fly: held under LQR control for {args.cycles} wingbeats forward ({schedule.rate}); last {len(last)} "
              f"beats: forward speed error <= {max(abs(b['speed_error']) for b in last):.4f} m/s, pitch error <= "
              f"{max(abs(b['pitch_error_deg']) for b in last):.2f} deg, roll <= "
              f"{max(abs(b['roll_deg']) for b in last):.2f} deg", file=sys.stderr)
    out["rrd"] = None
    return report(args, out, result, None, {"flight_s": result.wall_time_s, "orbit_s": orbit.wall_time_s,
                                            "recording_s": 0.0})
