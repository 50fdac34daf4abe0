"""Where numba's ``cache=True`` files go: a per-user cache folder, never the installed package.

numba writes its compiled-function cache beside the source file by default (``__pycache__`` inside
``site-packages/aero`` for a non-editable install). pip does not know those files, so uninstalling leaves the
folder behind, where it then shadows a later editable install as a namespace package (the README's two set-up
commands in a row broke ``import hawksim`` that way). Importing :mod:`aero` therefore points
``NUMBA_CACHE_DIR`` at ``$XDG_CACHE_HOME/hawksim/numba`` (default ``~/.cache/hawksim/numba``) unless the user set
it; numba keys its cache by the source file's path, so installs in different places do not collide.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ENV = "NUMBA_CACHE_DIR"


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/hawksim/numba``, or ``~/.cache/hawksim/numba``."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "hawksim" / "numba"


def apply_cache_dir() -> str:
    """Set ``NUMBA_CACHE_DIR`` (if unset) before numba is imported; returns the folder in force."""
    os.environ.setdefault(ENV, str(default_cache_dir()))
    if "numba" in sys.modules:  # imported before aero: make numba read the setting again
        from numba.core import config

        config.reload_config()
    return os.environ[ENV]
