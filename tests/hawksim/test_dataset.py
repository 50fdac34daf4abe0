"""`hawksim dataset`: samples are pure functions of (seed, speed, i); the file is resumable after SIGKILL, never
holds a sample twice, and a file that is not a hawksim data set is refused with a clear error (exit 2)."""

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from hawksim.backends.resolution import Resolution
from hawksim.cli import main
from hawksim.insect.kinematics import PARAM_NAMES, bounds_si
from hawksim.surrogate.dataset import (
    APPLICATION_ID,
    JOURNAL_MODE,
    OUTPUTS,
    PEAK_FORCE_CEILING,
    SETTLE_TOL,
    DatasetError,
    Sample,
    file_sha256,
    generate,
    insert_sample,
    open_dataset,
    read_samples,
    sample_kinematics,
    speeds_in,
)

TINY = Resolution(n_chord=2, n_span=3, steps_per_cycle=20, cycles=1)
"""A coarse UVLM (~10 ms per sample): the pipeline's logic, not its accuracy, is under test here."""
TINY_ARGS = ["--n-chord", "2", "--n-span", "3", "--steps-per-cycle", "20", "--cycles", "1"]

UNIFORM_MEAN_SE = 4
"""Standard errors (sqrt(1/12/n) of a uniform variable): each parameter's sample mean over 2000 draws vs the box
centre. A 4-sigma bound: a false alarm has probability ~6e-5 per parameter, ~4e-4 for the seven (normal
approximation); the samples are seeded, so the test is deterministic. Measured 1.26 at worst."""


def _hawksim_cmd():
    exe = Path(sys.executable).with_name("hawksim")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "hawksim.cli"]


def _rows(path):
    conn = sqlite3.connect(path)
    try:
        return conn.execute("SELECT speed, seed, idx FROM samples ORDER BY idx").fetchall()
    finally:
        conn.close()


def test_sample_is_a_pure_function_of_seed_speed_index():
    a = sample_kinematics(0, 1.0, 17).as_array()
    assert np.array_equal(a, sample_kinematics(0, 1.0, 17).as_array())
    for other in (sample_kinematics(1, 1.0, 17), sample_kinematics(0, 1.5, 17), sample_kinematics(0, 1.0, 18)):
        assert not np.allclose(a, other.as_array())
    lo, hi = bounds_si()
    x = np.array([sample_kinematics(3, 0.5, i).as_array() for i in range(2000)])
    assert np.all(x >= lo) and np.all(x <= hi)
    # uniform in the box: each parameter's mean within UNIFORM_MEAN_SE standard errors of the box centre
    u = (x - lo) / (hi - lo)
    assert np.all(np.abs(u.mean(axis=0) - 0.5) < UNIFORM_MEAN_SE * np.sqrt(1 / 12 / len(u)))
    with pytest.raises(ValueError, match="seed"):
        sample_kinematics(-1, 0.0, 0)


def test_generate_is_deterministic_and_continues_without_duplicates(tmp_path):
    a, b = tmp_path / "a.sqlite", tmp_path / "b.sqlite"
    ra = generate(a, 1.0, 12, seed=5, resolution=TINY, workers=2)
    assert (ra.samples, ra.new) == (12, 12)
    # the same 12 in two installments (6, then the 6 missing), in another order of arrival
    generate(b, 1.0, 6, seed=5, resolution=TINY, workers=1)
    rb = generate(b, 1.0, 12, seed=5, resolution=TINY, workers=2)
    assert (rb.samples, rb.new) == (12, 6)
    assert file_sha256(a) == file_sha256(b)
    again = generate(b, 1.0, 12, seed=5, resolution=TINY, workers=1)
    assert again.new == 0 and again.samples == 12
    t = read_samples(b)
    assert t.x.shape == (12 - t.n_left_out, 7) and t.y.shape == (12 - t.n_left_out, 4)
    assert speeds_in(b) == [1.0]
    # another resolution for the same (speed, seed) would mix data: refused
    with pytest.raises(DatasetError, match="resolution"):
        generate(b, 1.0, 13, seed=5, resolution=Resolution(n_chord=2, n_span=4, steps_per_cycle=20, cycles=1),
                 workers=1)
    # samples of another hawksim version (another UVLM) are not continued either
    conn = sqlite3.connect(b)
    conn.execute("UPDATE samples SET version='0.0.1' WHERE idx=3")
    conn.commit()
    conn.close()
    with pytest.raises(DatasetError, match="0.0.1"):
        generate(b, 1.0, 13, seed=5, resolution=TINY, workers=1)


