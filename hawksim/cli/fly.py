"""`hawksim fly`: a free flight from the shipped trim of the chosen aerodynamic model (or given kinematics)."""

from __future__ import annotations

from hawksim.backends.registry import descriptor
from hawksim.backends.registry import names as backend_names
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE as STEPS_PER_CYCLE
from hawksim.backends.resolution import FLY_WAKE_CYCLES
from hawksim.backends.resolution import MIN_STEPS_PER_CYCLE
from hawksim.cli.args import (INSECT_HELP, KINEMATICS_HELP, MAX_FLY_STEPS, MAX_STEPS_PER_CYCLE, UsageError, cycles_arg,
                              add_forward_speed_arg, insect_arg,
                              parse_kinematics, perturbation_arg, positive_int_arg, speed_arg, wake_precision_arg,
                              writable_file)
from hawksim.cli.progress import NoStage, progress_for


MAX_WAKE_CYCLES = 100
"""Largest --wake-cycles (4000 wake rows at the fly lattice: ~1e10 pair evaluations a step by the direct sum)."""

START_CHOICES = ("orbit", "trim")
"""Where `hawksim fly` starts: the periodic orbit of the free body (the shipped one of the backend at that speed,
insects/hawkmoth/data/orbit_table_*.json; the quasi-steady one is solved at other speeds) or the held-body trim with one
calibration wingbeat (where no orbit is available, or on request)."""


def plan_start(speed: float, aero: str, kinematics=None, steps_per_cycle: int = STEPS_PER_CYCLE,
               start: str | None = None, insect=None):
    """Where an open-loop `hawksim fly` starts, decided before any work: (start, shipped orbit or None, why).

    start: 'orbit' (the free body's periodic orbit: the shipped one of ``aero`` at ``speed``, else solved here for
    the quasi-steady model and the surrogate) or 'trim' (the held-body trim, or the given kinematics, with one
    calibration wingbeat). why: None where the start is the one asked for or the default orbit; otherwise one line
    saying what the flight starts from instead of an orbit, and why (the CLI prints it on stderr and in the
    summary). ValueError / FloatingPointError for a start that cannot be had (``--start orbit`` without an orbit).
    ``insect``: another insect than the default (--insect) has no shipped orbit."""
    from hawksim.flight.orbit import shipped_orbit
    from hawksim.insect.folder import default_insect

    own = insect is None or insect == default_insect()
    shipped = shipped_orbit(speed, aero) if kinematics is None and own else None
    unconverged = shipped is not None and not shipped.converged
    if unconverged:
        if start == "orbit":
            raise FloatingPointError(f"the shipped {aero} orbit at {speed:g} m/s did not converge (residual "
                                     f"{shipped.residual:.2e}, the wake's beat-to-beat floor {shipped.floor:.2e}): "
                                     "fly with --start trim")
        shipped = None
    desc = descriptor(aero)
    solvable = desc.orbits_on_demand  # orbits solved in ~1 s (quasi-steady), ~10 s (surrogate)
    why = None
    if start is None:
        start = ("orbit" if steps_per_cycle == STEPS_PER_CYCLE and kinematics is None and (shipped or solvable)
                 else "trim")
        if start == "trim":
            what = ("the given kinematics (--kinematics)" if kinematics is not None
                    else f"the held-body trim of {aero} at {speed:g} m/s")
            if kinematics is not None:
                reason = ("an orbit would change their f and phi0; --start orbit solves one from them"
                          if solvable and steps_per_cycle == STEPS_PER_CYCLE else
                          "no periodic orbit is shipped for given kinematics")
            elif steps_per_cycle != STEPS_PER_CYCLE:
                reason = (f"--steps-per-cycle {steps_per_cycle} has no periodic orbit (orbits are solved at "
                          f"{STEPS_PER_CYCLE} steps per wingbeat)")
            elif unconverged:
                reason = f"the shipped {aero} orbit at {speed:g} m/s did not converge"
            elif not desc.orbits:
                reason = desc.orbits.why_not
            elif not own:
                reason = (f"no {aero} periodic orbit is shipped for the insect {insect.name!r} and solving one takes "
                          "minutes")
            else:
                reason = f"no {aero} periodic orbit is shipped at {speed:g} m/s and solving one takes minutes"
            why = (f"starting from {what} with one calibration wingbeat, not from a periodic orbit of the free body "
                   f"({reason}); such a start is not an equilibrium, so an open-loop flight leaves it within a few "
                   "beats")
    if start not in START_CHOICES:
        raise ValueError(f"--start {start!r}: choose {', '.join(START_CHOICES)}")
    if start == "orbit" and (steps_per_cycle != STEPS_PER_CYCLE or not (shipped or solvable)):
        raise ValueError(f"--start orbit: no {aero} orbit at {speed:g} m/s and {steps_per_cycle} steps per cycle "
                         f"(orbits are solved at {STEPS_PER_CYCLE}; `hawksim trim --free-flight --aero {aero}` "
                         "solves one)")
    if start == "orbit" and kinematics is not None:
        why = ("solving the periodic orbit of the free body from the given kinematics (--start orbit): its f and "
               "phi0 are solved, the other five parameters kept")
    return start, shipped, why


