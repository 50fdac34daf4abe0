"""Argument types shared by the subcommands: each parses one option's text into SI values or raises
argparse.ArgumentTypeError naming the option (one line; the CLI exits with status 2)."""

from __future__ import annotations

import argparse
import math
import os
import stat
from pathlib import Path

from hawksim.insect.folder import default_insect
from hawksim.insect.kinematics import PARAM_NAMES, SPEED_RANGE, Kinematics

KINEMATICS_HELP = (",".join(f"{k}=.." for k in PARAM_NAMES) + " (Hz, deg; Table 2 bounds: "
                   + ", ".join(f"{k} {lo:g}..{hi:g}" for k, (lo, hi) in default_insect().bounds_deg.items()) + ")")
"""Help text of every --kinematics option, generated from the parameter names and the default insect's bounds (Table
2)."""


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


def insect_arg(text: str):
    """The insect of ``--insect NAME|FILE`` (a shipped insect's name, an insect folder, or a TOML or JSON spec:
    :func:`hawksim.insect.folder.load_insect`), or argparse.ArgumentTypeError naming the file and the field. The
    default insect itself is returned as given: :func:`default_insect_as_none` maps it to None after parsing."""
    from hawksim.insect.folder import load_insect

    try:
        return load_insect(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def default_insect_as_none(args) -> None:
    """``args.insect`` set to None where it is the default insect (``--insect hawkmoth``, or a copy of its spec):
    the commands then behave exactly as without ``--insect`` (shipped tables, networks and orbits)."""
    if getattr(args, "insect", None) is not None and args.insect == default_insect():
        args.insect = None


def refuse_insect(args, command: str, why: str) -> None:
    """UsageError (exit 2) if ``args.insect`` (after :func:`default_insect_as_none`) is not the default insect:
    ``command`` cannot do another insect yet, for the reason ``why``."""
    insect = getattr(args, "insect", None)
    if insect is not None:
        raise UsageError(f"hawksim {command}: --insect {insect.name} is not the default insect "
                         f"({default_insect().name}) and {why}")


INSECT_HELP = ("the insect: a shipped insect's name (hawkmoth), an insect folder, or a TOML or JSON spec file "
               "(docs/insects.md: morphology in SI with each number's source, P0 [W], bounds in Hz and deg; a flat "
               "JSON of Morphology's fields, P0_W and bounds_deg keeps the default insect's values for the fields left "
               "out); default: the hawkmoth")
"""Help text of every --insect option."""


def add_insect_arg(p, extra: str = "") -> None:
    """The ``--insect NAME|FILE`` option of a subcommand (``extra``: what it means there, appended to the help)."""
    p.add_argument("--insect", type=insect_arg, metavar="NAME|FILE", help=INSECT_HELP + extra)


def _ranged_speed(flag: str, text: str, rng: tuple[float, float], what: str) -> float:
    """``--FLAG text`` as a speed [m/s]: finite, at least rng[0] ("must be a finite WHAT >= ..."), at most rng[1]."""
    v = _number(flag, text, float, "a number")
    lo, hi = rng
    if not math.isfinite(v) or v < lo:
        raise argparse.ArgumentTypeError(f"--{flag} {text} must be a finite {what} >= {lo:g} m/s")
    if v > hi:
        raise argparse.ArgumentTypeError(f"--{flag} {text} is outside the study's range [{lo:g}, {hi:g}] m/s")
    return v


def speed_arg(text: str) -> float:
    return _ranged_speed("speed", text, SPEED_RANGE, "ascent speed")


def forward_speed_arg(text: str) -> float:
    """``--forward-speed U`` [m/s]: finite, in :data:`hawksim.condition.FORWARD_SPEED_RANGE` (hover to 5 m/s)."""
    from hawksim.condition import FORWARD_SPEED_RANGE

    return _ranged_speed("forward-speed", text, FORWARD_SPEED_RANGE, "forward speed")


FORWARD_SPEED_HELP = "forward speed U [m/s], 0 (default: vertical flight) to 5; flight along world +x"
"""Help text of every --forward-speed option."""


def add_forward_speed_arg(p, extra: str = "") -> None:
    """The ``--forward-speed U`` option of a subcommand (default 0; ``extra`` appended to the help)."""
    p.add_argument("--forward-speed", type=forward_speed_arg, default=0.0, metavar="U",
                   help=FORWARD_SPEED_HELP + extra)


def check_forward_condition(args) -> None:
    """UsageError (exit 2, one line) where ``args.forward_speed`` > 0 cannot be had: a network backend (``--aero``
    trained on vertical flight only, :data:`hawksim.condition.FORWARD_FLIGHT_BACKENDS`; ``args.aero`` None is the
    UVLM, `trim --free-flight`'s default), or ``--insect`` (forward flight is the default hawkmoth's). Without
    ``--kinematics`` the start is the shipped forward trim at U (:func:`default_forward_kinematics`: it sets
    ``args.kinematics``, or refuses where none is shipped)."""
    from hawksim.condition import FORWARD_FLIGHT_BACKENDS

    u = args.forward_speed
    aero = args.aero or "uvlm"
    if aero not in FORWARD_FLIGHT_BACKENDS:
        raise UsageError(f"--forward-speed {u:g}: --aero {aero} was trained on vertical flight only; forward "
                         f"flight takes --aero {' or '.join(FORWARD_FLIGHT_BACKENDS)}")
    if getattr(args, "insect", None) is not None:
        raise UsageError(f"--forward-speed {u:g} with --insect: not yet (forward flight is the default hawkmoth's)")
    default_forward_kinematics(args)


def default_forward_kinematics(args) -> None:
    """Where ``args.kinematics`` is None, set it to the kinematics of the shipped quasi-steady minimum-power trim in
    level flight at ``args.forward_speed`` U [m/s] (:func:`hawksim.trim.tables.forward_trim`; between two shipped
    speeds the parameters interpolated linearly, :func:`hawksim.trim.tables.forward_trim_kinematics`, as the
    forward-flight schedule's orbits start: not a balanced trim, an orbit solve balances it through f and phi0; the
    same start for every backend, as the UVLM's forward orbits are solved from quasi-steady trims) and
    ``args.kinematics_source`` to where it came from ("given (--kinematics)" where ``--kinematics`` was given).
    UsageError (exit 2, one line naming ``--forward-speed``) where no shipped trim covers (U, ``args.speed``): in a
    climb (the shipped trims are level) and above the last balanced one (5 m/s: none balanced within Table 2's
    bounds)."""
    from hawksim.cli.summary import balance_residual
    from hawksim.trim.registry import shipped_table
    from hawksim.trim.tables import FORWARD_TRIM_TABLE, forward_trim_kinematics

    if args.kinematics is not None:
        args.kinematics_source = "given (--kinematics)"
        return
    u, v = args.forward_speed, args.speed
    rows = {float(r["forward_speed"]): r for r in (shipped_table(FORWARD_TRIM_TABLE) or {"rows": []})["rows"]}
    balanced = sorted(k for k, r in rows.items() if r["converged"])
    speeds = ", ".join(f"{k:g}" for k in balanced)
    if v:
        raise UsageError(f"--forward-speed {u:g} at --speed {v:g}: the shipped forward trims are level flight (--speed "
                         f"0, at {speeds} m/s); give --kinematics")
    if u in rows and not rows[u]["converged"]:
        raise UsageError(f"--forward-speed {u:g}: no shipped forward trim there (none balanced within Table 2's "
                         f"bounds: the search's best residual {balance_residual(rows[u]):.3f}); give --kinematics")
    if not balanced or not balanced[0] <= u <= balanced[-1]:
        raise UsageError(f"--forward-speed {u:g}: no shipped forward trim there (none balanced within Table 2 is "
                         f"shipped above {balanced[-1] if balanced else 0:g} m/s; they are at {speeds} m/s); give "
                         "--kinematics")
    args.kinematics = forward_trim_kinematics(u)
    if u in balanced:
        args.kinematics_source = f"the shipped forward trim at {u:g} m/s ({FORWARD_TRIM_TABLE})"
    else:
        lo, hi = max(k for k in balanced if k < u), min(k for k in balanced if k > u)
        args.kinematics_source = (f"the shipped forward trims at {lo:g} and {hi:g} m/s interpolated to {u:g} m/s "
                                  f"({FORWARD_TRIM_TABLE}; not a balanced trim)")
    if not getattr(args, "no_progress", False):
        import sys

        print(f"hawksim {getattr(args, 'command', '')}: --forward-speed {u:g} without --kinematics: from "
              f"{args.kinematics_source}", file=sys.stderr)



def refuse_forward_speed(args, command: str, why: str) -> None:
    """UsageError (exit 2) if ``args.forward_speed`` is nonzero: ``command`` does not fly forward yet (``why``)."""
    if getattr(args, "forward_speed", 0.0):
        raise UsageError(f"hawksim {command}: --forward-speed {args.forward_speed:g} is not supported {why} "
                         "(docs/forward_flight.md, 'Not yet')")


def _integer(text: str) -> int:
    """int of '100000', '1e5' or '1.0e5' (an integral number); ValueError otherwise."""
    try:
        return int(text)
    except ValueError:
        v = float(text)
        if not math.isfinite(v) or v != int(v):
            raise ValueError(text) from None
        return int(v)


def positive_int_arg(name: str, maximum: int | None = None, why: str = ""):
    """argparse type for a positive integer option --name (also written as 1e5), at most ``maximum``."""
    def parse(text: str) -> int:
        v = _number(name, text, _integer, "an integer")
        if v < 1:
            raise argparse.ArgumentTypeError(f"--{name} {text} must be >= 1")
        if maximum is not None and v > maximum:
            raise argparse.ArgumentTypeError(f"--{name} {text} exceeds the limit {maximum:g}{why}")
        return v

    return parse


cycles_arg = positive_int_arg("cycles")

# ---- resource limits, checked before any work starts ----------------------------------------------------------
MAX_FLY_STEPS = 2_000_000
"""Largest cycles x steps-per-cycle of `hawksim fly` (10 000 beats at 200 steps): the recorded series hold ~1.5 kB
per step (eleven small arrays), so ~3 GB; estimated from the arrays' sizes, not a measured peak."""
MAX_STEPS_PER_CYCLE = 20_000
"""Largest --steps-per-cycle (100x the default; RK4's error is already ~1e-6 m/s at 200)."""
MAX_AERO_CYCLES = 20
"""Largest --cycles of a held-body UVLM run: the free wake is kept whole, and its cost grows with the square of its
length (3 beats: ~1.2 s; 20 beats: minutes)."""
MAX_RINGS = 256
"""Largest --n-chord or --n-span (the default lattice is 6 x 12; a 256 x 256 lattice takes minutes per step)."""
MAX_UVLM_STEPS_PER_CYCLE = 640
"""Largest --steps-per-cycle of a held-body UVLM run (`hawksim aero`, `hawksim dataset`): 16x the default 40 and 4x
the finest step of the convergence study (160, docs/validation.md section 4), past which nothing was measured. The
free wake grows by a row of rings each step, so a run's cost grows at least with the square of the steps: the
default's ~1.2 s for 3 beats becomes at least 256 x 1.2 s, ~5 min, at 640 (an estimate from that scaling, not a
timing). It was unbounded (issue 53, defect 14)."""
MAX_POPULATION = 2_000_000
"""Largest GA population (20x the paper's 1e5): ~10 arrays of population x 7 float64, ~1 GB."""

MAX_DATASET_SAMPLES = 1_000_000
"""Largest ``hawksim dataset --samples`` (samples or flights per file and seed): 300x the largest shipped run (3000
samples per speed; 700 flights), ~3 core-days at the training resolution's ~0.25 s a sample (4 samples/s on one
worker, measured), yet the indices to do and the stored ones (Python integers, ~100 MB at the bound) are found with
one query and held in memory with room to spare. A larger value was an unbounded list of indices (issue 53,
defect 5)."""

aero_cycles_arg = positive_int_arg("cycles", MAX_AERO_CYCLES, " (the free wake's cost grows with its length squared)")


def parse_kinematics(text: str) -> Kinematics:
    """``f=..,beta=..,phi0=..,theta0=..,alpha0=..,phi_a=..,alpha_a=..`` (Hz, deg) -> Kinematics. Raises
    argparse.ArgumentTypeError naming the bad key or value. The bounds are the insect's, checked once every option is
    parsed (:func:`check_kinematics_bounds`: ``--insect`` may come after ``--kinematics``)."""
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
        return Kinematics.from_edge(values, check_bounds=False)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"--kinematics: {exc}") from None


