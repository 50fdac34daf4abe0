"""The README and the guide say what the code does.

- Every Python snippet in README.md and docs/guide/ that is followed by a ```text block (the output it printed when
  the page was written) is run in a fresh interpreter and must print that output: the same text, each number
  within two units of its last printed digit (a flight's last digits may differ between CPUs).
- Every relative link in the pages a reader starts from (README.md, docs/index.md, the guide, docs/cli.md,
  docs/layout.md) points at a file of the repository (the pages other work is writing are listed in PENDING).
- The README stays a guide: the two set-up commands first (.ci/run runs them), at most ~100 lines, no issue numbers.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GUIDE = sorted((ROOT / "docs" / "guide").glob("*.md"))
PAGES = [README, *(ROOT / "docs" / n for n in ("index.md", "cli.md", "layout.md")), *GUIDE]

PENDING: set[str] = set()
"""Pages the README and the guide link to that other work in progress writes; a link to one of them may dangle."""

README_MAX_LINES = 115
"""The README's length bound [lines]: a guide of about 100 lines (the old one, a lab notebook, had 187)."""

NUMBER = re.compile(r"-?\d+(?:\.\d*)?(?:e[-+]?\d+)?")
LINK = re.compile(r"\]\(([^)\s]+)\)")
SNIPPET = re.compile(r"```python\n(.*?)```\n```text\n(.*?)```", re.S)


def _snippets():
    out = []
    for page in [README, *GUIDE]:
        for k, m in enumerate(SNIPPET.finditer(page.read_text())):
            out.append(pytest.param(m.group(1), m.group(2), id=f"{page.relative_to(ROOT)}#{k + 1}"))
    return out


def _tolerance(text: str) -> float:
    """Two units of the last printed digit of ``text`` (0 for an integer)."""
    mantissa, _, exponent = text.lower().partition("e")
    if "." not in mantissa:
        return 0.0 if not exponent else 2 * 10.0 ** int(exponent)
    decimals = len(mantissa.split(".")[1])
    return 2 * 10.0 ** (int(exponent or 0) - decimals)


def outputs_match(expected: str, actual: str) -> str | None:
    """None if ``actual`` is ``expected`` up to the numbers' tolerance, else what differs (one line)."""
    exp_text, act_text = NUMBER.split(expected.strip()), NUMBER.split(actual.strip())
    if exp_text != act_text:
        return f"the text differs: expected {expected.strip()!r}, printed {actual.strip()!r}"
    for e, a in zip(NUMBER.findall(expected), NUMBER.findall(actual)):
        ev, av = float(e), float(a)
        if abs(ev - av) > max(_tolerance(e), _tolerance(a)):
            return f"printed {a} where the page says {e}"
    return None


def test_outputs_match_can_fail():
    assert outputs_match("f = 28.53 Hz (4000,)", "f = 28.54 Hz (4000,)") is None
    assert outputs_match("f = 28.53 Hz", "f = 28.60 Hz") is not None
    assert outputs_match("(4000,)", "(4001,)") is not None
    assert outputs_match("roll -0.0003 m/s", "roll -0.0001 m/s") is None
    assert outputs_match("roll -0.0003 m/s", "roll 0.0001 m/s") is not None
    assert outputs_match("converged: True", "converged: False") is not None
    assert outputs_match("[1.459 0.387]", "[1.459 0.387 0.1]") is not None


def test_there_are_snippets():
    """The README shows the Python API, and the guide's Floquet, gust and export tutorials have Python too."""
    ids = [p.id for p in _snippets()]
    assert any(i.startswith("README.md") for i in ids)
    assert len(ids) >= 4, ids


@pytest.mark.parametrize("code,expected", _snippets())
def test_snippet_prints_what_the_page_says(code, expected, tmp_path):
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    problem = outputs_match(expected, run.stdout)
    assert problem is None, problem


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(page):
    text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)  # links inside code blocks are not links
    missing = []
    for target in LINK.findall(text):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        path = (page.parent / target.split("#")[0]).resolve()
        rel = path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path)
        if not path.exists() and rel not in PENDING:
            missing.append(target)
    assert not missing, f"{page.relative_to(ROOT)} links to missing files: {missing}"


def test_readme_is_a_guide():
    text = README.read_text()
    first = re.search(r"```bash\n(.*?)```", text, re.S)
    assert first is not None and text.index("```bash") == text.index("```"), "the set-up commands come first"
    commands = first.group(1).strip().splitlines()
    assert len(commands) == 2 and "python -m pytest" in commands[1], commands  # as .ci/run reads them
    assert len(text.splitlines()) <= README_MAX_LINES
    assert not re.search(r"\bissues? \d+", text, re.I), "issue numbers mean nothing to a reader"
