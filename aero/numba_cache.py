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

A damaged cache entry (random bytes in a ``.nbi`` index or ``.nbc`` data file: a full disk, a crash, a user's
mistake) made numba raise ``UnpicklingError`` in every command that loads that kernel, until the user deleted the
folder (issue 53, defect 6). :func:`guard_cache_loads` wraps numba's ``Cache.load_overload``: an entry that fails
to load is a cache miss; its index and data files are deleted, numba compiles the kernel again and saves a fresh
entry, and one line on stderr (:data:`CORRUPT_ENTRY_MESSAGE`, once per process) says so. Importing :mod:`aero`
arranges the wrapping for the moment numba's caching module is imported (it does not import numba itself).
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
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
    guard_cache_loads()
    return os.environ[ENV]


CACHING_MODULE = "numba.core.caching"
"""numba's module holding ``Cache``, whose ``load_overload`` :func:`guard_cache_loads` wraps."""

CORRUPT_ENTRY_MESSAGE = ("hawksim: discarded a corrupt numba cache entry ({entry}: {error}) in {folder}; "
                         "compiling the kernels again")
"""The one line on stderr, printed once per process, when a cache entry fails to load (issue 53, defect 6)."""

_reported = False
"""Whether this process has printed :data:`CORRUPT_ENTRY_MESSAGE` (further corrupt entries are discarded quietly)."""


def _discard(cache, error: BaseException) -> None:
    """Delete the index file of numba ``Cache`` ``cache`` and its data files, and say so once per process; a
    cache whose files cannot be deleted is disabled for this process (numba would fail again saving into it)."""
    global _reported
    cache_file = cache._cache_file
    index = Path(cache_file._index_path)
    stem = index.name[: -len(".nbi")] if index.name.endswith(".nbi") else index.name
    try:
        for path in [index, *index.parent.glob(f"{stem}.*.nbc")]:
            path.unlink(missing_ok=True)
    except OSError:
        cache.disable()
    if not _reported:
        _reported = True
        kind = type(error).__name__
        print(CORRUPT_ENTRY_MESSAGE.format(entry=index.name, error=kind, folder=index.parent), file=sys.stderr,
              flush=True)


def _patch(caching) -> None:
    """Wrap ``caching.Cache.load_overload`` (once): any failure but an ``OSError`` to read an entry back (a bad
    pickle in the index or data file, an entry that does not rebuild) discards the entry and is a cache miss."""
    cache_class = caching.Cache
    if getattr(cache_class.load_overload, "_hawksim_guarded", False):
        return
    load = cache_class.load_overload

    def load_overload(self, sig, target_context):
        try:
            return load(self, sig, target_context)
        except OSError:
            raise
        except Exception as error:  # noqa: BLE001 - whatever a damaged pickle raises (UnpicklingError, EOF, ...)
            _discard(self, error)
            return None

    load_overload._hawksim_guarded = True
    cache_class.load_overload = load_overload


class _PatchOnImport(importlib.abc.MetaPathFinder):
    """Finds nothing itself: when :data:`CACHING_MODULE` is about to be imported, it wraps that module's loader
    so that :func:`_patch` runs right after the module is executed, then steps out of ``sys.meta_path``."""

    def find_spec(self, name, path=None, target=None):
        if name != CACHING_MODULE:
            return None
        if self in sys.meta_path:
            sys.meta_path.remove(self)
        spec = importlib.machinery.PathFinder.find_spec(name, path)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        execute = spec.loader.exec_module

        def exec_module(module):
            execute(module)
            _patch(module)

        spec.loader.exec_module = exec_module
        return spec


def guard_cache_loads() -> None:
    """Make a corrupt numba cache entry a cache miss (see the module's docstring): at once if numba's caching
    module is imported, else when it is."""
    if CACHING_MODULE in sys.modules:
        _patch(sys.modules[CACHING_MODULE])
    elif not any(isinstance(f, _PatchOnImport) for f in sys.meta_path):
        sys.meta_path.insert(0, _PatchOnImport())
