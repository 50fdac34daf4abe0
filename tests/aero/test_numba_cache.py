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


PROBE_KERNEL = "from numba import njit\n\n\n@njit(cache=True)\ndef plus_one(x):\n    return x + 1\n"
"""A one-line numba kernel with ``cache=True``: its cache entry is one ``.nbi`` index and one ``.nbc`` data file."""


def _run_probe(tmp_path: Path, import_aero: bool = True) -> subprocess.CompletedProcess:
    code = ("import aero\n" if import_aero else "") + "import probe_kernel\nprint(probe_kernel.plus_one(1))\n"
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)


CORRUPT_BYTES = b"\xff" * 300
"""What a damaged cache file holds here: fixed bytes that no pickle starts with, so the unguarded load fails the
same way every run (``UnpicklingError: invalid load key``; random bytes failed in several ways: one run raised
``OverflowError`` from a garbage frame length, failing this test's precondition)."""


def _corrupt(tmp_path: Path, suffix: str) -> None:
    files = list((tmp_path / "cache").rglob(f"*{suffix}"))
    assert files, f"no {suffix} file in the cache"
    for path in files:
        path.write_bytes(CORRUPT_BYTES)


def test_a_corrupt_cache_entry_is_discarded_recompiled_and_reported_in_one_line(tmp_path):
    """Issue 53, defect 6: damaged bytes in the cache's index (then data) files were an ``UnpicklingError``
    traceback in every command until the user deleted the cache; now one line, the kernel compiled again."""
    (tmp_path / "probe_kernel.py").write_text(PROBE_KERNEL)
    first = _run_probe(tmp_path)
    assert (first.returncode, first.stdout.strip(), first.stderr) == (0, "2", "")
    _corrupt(tmp_path, ".nbi")
    bare = _run_probe(tmp_path, import_aero=False)  # the fault, without aero's guard
    assert bare.returncode != 0 and "UnpicklingError" in bare.stderr
    for suffix in (".nbi", ".nbc"):
        _corrupt(tmp_path, suffix)
        run = _run_probe(tmp_path)
        assert run.returncode == 0 and run.stdout.strip() == "2", run.stderr
        lines = run.stderr.splitlines()
        assert len(lines) == 1 and "Traceback" not in run.stderr, run.stderr
        assert lines[0].startswith("hawksim: discarded a corrupt numba cache entry (probe_kernel.plus_one")
        assert str(tmp_path / "cache") in lines[0]
        again = _run_probe(tmp_path)  # the entry was saved afresh: loaded quietly
        assert (again.returncode, again.stdout.strip(), again.stderr) == (0, "2", "")