def fly_named(speed: float, cycles: int, aero: str = "quasi-steady", *, kinematics=None, perturb=None,
              model_path=None, steps_per_cycle: int = STEPS_PER_CYCLE, keep_extras_every: int = 0,
              start: str | None = None, log=None, wake_cycles: int | None = None, wake_summation: str = "auto",
              wake_precision: str = "float64", note=None, stage=None, insect=None, **kw):
    """`hawksim fly`'s flight: from the free body's periodic orbit (``start='orbit'``, the default where one is
    available: no given kinematics, the orbit solver's 200 steps per beat, and a shipped orbit of ``aero`` at
    ``speed`` or the quasi-steady backend or the surrogate, whose orbits are solved in seconds) or from the shipped
    held-body trim of ``aero`` at ``speed`` (or ``kinematics``) with a calibration beat (``start='trim'``), with the
    backend of that name, then :func:`hawksim.flight.fly.fly` (:func:`plan_start` decides). wake_cycles: wingbeats of
    UVLM wake kept (default :data:`hawksim.backends.resolution.FLY_WAKE_CYCLES`); wake_summation, wake_precision:
    the UVLM's (:func:`hawksim.backends.flight_backend`). ``note``: called with :func:`plan_start`'s line (what the
    flight starts from when that is not the default orbit) once the inputs are checked, before the work; ``stage``:
    a factory of progress stages (:func:`hawksim.cli.progress.stage_for`'s signature without args) for the orbit
    solve; ``log``: also gets the orbit solver's lines. ``insect``: the insect flown (default the hawkmoth,
    :class:`hawksim.insect.insect.Insect`): its MJCF unless ``model_path`` is given, its wings in the backend, its own
    orbit (never the shipped ones; the held-body trim, if the start is one, is the default insect's)."""
    from hawksim.backends import flight_backend
    from hawksim.flight.fly import fly
    from hawksim.flight.start import is_lateral, parse_perturbations
    from hawksim.insect.model import load_model
    from hawksim.trim.point import Trim
    from hawksim.trim.tables import shipped_trim

    perturb = parse_perturbations(perturb or {})
    from hawksim.flight.orbit import periodic_orbit

    start, shipped, why = plan_start(speed, aero, kinematics, steps_per_cycle, start, insect)
    model = load_model(model_path) if model_path is not None or insect is None else load_model(morph=insect.morphology)
    morphology = None if insect is None else insect.morphology
    if why is not None and note is not None:
        note(why)
    stage = stage or NoStage
    start_state = None
    if start == "orbit":
        if shipped is not None:
            orbit = shipped
        else:
            with stage("fly: solving the periodic orbit") as st:
                def lines(m):
                    st.note(m)
                    if log is not None:
                        log(m)

                orbit = periodic_orbit(speed, aero, kinematics=kinematics, log=lines, model=model, insect=insect)
        if not orbit.converged:
            raise FloatingPointError(f"the periodic orbit at {speed:g} m/s did not converge "
                                     f"(residual {orbit.residual:.2e}); fly with --start trim")
        given = ""
        if kinematics is not None:
            given = (f"; f {kinematics.f:.4g} -> {orbit.kinematics.f:.4g} Hz, phi0 {kinematics.to_edge()['phi0']:.4g} "
                     f"-> {orbit.kinematics.to_edge()['phi0']:.4g} deg")
        trim = Trim(float(speed), orbit.kinematics, model=aero, source=(
            f"{'shipped ' if shipped is not None else ''}periodic orbit of the free body ({orbit.iterations} Newton "
            f"iterations, residual {orbit.residual:.1e}) from the "
            f"{'given kinematics' if kinematics is not None else 'held-body trim'}{given}"))
        start_state = (orbit.launch_state.as_array(), orbit.chi_ref)
    else:
        trim = (Trim(float(speed), kinematics, model=aero, source="given kinematics, one calibration wingbeat")
                if kinematics is not None else shipped_trim(speed, aero))
    backend = flight_backend(aero, kinematics=trim.kinematics, symmetric=not is_lateral(perturb),
                             keep_panels=keep_extras_every > 0, wake_summation=wake_summation,
                             wake_precision=wake_precision, morphology=morphology,
                             **({} if wake_cycles is None else {"wake_cycles": wake_cycles}))
    if start_state is not None:
        orbit.seed(backend)  # the flight starts with the orbit's record (a history network's) and far wake (UVLM)
    return fly(trim, backend, cycles, perturb=perturb, model=model, steps_per_cycle=steps_per_cycle,
               keep_extras_every=keep_extras_every, start_state=start_state, insect=insect, **kw)


