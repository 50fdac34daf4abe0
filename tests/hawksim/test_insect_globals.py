"""No hawkmoth global outside the insect's own modules (issue 50, item 1): hawksim reads the insect through an
argument that defaults to :func:`hawksim.insect.folder.default_insect` (loaded from ``hawksim/insects/hawkmoth``),
never through ``HAWKMOTH``, ``P0_W``, ``DEFAULT_INSECT``, ``TABLE2_BOUNDS_DEG`` or the bare ``bounds_si()``.

Code is read token by token (names only: a docstring, comment or help text that mentions a name does not count)."""

import io
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

GLOBALS = ("HAWKMOTH", "P0_W", "DEFAULT_INSECT", "TABLE2_BOUNDS_DEG", "bounds_si")
"""The hawkmoth's globals (``bounds_si`` as a bare function; the method ``insect.bounds_si()`` is the insect's)."""

ALLOWED = ("hawksim/insect/__init__.py", "hawksim/insect/morphology.py", "hawksim/insect/kinematics.py",
           "hawksim/insect/insect.py")
"""Where they are defined (and exported, for scripts written against them)."""

def offenders(root: Path = ROOT) -> dict[str, list[str]]:
    """{module path: ["NAME (line n)", ...]} of the uses outside :data:`ALLOWED` in ``root``/hawksim."""
    out = {}
    for path in sorted((root / "hawksim").rglob("*.py")):
        rel = path.relative_to(root).as_posix()
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


def test_no_module_reads_a_hawkmoth_global():
    found = offenders()
    assert not found, f"hawkmoth globals outside the insect's modules (take an insect argument instead): {found}"


def test_the_scan_can_fail(tmp_path):
    """The scan finds a global read in code, and not one named in a docstring or comment or the insect's method."""
    (tmp_path / "hawksim").mkdir()
    (tmp_path / "hawksim" / "bad.py").write_text(
        '"""HAWKMOTH in a docstring."""\n# P0_W in a comment\nx = DEFAULT_INSECT\ny = bounds_si()\n'
        "z = insect.bounds_si()\n")
    assert offenders(tmp_path) == {"hawksim/bad.py": ["DEFAULT_INSECT (line 3)", "bounds_si (line 4)"]}
