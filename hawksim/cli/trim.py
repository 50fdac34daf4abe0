"""`hawksim trim`: minimum-power trim on the surrogate (GA + Nelder-Mead), optionally checked by the UVLM; with
``--aero quasi-steady`` the same search on the quasi-steady model itself (any ``--forward-speed``); with ``--aero
uvlm`` the UVLM's local minimum-power trim from the shipped quasi-steady forward trim (or ``--kinematics``); with
``--free-flight`` the free body's periodic orbit (at ``--forward-speed`` from the shipped forward trim or
``--kinematics``)."""

from __future__ import annotations

import math

from hawksim.cli.args import (MAX_POPULATION, add_forward_speed_arg, add_insect_arg, add_resolution_args,
                              parse_kinematics, positive_int_arg, seed_arg, speed_arg)
from hawksim.cli.predict import add_network_args, network_choice
from hawksim.cli.progress import progress_for
from hawksim.backends.registry import descriptor, names
from hawksim.cli.trim_report import render_trim

DEFAULT_POPULATION = 100_000
"""The GA population when --population is not given: the paper's 1e5."""


def cmd_free_flight(args) -> dict:
    """The periodic orbit of the free body (:func:`hawksim.flight.orbit.periodic_orbit`)."""
    import sys

    from hawksim.cli.stability import orbit_json
    from hawksim.flight.orbit import periodic_orbit

    from hawksim.cli.args import check_forward_condition

    if args.forward_speed:  # forward flight (issue 51): from the shipped forward trim at U, or --kinematics
        check_forward_condition(args)
    log = None if args.no_progress else (lambda m: print(f"orbit: {m}", file=sys.stderr))
    orbit = periodic_orbit(args.speed, args.aero or "uvlm", kinematics=args.kinematics, log=log,
                           insect=getattr(args, "insect", None),
                           **({"forward_speed": args.forward_speed} if args.forward_speed else {}))
    tol = descriptor(orbit.aero).orbit_tolerance
    tol_text = (f"{tol.residual:g} (normalized)" if tol.velocity is None
                else f"{tol.velocity:g} m/s and {tol.rate:g} rad/s")
    if not orbit.converged:  # reported, not raised (exit 0, as in vertical flight): the nearest state found
        print(f"hawksim trim: the periodic orbit did not converge (residual {orbit.residual:.2e}, tolerance "
              f"{tol_text}, {orbit.iterations} iterations): 'converged' is false", file=sys.stderr)
    out = orbit_json(orbit, given=args.kinematics) | {"tolerance": tol_text}
    if getattr(args, "kinematics_source", None):
        out["start"] = args.kinematics_source
    return out


MODEL_SEARCH = ("quasi-steady",)
"""The models ``--aero`` searches on without ``--free-flight`` by the population search
(:func:`hawksim.trim.model_search.trim_on_model`; a UVLM population search would take hours per condition)."""

LOCAL_SEARCH = ("uvlm",)
"""The models ``--aero`` trims on without ``--free-flight`` by the local search from a start
(:func:`hawksim.trim.model_search.refine_on_model`)."""

MAX_EVALS = 10_000
"""Largest ``--max-evals`` (days of UVLM runs)."""

UVLM_ONLY = ("max_evals", "n_chord", "n_span", "steps_per_cycle", "cycles")
"""Options of ``--aero uvlm``'s local trim alone."""

NETWORK_ONLY = ("model", "network", "verify", "balance")
"""Options of the surrogate trim that a search on a model (``--aero`` without ``--free-flight``) does not use."""

SURROGATE_ONLY = ("model", "network", "seed", "population", "verify", "balance")
"""Options of the surrogate trim alone: ``--free-flight`` solves the free body's periodic orbit with ``--aero``'s
model (Newton shooting, no network, no GA, no random draw), so each of these given with it is refused (exit 2)
rather than silently ignored (issue 53, defect 14); ``--aero`` without ``--free-flight`` likewise."""