def cmd_fly(args) -> dict:
    forward = bool(args.forward_speed or getattr(args, "forward_profile", None))
    if forward:
        from hawksim.cli.fly_forward import check_forward_fly

        check_forward_fly(args)
    if args.json_full:
        args.json = True
    if args.cycles * args.steps_per_cycle > MAX_FLY_STEPS:
        raise UsageError(f"--cycles {args.cycles} x --steps-per-cycle {args.steps_per_cycle} exceeds the limit of "
                         f"{MAX_FLY_STEPS:g} steps (the recorded series would not fit in memory)")
    names = [k for k, _ in args.perturb or []]
    twice = sorted({k for k in names if names.count(k) > 1})
    if twice:
        raise UsageError(f"--perturb gives {', '.join(twice)} more than once")
    for opt in ("wake_cycles", "wake_precision"):
        if getattr(args, opt, None) is not None and opt not in descriptor(args.aero).flight_options:
            raise UsageError(f"--{opt.replace('_', '-')} applies to --aero "
                             f"{' or '.join(n for n in backend_names() if opt in descriptor(n).flight_options)} only")
    if getattr(args, "insect", None) is not None and getattr(args, "control", None) is None:
        args.control = "none"  # another insect flies open loop unless asked (its orbits are solved, not shipped)
    # issue 20: --control lqr (default for quasi-steady from the orbit), --gust; forward flight: open loop
    control = None if forward else _control_of(args)
    if getattr(args, "insect", None) is not None and control is not None:
        if control == "clqr" or descriptor(args.aero).shipped_orbits_only:
            raise UsageError(f"--insect under control takes --control lqr with --aero {_insect_control()} (its own "
                             f"orbits and gains are solved here; got --control {control} --aero {args.aero})")
    for opt in ("wake_cycles", "wake_precision"):
        if control is not None and getattr(args, opt, None) is not None:
            raise UsageError(f"--{opt.replace('_', '-')} applies to open-loop flights only (no --control, --gust or "
                             "--ascent-profile)")
    if args.sensing_delay is not None and control in (None, "none"):  # issue 53, defect 14: it was ignored
        raise UsageError(f"--sensing-delay applies to a controlled flight only (--control lqr or clqr); this flight is "
                         f"open loop (--control {control or 'none'})")
    progress = progress_for(args, "fly") if control is None else progress_for(args, "fly", "beat")
    guard = None
    if args.rrd:  # Ctrl-C / SIGTERM: write the recording of the steps flown (hawksim.flight.recording.InterruptGuard)
        from hawksim.flight.recording import InterruptGuard

        guard = InterruptGuard().__enter__()
        progress = guard.progress(progress)
    try:
        if forward:
            from hawksim.cli.fly_forward import fly_forward

            out = fly_forward(args, progress)
        else:
            out = _fly_controlled(args, control, progress, guard) if control is not None else _fly_open_loop(
                args, progress, guard)
        if getattr(args, "insect", None) is not None:  # another insect than the default: say which
            out["insect"] = args.insect.name
        return out
    finally:
        if guard is not None:
            guard.__exit__(None, None, None)


