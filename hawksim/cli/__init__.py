"""The `hawksim` command line (docs/conventions.md, "The CLI contract").

Edge units: angles in degrees, frequencies in Hz, speeds in m/s. With ``--json`` each subcommand prints exactly
one JSON object on stdout; logs and progress bars go to stderr. A user mistake exits with status 2 and a
one-line message naming the bad input, never a traceback.

Exit status: 0 success; 2 a bad input (named); 3 a numerical failure (step, time and cause named; no result);
1 the environment (disk full, unreachable scheduler, out of memory); 130 interrupted.

Each subcommand is one module of this package exposing ``register(subparsers)``, which adds its parser and sets
``func`` (args -> dict, the JSON output); :data:`SUBCOMMANDS` lists them in help order.
"""

from __future__ import annotations

import json
import sys

from aero.vector_width import apply_vector_width
from hawksim.backends.resolution import MIN_STEPS_PER_CYCLE
from hawksim.cli import aero, dataset, fly, predict, reproduce, stability, train, trim
from hawksim.cli.args import Parser, UsageError

SUBCOMMANDS = (fly, aero, stability, dataset, train, predict, trim, reproduce)
"""The subcommand modules, in the order `hawksim --help` lists them."""


def _print_human(out: dict) -> None:
    for k, v in out.items():
        if isinstance(v, float):
            print(f"{k:>22}: {v:.6g}")
        else:
            print(f"{k:>22}: {v}")


def build_parser() -> Parser:
    from hawksim import __version__

    p = Parser(prog="hawksim", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"hawksim {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in SUBCOMMANDS:
        module.register(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        apply_vector_width(strict=True)  # checks HAWKSIM_VECTOR_WIDTH (importing aero applied it)
        args = parser.parse_args(argv)
        spc = getattr(args, "steps_per_cycle", None)
        if spc is not None and spc < MIN_STEPS_PER_CYCLE:
            raise UsageError(f"--steps-per-cycle {spc} must be >= {MIN_STEPS_PER_CYCLE}")
        out = args.func(args)
    except UsageError as exc:
        print(str(exc).splitlines()[0], file=sys.stderr)
        return 2
    except ValueError as exc:  # bad input detected by the library (model file, kinematics, ...)
        print(f"hawksim: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 2
    except FloatingPointError as exc:  # a numerical failure: a non-finite state, a MuJoCo warning, a diverged run
        print(f"hawksim: numerical failure: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 3
    except MemoryError:
        print("hawksim: out of memory (ask for a smaller run)", file=sys.stderr)
        return 1
    except OSError as exc:  # the environment: disk full, read-only file system, unreachable cluster
        where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
        print(f"hawksim: {exc.strerror or exc}{where}".splitlines()[0], file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("hawksim: interrupted", file=sys.stderr)
        return 130
    if args.json:
        print(json.dumps(out))
    else:
        _print_human(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