def _refuse_ignored(args) -> None:
    """UsageError naming the first option given that the chosen trim does not use."""
    from hawksim.cli.args import UsageError

    for name in UVLM_ONLY:
        if getattr(args, name, None) is not None and (args.free_flight or args.aero not in LOCAL_SEARCH):
            raise UsageError(f"--{name.replace('_', '-')} applies to --aero {' or '.join(LOCAL_SEARCH)} without "
                             "--free-flight only (the UVLM's local trim search)")
    if args.kinematics is not None and not args.free_flight and args.aero not in LOCAL_SEARCH:
        raise UsageError("--kinematics applies to --free-flight (the orbit's start) or --aero "
                         f"{' or '.join(LOCAL_SEARCH)} (the local search's start) only")
    if args.free_flight:
        for name in SURROGATE_ONLY:
            if getattr(args, name, None) not in (None, False):
                raise UsageError(f"--{name} does not apply to --free-flight: the free body's periodic orbit uses "
                                 "--aero's model, no surrogate network and no GA")
    elif args.aero is not None:
        if args.aero not in MODEL_SEARCH + LOCAL_SEARCH:
            raise UsageError(f"--aero {args.aero} does not apply without --free-flight: the trim searches on the "
                             f"surrogate network (no --aero) or on the {', '.join(MODEL_SEARCH + LOCAL_SEARCH)} "
                             "model")
        if args.aero in LOCAL_SEARCH and getattr(args, "insect", None) is not None:
            raise UsageError(f"--insect with --aero {args.aero}: not yet (its start is the default hawkmoth's "
                             "shipped forward trim)")
        if args.aero in LOCAL_SEARCH and args.population is not None:
            raise UsageError(f"--population does not apply to --aero {args.aero}: a local search (--max-evals), "
                             "no GA")
        for name in NETWORK_ONLY:
            if getattr(args, name, None) not in (None, False):
                raise UsageError(f"--{name} does not apply to --aero {args.aero}: the search runs on that model "
                                 "and balances on it")
    elif args.forward_speed:
        raise UsageError(f"--forward-speed {args.forward_speed:g} needs --aero quasi-steady or uvlm (or "
                         "--free-flight): the surrogate network covers vertical flight only")
    elif getattr(args, "insect", None) is not None:
        for name in ("verify", "balance"):
            if getattr(args, name, False):
                raise UsageError(f"--{name} does not apply with --insect: the UVLM check and balance search Table 2 "
                                 "with the default hawkmoth's P0")


def cmd_trim(args) -> dict:
    _refuse_ignored(args)
    if args.free_flight:
        return cmd_free_flight(args)
    if args.aero in LOCAL_SEARCH:
        return cmd_local_trim(args)
    if args.aero is not None:
        return cmd_model_trim(args)
    path, network = network_choice(args)
    args.population = args.population or DEFAULT_POPULATION
    args.seed = 0 if args.seed is None else args.seed
    from dataclasses import replace

    from hawksim.backends.network import load_for_speed
    from hawksim.trim.search import GAConfig, trim_on_surrogate

    sur = load_for_speed(path, args.speed, network)
    cfg = replace(GAConfig(), population=args.population)
    bar = progress_for(args, "trim (GA)", "gen")
    progress = None if bar is None else (lambda g, n, best: bar(g, n, best=f"{best:.6f}"))
    insect = getattr(args, "insect", None)
    r = trim_on_surrogate(sur, args.speed, seed=args.seed, cfg=cfg, progress=progress, insect=insect)
    if bar is not None:
        bar.close()
    out = {"kinematics": r.kinematics.to_edge(), "chi": math.degrees(r.kinematics.chi), **r.outputs,
           "fitness": r.fitness, "speed": args.speed, "seed": args.seed, "generations": r.search.generations,
           "nm_evaluations": r.evaluations, "wall_time_s": r.wall_time_s,
           "model": sur.meta.get("command", args.model or args.network)} | (
               {} if insect is None else {"insect": insect.name,
                                          "bounds_deg": {k: list(v) for k, v in insect.bounds_deg.items()}})
    if args.verify:
        from hawksim.backends.held import run
        from hawksim.backends.resolution import DEFAULT
        from hawksim.surrogate.dataset import held_status

        run_ = run(r.kinematics, args.speed, DEFAULT, insect=insect)  # its weight and P0, as the trim
        a = run_.averages
        status, peak = held_status(run_, DEFAULT.average_cycles)  # 'diverged': the UVLM's check is not a result
        out["uvlm"] = {"L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus,
                       "power_W": a.power_W, "status": status, "peak_force_coefficient": peak,
                       "resolution": DEFAULT.to_dict()}
    if args.balance:
        from hawksim.trim.balance import balance_on_uvlm

        b = balance_on_uvlm(r.kinematics, args.speed, insect=insect)  # in its bounds, P+ in its P0
        av = b.averages
        out["uvlm_balanced"] = {"kinematics": b.kinematics.to_edge(), "chi": math.degrees(b.kinematics.chi),
                                "L_plus": av.L_plus, "D_plus": av.D_plus, "M_plus": av.M_plus, "P_plus": av.P_plus,
                                "converged": b.converged, "evaluations": b.evaluations}
    return out


