"""A full disk under `hawksim fly --rrd` and `hawksim dataset --out` (issue 18): exit 1 (the environment), one line on
stderr naming the file, nothing half-written (no partial .rrd, no hidden temporary file; for the data set no
-journal, -wal or -shm beside it, the rows committed before intact and readable, and a rerun continues).

Two honest ways to fill a disk without root privileges:

* RLIMIT_FSIZE: hawksim runs in a subprocess whose files may not grow past :data:`LIMIT` bytes, with SIGXFSZ
  ignored (its default action kills the process), so a write past the limit fails with EFBIG exactly where a write
  to a full disk fails with ENOSPC (the same system calls, the same error paths). The limit is above the largest
  numba cache file (~126 kB), so a cold cache can still be written.
* A real full file system: a 1 MiB tmpfs mounted in a private user and mount namespace (``unshare -rm``), filled
  with a filler file; ENOSPC. Skipped where unprivileged namespaces are not allowed.
"""

from __future__ import annotations

import json
import resource
import shutil
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from hawksim.backends.resolution import Resolution
from hawksim.surrogate.dataset import Sample, file_sha256, insert_sample, open_dataset

LIMIT = 1 << 20
"""Bytes a file of the limited hawksim may reach (1 MiB): above numba's largest cache file (126 kB), below a
12-beat quasi-steady recording (~1.6 MB) and a 2-beat UVLM recording with its panels and wake (~2.7 MB)."""

TINY = ["--n-chord", "2", "--n-span", "3", "--steps-per-cycle", "20", "--cycles", "1"]
TINY_RES = Resolution(n_chord=2, n_span=3, steps_per_cycle=20, cycles=1)
HAWKSIM = str(Path(sys.executable).with_name("hawksim"))


def run_limited(argv: list[str], limit: int = LIMIT, timeout: float = 300) -> subprocess.CompletedProcess:
    """`hawksim ARGV` whose files may not grow past ``limit`` bytes (RLIMIT_FSIZE, SIGXFSZ ignored: EFBIG)."""
    def limit_files():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run([HAWKSIM, *argv], preexec_fn=limit_files, capture_output=True, text=True, timeout=timeout)


def one_line(p: subprocess.CompletedProcess) -> str:
    lines = p.stderr.strip().splitlines()
    assert p.stdout == "" and len(lines) == 1, p.stderr
    return lines[0]


@pytest.mark.parametrize("flight", [["--cycles", "12"], ["--cycles", "12", "--control", "none"],
                                    ["--cycles", "2", "--aero", "uvlm"]],
                         ids=["quasi-steady-lqr", "quasi-steady-open-loop", "uvlm"])
def test_a_full_disk_under_a_recording(tmp_path, flight):
    rrd = tmp_path / "flight.rrd"
    p = run_limited(["fly", "--speed", "1", *flight, "--rrd", str(rrd), "--json", "--no-progress"])
    line = one_line(p)
    assert p.returncode == 1 and str(rrd) in line and "File too large" in line, p.stderr
    assert list(tmp_path.iterdir()) == []  # no partial recording, no hidden temporary file


def _filled_dataset(path: Path, rows: int) -> str:
    """A data set holding ``rows`` stand-in rows of speed 1 seed 99 (written directly, no UVLM); their sha256."""
    conn = open_dataset(path, create=True)
    conn.execute("PRAGMA synchronous=OFF")  # fast to fill; the runs under test use the default
    for i in range(rows):
        insert_sample(conn, Sample(1.0, 99, i, (26.0, 0.1, 0.2, 0.0, 0.0, 1.0, 0.8), (1.0, 0.1, 0.0, 0.9), 0.08,
                                   0.5, peak_cf=1.5, y_prev=(1.0, 0.1, 0.0, 0.9)), TINY_RES)
    conn.close()
    return file_sha256(path, 1.0, 99)


def _rows(path: Path, seed: int) -> int:
    with sqlite3.connect(path) as c:
        assert c.execute("PRAGMA integrity_check").fetchone() == ("ok",)
        return c.execute("SELECT count(*) FROM samples WHERE seed=?", (seed,)).fetchone()[0]


