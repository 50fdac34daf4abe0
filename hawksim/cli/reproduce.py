"""`hawksim reproduce`: regenerate the paper's tables and figures (:mod:`hawksim.paper.reproduce`)."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from hawksim.cli.args import UsageError, add_insect_arg, refuse_insect
from hawksim.cli.reproduce_report import render_reproduce
from hawksim.paper.reproduce import STEPS

EXPECTED_MINUTES = {"uvlm_table4": 1, "stability": 5, "stability_table3": 5, "orbits": 15, "validation": 2,
                    "validation_uvlm": 30, "control_uvlm": 10, "control_surrogate": 1, "backends": 5, "trim": 10,
                    "forward_flight": 1}
"""Rough wall time of each step on 2 cores [min], for the start-up line only (the measurements behind them:
docs/performance.md, "Figures moved from docstrings"; validation_uvlm is a guess: it has not been run in full)."""


def cmd_reproduce(args) -> dict:
    refuse_insect(args, "reproduce", "the paper's pipeline is the hawkmoth's (Nguyen et al. 2020: its data sets, "
                  "networks, trims and tables)")
    from hawksim.paper.reproduce import run_all

    out = Path(args.out)
    parent = out.parent if str(out.parent) else Path(".")
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {args.out!r} is a file, not a directory")
    if not parent.is_dir():
        raise UsageError(f"--out {args.out!r}: its parent directory does not exist")
    if not os.access(out if out.exists() else parent, os.W_OK):
        raise UsageError(f"--out {args.out!r} is not writable")
    if out.is_dir() and any(out.iterdir()) and not args.force:
        raise UsageError(f"--out {args.out!r} exists and is not empty: pass --force to overwrite its files, or "
                         "name another directory")
    minutes = sum(EXPECTED_MINUTES[s] for s in args.only)
    print(f"hawksim reproduce: {', '.join(args.only)} into {out}/, about {minutes} min on 2 cores", file=sys.stderr)
    before = _directories(out)
    try:
        done = run_all(out, log=lambda m: print(m, file=sys.stderr), only=tuple(args.only))
    except BaseException:
        _remove_new_empty_directories(out, before)
        raise
    t0 = getattr(args, "t0", None)
    wall = time.perf_counter() - t0 if t0 is not None else None
    args.human = lambda result: render_reproduce(result, str(out), wall)
    return done


def _directories(root: Path) -> set[Path]:
    return {root, *(p for p in root.rglob("*") if p.is_dir())} if root.is_dir() else set()


def _remove_new_empty_directories(root: Path, before: set[Path]) -> None:
    """After a failure (a full disk, an interrupt): remove the directories this run made and left empty, deepest
    first. Every file written is whole (hawksim.atomic) and stays: the parts done before the failure."""
    for d in sorted(_directories(root) - before, key=lambda p: len(p.parts), reverse=True):
        try:
            d.rmdir()
        except OSError:  # not empty: it holds a finished part
            pass


def register(sub) -> None:
    p = sub.add_parser("reproduce", help="regenerate the paper's tables and figures from the pipeline")
    p.add_argument("--out", default="results", help="output directory (default results/)")
    p.add_argument("--only", nargs="+", choices=STEPS, default=list(STEPS),
                   help="regenerate only these parts (default: all)")
    p.add_argument("--force", action="store_true", help="overwrite the files of an existing --out")
    add_insect_arg(p, "; only the default insect (the paper's)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_reproduce)
