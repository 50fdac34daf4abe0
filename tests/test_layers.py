"""The import contract (docs/layout.md): ``aero`` <- ``hawksim`` <- scripts/tests, and
inside hawksim each subpackage imports only from the layers below it or its own. Every import statement counts,
including those inside functions (the lazy imports that keep the CLI fast), so a cycle cannot hide in one."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

HAWKSIM_LAYERS = (
    ("hawksim", "hawksim.frames", "hawksim.cluster", "hawksim.plotting"),
    ("hawksim.insect",),
    ("hawksim.backends",),
    ("hawksim.trim",),
    ("hawksim.flight",),
    ("hawksim.stability",),
    ("hawksim.control",),
    ("hawksim.surrogate",),
    ("hawksim.paper",),
    ("hawksim.cli", "hawksim.__main__"),
)
"""Subpackages (and top-level modules) from the bottom up; a unit may import its own layer and those below."""

AERO_FORBIDDEN = ("hawksim", "mujoco", "rerun", "torch", "dask", "sqlite3")
"""What the generic aerodynamics never imports (no MuJoCo, no application, no I/O stacks)."""


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(), str(path))
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names += [node.module] + [f"{node.module}.{a.name}" for a in node.names]
    return names


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _unit(name: str) -> int | None:
    """Layer index of a hawksim module name (the longest matching unit), None outside hawksim."""
    best = None
    for i, units in enumerate(HAWKSIM_LAYERS):
        for u in units:
            if (name == u or name.startswith(u + ".")) and (best is None or len(u) > len(best[1])):
                best = (i, u)
    return None if best is None else best[0]


def _files(package: str) -> list[Path]:
    return sorted((ROOT / package).rglob("*.py"))


@pytest.mark.parametrize("path", _files("hawksim"), ids=lambda p: str(p.relative_to(ROOT)))
def test_hawksim_imports_only_downwards(path):
    me = _unit(_module(path))
    assert me is not None, f"{path} is in no layer of HAWKSIM_LAYERS"
    bad = [n for n in _imports(path) if n.startswith("hawksim") and _unit(n) is not None and _unit(n) > me]
    assert not bad, f"{_module(path)} (layer {me}) imports from above: {sorted(set(bad))}"


@pytest.mark.parametrize("path", _files("aero"), ids=lambda p: str(p.relative_to(ROOT)))
def test_aero_stays_generic(path):
    bad = [n for n in _imports(path) if n.split(".")[0] in AERO_FORBIDDEN]
    assert not bad, f"{_module(path)} imports {sorted(set(bad))}"


def test_every_subpackage_is_in_a_layer():
    packages = {p.parent.relative_to(ROOT).as_posix().replace("/", ".")
                for p in (ROOT / "hawksim").rglob("__init__.py")}
    assert all(_unit(p) is not None for p in packages), packages


def test_the_contract_can_fail():
    """A downward-only check that finds nothing because it reads nothing would pass vacuously."""
    assert _unit("hawksim.cli.fly") > _unit("hawksim.flight.fly") > _unit("hawksim.trim.point")
    assert "hawksim.flight.fly" in _imports(ROOT / "hawksim" / "cli" / "fly.py")