def _note(text: str) -> None:
    import sys

    from hawksim.cli.progress import close_all

    close_all()  # a stage's bar ends its line first, on a terminal
    print(f"fly: {text}", file=sys.stderr)


def _fly_open_loop(args, progress, guard) -> dict:
    import sys
    import time

    from hawksim.cli.fly_report import report
    from hawksim.cli.progress import stage_for

    notes = []

    def note(text):
        notes.append(text)
        _note(text)

    result = fly_named(args.speed, args.cycles, args.aero, perturb=dict(args.perturb or []), model_path=args.model,
                       insect=getattr(args, "insect", None),
                       kinematics=args.kinematics, steps_per_cycle=args.steps_per_cycle,
                       # the UVLM's panels and wake at every UVLM update (every aero_every steps)
                       keep_extras_every=(descriptor(args.aero).update_interval(args.steps_per_cycle)
                                          if args.rrd and "keep_panels" in descriptor(args.aero).flight_options
                                          else 0),
                       progress=progress, start=args.start, wake_cycles=getattr(args, "wake_cycles", None),
                       wake_precision=getattr(args, "wake_precision", None) or "float64", note=note,
                       stage=lambda desc: stage_for(args, desc),
                       **({"partial_on_interrupt": True} if args.rrd else {}))
    interrupted = len(result.t) < args.cycles * args.steps_per_cycle or (guard and guard.signum is not None)
    t_rec = time.perf_counter()
    rrd = _write_recording(args, result, guard, interrupted) if args.rrd else None  # first: a failure says one line
    times = {"flight_s": result.wall_time_s, "recording_s": time.perf_counter() - t_rec if args.rrd else 0.0}
    out = result.summary()
    start = "orbit" if "periodic orbit" in result.trim_source else "trim"
    out["start"] = {"from": start, "source": result.trim_source, "note": notes[0] if notes else None}
    if out["departed_at_beat"] is not None:
        b = out["beats"][out["departed_at_beat"] - 1]
        left = ("its periodic orbit" if start == "orbit" else
                "its start (given kinematics, not an orbit)" if args.kinematics is not None else
                "its start (the held-body trim, not an orbit)")
        print(f"fly: departed at beat {out['departed_at_beat']} of {args.cycles} (mean vertical speed "
              f"{b['mean_vertical_speed']:.3f} m/s against {args.speed:g}; pitch {b['pitch_deg']:.1f} deg): "
              f"an open-loop flight of this unstable model leaves {left}", file=sys.stderr)
    out["rrd"] = rrd
    return report(args, out, result, None, times)


def _fly_controlled(args, control: str, progress, guard) -> dict:
    """The closed-loop flight of hawksim.control (--control lqr, or a gust / profile open loop); with --rrd an
    interrupt writes the beats flown (exit 130), as the open-loop flight does. The controller's start-up (orbits,
    maps, gains: seconds the first time) shows as a stage until the first beat."""
    import time

    from hawksim.cli.fly_report import report
    from hawksim.cli.progress import stage_for
    from hawksim.control.command import command_summary, fly_command
    from hawksim.control.schedule import default_rate

    rate = getattr(args, "control_rate", None) or ("beat" if control == "clqr" else default_rate(args.aero))
    t0 = time.perf_counter()
    startup = {}
    with stage_for(args, "fly: controller start-up") as st:
        def first(k, n):  # the start-up ends at the first beat's progress call
            if "s" not in startup:
                startup["s"] = time.perf_counter() - t0
                st.close()
            if progress is not None:
                progress(k, n)

        cl = fly_command(args.speed, args.cycles, control=control, profile=getattr(args, "ascent_profile", None),
                         gusts=getattr(args, "gust", None) or [], delay=args.sensing_delay or 0,
                         perturb=dict(args.perturb or []), model_path=args.model, progress=first,
                         partial_on_interrupt=bool(args.rrd), aero=args.aero, rate=rate, log=st.note,
                         insect=getattr(args, "insect", None))
    flight_s = time.perf_counter() - t0
    interrupted = len(cl.result.t) < args.cycles * args.steps_per_cycle or (guard and guard.signum is not None)
    t_rec = time.perf_counter()
    rrd = (_write_recording(args, cl.result, guard, interrupted, control=cl.beats, ghost=False)
           if args.rrd else None)  # first: a failure (disk full) says one line, not a verdict and then the error
    times = {"controller_start_up_s": startup.get("s", flight_s), "flight_s": flight_s - startup.get("s", flight_s),
             "recording_s": time.perf_counter() - t_rec if args.rrd else 0.0}
    out = command_summary(cl, args.cycles, control, args.aero, rate)
    out["start"] = {"from": "orbit", "source": _controlled_start(out, args), "note": None}
    out["rrd"] = rrd
    return report(args, out, cl.result, cl, times)


