"""The suite never writes into the user's own caches.

Before any test module is imported, ``XDG_CACHE_HOME`` (where hawksim keeps its compiled kernels,
:func:`aero.numba_cache.default_cache_dir`, and its controller maps, :mod:`hawksim.control.cache`) and
``MPLCONFIGDIR`` (matplotlib's font cache) point into a temporary directory for the whole session, and every
subprocess a test starts inherits them. The compiled kernels already in the user's cache are copied in first (read,
never written), so the suite does not compile them again. At the end of the session the user's hawksim cache is
compared with a snapshot taken before (every file's path, size and modification time): a change fails the run
and names the files.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import pytest

_STATE: dict = {}


def _user_cache() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "hawksim"


def _snapshot(root: Path) -> dict[str, tuple[int, int]]:
    if not root.is_dir():
        return {}
    return {str(p.relative_to(root)): (p.stat().st_size, p.stat().st_mtime_ns)
            for p in root.rglob("*") if p.is_file()}


def pytest_configure(config):
    if "tmp" in _STATE:  # pytester sessions inside a session
        return
    user = _user_cache()
    tmp = Path(tempfile.mkdtemp(prefix="hawksim-test-cache-"))
    if (user / "numba").is_dir():
        shutil.copytree(user / "numba", tmp / "hawksim" / "numba")
    _STATE.update(tmp=tmp, user=user, before=_snapshot(user),
                  env={k: os.environ.get(k) for k in ("XDG_CACHE_HOME", "MPLCONFIGDIR")})
    os.environ["XDG_CACHE_HOME"] = str(tmp)
    os.environ["MPLCONFIGDIR"] = str(tmp / "matplotlib")


def pytest_sessionfinish(session, exitstatus):
    if "tmp" not in _STATE:
        return
    after = _snapshot(_STATE["user"])
    changed = sorted(k for k in set(after) | set(_STATE["before"]) if after.get(k) != _STATE["before"].get(k))
    for k, v in _STATE["env"].items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v
    shutil.rmtree(_STATE["tmp"], ignore_errors=True)
    if changed:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
        tr = session.config.pluginmanager.get_plugin("terminalreporter")
        msg = (f"the test session changed {len(changed)} file(s) in the user's cache {_STATE['user']}: "
               + ", ".join(changed[:5]))
        if tr is not None:
            tr.write_line(msg, red=True)
