"""The import contract (docs/layout.md): ``aero`` <- ``hawksim`` <- scripts/tests, and
inside hawksim each subpackage imports only from the layers below it or its own. Every import statement counts,
including those inside functions (the lazy imports that keep the CLI fast), so a cycle cannot hide in one.

Every hawksim module must be named by a layer: the root package ``hawksim`` is a unit of its own (its
``__init__`` and ``__version__``), not a prefix that would take in any new subpackage. scripts/ is a package
(``python -m scripts.<group>.<name>`` from the repository root) on the same footing: it imports aero, hawksim,
its own modules as ``scripts.*`` and third-party packages, never tests, never private (``_name``) names of
aero or hawksim, and never edits ``sys.path``; no test imports or runs a script."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

HAWKSIM_LAYERS = (
    ("hawksim", "hawksim.atomic", "hawksim.cluster", "hawksim.environment", "hawksim.frames", "hawksim.inputfile",
     "hawksim.interrupts", "hawksim.jsonout", "hawksim.lazy", "hawksim.plotting", "hawksim.state",
     "hawksim.condition"),
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
"""Subpackages and top-level modules from the bottom up; a unit may import its own layer and those below. A unit
names a module and, if it is a package other than the root, everything inside it."""

ROOT_PACKAGE = "hawksim"
"""The root package: a unit for itself (and its attributes such as ``__version__``), never a prefix."""

AERO_FORBIDDEN = ("hawksim", "mujoco", "rerun", "torch", "dask", "sqlite3")
"""What the generic aerodynamics never imports (no MuJoCo, no application, no I/O stacks)."""

OWN_PACKAGES = ("aero", "hawksim", "scripts", "tests")


def _doc_strings(tree: ast.AST) -> set[int]:
    """ids of the string constants that are documentation: docstrings and bare string statements (attribute
    docstrings)."""
    return {id(n.value) for n in ast.walk(tree)
            if isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant) and isinstance(n.value.value, str)}


def _imports(path: Path) -> list[str]:
    return _imports_of(ast.parse(path.read_text(), str(path)))


def _imports_of(tree: ast.AST) -> list[str]:
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


def _unit(name: str, layers=HAWKSIM_LAYERS) -> int | None:
    """Layer index of a hawksim module name (the longest matching unit), None outside the layers: the root package
    matches only itself and its dunder attributes (``hawksim.__version__``), never a module inside it."""
    best = None
    for i, units in enumerate(layers):
        for u in units:
            inside = name.startswith(u + ".") and (u != ROOT_PACKAGE or re.fullmatch(r"hawksim\.__\w+__", name))
            if (name == u or inside) and (best is None or len(u) > len(best[1])):
                best = (i, u)
    return None if best is None else best[0]


def _files(package: str) -> list[Path]:
    return sorted(p for p in (ROOT / package).rglob("*.py") if "__pycache__" not in p.parts)


def _outside_layers(modules, layers=HAWKSIM_LAYERS) -> list[str]:
    return sorted(m for m in modules if _unit(m, layers) is None)


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


def test_every_module_is_in_a_layer():
    """Every package and module of hawksim, named by a unit of HAWKSIM_LAYERS (the root is no catch-all)."""
    modules = [_module(p) for p in _files("hawksim")]
    assert "hawksim.flight.simulator" in modules and len(modules) > 50
    assert not _outside_layers(modules), f"not in any layer of HAWKSIM_LAYERS: {_outside_layers(modules)}"


def test_the_membership_check_can_fail():
    """A new subpackage or top-level module that no layer names is reported, the root's attributes are not."""
    assert _outside_layers(["hawksim.newpackage", "hawksim.newpackage.module", "hawksim.flight.fly"]) == [
        "hawksim.newpackage", "hawksim.newpackage.module"]
    assert _outside_layers(["hawksim.newmodule"]) == ["hawksim.newmodule"]
    assert _unit("hawksim") == 0 and _unit("hawksim.__version__") == 0
    assert _unit("hawksim.flight") == _unit("hawksim.flight.fly") == 4
    # the layers of before issue 50 took everything in through the root: nothing could be outside them
    old = (("hawksim", "hawksim.frames"),) + HAWKSIM_LAYERS[1:]
    assert _unit("hawksim.newpackage.module", old) is None  # the root is no longer a prefix, even in old layers