def _controlled_start(out: dict, args) -> str:
    """What a controlled flight starts from, in words: the schedule's orbit at the start speed (shipped for the UVLM
    and the surrogate, solved in this process for the quasi-steady model), or the reference interpolated between two
    of them."""
    pts = out["control"]["schedule"]
    how = "shipped" if descriptor(args.aero).shipped_orbits_only else "solved here"
    exact = [p for p in pts if abs(p["speed"] - args.speed) < 1e-9]
    if exact:
        p = exact[0]
        return (f"the periodic orbit of the free body at {p['speed']:g} m/s ({how}; residual {p['orbit_residual']:.1e})"
                f", {out['control']['mode']} control")
    near = sorted(p["speed"] for p in sorted(pts, key=lambda p: abs(p["speed"] - args.speed))[:2])
    return (f"the reference interpolated between the periodic orbits at "
            f"{' and '.join(f'{v:g}' for v in near)} m/s ({how}), "
            f"{out['control']['mode']} control")


def _write_recording(args, result, guard, interrupted: bool, *, control=None, ghost: bool = True) -> str:
    """`--rrd`: the recording (with the linear prediction's ghost for a perturbed open-loop quasi-steady flight from
    its orbit; ``control``: the per-beat commands of a controlled flight); after an interrupt (Ctrl-C, SIGTERM) the
    steps flown, then KeyboardInterrupt saying so (exit 130, that one line)."""
    import sys

    from hawksim.flight.recording import write_rrd
    from hawksim.stability.prediction import NoPrediction, predict_cli_flight

    prediction = None
    if ghost and args.perturb and not interrupted:
        try:
            from hawksim.insect.model import load_model

            prediction = predict_cli_flight(result, dict(args.perturb), speed=args.speed, aero=args.aero,
                                            kinematics=args.kinematics, model=load_model(args.model))
        except NoPrediction as exc:
            print(f"fly: no ghost in the recording: {exc}", file=sys.stderr)
        except KeyboardInterrupt:
            interrupted = True
            print("fly: interrupted while computing the linear prediction; recording without the ghost",
                  file=sys.stderr)
    from hawksim.cli.progress import stage_for

    with guard.deferred(), stage_for(args, f"fly: writing the recording {args.rrd}"):
        path = str(write_rrd(args.rrd, result, prediction=prediction, control=control))
    if interrupted or guard.signum is not None:  # the CLI's one line (exit 130) says where and what was saved
        n = len(result.t)
        raise KeyboardInterrupt(f"interrupted at step {n} of {args.cycles * args.steps_per_cycle} (t = "
                                f"{result.t[-1]:.5f} s); {path} holds steps 0 to {n - 1}")
    return path


def _insect_control() -> str:
    """The backends that control another insect than the default: those whose schedule solves its orbits."""
    return " or ".join(n for n in backend_names() if descriptor(n).control and not descriptor(n).shipped_orbits_only)