def test_a_full_disk_under_a_new_data_set_leaves_nothing(tmp_path):
    out = tmp_path / "d.sqlite"
    p = run_limited(["dataset", "--speed", "1", "--samples", "4", "--out", str(out), "--workers", "1", "--json",
                     "--no-progress", *TINY], limit=4096)  # the schema alone needs two pages and a journal
    line = one_line(p)
    assert p.returncode == 1 and str(out) in line and "cannot write data set" in line
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_under_a_new_flights_data_set_leaves_nothing(tmp_path):
    """Issue 53, defect 3: `dataset --kind flights` let SQLite's "disk I/O error" (a file-size limit; "database or
    disk is full" on a full tmpfs) out as a traceback and left the file it had begun. Now as the samples kind: one
    line naming the file, exit 1, nothing left. (The limit stops the schema's write, before any flight is flown; a
    commit later in the run takes the same path.)"""
    out = tmp_path / "f.sqlite"
    p = run_limited(["dataset", "--kind", "flights", "--samples", "2", "--out", str(out), "--workers", "1",
                     "--json", "--no-progress"], limit=4096)
    line = one_line(p)
    assert p.returncode == 1 and str(out) in line and "cannot write data set" in line and "SQLITE_IOERR" in line
    assert "Traceback" not in p.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_under_an_existing_data_set_keeps_its_rows_and_a_rerun_continues(tmp_path):
    out = tmp_path / "d.sqlite"
    sha = _filled_dataset(out, 1000)  # ~0.3 MB: above numba's largest cache file, as LIMIT
    size = out.stat().st_size
    p = run_limited(["dataset", "--speed", "1", "--samples", "400", "--out", str(out), "--workers", "1", "--json",
                     "--no-progress", *TINY], limit=size)  # no room to grow
    line = one_line(p)
    assert p.returncode == 1 and str(out) in line and "SQLITE_IOERR" in line
    assert [q.name for q in tmp_path.iterdir()] == ["d.sqlite"]  # no -journal, -wal, -shm
    assert file_sha256(out, 1.0, 99) == sha and _rows(out, 99) == 1000  # the rows before: intact, readable
    stored = _rows(out, 0)  # what fitted in the free space of the file's pages (committed one by one)
    assert stored < 400
    r = subprocess.run([HAWKSIM, "dataset", "--speed", "1", "--samples", str(stored + 3), "--out", str(out),
                        "--workers", "1", "--json", "--no-progress", *TINY], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["new"] == 3 and _rows(out, 0) == stored + 3


INNER = r'''
import json, os, sqlite3, subprocess, sys
hawksim, mnt, report, data = sys.argv[1:5]
subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", mnt], check=True)
out = {}
with open(data, "rb") as src, open(os.path.join(mnt, "d.sqlite"), "wb") as dst:
    dst.write(src.read())
try:  # fill the file system
    with open(os.path.join(mnt, "filler"), "wb") as fh:
        while True:
            fh.write(b"x" * 4096)
            fh.flush()
except OSError as exc:
    out["filler_errno"] = exc.errno
def run(*argv):
    p = subprocess.run([hawksim, *argv], capture_output=True, text=True, timeout=300)
    return {"rc": p.returncode, "stdout": p.stdout, "stderr": p.stderr, "files": sorted(os.listdir(mnt))}
tiny = ["--n-chord", "2", "--n-span", "3", "--steps-per-cycle", "20", "--cycles", "1"]
db = os.path.join(mnt, "d.sqlite")
out["dataset"] = run("dataset", "--speed", "1", "--samples", "400", "--out", db, "--workers", "1", "--json",
                     "--no-progress", *tiny)
try:
    with sqlite3.connect(db) as c:
        out["integrity"] = c.execute("PRAGMA integrity_check").fetchone()[0]
        out["rows"] = dict(c.execute("SELECT seed, count(*) FROM samples GROUP BY seed").fetchall())
    from hawksim.surrogate.dataset import file_sha256
    out["sha99"] = file_sha256(db, 1.0, 99)
except Exception as exc:  # reported, so that the test says what failed
    out["integrity"], out["rows"] = repr(exc), {}
out["fly"] = run("fly", "--speed", "1", "--cycles", "2", "--rrd", os.path.join(mnt, "f.rrd"), "--json",
                 "--no-progress")
os.unlink(os.path.join(mnt, "filler"))  # room again: the same command continues
out["rerun"] = run("dataset", "--speed", "1", "--samples", str(out["rows"].get(0, 0) + 2), "--out", db,
                   "--workers", "1", "--json", "--no-progress", *tiny)
with open(report, "w") as fh:
    json.dump(out, fh)
'''


def _namespaces() -> bool:
    return shutil.which("unshare") is not None and subprocess.run(
        ["unshare", "-rm", "true"], capture_output=True).returncode == 0


@pytest.mark.skipif(not _namespaces(), reason="unprivileged user and mount namespaces (unshare -rm) not allowed")
def test_a_really_full_file_system(tmp_path):
    """ENOSPC on a full tmpfs: the data set's failed commit is rolled back (hawksim <= 0.3's WAL journal left -wal and
    -shm here, its checkpoint having no room), the recording leaves nothing, and a rerun with room continues."""
    mnt, report, data = tmp_path / "mnt", tmp_path / "report.json", tmp_path / "seed.sqlite"
    mnt.mkdir()
    sha = _filled_dataset(data, 200)
    (tmp_path / "inner.py").write_text(INNER)
    subprocess.run(["unshare", "-rm", sys.executable, str(tmp_path / "inner.py"), HAWKSIM, str(mnt), str(report),
                    str(data)], check=True, timeout=900)
    r = json.loads(report.read_text())
    assert r["filler_errno"] == 28  # ENOSPC: the file system is full
    d = r["dataset"]
    lines = d["stderr"].strip().splitlines()
    assert d["rc"] == 1 and d["stdout"] == "" and len(lines) == 1, d
    assert "d.sqlite" in lines[0] and "SQLITE_FULL" in lines[0]
    assert d["files"] == ["d.sqlite", "filler"] and r["integrity"] == "ok" and r["rows"]["99"] == 200
    f = r["fly"]
    lines = f["stderr"].strip().splitlines()
    assert f["rc"] == 1 and len(lines) == 1 and "f.rrd" in lines[0] and "No space left" in lines[0], f
    assert f["files"] == ["d.sqlite", "filler"]
    assert r["sha99"] == sha  # the rows committed before the disk filled: unchanged
    assert r["rerun"]["rc"] == 0 and json.loads(r["rerun"]["stdout"])["new"] == 2, r["rerun"]


def test_a_full_disk_under_a_trained_network(tmp_path):
    """`hawksim train --out` (safetensors, encoded in memory and written all or nothing by hawksim.atomic): exit 1,
    one line naming the file, no model file and no temporary file (safetensors' own writer raised SafetensorError
    with a traceback). The data set (rollback journal) is read without writing anything."""
    data = tmp_path / "d.sqlite"
    conn = open_dataset(data, create=True)
    for i in range(60):  # stand-in rows: the fit does not matter here
        u = ((i * 37) % 60) / 60  # every input and output varies (R^2 needs a spread)
        insert_sample(conn, Sample(1.0, 0, i, (20.0 + 0.1 * i, 0.1 * u, 0.2, 0.1 * u, 0.0, 1.0 - 0.1 * u, 0.8),
                                   (1.0 + 0.01 * i, 0.1 + u, u * u, 0.9 - u), 0.08, 0.5, peak_cf=1.5), TINY_RES)
    conn.close()
    out = tmp_path / "m.safetensors"
    p = run_limited(["train", "--data", str(data), "--out", str(out), "--hidden", "20", "--max-iter", "1", "--json",
                     "--no-progress"], limit=1024)  # the 7-20-4 network takes ~2.6 kB
    line = one_line(p)
    assert p.returncode == 1 and str(out) in line and "File too large" in line, p.stderr
    assert [q.name for q in tmp_path.iterdir()] == ["d.sqlite"]


REPRODUCE = r"""
import json, resource, signal, sys
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
import hawksim.paper.reproduce as rp
# the writing under test, not the UVLM (`hawksim reproduce --only uvlm_table4` flies 20 UVLM beats, ~1 min): a
# stand-in table of the real one's size (~20 kB)
rp.table4_comparison = lambda: {"rows": [{"speed": v, "per_cycle": [[0.123456789] * 4] * 40} for v in range(5)]}
sys.argv = ["hawksim", "reproduce", "--only", "uvlm_table4", "--out", sys.argv[1], *sys.argv[2:]]
from hawksim.__main__ import run
sys.exit(run())
"""


@pytest.mark.parametrize("existing", [False, True], ids=["new-out", "existing-out-force"])
def test_a_full_disk_under_reproduce(tmp_path, existing):
    """`hawksim reproduce` on a full disk: exit 1, the failure in one last line naming the file (after the command's
    progress lines), no traceback; the directory it made is removed again, and with --force an earlier file is left
    as it was (each file is written all or nothing, hawksim.atomic)."""
    out = tmp_path / "r"
    extra = []
    if existing:
        out.mkdir()
        (out / "uvlm_table4.json").write_text('{"old": 1}')
        extra = ["--force"]
    p = subprocess.run([sys.executable, "-c", REPRODUCE, str(out), *extra], capture_output=True, text=True,
                       timeout=120)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 1 and p.stdout == "" and "Traceback" not in p.stderr, p.stderr
    assert lines[:-1] == [f"hawksim reproduce: uvlm_table4 into {out}/, about 1 min on 2 cores", "uvlm_table4 ..."]
    assert str(out / "uvlm_table4.json") in lines[-1] and "File too large" in lines[-1], lines[-1]
    if existing:
        assert [q.name for q in out.iterdir()] == ["uvlm_table4.json"]
        assert (out / "uvlm_table4.json").read_text() == '{"old": 1}'
    else:
        assert list(tmp_path.iterdir()) == []
