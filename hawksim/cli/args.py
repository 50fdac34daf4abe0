"""Argument types shared by the subcommands: each parses one option's text into SI values or raises
argparse.ArgumentTypeError naming the option (one line; the CLI exits with status 2)."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

from hawksim.insect.kinematics import PARAM_NAMES, SPEED_RANGE, TABLE2_BOUNDS_DEG, Kinematics

KINEMATICS_HELP = (",".join(f"{k}=.." for k in PARAM_NAMES) + " (Hz, deg; Table 2 bounds: "
                   + ", ".join(f"{k} {lo:g}..{hi:g}" for k, (lo, hi) in TABLE2_BOUNDS_DEG.items()) + ")")
"""Help text of every --kinematics option, generated from the parameter names and Table 2."""


class UsageError(Exception):
    """A bad input: reported in one line, exit status 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse prints usage + message otherwise)
        raise UsageError(f"{self.prog}: {message}")


def _number(option: str, text: str, convert, what: str):
    """``convert(text)`` or argparse.ArgumentTypeError "--option 'text' is not <what>"."""
    try:
        return convert(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--{option} {text!r} is not {what}") from None


def speed_arg(text: str) -> float:
    v = _number("speed", text, float, "a number")
    lo, hi = SPEED_RANGE
    if not math.isfinite(v) or v < lo:
        raise argparse.ArgumentTypeError(f"--speed {text} must be a finite ascent speed >= {lo:g} m/s")
    if v > hi:
        raise argparse.ArgumentTypeError(f"--speed {text} is outside the study's range [{lo:g}, {hi:g}] m/s")
    return v


def positive_int_arg(name: str):
    """argparse type for a positive integer option --name."""
    def parse(text: str) -> int:
        v = _number(name, text, int, "an integer")
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


def perturbation_arg(text: str) -> tuple[str, float]:
    from hawksim.flight.start import PERTURBATIONS

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


def seed_arg(text: str) -> int:
    v = _number("seed", text, int, "an integer")
    if v < 0:
        raise argparse.ArgumentTypeError(f"--seed {text} must be >= 0")
    return v


def seconds_arg(text: str) -> float:
    v = _number("time-limit", text, float, "a number of seconds")
    if not math.isfinite(v) or v <= 0:
        raise argparse.ArgumentTypeError(f"--time-limit {text} must be a positive number of seconds")
    return v
