"""aero.numba_cache: the per-user cache folder is keyed by the project's sources, so a kernel compiled against
another file's older code (numba checks only the function's own file) is never loaded."""

import os
import subprocess
import sys
from pathlib import Path

from aero.numba_cache import default_cache_dir, sources_digest


def _package(root: Path, body: str) -> None:
    (root / "pkg_digest_probe").mkdir(exist_ok=True)
    (root / "pkg_digest_probe" / "__init__.py").write_text("")
    (root / "pkg_digest_probe" / "kernels.py").write_text(body)


def test_digest_follows_every_source_file(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(tmp_path))
    _package(tmp_path, "A = 1\n")
    first = sources_digest(("pkg_digest_probe",))
    assert sources_digest(("pkg_digest_probe",)) == first  # deterministic
    _package(tmp_path, "A = 2\n")
    assert sources_digest(("pkg_digest_probe",)) != first
    _package(tmp_path, "A = 1\n")
    assert sources_digest(("pkg_digest_probe",)) == first  # the bytes, not the time stamps
    assert sources_digest(("no_such_package_here",)) == sources_digest(())


def test_the_default_folder_is_keyed_by_the_digest_and_a_user_setting_wins(tmp_path):
    assert default_cache_dir().name == sources_digest()
    assert default_cache_dir().parent.parts[-2:] == ("hawksim", "numba")
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    code = "import aero, os; print(os.environ['NUMBA_CACHE_DIR'])"
    got = subprocess.run([sys.executable, "-c", code], env={**env, "XDG_CACHE_HOME": str(tmp_path)},
                         capture_output=True, text=True, check=True).stdout.strip()
    assert got == str(tmp_path / "hawksim" / "numba" / sources_digest())
    mine = str(tmp_path / "mine")
    got = subprocess.run([sys.executable, "-c", code], env={**env, "NUMBA_CACHE_DIR": mine},
                         capture_output=True, text=True, check=True).stdout.strip()
    assert got == mine