def test_the_contract_can_fail():
    """A downward-only check that finds nothing because it reads nothing would pass vacuously."""
    assert _unit("hawksim.cli.fly") > _unit("hawksim.flight.fly") > _unit("hawksim.trim.point")
    assert "hawksim.flight.fly" in _imports(ROOT / "hawksim" / "cli" / "fly.py")


def test_no_library_module_imports_the_flat_top_level():
    """The names of ``hawksim.__all__`` are the facade over the layers (resolved lazily); a module inside hawksim
    imports them from where they live, or it would import upwards through the root."""
    import hawksim

    facade = {f"hawksim.{n}" for n in hawksim.__all__}
    bad = {_module(p): sorted(facade & set(_imports(p))) for p in _files("hawksim")}
    assert not {k: v for k, v in bad.items() if v}


# ---- scripts/ and tests/ ---------------------------------------------------------------------------------------

SCRIPT_STEMS = ({p.stem for p in _files("scripts")} | {p.stem for p in _files("tests")}) - {"__init__"}
"""Names that only a ``sys.path`` edit would make importable as top-level modules."""


def _sys_path_edits(tree: ast.AST) -> list[str]:
    """``sys.path.insert(...)``/``append``/``extend``/``+=``/assignment, also inside code strings run by a child."""
    found = []
    for n in ast.walk(tree):
        if isinstance(n, ast.Attribute) and ast.unparse(n) == "sys.path" and isinstance(n.ctx, ast.Store):
            found.append(f"line {n.lineno}: sys.path =")
        elif isinstance(n, ast.AugAssign) and ast.unparse(n.target) == "sys.path":
            found.append(f"line {n.lineno}: sys.path +=")
        elif (isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and ast.unparse(n.func.value) == "sys.path"
              and n.func.attr in ("insert", "append", "extend")):
            found.append(f"line {n.lineno}: {ast.unparse(n)[:80]}")
        elif isinstance(n, ast.Constant) and isinstance(n.value, str) and re.search(r"sys\.path\.(insert|append)",
                                                                                     n.value):
            found.append(f"line {n.lineno}: a code string edits sys.path")
    return found


def _private_uses(tree: ast.AST) -> list[str]:
    """Private (``_name``, not dunder) names of aero or hawksim that a file imports or reads off a module it
    imported (``import hawksim.x as M; M._y``)."""
    def private(part):
        return part.startswith("_") and not (part.startswith("__") and part.endswith("__"))

    def ours(mod):
        return mod.split(".")[0] in ("aero", "hawksim")

    def is_module(dotted):
        p = ROOT.joinpath(*dotted.split("."))
        return p.with_suffix(".py").is_file() or (p / "__init__.py").is_file()

    found, modules = [], set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Import):
            for a in n.names:
                if ours(a.name):
                    found += [f"line {n.lineno}: import {a.name}"] if any(map(private, a.name.split("."))) else []
                    if a.asname:
                        modules.add(a.asname)
        elif isinstance(n, ast.ImportFrom) and n.level == 0 and n.module and ours(n.module):
            if any(map(private, n.module.split("."))):
                found.append(f"line {n.lineno}: from {n.module}")
            for a in n.names:
                if private(a.name):
                    found.append(f"line {n.lineno}: from {n.module} import {a.name}")
                elif is_module(f"{n.module}.{a.name}"):
                    modules.add(a.asname or a.name)
    for n in ast.walk(tree):
        if (isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id in modules
                and private(n.attr)):
            found.append(f"line {n.lineno}: {n.value.id}.{n.attr}")
    return found


