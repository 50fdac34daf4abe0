"""Public names of a package imported on first use (PEP 562), so that a package's ``__init__`` can list its API
(``__all__``) without importing its modules: ``import hawksim`` and the CLI's start-up stay as light as before."""

from __future__ import annotations

import importlib
import sys


def lazy_exports(package: str, exports: dict[str, tuple[str, ...]]):
    """``(__all__, __getattr__, __dir__)`` for the package named ``package``.

    Args:
        package: the package's ``__name__``.
        exports: for each module (relative to the package, ``".kinematics"``, or absolute), the public names it
            defines, in the order the reference lists them.

    A name is looked up in its module on first access and then kept in the package's namespace; an unknown name
    raises AttributeError as for any module.
    """
    where = {name: module for module, names in exports.items() for name in names}
    if len(where) != sum(len(names) for names in exports.values()):
        raise ValueError(f"{package}: a public name is listed for two modules")

    def __getattr__(name: str):
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(where))

    return list(where), __getattr__, __dir__
