"""No hawkmoth global outside the insect's own modules (issue 50, item 1): hawksim reads the insect through an
argument that defaults to :func:`hawksim.insect.folder.default_insect` (loaded from ``hawksim/insects/hawkmoth``),
never through ``HAWKMOTH``, ``P0_W``, ``DEFAULT_INSECT``, ``TABLE2_BOUNDS_DEG`` or the bare ``bounds_si()``.

Code is read token by token (names only: a docstring, comment or help text that mentions a name does not count)."""

import io
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

GLOBALS = ("HAWKMOTH", "P0_W", "DEFAULT_INSECT", "TABLE2_BOUNDS_DEG", "bounds_si")
"""The hawkmoth's globals (``bounds_si`` as a bare function; the method ``insect.bounds_si()`` is the insect's)."""

ALLOWED = ("hawksim/insect/__init__.py", "hawksim/insect/morphology.py", "hawksim/insect/kinematics.py",
           "hawksim/insect/insect.py")
"""Where they are defined (and exported, for scripts written against them)."""

REMAINING = frozenset({
    "hawksim/cli/fly.py", "hawksim/control/closed_loop.py", "hawksim/control/constrained.py",
    "hawksim/control/plant.py", "hawksim/control/schedule.py", "hawksim/flight/fly.py", "hawksim/flight/orbit.py",
    "hawksim/flight/points.py", "hawksim/flight/result.py", "hawksim/stability/floquet.py",
    "hawksim/stability/system.py", "hawksim/trim/point.py", "hawksim/trim/registry.py"})
"""Modules that still read a global (owned by the parallel operating-point and flight-loop work of issue 50; each
is to take the insect as an argument defaulting to ``default_insect()``). Empty when the issue is done."""


def offenders() -> dict[str, list[str]]:
    """{module path: ["NAME (line n)", ...]} of the uses outside :data:`ALLOWED`."""
    out = {}
    for path in sorted((ROOT / "hawksim").rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if rel in ALLOWED:
            continue
        hits, previous = [], None
        for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
            if tok.type == tokenize.NAME and tok.string in GLOBALS and not (
                    tok.string == "bounds_si" and previous is not None and previous.string == "."):
                hits.append(f"{tok.string} (line {tok.start[0]})")
            if tok.type not in (tokenize.NL, tokenize.NEWLINE, tokenize.COMMENT):
                previous = tok
        if hits:
            out[rel] = hits
    return out


def test_no_new_module_reads_a_hawkmoth_global():
    new = {k: v for k, v in offenders().items() if k not in REMAINING}
    assert not new, f"hawkmoth globals outside the insect's modules (take an insect argument instead): {new}"


@pytest.mark.xfail(strict=True, reason=f"still reading a hawkmoth global: {', '.join(sorted(REMAINING))}")
def test_no_module_reads_a_hawkmoth_global():
    assert not offenders(), offenders()