def test_sigkill_mid_run_then_rerun_gives_exact_count_and_same_data(tmp_path):
    path = tmp_path / "killed.sqlite"
    n = 60
    cmd = [*_hawksim_cmd(), "dataset", "--speed", "0.5", "--samples", str(n), "--out", str(path), "--seed", "2",
           "--workers", "1", "--no-progress", "--json", *TINY_ARGS]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    t0 = time.monotonic()
    got = 0
    while time.monotonic() - t0 < 120:
        time.sleep(0.2)
        if path.exists():
            try:
                got = len(_rows(path))
            except sqlite3.OperationalError:
                continue
            if got >= 5:
                break
    os.killpg(p.pid, signal.SIGKILL)  # the CLI and its Dask workers, mid-run
    p.wait(timeout=30)
    assert 5 <= got < n, f"the run was not caught mid-way ({got} rows)"
    partial = len(_rows(path))
    assert partial < n
    q = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert q.returncode == 0, q.stderr
    out = json.loads(q.stdout)
    assert out["samples"] == n and out["new"] == n - partial
    rows = _rows(path)
    assert len(rows) == n and len(set(rows)) == n and [r[2] for r in rows] == list(range(n))
    # the resumed file holds exactly what an uninterrupted run computes
    ref = tmp_path / "ref.sqlite"
    generate(ref, 0.5, n, seed=2, resolution=TINY, workers=2)
    assert file_sha256(ref) == file_sha256(path)