def cmd_model_trim(args) -> dict:
    """The minimum-power trim searched and balanced on ``--aero``'s model (:func:`hawksim.trim.model_search.
    trim_on_model`), at ``--speed`` and ``--forward-speed``."""
    from dataclasses import replace

    from hawksim.trim.model_search import SEARCH_CONFIG, trim_on_model

    seed = 0 if args.seed is None else args.seed
    cfg = SEARCH_CONFIG if args.population is None else replace(SEARCH_CONFIG, population=args.population)
    bar = progress_for(args, "trim (GA)", "gen")
    progress = None if bar is None else (lambda g, n, best: bar(g, n, best=f"{best:.6f}"))
    insect = getattr(args, "insect", None)
    r = trim_on_model(args.speed, forward_speed=args.forward_speed, aero=args.aero, seed=seed, cfg=cfg,
                      insect=insect, progress=progress)
    if bar is not None:
        bar.close()
    return trim_json(r) | {"seed": seed, "population": cfg.population, "generations": r.search.generations} | (
        {} if insect is None else {"insect": insect.name})


def cmd_local_trim(args) -> dict:
    """The UVLM's local minimum-power trim at ``--speed`` and ``--forward-speed`` (:func:`hawksim.trim.model_search.
    refine_on_model` at :data:`hawksim.trim.balance.TRIM_RESOLUTION`, or the resolution options given, at most
    ``--max-evals`` runs, then the balance, 30 + 20 runs, where no run balanced) from the shipped quasi-steady
    forward trim at U (:func:`hawksim.cli.args.default_forward_kinematics`) or ``--kinematics``. Each search run's
    averages on stderr."""
    import sys

    import numpy as np

    from hawksim.cli.args import default_forward_kinematics, resolution_from
    from hawksim.insect.folder import default_insect
    from hawksim.trim.balance import TRIM_RESOLUTION
    from hawksim.trim.model_search import REFINE_MAX_EVALS, refine_on_model
    from hawksim.trim.search import R_PENALTY, fitness

    from dataclasses import replace

    default_forward_kinematics(args)
    base = TRIM_RESOLUTION  # --cycles: all but the first beat averaged, as TRIM_RESOLUTION's 4 and 3
    res = resolution_from(args, base if args.cycles is None else replace(base, cycles=args.cycles,
                                                                          average_cycles=max(1, args.cycles - 1)))
    max_evals = args.max_evals or REFINE_MAX_EVALS
    progress = None
    if not args.no_progress:
        def progress(n, a):
            print(f"trim ({args.aero}) search run {n} of at most {max_evals}: L+ {a.L_plus:.4f} D+ {a.D_plus:.4f} "
                  f"M+ {a.M_plus:.4f} P+ {a.P_plus:.4f}", file=sys.stderr, flush=True)
    r = refine_on_model(args.kinematics, args.speed, res, forward_speed=args.forward_speed, max_evals=max_evals,
                        progress=progress)
    lo, hi = default_insect().bounds_si()
    f = fitness(np.array([r.averages.as_tuple()]), np.array([r.kinematics.as_array()]), r=R_PENALTY, lo=lo, hi=hi)
    if not r.converged:
        print(f"hawksim trim: the {args.aero} trim did not balance within {r.tolerance:g} (its residuals are in the "
              "result): 'converged' is false", file=sys.stderr)
    return trim_json(replace(r, fitness=float(f[0]))) | {"start_source": args.kinematics_source,
                                                        "max_evals": max_evals, "resolution": res.to_dict()}