def _control_of(args) -> str | None:
    """The control mode of the closed-loop flight of hawksim.control when --control lqr applies (or a gust or an
    ascent profile is asked), else None (the open-loop flight of :func:`fly_named`); ValueError (exit 2) when
    control is asked where it does not apply."""
    from hawksim.control.command import default_control

    control = getattr(args, "control", None) or default_control(args.aero, args.kinematics, args.steps_per_cycle,
                                                                args.start, STEPS_PER_CYCLE)
    profile, gusts = getattr(args, "ascent_profile", None), getattr(args, "gust", None) or []
    rate = getattr(args, "control_rate", None)
    if control == "none" and not profile and not gusts:
        if rate is not None:
            raise ValueError(f"--control-rate {rate} needs --control lqr")
        return None
    desc = descriptor(args.aero)
    if not desc.control or args.kinematics is not None \
            or args.steps_per_cycle != STEPS_PER_CYCLE or args.start == "trim":
        raise ValueError(f"--control {control} / --gust / --ascent-profile need --aero {_either('control')} "
                         f"from the orbit (no --kinematics, --start trim or --steps-per-cycle other than "
                         f"{STEPS_PER_CYCLE})")
    if control == "clqr" and (not desc.constrained_control or rate == "half-stroke"):
        raise ValueError(f"--control clqr needs --aero {_either('constrained_control')} and --control-rate beat (its "
                         "plans use per-wing derivatives differenced from a settable orbit state, once per wingbeat)")
    if not desc.half_stroke and rate == "half-stroke":
        raise ValueError(f"--control-rate half-stroke needs --aero {_either('half_stroke')} "
                         f"({desc.half_stroke.why_not})")
    if control == "none" and profile:
        raise ValueError("--ascent-profile needs --control lqr (an open-loop flight cannot follow it)")
    return control


def _either(feature: str) -> str:
    """The --aero names whose descriptor supports ``feature``, as "a, b or c"."""
    n = backend_names(having=feature)
    return n[0] if len(n) == 1 else f"{', '.join(n[:-1])} or {n[-1]}"