def check_kinematics_bounds(args) -> None:
    """UsageError (exit 2, the message argparse gives a bad option) if ``args.kinematics`` lies outside the insect's
    kinematic bounds (``args.insect``'s; Table 2 for the default insect)."""
    kin = getattr(args, "kinematics", None)
    if not isinstance(kin, Kinematics):
        return
    insect = getattr(args, "insect", None)
    try:
        Kinematics.from_edge(kin.to_edge(), bounds_deg=None if insect is None else insect.bounds_deg)
    except ValueError as exc:
        raise UsageError(f"hawksim {args.command}: argument --kinematics: --kinematics: {exc}") from None


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
    """An output file's path, checked before any work: its directory exists and is writable, and the path is missing
    or a regular file, or a symbolic link to one (whose target is then replaced, :func:`hawksim.atomic.output_target`).
    A device (``/dev/null``), FIFO, socket or directory is refused: outputs are written all or nothing by renaming a
    temporary file over the target, which would replace the device by a regular file. argparse prefixes the option's
    name (``argument --rrd: ...``)."""
    from hawksim.atomic import file_kind

    if not text.strip():
        raise argparse.ArgumentTypeError("the file name is empty")
    p = Path(text)
    target = Path(os.path.realpath(p)) if p.is_symlink() else p
    via = f" (the target of the link, {str(target)!r})" if target != p else ""
    try:
        mode = os.stat(target).st_mode
    except OSError:
        mode = None
    if mode is not None and not stat.S_ISREG(mode):
        raise argparse.ArgumentTypeError(f"{text!r} is {file_kind(mode)}{via}, not a regular file (outputs are "
                                         "written all or nothing, by renaming a temporary file over the path)")
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise argparse.ArgumentTypeError(f"directory of {text!r}{via} does not exist")
    if not os.access(parent, os.W_OK):
        raise argparse.ArgumentTypeError(f"directory of {text!r}{via} is not writable")
    return p


