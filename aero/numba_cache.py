"""Where numba's ``cache=True`` files go: a per-user cache folder, never the installed package.

numba writes its compiled-function cache beside the source file by default (``__pycache__`` inside
``site-packages/aero`` for a non-editable install). pip does not know those files, so uninstalling leaves the
folder behind, where it then shadows a later editable install as a namespace package (the README's two set-up
commands in a row broke ``import hawksim`` that way). Importing :mod:`aero` therefore points
``NUMBA_CACHE_DIR`` at ``$XDG_CACHE_HOME/hawksim/numba`` (default ``~/.cache/hawksim/numba``) unless the user set
it; numba keys its cache by the source file's path, so installs in different places do not collide.

That folder has one sub-folder per version of the sources (:func:`sources_digest`): numba checks a cached
function against its *own* file's time stamp only, so a kernel that calls a kernel of another file (the flight
callback calls the per-step network, ``hawksim.flight.native``; the treecode's near field calls the lattice
kernel's ``corner_vectors``) would otherwise be loaded compiled against the other file's older code. Any change
to a ``.py`` file of :data:`PACKAGES` compiles everything once more (~10 s; `hawksim warmup`); each version's
folder holds ~4 MB and old ones may be deleted at any time.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ENV = "NUMBA_CACHE_DIR"

PACKAGES = ("aero", "hawksim")
"""The packages whose sources key the cache folder (located without importing them)."""


def sources_digest(packages: tuple[str, ...] = PACKAGES) -> str:
    """16 hex digits of SHA-256 over the relative paths and bytes of every ``.py`` file of ``packages`` (those
    that are installed), in sorted order."""
    import hashlib
    from importlib.util import find_spec

    h = hashlib.sha256()
    for name in packages:
        spec = find_spec(name)
        for root in (spec.submodule_search_locations or []) if spec is not None else []:
            for f in sorted(Path(root).rglob("*.py")):
                h.update(f"{name}/{f.relative_to(root).as_posix()}".encode())
                h.update(f.read_bytes())
    return h.hexdigest()[:16]


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/hawksim/numba/<sources digest>``, or ``~/.cache/hawksim/numba/<sources digest>``."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "hawksim" / "numba" / sources_digest()


def apply_cache_dir() -> str:
    """Set ``NUMBA_CACHE_DIR`` (if unset) before numba is imported; returns the folder in force."""
    os.environ.setdefault(ENV, str(default_cache_dir()))
    if "numba" in sys.modules:  # imported before aero: make numba read the setting again
        from numba.core import config

        config.reload_config()
    return os.environ[ENV]
