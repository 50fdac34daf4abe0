"""`hawksim reproduce`: regenerate the paper's tables and figures (:mod:`hawksim.paper.reproduce`)."""

from __future__ import annotations

import sys
from pathlib import Path

from hawksim.paper.reproduce import STEPS


def cmd_reproduce(args) -> dict:
    from hawksim.paper.reproduce import run_all

    return run_all(Path(args.out), log=lambda m: print(m, file=sys.stderr), only=tuple(args.only))


def register(sub) -> None:
    p = sub.add_parser("reproduce", help="regenerate the paper's tables and figures from the pipeline")
    p.add_argument("--out", default="results", help="output directory (default results/)")
    p.add_argument("--only", nargs="+", choices=STEPS, default=list(STEPS),
                   help="regenerate only these parts (default: all)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_reproduce)
