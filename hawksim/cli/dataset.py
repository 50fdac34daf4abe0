"""`hawksim dataset`: resumable, Dask-parallel generation of UVLM samples into a SQLite file."""

from __future__ import annotations

from pathlib import Path

from hawksim.backends.resolution import NAMED, TRAINING
from hawksim.cli.args import (MAX_DATASET_SAMPLES, add_insect_arg, add_resolution_args, positive_int_arg, refuse_insect,
                              resolution_from, seed_arg, speed_arg, writable_file)
from hawksim.cli.progress import progress_for
from hawksim.cli.surrogate_report import render_dataset

DEFAULT_RESOLUTION = "training"
"""The named resolution of `hawksim dataset --kind samples` without --resolution (the shipped training sets')."""


def samples_resolution(args):
    """The resolution a samples data set is labelled at: --resolution's (default :data:`DEFAULT_RESOLUTION`) with the
    single options given (--n-chord, ...) replacing its fields."""
    return resolution_from(args, NAMED[args.resolution or DEFAULT_RESOLUTION])

def cmd_flights(args) -> dict:
    """`hawksim dataset --kind flights`: UVLM-in-the-loop free flights recorded every UVLM update."""
    import sys

    from hawksim.surrogate.flights import generate_flights

    family = args.family or "orbit"
    progress = progress_for(args, "dataset flights", "flight", mininterval=1.0, smoothing=0.05)
    r = generate_flights(args.out, args.samples, seed=args.seed, scheduler=args.scheduler, workers=args.workers,
                         progress=progress, log=lambda s: print(s, file=sys.stderr, flush=True), family=family)
    return {"path": str(Path(r.path)), "kind": "flights", "family": family, "samples": r.flights, "new": r.new,
            "diverged_new": r.diverged, "rows_new": r.rows_new, "seed": args.seed, "wall_time_s": r.wall_time_s}


SAMPLES_ONLY = ("speed", "resolution", "n_chord", "n_span", "steps_per_cycle", "cycles")
"""Options of ``--kind samples`` alone: a flights data set flies the orbits at 0-2 m/s at the flights' own UVLM
resolution (hawksim.surrogate.flights), so each of these given with ``--kind flights`` is refused (exit 2) rather than
silently ignored (issue 53, defect 14)."""
FLIGHTS_ONLY = ("family",)
"""Options of ``--kind flights`` alone, refused with ``--kind samples`` for the same reason."""


def _refuse_ignored(args) -> None:
    """UsageError naming the first option given that the chosen ``--kind`` does not use."""
    from hawksim.cli.args import UsageError

    unused = SAMPLES_ONLY if args.kind == "flights" else FLIGHTS_ONLY
    for name in unused:
        if getattr(args, name, None) is not None:
            why = ("flights fly the orbits at 0-2 m/s at their own UVLM resolution (hawksim.surrogate.flights)"
                   if args.kind == "flights" else "held-body samples have no flight family")
            raise UsageError(f"--{name.replace('_', '-')} does not apply to --kind {args.kind}: {why}")


def cmd_dataset(args) -> dict:
    from hawksim.cli.args import UsageError
    from hawksim.surrogate.dataset import generate

    refuse_insect(args, "dataset", "its UVLM data sets are the default insect's (the networks trained on them and "
                  "the tables solved with those are keyed to it; docs/insects.md)")
    _refuse_ignored(args)
    if args.kind == "flights":
        return cmd_flights(args)
    if args.speed is None:
        raise UsageError("--speed is required for --kind samples")

    res = samples_resolution(args)
    progress = progress_for(args, f"dataset V={args.speed:g}", "sample", mininterval=1.0, smoothing=0.05)
    r = generate(args.out, args.speed, args.samples, seed=args.seed, resolution=res, scheduler=args.scheduler,
                 workers=args.workers, progress=progress)
    return {"path": str(Path(r.path)), "samples": r.samples, "new": r.new, "diverged_new": r.diverged,
            "unsettled_new": r.unsettled, "speed": args.speed, "seed": args.seed, "resolution": res.to_dict(),
            "wall_time_s": r.wall_time_s, "samples_per_s": r.samples_per_s}


def _preload(args) -> tuple[str, ...]:
    """The modules the command imports (hawksim.cli._preload)."""
    mod = "hawksim.surrogate.flights" if args.kind == "flights" else "hawksim.surrogate.dataset"
    return (mod, "hawksim.cluster", "dask.distributed")


def register(sub) -> None:
    p = sub.add_parser("dataset", help="resumable generation of UVLM training samples (SQLite, Dask)")
    p.add_argument("--kind", choices=("samples", "flights"), default="samples",
                   help="samples: held-body cycle averages at --speed (the cycle-mean surrogate's data); flights: "
                        "UVLM-in-the-loop free flights around the orbits at 0-2 m/s recorded every UVLM update "
                        "(the per-step surrogate's data; hawksim.surrogate.flights)")
    p.add_argument("--family", choices=("orbit", "wide"),
                   help="--kind flights: orbit (small changes about the orbits, the shipped set) or wide (the "
                        "states of controlled flights in gusts; hawksim.surrogate.flights.FAMILIES); one per file")
    p.add_argument("--speed", type=speed_arg, help="ascent speed V [m/s], 0 to 2 (--kind samples)")
    p.add_argument("--samples", required=True,
                   type=positive_int_arg("samples", MAX_DATASET_SAMPLES, " (hawksim.cli.args.MAX_DATASET_SAMPLES)"),
                   help="samples (or flights) 0..N-1 of (seed, speed) present in the file when done")
    p.add_argument("--out", type=writable_file, required=True, help="SQLite file (created or continued)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the kinematics draw (0)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    p.add_argument("--workers", type=positive_int_arg("workers"),
                   help="LocalCluster worker processes (default: the machine's cores)")
    p.add_argument("--resolution", choices=tuple(NAMED),
                   help="named UVLM resolution of the labels: training (4 x 8 rings, 30 steps per beat: the shipped "
                        "networks' data) or reference (`hawksim aero`'s default lattice, 6 x 12 rings, 40 steps: "
                        "the reference surrogate's labels); --n-chord, --n-span, --steps-per-cycle, --cycles "
                        "override single values (default: training)")
    add_resolution_args(p, TRAINING, "training")
    p.add_argument("--no-progress", action="store_true")
    add_insect_arg(p, "; only the default insect yet (its data sets feed its networks)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_dataset, preload=_preload, human=render_dataset)
