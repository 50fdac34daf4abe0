"""The `hawksim` command line (docs/conventions.md, "The CLI contract").

Edge units: angles in degrees, frequencies in Hz, speeds in m/s. With ``--json`` each subcommand prints exactly
one JSON object on stdout; logs and progress bars go to stderr. A user mistake exits with status 2 and a
one-line message naming the bad input, never a traceback.

Exit status: 0 success; 2 a bad input (named); 3 a numerical failure (step, time and cause named; no result);
1 the environment (disk full, unreachable scheduler, out of memory); 130 interrupted.

Each subcommand is one module of this package exposing ``register(subparsers)``, which adds its parser and sets
``func`` (args -> dict, the JSON output) and ``human`` (that dict -> the summary printed without ``--json``, a
function of the JSON object alone: its ``*_report`` module; a command may set ``args.human`` while it runs instead);
:data:`SUBCOMMANDS` lists them in help order.
"""

from __future__ import annotations

import json
import math
import os
import sys

from aero.vector_width import apply_vector_width
from hawksim import interrupts
from hawksim.backends.resolution import MIN_STEPS_PER_CYCLE
from hawksim.cli import aero, dataset, fly, predict, reproduce, stability, train, trim, warmup
from hawksim.cli.args import Parser, UsageError, check_kinematics_bounds, default_insect_as_none
from hawksim.cli.progress import close_all
from hawksim.environment import check_environment

SUBCOMMANDS = (fly, aero, stability, dataset, train, predict, trim, reproduce, warmup)
"""The subcommand modules, in the order `hawksim --help` lists them."""