def trim_json(r) -> dict:
    """The JSON of a trim searched and balanced on a model (:func:`hawksim.trim.model_search.trim_on_model`): its
    kinematics (Hz, deg), body angle, averages, the search's optimum before the balance and the body's share of
    the averages in forward flight."""
    out = {"kinematics": r.kinematics.to_edge(), "chi": math.degrees(r.kinematics.chi), **r.outputs,
           "converged": r.converged, "tolerance": r.tolerance, "fitness": r.fitness, "speed": r.speed,
           "forward_speed": r.forward_speed, "evaluations": r.evaluations, "wall_time_s": r.wall_time_s,
           "model": r.aero, "source": r.source,
           "search_optimum": {"kinematics": r.start.kinematics.to_edge(), **r.start.outputs}}
    if r.forward_speed:
        from hawksim.backends.held import body_averages

        b = body_averages(r.kinematics, r.speed, r.forward_speed, r.insect)
        out["body"] = {k: getattr(b, k) for k in ("L_plus", "D_plus", "M_plus")}
    return out


def register(sub) -> None:
    from dataclasses import replace

    from hawksim.backends.resolution import DEFAULT

    trim_res = replace(DEFAULT, cycles=4, average_cycles=3)  # hawksim.trim.balance.TRIM_RESOLUTION (not imported
    # here: it imports the backends, and every command registers its parser)
    p = sub.add_parser("trim", help="minimum-power trim on the surrogate (GA + Nelder-Mead, paper Eq. 3)")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    add_forward_speed_arg(p, "; with --aero quasi-steady or uvlm (the search on that model), or --free-flight (the "
                             "orbit at (U, V) from the shipped forward trim at U or --kinematics)")
    add_network_args(p, None)
    p.add_argument("--seed", type=seed_arg, help="seed of the GA (0)")
    p.add_argument("--population", type=positive_int_arg("population", MAX_POPULATION),
                   help=f"GA population (1e5, as in the paper; at most {MAX_POPULATION:g})")
    p.add_argument("--verify", action="store_true", help="evaluate the optimum with the UVLM")
    p.add_argument("--balance", action="store_true",
                   help="then balance the optimum on the UVLM itself (f, beta, phi0, alpha0; |residuals| <= 0.01)")
    p.add_argument("--free-flight", action="store_true",
                   help="instead: the periodic orbit of the free body (Newton shooting on the one-wingbeat map; "
                        "frees f and phi0 and the body state at phase 0)")
    p.add_argument("--aero", choices=names(having="orbits"),
                   help="with --free-flight: the aerodynamic model (default uvlm); without it: search the "
                        "minimum-power trim on that model itself (quasi-steady: GA + Nelder-Mead, a population of "
                        "80 unless --population, then balanced to |residuals| <= 0.01; minutes; uvlm: the local "
                        "search from the shipped quasi-steady forward trim at --forward-speed or --kinematics, "
                        "at most --max-evals runs; 5-15 min)")
    p.add_argument("--kinematics", type=parse_kinematics,
                   help="with --free-flight: the orbit's start (f and phi0 are solved); with --aero uvlm: the local "
                        "search's start (default: the shipped quasi-steady forward trim at --forward-speed, level "
                        "flight at 0-4 m/s)")
    p.add_argument("--max-evals", type=positive_int_arg("max-evals", MAX_EVALS),
                   help="with --aero uvlm: UVLM runs of the local search (default hawksim.trim.model_search."
                        "REFINE_MAX_EVALS, 5-15 min; then the UVLM balance, 30 + 20 runs, where none balanced)")
    add_resolution_args(p, trim_res, "with --aero uvlm; default; --cycles: all but the first averaged")
    add_insect_arg(p, "; the GA searches its bounds_deg (inside Table 2, the network's training box; "
                        "its morphology must be the hawkmoth's) and P+ is in its reference power; with --free-flight "
                        "its own periodic orbit (any morphology)")
    p.add_argument("--no-progress", action="store_true")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_trim, human=render_trim)
