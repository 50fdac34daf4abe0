"""The `hawksim` command line (DESIGN.md, "CLI contract").

Edge units: angles in degrees, frequencies in Hz, speeds in m/s. With ``--json`` each subcommand prints exactly
one JSON object on stdout; logs and progress bars go to stderr. A user mistake exits with status 2 and a
one-line message naming the bad input, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

from aero.vector_width import apply_vector_width
from hawksim.kinematics import PARAM_NAMES, TABLE2_BOUNDS_DEG, Kinematics


class UsageError(Exception):
    """A bad input: reported in one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse prints usage + message otherwise)
        raise UsageError(f"{self.prog}: {message}")


def speed_arg(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--speed {text!r} is not a number") from None
    if not math.isfinite(v) or v < 0:
        raise argparse.ArgumentTypeError(f"--speed {text} must be a finite ascent speed >= 0 m/s")
    if v > 2.0:
        raise argparse.ArgumentTypeError(f"--speed {text} is outside the study's range [0, 2] m/s")
    return v


def positive_int_arg(name: str):
    """argparse type for a positive integer option --name."""
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name} {text!r} is not an integer") from None
        if v < 1:
            raise argparse.ArgumentTypeError(f"--{name} {text} must be >= 1")
        return v

    return parse


cycles_arg = positive_int_arg("cycles")


def parse_kinematics(text: str) -> Kinematics:
    """``f=..,beta=..,phi0=..,theta0=..,alpha0=..,phi_a=..,alpha_a=..`` (Hz, deg) -> Kinematics, checked
    against Table 2. Raises argparse.ArgumentTypeError naming the bad key or value."""
    values: dict[str, float] = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        key, sep, val = item.partition("=")
        key = key.strip()
        if not sep:
            raise argparse.ArgumentTypeError(f"--kinematics item {item!r} is not KEY=VALUE")
        if key not in PARAM_NAMES:
            raise argparse.ArgumentTypeError(
                f"--kinematics has unknown key {key!r}; expected {', '.join(PARAM_NAMES)}")
        if key in values:
            raise argparse.ArgumentTypeError(f"--kinematics gives {key!r} twice")
        try:
            values[key] = float(val)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--kinematics {key}={val!r} is not a number") from None
        if not math.isfinite(values[key]):
            raise argparse.ArgumentTypeError(f"--kinematics {key}={val} is not finite")
    try:
        return Kinematics.from_edge(values)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"--kinematics: {exc}") from None


def _perturbation(text: str) -> tuple[str, float]:
    from hawksim.flight import PERTURBATIONS

    key, sep, val = text.partition("=")
    if not sep or key not in PERTURBATIONS:
        raise argparse.ArgumentTypeError(
            f"--perturb {text!r}: expected NAME=VALUE with NAME one of {', '.join(PERTURBATIONS)}")
    try:
        v = float(val)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--perturb {key}={val!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"--perturb {key}={val} is not finite")
    return key, v


def writable_file(text: str) -> Path:
    p = Path(text)
    parent = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a directory, not a file")
    if not parent.is_dir():
        raise argparse.ArgumentTypeError(f"directory of {text!r} does not exist")
    if not os.access(parent, os.W_OK):
        raise argparse.ArgumentTypeError(f"directory of {text!r} is not writable")
    return p


def progress_bar(desc: str, total: int):
    from tqdm import tqdm

    bar = tqdm(total=total, desc=desc, unit="step", file=sys.stderr, disable=None, mininterval=0.5)

    def update(i, n):
        bar.update(i - bar.n)
        if i == n:
            bar.close()

    return update


def cmd_fly(args) -> dict:
    from hawksim.flight import fly

    progress = None if args.no_progress else progress_bar("fly", args.cycles * args.steps_per_cycle)
    result = fly(args.speed, args.cycles, args.aero, perturb=dict(args.perturb or []), model_path=args.model,
                 kinematics=args.kinematics, steps_per_cycle=args.steps_per_cycle,
                 keep_extras_every=args.steps_per_cycle // 10 if args.rrd else 0, progress=progress)
    out = result.summary()
    out["rrd"] = None
    if args.rrd:
        from hawksim.recording import write_rrd

        out["rrd"] = str(write_rrd(args.rrd, result))
    return out


def _print_human(out: dict) -> None:
    for k, v in out.items():
        if isinstance(v, float):
            print(f"{k:>22}: {v:.6g}")
        else:
            print(f"{k:>22}: {v}")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="hawksim", description=__doc__.splitlines()[0])
    from hawksim import __version__

    p.add_argument("--version", action="version", version=f"hawksim {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    f = sub.add_parser("fly", help="fly the insect from its trim at an ascent speed (MuJoCo, 6-DOF)")
    f.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 (hover) to 2")
    f.add_argument("--cycles", type=cycles_arg, required=True, help="number of wingbeats N")
    f.add_argument("--aero", choices=("uvlm", "surrogate", "quasi-steady"), default="quasi-steady",
                   help="aerodynamic model (default quasi-steady)")
    f.add_argument("--rrd", type=writable_file, help="write a Rerun recording to FILE")
    f.add_argument("--perturb", type=_perturbation, action="append", metavar="NAME=VALUE",
                   help="initial disturbance: u, v, w [m/s]; p, q, r [deg/s]; theta, phi [deg] (stability axes)")
    f.add_argument("--kinematics", type=parse_kinematics,
                   help="override the trim: " + ",".join(f"{k}=.." for k in PARAM_NAMES)
                   + " (Hz, deg; Table 2 bounds: "
                   + ", ".join(f"{k} {lo:g}..{hi:g}" for k, (lo, hi) in TABLE2_BOUNDS_DEG.items()) + ")")
    f.add_argument("--model", help="MJCF file (default: the model generated from hawksim.morphology)")
    f.add_argument("--steps-per-cycle", type=int, default=200, help="integration steps per wingbeat (200)")
    f.add_argument("--no-progress", action="store_true", help="no progress bar")
    f.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    f.set_defaults(func=cmd_fly)
    for register in _plugins():
        register(sub)
    return p


def _plugins():
    """Subcommands defined in their own modules: each ``hawksim.cli_<name>`` exposes ``register(subparsers)``
    that adds its parser and sets ``func`` (args -> dict for the JSON output)."""
    import importlib

    for name in PLUGIN_MODULES:
        try:
            mod = importlib.import_module(f"hawksim.cli_{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"hawksim.cli_{name}":
                raise
            continue
        yield mod.register


PLUGIN_MODULES = ("aero", "dataset", "predict", "train", "trim", "stability", "reproduce")


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        apply_vector_width(strict=True)  # checks HAWKSIM_VECTOR_WIDTH (importing aero applied it)
        args = parser.parse_args(argv)
        if (getattr(args, "steps_per_cycle", None) or 200) < 20:
            raise UsageError(f"--steps-per-cycle {args.steps_per_cycle} must be >= 20")
        out = args.func(args)
    except UsageError as exc:
        print(str(exc).splitlines()[0], file=sys.stderr)
        return 2
    except ValueError as exc:  # bad input detected by the library (model file, kinematics, ...)
        print(f"hawksim: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 2
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