SEED_MAX = 2**63 - 1
"""Largest seed: stored in SQLite's 64-bit INTEGER and numpy's SeedSequence."""


def seed_arg(text: str) -> int:
    v = _number("seed", text, int, "an integer")
    if not 0 <= v <= SEED_MAX:
        raise argparse.ArgumentTypeError(f"--seed {text} must be in [0, 2^63 - 1]")
    return v


def wake_precision_arg(text: str) -> str:
    """--wake-precision: one of ``aero.biot_savart.PRECISIONS`` (imported only when the option is given: it imports
    numba)."""
    from aero.biot_savart import PRECISIONS

    if text not in PRECISIONS:
        raise argparse.ArgumentTypeError(f"--wake-precision {text!r}: choose {', '.join(PRECISIONS)}")
    return text


def seconds_arg(text: str) -> float:
    v = _number("time-limit", text, float, "a number of seconds")
    if not math.isfinite(v) or v <= 0:
        raise argparse.ArgumentTypeError(f"--time-limit {text} must be a positive number of seconds")
    return v


def add_resolution_args(p, base, label: str = "default") -> None:
    """--n-chord, --n-span, --steps-per-cycle, --cycles of a held-body UVLM run, their help showing ``base``'s
    values (a :class:`hawksim.backends.resolution.Resolution`) as ``label``."""
    p.add_argument("--n-chord", type=positive_int_arg("n-chord", MAX_RINGS),
                   help=f"chordwise vortex rings per wing ({label}: {base.n_chord})")
    p.add_argument("--n-span", type=positive_int_arg("n-span", MAX_RINGS),
                   help=f"spanwise vortex rings per wing ({label}: {base.n_span})")
    p.add_argument("--steps-per-cycle",
                   type=positive_int_arg("steps-per-cycle", MAX_UVLM_STEPS_PER_CYCLE,
                                         " (hawksim.cli.args.MAX_UVLM_STEPS_PER_CYCLE: the free wake's cost grows "
                                         "with the steps squared)"),
                   help=f"time steps per wingbeat ({label}: {base.steps_per_cycle})")
    p.add_argument("--cycles", type=aero_cycles_arg,
                   help=f"wingbeats ({label}: {base.cycles}; the last {base.average_cycles} averaged)")


def resolution_from(args, base):
    """``base`` with the options of :func:`add_resolution_args` that were given."""
    from dataclasses import replace

    given = {k: getattr(args, k) for k in ("n_chord", "n_span", "steps_per_cycle", "cycles")
             if getattr(args, k, None)}
    return replace(base, **given)