def _script_import_faults(tree: ast.AST) -> list[str]:
    """Imports a script may not make: tests, a sibling by its bare name (what a sys.path edit allowed), a
    ``scripts.*`` module that does not exist, or a relative import (scripts import their package absolutely)."""
    def exists(dotted):
        p = ROOT.joinpath(*dotted.split("."))
        return p.with_suffix(".py").is_file() or (p / "__init__.py").is_file()

    found = []
    for n in ast.walk(tree):
        if isinstance(n, ast.ImportFrom) and n.level:
            found.append(f"line {n.lineno}: relative import")
            continue
        if isinstance(n, ast.Import):
            modules = [a.name for a in n.names]
        elif isinstance(n, ast.ImportFrom):
            modules = [n.module]
        else:
            continue
        for m in modules:
            top = m.split(".")[0]
            if top == "tests" or top in SCRIPT_STEMS - set(OWN_PACKAGES):
                found.append(f"line {n.lineno}: imports {m}")
            elif top == "scripts" and not exists(m):
                found.append(f"line {n.lineno}: imports {m}, no such module")
    return found


def _loads_scripts(tree: ast.AST) -> list[str]:
    """A test that imports a script, or names one in code (a path to load or run, ``-m scripts...``, a child's code
    string): any string that is not documentation and has ``scripts`` as a path or module component."""
    found = [f"imports {n}" for n in _imports_of(tree) if n.split(".")[0] == "scripts"]
    docs = _doc_strings(tree)
    for n in ast.walk(tree):
        if (isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs
                and re.search(r"(^|[\s/\\.'\"])scripts($|[/\\.])", n.value)):
            found.append(f"line {n.lineno}: {n.value[:60]!r}")
    return found


SCRIPT_FILES = _files("scripts")
TEST_FILES = [p for p in _files("tests") if p != Path(__file__).resolve()]
"""The tests, less this one: it reads scripts/ as text (the checks here), never imports or runs them."""


def test_scripts_is_a_package():
    assert all((d / "__init__.py").is_file() for d in {p.parent for p in SCRIPT_FILES}), \
        "every folder of scripts/ has an __init__.py (python -m scripts.<group>.<name>)"


@pytest.mark.parametrize("path", SCRIPT_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_scripts_import_like_a_package(path):
    tree = ast.parse(path.read_text(), str(path))
    faults = _sys_path_edits(tree) + _private_uses(tree) + _script_import_faults(tree)
    assert not faults, f"{path.relative_to(ROOT)}: {faults}"


@pytest.mark.parametrize("path", TEST_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_test_loads_a_script(path):
    faults = _loads_scripts(ast.parse(path.read_text(), str(path)))
    assert not faults, f"{path.relative_to(ROOT)}: {faults}"


def test_the_script_checks_can_fail():
    """Each check flags the pattern it exists for (the ones scripts/ held before issue 50, item 8)."""
    bad_script = ast.parse(
        "import os, sys\n"
        "sys.path.insert(0, os.path.dirname(__file__))\n"
        "from bench_uvlm import reference_wing\n"
        "from aero.biot_savart import _edge_sum\n"
        "from hawksim.surrogate import step_train as T\n"
        "x = T._cols('t')\n"
        "from tests.hawksim.test_heavy_body import HEAVY\n"
        "from scripts.benchmarks.no_such_bench import run\n"
        "CHILD = 'import sys; sys.path.insert(0, sys.argv[1])'\n")
    assert len(_sys_path_edits(bad_script)) == 2
    assert _private_uses(bad_script) == ["line 4: from aero.biot_savart import _edge_sum", "line 6: T._cols"]
    assert len(_script_import_faults(bad_script)) == 3
    good = ast.parse("from hawksim import __version__\nfrom scripts.benchmarks.bench_uvlm import run_case\n"
                     "import hawksim.backends as backends\nbackends.FLY_WAKE_CYCLES = 3\n")
    assert not (_sys_path_edits(good) + _private_uses(good) + _script_import_faults(good))
    bad_test = ast.parse(
        '"""Checks scripts/studies/x.py\'s numbers."""\n'
        "import scripts.benchmarks.bench_targets as bt\n"
        "path = ROOT / 'scripts' / 'studies' / 'x.py'\n"
        "cmd = [sys.executable, '-m', 'scripts.studies.x']\n")
    assert len(_loads_scripts(bad_test)) == 3  # the import and two strings; the docstring is prose