def _control_type(parse):
    import argparse

    def f(text):
        try:
            return parse(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return f


MAX_SENSING_DELAY = 20
"""Largest --sensing-delay [wingbeats]: the LQR's state is augmented by the 4 to 7 commands of each beat of delay
and its Riccati solve costs the cube of that size (20 beats: ~150 states; 10**9 asked numpy for an array "too big"),
and 20 beats (0.8 s at 25 Hz) is ten times the hawkmoth's visual latency, past any delay a controller is designed
for."""


def _delay(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise ValueError(f"--sensing-delay {text!r} is not an integer") from None
    if v < 0:
        raise ValueError(f"--sensing-delay {text} must be >= 0 wingbeats")
    if v > MAX_SENSING_DELAY:
        raise ValueError(f"--sensing-delay {text} exceeds the limit of {MAX_SENSING_DELAY} wingbeats (the "
                         "controller's state grows with the delay)")
    return v


def register(sub) -> None:
    f = sub.add_parser("fly", help="fly the insect from its trim at an ascent speed (MuJoCo, 6-DOF)")
    f.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 (hover) to 2")
    add_forward_speed_arg(f, "; > 0: open loop from the free body's periodic orbit solved from --kinematics "
                             "(--aero quasi-steady or uvlm)")
    f.add_argument("--cycles", type=cycles_arg, required=True, help="number of wingbeats N")
    f.add_argument("--aero", choices=backend_names(), default="quasi-steady",
                   help="aerodynamic model (default quasi-steady): uvlm, the extended UVLM in the loop; surrogate, the "
                        "per-step neural surrogate of the UVLM (each wing's instantaneous loads from the kinematics, "
                        "phase and body motion); surrogate-mean, the cycle-mean network's averaged L+, D+, M+ (no "
                        "within-beat loads, no damping)")
    f.add_argument("--rrd", type=writable_file, help="write a Rerun recording to FILE")
    f.add_argument("--perturb", type=perturbation_arg, action="append", metavar="NAME=VALUE",
                   help="initial disturbance: u, v, w [m/s]; p, q, r [deg/s]; theta, phi [deg] (stability axes)")
    f.add_argument("--kinematics", type=parse_kinematics, help="override the trim: " + KINEMATICS_HELP)
    f.add_argument("--model", help="MJCF file (default: the model generated from the insect's morphology; its total "
                                   "mass must be the insect's)")
    f.add_argument("--insect", type=insect_arg, metavar="FILE",
                   help=INSECT_HELP + " (open loop by default; --control lqr with --aero quasi-steady: its own orbits "
                        "and gains, solved here)")
    f.add_argument("--steps-per-cycle", type=positive_int_arg("steps-per-cycle", MAX_STEPS_PER_CYCLE),
                   default=STEPS_PER_CYCLE,
                   help=f"integration steps per wingbeat ({STEPS_PER_CYCLE}; at least {MIN_STEPS_PER_CYCLE})")
    f.add_argument("--wake-cycles", type=positive_int_arg("wake-cycles", MAX_WAKE_CYCLES), default=None,
                   help=f"--aero uvlm, open loop: wingbeats of free wake kept (default {FLY_WAKE_CYCLES}; its cost "
                        "grows with its length squared: docs/performance.md, 'Treecode')")
    f.add_argument("--wake-precision", type=wake_precision_arg, default=None,
                   help="--aero uvlm, open loop: the wake-on-wake pair evaluations (default float64; mixed: float32 "
                        "pair evaluations summed in float64, opt-in: docs/uvlm.md, 'Speed')")
    f.add_argument("--start", choices=START_CHOICES, default=None,
                   help="orbit: the free body's periodic orbit (the default where there is one: quasi-steady and "
                        "surrogate at any speed, the shipped UVLM orbits); trim: the held-body trim with a "
                        "calibration wingbeat (the default otherwise, and for surrogate-mean)")
    from hawksim.control.command import CONTROL_CHOICES, parse_forward_profile, parse_gust, parse_profile

    f.add_argument("--control", choices=CONTROL_CHOICES, default=None,
                   help="lqr: the wingbeat-to-wingbeat LQR (default for quasi-steady from the orbit; with --aero uvlm "
                        "at 1, 1.5 or 2 m/s, the shipped UVLM orbits, scheduled over 1-2 m/s; with --aero surrogate "
                        "over 0-2 m/s from its shipped orbits); clqr: the same cost minimised over 10 beats within "
                        "Table 2 (the constrained LQR, per beat, quasi-steady or surrogate; docs/control.md); none: "
                        "open loop (default otherwise)")
    from hawksim.control.schedule import RATES

    f.add_argument("--control-rate", choices=RATES, default=None,
                   help="update the kinematics once per wingbeat (beat) or per half-stroke (at phases 0 and 0.5; "
                        "quasi-steady and surrogate; docs/control.md compares them); default: half-stroke for "
                        "--aero surrogate, beat otherwise")
    f.add_argument("--ascent-profile", type=_control_type(parse_profile), metavar="V:BEATS,...",
                   help="piecewise-constant speed commands [m/s] for that many wingbeats each, e.g. 0:2,1:10,2:10 "
                        "(the last speed holds after it)")
    f.add_argument("--forward-profile", type=_control_type(parse_forward_profile), metavar="U:BEATS,...",
                   help="piecewise-constant forward-speed commands [m/s] in level flight (--speed 0), that many "
                        "wingbeats each, e.g. 1:40,4:120,0:120: the LQR on the forward-flight schedule (0-4 m/s, "
                        "quasi-steady) from --forward-speed (default 0, hover)")
    f.add_argument("--gust", type=_control_type(parse_gust), action="append", metavar="VX,VY,VZ@START:BEATS",
                   help="uniform air-velocity pulse [m/s], world frame (z up, y left), over wingbeats START.. "
                        "START+BEATS-1 (from 1), e.g. 0,0.5,0@5:2")
    f.add_argument("--sensing-delay", type=_control_type(_delay),
                   metavar="BEATS", help="the controller senses the state this many wingbeats late (default 0; "
                                         "--control lqr or clqr only)")
    f.add_argument("--out", type=writable_file, metavar="FILE",
                   help="save the whole flight to FILE (numpy .npz, read without hawksim: per-step arrays, the "
                        "per-beat table, units and the command in its metadata; docs/output.md)")
    f.add_argument("--no-progress", action="store_true", help="no progress bar")
    f.add_argument("--json", action="store_true",
                   help="print one compact JSON object on stdout (docs/output.md lists its keys)")
    f.add_argument("--json-full", action="store_true",
                   help="like --json, with the controller's gains, every closed-loop multiplier of its (augmented) "
                        "states and each beat's end state and half-stroke commands")
    f.set_defaults(func=cmd_fly)