def build_parser() -> Parser:
    from hawksim import __version__

    p = Parser(prog="hawksim", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"hawksim {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in SUBCOMMANDS:
        module.register(sub)
    return p


def _interrupted(exc: BaseException) -> bool:
    """Whether ``exc`` is, or was raised while handling or because of, a KeyboardInterrupt (a Ctrl-C inside an
    extension module's import surfaces as ImportError("initialization failed") chained to it)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _preload(args) -> None:
    """Import the modules a subcommand names in ``preload`` (a tuple, or a function of the arguments giving one)
    while a Ctrl-C still leaves at once (:mod:`hawksim.interrupts`): once the command works, a Ctrl-C during an
    import waits for its end, and dask.distributed took 1.3 s of it when compiled from source (the Dask commands'
    first lazy import; measured with scripts/studies/interrupt_cold_trial.py --cold all)."""
    import importlib

    names = getattr(args, "preload", ())
    for name in names(args) if callable(names) else names:
        importlib.import_module(name)


def main(argv: list[str] | None = None) -> int:
    import time

    t0 = time.perf_counter()  # the commands' wall_time_s counts from here (fly: recording and files included)
    try:
        check_environment()  # (also before numba's import when run as the command: hawksim.__main__)
        parser = build_parser()  # imports the subcommands' modules (mujoco, ...): a Ctrl-C may come here too
        apply_vector_width(strict=True)  # checks HAWKSIM_VECTOR_WIDTH (importing aero applied it)
        args = parser.parse_args(argv)
        args.t0 = t0
        default_insect_as_none(args)  # --insect hawkmoth: exactly as without --insect
        check_kinematics_bounds(args)  # the insect's bounds (Table 2 for the hawkmoth)
        spc = getattr(args, "steps_per_cycle", None)
        if spc is not None and spc < MIN_STEPS_PER_CYCLE:
            raise UsageError(f"--steps-per-cycle {spc} must be >= {MIN_STEPS_PER_CYCLE}")
        _preload(args)
        interrupts.set_before_leaving(close_all)  # a progress bar ends its line before the interrupt's
        if not getattr(args, "no_progress", False):  # one line on a terminal if this command must compile first
            warmup.install_compile_notice()
        if not getattr(args, "work_begins_in_command", False):  # (train: at its first write)
            interrupts.begin_work()  # from here a Ctrl-C lets the command clean up (until here it left at once)
        out = args.func(args)
    except BaseException as exc:
        code, line = failure(exc)  # re-raises what is not one of the contract's failures (a bug: its traceback)
        close_all()  # an open progress bar ends its line first, on a terminal
        print(line, file=sys.stderr)
        return code
    try:
        _check_finite(out)
    except FloatingPointError as exc:
        code, line = failure(exc)
        print(line, file=sys.stderr)
        return code
    return write_output(out, args.json, getattr(args, "human", None))


EXIT_BROKEN_PIPE = 141
"""Exit status when stdout's reader has gone (EPIPE: ``hawksim fly --json | head -c 1``): 128 + SIGPIPE, the status
a shell shows for a Unix tool that SIGPIPE ended (``yes | head -1`` with ``set -o pipefail``), quietly: the reader
chose to stop reading, nothing is wrong to report."""
EXIT_STDOUT_FAILED = 1
"""Exit status when stdout cannot be written for the environment (ENOSPC: ``> /dev/full``, a full disk; EIO): the
contract's environment failure, with one line on stderr."""


def _silence_stdout() -> None:
    """Point stdout's file descriptor at /dev/null, so that the interpreter's final flush of what is still buffered
    does not fail again (Python prints "Exception ignored ... BrokenPipeError" then)."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # a stream without a descriptor (pytest's capture)
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)


def write_output(out: dict, as_json: bool, human=None) -> int:
    """Print the result (one strict JSON object with ``--json``: no NaN or Infinity, ``allow_nan=False``; else the
    command's own summary ``human(out)``, or the JSON object where a command has none) and flush it; the exit
    status. A reader that
    has gone (EPIPE) ends the command quietly with :data:`EXIT_BROKEN_PIPE`; any other failure to write stdout
    (ENOSPC) is one line on stderr and :data:`EXIT_STDOUT_FAILED`."""
    try:
        if as_json or human is None:
            print(json.dumps(out, allow_nan=False))
        else:
            print(human(out))
        sys.stdout.flush()
    except BrokenPipeError:
        _silence_stdout()
        return EXIT_BROKEN_PIPE
    except OSError as exc:
        _silence_stdout()
        print(f"hawksim: cannot write the result to stdout: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_STDOUT_FAILED
    return 0


def _check_finite(obj, key: str = "") -> None:
    """FloatingPointError naming the first key (dotted path) whose value is a non-finite float: a result holding NaN
    or Infinity is a numerical failure (exit 3), and strict JSON has no such values (issue 53, a crafted network's
    outputs)."""
    if isinstance(obj, float) and not math.isfinite(obj):
        raise FloatingPointError(f"the result's {key or 'value'} is {obj} (no result)")
    if isinstance(obj, dict):
        for k, v in obj.items():
            _check_finite(v, f"{key}.{k}" if key else str(k))
    elif isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            _check_finite(v, f"{key}[{i}]")


def failure(exc: BaseException) -> tuple[int, str]:
    """(exit status, the one line for stderr) of a failure, by the contract: 2 a bad input (UsageError, or a
    ValueError from the library: model file, kinematics, ...), 3 a numerical failure (FloatingPointError: a
    non-finite state, a MuJoCo warning, a diverged run), 1 the environment (MemoryError, OSError: disk full,
    read-only file system, unreachable cluster), 130 an interrupt (KeyboardInterrupt, or an exception chained to
    one). Anything else is re-raised."""
    if isinstance(exc, UsageError):
        return 2, str(exc).splitlines()[0]
    if isinstance(exc, KeyboardInterrupt):  # its text, if any, says what was saved (fly --rrd)
        return 130, f"hawksim: {str(exc).splitlines()[0] if str(exc) else 'interrupted'}"
    if isinstance(exc, Exception) and _interrupted(exc):
        return 130, "hawksim: interrupted"
    if isinstance(exc, ValueError):
        return 2, f"hawksim: {str(exc).splitlines()[0]}"
    if isinstance(exc, FloatingPointError):
        return 3, f"hawksim: numerical failure: {str(exc).splitlines()[0]}"
    if isinstance(exc, MemoryError):
        return 1, "hawksim: out of memory (ask for a smaller run)"
    if isinstance(exc, OSError):
        where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
        return 1, f"hawksim: {exc.strerror or exc}{where}".splitlines()[0]
    raise exc


if __name__ == "__main__":
    sys.exit(main())