def test_foreign_and_corrupt_files_are_refused(tmp_path, capsys):
    garbage = tmp_path / "garbage.sqlite"
    garbage.write_bytes(b"this is not a database" * 50)
    foreign = tmp_path / "foreign.sqlite"
    conn = sqlite3.connect(foreign)
    conn.execute("CREATE TABLE t (a)")
    conn.commit()
    conn.close()
    empty = tmp_path / "empty.sqlite"
    sqlite3.connect(empty).execute("PRAGMA user_version=0").connection.close()
    truncated = tmp_path / "truncated.sqlite"
    generate(truncated, 0.0, 3, seed=0, resolution=TINY, workers=1)
    data = truncated.read_bytes()
    truncated.write_bytes(data[:100] + b"\xff" * 200 + data[300:])  # header kept, schema page damaged

    for f in (garbage, foreign):
        with pytest.raises(DatasetError, match=f.name):
            open_dataset(f)
        before = f.read_bytes()
        assert main(["dataset", "--speed", "0", "--samples", "3", "--out", str(f), "--json", "--no-progress",
                     *TINY_ARGS]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f.name in err[0]
        assert f.read_bytes() == before  # nothing written into someone else's file
    for f in (foreign, empty, truncated, tmp_path / "missing.sqlite"):
        assert main(["train", "--data", str(f), "--out", str(tmp_path / "m.safetensors"), "--json"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f.name in err[0]
        assert not (tmp_path / "m.safetensors").exists()


def test_file_carries_the_application_id(tmp_path):
    path = tmp_path / "d.sqlite"
    generate(path, 2.0, 2, seed=0, resolution=TINY, workers=1)
    conn = sqlite3.connect(path)
    assert conn.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == JOURNAL_MODE.lower()  # no -wal / -shm beside it
    res = json.loads(conn.execute("SELECT resolution FROM samples LIMIT 1").fetchone()[0])
    conn.close()
    assert res == TINY.to_dict()


def test_status_marks_labels_that_still_change_between_wingbeats():
    x = (26.0,) * 7
    y = (1.0, 0.1, 0.0, 0.9)
    ok = Sample(0.0, 0, 0, x, y, 0.08, 1.0, peak_cf=1.5, y_prev=(1.0 + 0.5 * SETTLE_TOL, 0.1, 0.0, 0.9))
    assert ok.status == "ok" and ok.ok
    moving = Sample(0.0, 0, 1, x, y, 0.08, 1.0, peak_cf=1.5, y_prev=(1.0, 0.1, 0.0, 0.9 + 1.5 * SETTLE_TOL))
    assert moving.status == "unsettled" and not moving.ok
    blown = Sample(0.0, 0, 2, x, y, 0.08, 1.0, peak_cf=2 * PEAK_FORCE_CEILING, y_prev=(0.0,) * 4)
    assert blown.status == "diverged"
    assert Sample(0.0, 0, 3, x, y, 0.08, 1.0, peak_cf=1.5).status == "ok"  # one wingbeat: nothing to compare


def test_rows_hold_the_previous_wingbeat_and_unsettled_samples_are_left_out(tmp_path):
    from hawksim.backends.held import beat_averages

    res = Resolution(n_chord=2, n_span=3, steps_per_cycle=20, cycles=2)
    path = tmp_path / "d.sqlite"
    generate(path, 0.5, 3, seed=1, resolution=res, workers=1)
    conn = sqlite3.connect(path)
    rows = conn.execute(f"SELECT idx, {', '.join(OUTPUTS)}, {', '.join(n + '_prev' for n in OUTPUTS)}, status "
                        "FROM samples ORDER BY idx").fetchall()
    conn.close()
    beats = beat_averages(sample_kinematics(1, 0.5, 0), 0.5, res, beats=3)  # one more beat than stored
    assert rows[0][1:5] == tuple(beats[1]) and rows[0][5:9] == tuple(beats[0])  # exact: later beats change nothing
    assert {r[9] for r in rows} <= {"ok", "unsettled", "diverged"}
    # a stored 'unsettled' sample is not training data
    before = read_samples(path)
    n_ok = len(before.y)
    conn = open_dataset(path)
    insert_sample(conn, Sample(0.5, 1, 99, (26.0,) * 7, (1.0, 0.0, 0.0, 1.0), 0.08, 1.0, peak_cf=1.0,
                               y_prev=(0.5, 0.0, 0.0, 1.0)), res)
    conn.close()
    t = read_samples(path)
    assert len(t.y) == n_ok and 99 not in t.idx and t.n_left_out == 3 - n_ok + 1
    assert t.n_unsettled == before.n_unsettled + 1 and t.n_diverged == before.n_diverged


LAYOUT_1_ROWS = 50
"""Rows of the generated layout-1 fixture (the first samples of the shipped 0.3 set at 1 m/s)."""


def layout_1_file(path: Path) -> Path:
    """A layout-1 data set (hawksim 0.2.0's: no ``*_prev`` columns, ``user_version`` 1) of LAYOUT_1_ROWS rows
    copied from the shipped 0.3 set: the small generated fixture that replaces the superseded 0.2 file."""
    import sqlite3

    src = sqlite3.connect(Path(__file__).resolve().parents[2] / "data" / "uvlm_training_0.3.sqlite")
    cols = ["speed", "seed", "idx", *PARAM_NAMES, *OUTPUTS, "power_W", "peak_cf", "status", "resolution", "version",
            "wall_s"]
    rows = src.execute(f"SELECT {', '.join(cols)} FROM samples WHERE speed = 1.0 AND status = 'ok' ORDER BY idx "
                       f"LIMIT {LAYOUT_1_ROWS}").fetchall()
    src.close()
    schema = ", ".join(f"{c} {'TEXT' if c in ('status', 'resolution', 'version') else 'REAL'}" for c in cols)
    conn = sqlite3.connect(path)
    with conn:
        conn.execute(f"CREATE TABLE samples ({schema}, PRIMARY KEY (speed, seed, idx))")
        conn.executemany(f"INSERT INTO samples VALUES ({', '.join('?' * len(cols))})", rows)
        conn.execute(f"PRAGMA application_id={APPLICATION_ID}")
        conn.execute("PRAGMA user_version=1")
    conn.close()
    return path


def test_layout_1_files_are_read_but_not_continued(tmp_path, capsys):
    """hawksim 0.2.0's data sets (layout 1) are read as they are; continuing one would mix rows with and without
    the previous wingbeat: refused, the file untouched."""
    old = layout_1_file(tmp_path / "old.sqlite")
    assert len(read_samples(old, speed=1.0).y) == LAYOUT_1_ROWS
    before = old.read_bytes()
    with pytest.raises(DatasetError, match="layout 1"):
        generate(old, 1.0, 3001, seed=0, resolution=TINY, workers=1)
    assert main(["dataset", "--speed", "1", "--samples", "3001", "--out", str(old), "--json", "--no-progress",
                 *TINY_ARGS]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "layout 1" in err[0]
    assert old.read_bytes() == before


SHIPPED_NETWORK_DATA = {"uvlm_training_0.3.sqlite": ("samples", 15000), "uvlm_flights_0.2.0.sqlite": ("flights", 700),
                        "uvlm_reference_0.1.sqlite": ("samples", 5000),
                        "uvlm_reference_heldout_s22.sqlite": ("samples", 500),
                        "uvlm_training_heldout_s22.sqlite": ("samples", 500)}
"""The committed data sets and their row counts (hawksim/insects/hawkmoth/data/surrogates/README.md)."""


@pytest.mark.parametrize("name", sorted(SHIPPED_NETWORK_DATA))
def test_the_shipped_data_sets_are_in_rollback_journal_mode(name):
    """A reader of a WAL-mode file needs a -shm file beside it, so the shipped sets could not be read from a
    read-only disk (one line, exit 1: issue 18); in rollback mode a reader writes nothing. The SQLite header's
    bytes 18-19 (write and read format versions) are 1 for the rollback journal, 2 for WAL
    (https://www.sqlite.org/fileformat.html, section 1.3)."""
    path = Path(__file__).resolve().parents[2] / "data" / name
    header = path.read_bytes()[:100]
    assert header[18:20] == b"\x01\x01", f"{name} is in WAL mode: PRAGMA journal_mode=DELETE on it"
    table, rows = SHIPPED_NETWORK_DATA[name]
    conn = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        assert conn.execute(f"SELECT count(*) FROM {table}").fetchone()[0] == rows
    finally:
        conn.close()
    assert not list(path.parent.glob(name + "-*"))  # no -wal / -shm / -journal made by reading
