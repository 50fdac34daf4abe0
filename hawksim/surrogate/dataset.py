"""UVLM training samples for the surrogate: resumable, parallel, in one SQLite file.

Sample ``i`` of a data set is a pure function of ``(seed, speed, i)``: its kinematics are drawn uniformly within
Table 2's bounds (Nguyen et al. 2020) by ``numpy.random.default_rng([seed, speed_mm_s, i])``
(:func:`sample_kinematics`), so any subset of indices can be computed in any order, on any machine, and the
result is the same file.

The file (SQLite, rollback journal: :data:`JOURNAL_MODE`) holds one row per sample, keyed by (speed, seed, idx)
so a sample can never be stored twice. Only the process that owns the file writes it; workers only compute. Each
sample is committed as soon as it arrives, so a run killed at any moment (SIGKILL included) loses at most the
samples in flight, and the same command continues with the missing indices. A write that fails for the
environment (a full disk) stops the run with OSError naming the file (:func:`generate`); the rows committed
before stay, and the same command continues once there is room.

Row contents: the speed [m/s], seed, index; the seven kinematic parameters in SI (f [Hz], angles [rad], in the
order of :data:`hawksim.insect.kinematics.PARAM_NAMES`); L+, D+, M+, P+ (paper Eq. 2) and the power [W] averaged over
the last wingbeat(s); the peak force coefficient (see :data:`PEAK_FORCE_CEILING`); from layout 2 on, the same
four averages one wingbeat earlier (``*_prev``: the window of averaged wingbeats moved back by one); ``status``
'ok', 'diverged' (the UVLM blew up, or its peak force exceeds the ceiling; its loads are NULL if non-finite) or
'unsettled' (a cycle average still changes by more than :data:`SETTLE_TOL` from one wingbeat to the next: the
label is not yet periodic); only 'ok' samples are used for training; the resolution as JSON; the hawksim
version; the evaluation's wall time [s]. Layout 1 files (hawksim 0.2's data sets, no ``*_prev``, no
'unsettled') are read as they are, not written.
"""

from __future__ import annotations

import errno
import functools
import itertools
import json
import math
import sqlite3
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hawksim import __version__
from hawksim.backends.averages import OUTPUTS
from hawksim.backends.resolution import Resolution
from hawksim.insect.folder import default_insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics

APPLICATION_ID = 0x48574B53
"""``PRAGMA application_id`` of a hawksim data set ('HWKS'): tells our files from other SQLite files."""

SCHEMA_VERSION = 2
"""``PRAGMA user_version`` of the layout written (2: adds the ``*_prev`` averages and the 'unsettled' status)."""

READABLE_VERSIONS = (1, 2)
"""Layouts read (layout 1: hawksim 0.2.0's data sets, on which the shipped 0.2 networks were trained)."""

PEAK_FORCE_CEILING = 4.0
"""Largest credible peak force coefficient: the peak of |total aerodynamic force| over the run divided by the
tip dynamic pressure 0.5 rho (2 pi f phi_a R)^2 and the two wings' area. Across 100 hover samples (the worst
case: the wings meet their own wake) healthy runs peak at 0.6-2.9 (translational + rotational + added-mass
loads of a revolving wing stay below C_F ~ 3, Dickinson et al. 1999, Sane & Dickinson 2002) while runs in which
a wake vortex crossing the lattice sets off a numerical blow-up reach 5 to 2000; those are stored as
'diverged' and left out of training."""

SETTLE_TOL = 0.1
"""Largest change of any of L+, D+, M+, P+ between the averaged wingbeat and the one before it for a label to
count as periodic ('ok'; otherwise 'unsettled'). Measured on the 1451 held-out samples of the 0.2 data set
(``python scripts/studies/label_periodicity.py``, results/surrogate/label_periodicity.json): the beat 2 -> 3
change of L+ has median 0.004-0.012 and 99th percentile 0.06-0.13 per speed, it is correlated with the beat
3 -> 4 change (r = 0.39-0.78: the same runs keep changing), and 0.1 leaves out 0-10 % of the samples (most at
hover, where the wake stays under the wings)."""

JOURNAL_MODE = "DELETE"
"""SQLite journal of a data set being written: the rollback journal. A commit that fails on a full disk
(SQLITE_FULL, or SQLITE_IOERR_WRITE where a file-size limit stops the write) is rolled back from the journal and
the journal deleted, leaving the file as the last commit left it and nothing beside it. In WAL mode (hawksim <=
0.3) committed rows wait in the -wal file for a checkpoint into the main file; on a full 256 kB tmpfs that
checkpoint failed and -wal and -shm stayed behind (tests/hawksim/test_disk_full.py). Readers never change a file's
journal mode; a writer turns a WAL file into this mode."""

_SCHEMA = f"""
CREATE TABLE samples (
    speed REAL NOT NULL,
    seed INTEGER NOT NULL,
    idx INTEGER NOT NULL,
    {", ".join(f"{n} REAL NOT NULL" for n in PARAM_NAMES)},
    {", ".join(f"{n} REAL" for n in OUTPUTS)},
    power_W REAL,
    peak_cf REAL,
    {", ".join(f"{n}_prev REAL" for n in OUTPUTS)},
    status TEXT NOT NULL,
    resolution TEXT NOT NULL,
    version TEXT NOT NULL,
    wall_s REAL NOT NULL,
    PRIMARY KEY (speed, seed, idx)
);
"""


class DatasetError(ValueError):
    """A data-set file that cannot be used (not SQLite, not ours, another layout, another resolution)."""


@dataclass(frozen=True)
class Sample:
    """One evaluated sample. x: the seven parameters (SI, PARAM_NAMES order); y: (L+, D+, M+, P+) or None when
    the UVLM diverged; power_W [W] or None; wall_s: evaluation time [s]; y_prev: the averages one wingbeat
    earlier (None if the run has no earlier window or diverged)."""

    speed: float
    seed: int
    idx: int
    x: tuple[float, ...]
    y: tuple[float, float, float, float] | None
    power_W: float | None
    wall_s: float
    peak_cf: float | None = None
    y_prev: tuple[float, float, float, float] | None = None

    @property
    def status(self) -> str:
        """'diverged', 'unsettled' or 'ok' (:func:`label_status`)."""
        return label_status(self.y, self.peak_cf, self.y_prev)

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def speed_key(speed: float) -> int:
    """The speed in integer mm/s: the seed component and the exact-match key of a speed."""
    return int(round(float(speed) * 1000.0))


def sample_kinematics(seed: int, speed: float, i: int) -> Kinematics:
    """Kinematics of sample i: uniform within Table 2's bounds, a pure function of (seed, speed, i)."""
    if seed < 0 or i < 0:
        raise ValueError(f"seed and sample index must be >= 0, got seed={seed}, i={i}")
    lo, hi = default_insect().bounds_si()
    u = np.random.default_rng([int(seed), speed_key(speed), int(i)]).random(len(PARAM_NAMES))
    return Kinematics.from_array(lo + u * (hi - lo))


def evaluate_sample(seed: int, speed: float, i: int, resolution: Resolution) -> Sample:
    """Evaluate sample i by the UVLM (body held at ascent speed ``speed``). Runs on a worker."""
    return evaluate_kinematics(sample_kinematics(seed, speed, i), speed, resolution, seed, i)


def evaluate_kinematics(kin: Kinematics, speed: float, resolution: Resolution, seed: int = 0, i: int = 0
                        ) -> Sample:
    """A data-set sample's evaluation of any kinematics: its labels, peak force coefficient and the averages one
    wingbeat earlier, so that :attr:`Sample.status` applies the data set's rule to it (seed, i: the sample's
    identifiers, recorded only)."""
    from hawksim.backends.held import run

    t0 = time.perf_counter()
    peak = prev = None
    try:
        y, power, peak, prev = held_labels(run(kin, speed, resolution), resolution.average_cycles)
    except FloatingPointError:
        y, power = None, None
    return Sample(float(speed), int(seed), int(i), tuple(float(v) for v in kin.as_array()), y, power,
                  time.perf_counter() - t0, peak, prev)


def held_labels(r, average_cycles: int) -> tuple:
    """What a data set records of a held-body run r (:class:`hawksim.backends.held.HeldResult`) averaged over its
    last ``average_cycles`` wingbeats: (y = (L+, D+, M+, P+), power_W [W], the peak force coefficient (see
    :data:`PEAK_FORCE_CEILING`), the averages one wingbeat earlier or None when the run has no earlier window);
    all None when any of them is not finite. :func:`label_status` turns them into the data set's status."""
    from hawksim.insect.morphology import RHO_AIR

    morph = default_insect().morphology

    a, kin, k = r.averages, r.kinematics, average_cycles
    y = (a.L_plus, a.D_plus, a.M_plus, a.P_plus)
    prev = None
    if len(r.per_cycle) > k:  # the averaged window moved back by one wingbeat (equal-length beats: mean)
        prev = tuple(float(np.mean([getattr(c, n) for c in r.per_cycle[-k - 1:-1]])) for n in OUTPUTS)
    u_tip = 2.0 * math.pi * kin.f * kin.phi_a * morph.R
    peak = float(np.linalg.norm(r.force_world, axis=1).max()
                 / (0.5 * RHO_AIR * u_tip**2 * 2.0 * morph.wing_area))
    if not all(math.isfinite(v) for v in (*y, a.power_W, peak, *(prev or ()))):
        return None, None, None, None
    return y, a.power_W, peak, prev


def held_status(r, average_cycles: int) -> tuple[str, float | None]:
    """The data set's status of a held-body run r (:func:`label_status` of :func:`held_labels`) and its peak force
    coefficient (None when not finite): the verdict `hawksim aero` and `hawksim trim --verify` print."""
    y, _, peak, prev = held_labels(r, average_cycles)
    return label_status(y, peak, prev), peak


def label_status(y, peak_cf, y_prev) -> str:
    """The data set's status of a label (module docstring): 'diverged' (no finite label, or a peak force
    coefficient above :data:`PEAK_FORCE_CEILING`), 'unsettled' (it differs from the averages one wingbeat earlier
    by more than :data:`SETTLE_TOL`) or 'ok'."""
    if y is None or peak_cf is None or peak_cf > PEAK_FORCE_CEILING:
        return "diverged"
    if y_prev is not None and max(abs(a - b) for a, b in zip(y, y_prev)) > SETTLE_TOL:
        return "unsettled"
    return "ok"


# --------------------------------------------------------------------------------------------- the file


def open_dataset(path: str | Path, *, create: bool = False) -> sqlite3.Connection:
    """Open (or with ``create`` make, for writing) a data-set file; DatasetError for a file that is not one of ours.
    sqlite3.OperationalError when the file cannot be made (a full disk: :func:`environment_error`)."""
    path = Path(path)
    exists = path.exists() and path.stat().st_size > 0
    if not exists and not create:
        raise DatasetError(f"data set {str(path)!r} does not exist")
    if exists:
        with open(path, "rb") as fh:
            if fh.read(16) != b"SQLite format 3\x00":
                raise DatasetError(f"{str(path)!r} is not a SQLite file (corrupt or another format)")
    try:
        conn = sqlite3.connect(path, timeout=30.0)
        app_id = conn.execute("PRAGMA application_id").fetchone()[0]
        version = conn.execute("PRAGMA user_version").fetchone()[0]
        n_tables = conn.execute("SELECT count(*) FROM sqlite_master").fetchone()[0]
    except sqlite3.DatabaseError as exc:
        env = environment_error(path, exc, writing=create) if isinstance(exc, sqlite3.OperationalError) else None
        if env is not None:  # e.g. a WAL file (hawksim <= 0.3) on a full disk: its -shm cannot be made
            raise env from None
        raise DatasetError(f"{str(path)!r} is not a readable SQLite file: {exc}") from None
    if app_id == 0 and version == 0 and n_tables == 0:
        if not create:
            conn.close()
            raise DatasetError(f"{str(path)!r} is an empty SQLite file, not a hawksim data set")
        with conn:
            conn.executescript(_SCHEMA)
            conn.execute(f"PRAGMA application_id={APPLICATION_ID}")
            conn.execute(f"PRAGMA user_version={SCHEMA_VERSION}")
    elif app_id != APPLICATION_ID:
        conn.close()
        raise DatasetError(f"{str(path)!r} is a SQLite file but not a hawksim data set (application_id {app_id:#x})")
    elif version not in READABLE_VERSIONS:
        conn.close()
        raise DatasetError(f"data set {str(path)!r} has layout version {version}; this hawksim reads "
                           f"{', '.join(map(str, READABLE_VERSIONS))}")
    else:
        try:
            _check_schema(conn, path)
        except DatasetError:
            conn.close()
            raise
    if create:  # the writer (see JOURNAL_MODE); if another connection holds a WAL file open the mode stays WAL
        conn.execute(f"PRAGMA journal_mode={JOURNAL_MODE}")
    return conn


SAMPLE_COLUMNS = ("speed", "seed", "idx", *PARAM_NAMES, *OUTPUTS, "status", "resolution", "version")
"""Columns of the samples table every reader and writer uses (:data:`_SCHEMA` has these and more): checked when a
file is opened, so that a damaged schema is one line naming the file, not ``no such table: samples`` deep in a
query (issue 53, defect 12)."""


def _check_schema(conn: sqlite3.Connection, path) -> None:
    """DatasetError naming ``path`` when its samples table, or a column of :data:`SAMPLE_COLUMNS`, is missing
    (every data set has one, the flights files too: an empty one)."""
    have = {r[1] for r in conn.execute("PRAGMA table_info(samples)")}
    if not have:
        raise DatasetError(f"data set {str(path)!r} has no samples table (its schema is damaged: start a new file "
                           "or restore it)")
    missing = [c for c in SAMPLE_COLUMNS if c not in have]
    if missing:
        raise DatasetError(f"data set {str(path)!r}: its samples table lacks the column(s) {', '.join(missing)} "
                           "(its schema is damaged: start a new file or restore it)")


def _where(speed: float | None = None, seed: int | None = None) -> tuple[str, list]:
    """SQL condition and arguments selecting one speed (matched in integer mm/s) and/or seed; '1' for all."""
    where, args = ["1"], []
    if speed is not None:
        where.append("CAST(round(speed*1000) AS INTEGER)=?")
        args.append(speed_key(speed))
    if seed is not None:
        where.append("seed=?")
        args.append(int(seed))
    return " AND ".join(where), args


def stored_indices(conn: sqlite3.Connection, speed: float, seed: int) -> set[int]:
    w, args = _where(speed, seed)
    return {r[0] for r in conn.execute(f"SELECT idx FROM samples WHERE {w}", args)}


def stored_resolution(conn: sqlite3.Connection, speed: float, seed: int) -> Resolution | None:
    w, args = _where(speed, seed)
    row = conn.execute(f"SELECT resolution FROM samples WHERE {w} LIMIT 1", args).fetchone()
    return None if row is None else Resolution(**json.loads(row[0]))


def stored_versions(conn: sqlite3.Connection, speed: float, seed: int) -> set[str]:
    """hawksim versions that computed the stored samples of (speed, seed)."""
    w, args = _where(speed, seed)
    return {r[0] for r in conn.execute(f"SELECT DISTINCT version FROM samples WHERE {w}", args)}


def insert_sample(conn: sqlite3.Connection, s: Sample, resolution: Resolution) -> None:
    """Store one sample and commit (INSERT OR IGNORE: a sample already stored is kept, never duplicated)."""
    y = s.y if s.y is not None else (None,) * len(OUTPUTS)
    y_prev = s.y_prev if s.y_prev is not None else (None,) * len(OUTPUTS)
    cols = ("speed", "seed", "idx", *PARAM_NAMES, *OUTPUTS, "power_W", "peak_cf", *(f"{n}_prev" for n in OUTPUTS),
            "status", "resolution", "version", "wall_s")
    vals = (s.speed, s.seed, s.idx, *s.x, *y, s.power_W, s.peak_cf, *y_prev, s.status,
            json.dumps(resolution.to_dict(), sort_keys=True), __version__, s.wall_s)
    with conn:
        conn.execute(f"INSERT OR IGNORE INTO samples ({', '.join(cols)}) VALUES ({', '.join('?' * len(cols))})",
                     vals)


@dataclass(frozen=True)
class Table:
    """Samples read back for training. x (n, 7) SI kinematics; y (n, 4) L+, D+, M+, P+; speed (n,) [m/s];
    idx (n,) sample indices; rows left out: n_diverged with status 'diverged', n_unsettled with 'unsettled'."""

    x: np.ndarray
    y: np.ndarray
    speed: np.ndarray
    idx: np.ndarray
    n_diverged: int
    n_unsettled: int = 0

    @property
    def n_left_out(self) -> int:
        """Rows of the file (that speed / seed) not used for training: diverged + unsettled."""
        return self.n_diverged + self.n_unsettled


def read_samples(path: str | Path, speed: float | None = None, seed: int | None = None) -> Table:
    """The 'ok' samples of a data set (optionally one speed and/or seed), ordered by (speed, seed, idx)."""
    conn = open_dataset(path)
    try:
        w, args = _where(speed, seed)
        rows = conn.execute(f"SELECT speed, idx, {', '.join(PARAM_NAMES)}, {', '.join(OUTPUTS)} FROM samples "
                            f"WHERE {w} AND status='ok' ORDER BY speed, seed, idx", args).fetchall()
        count = dict(conn.execute(f"SELECT status, count(*) FROM samples WHERE {w} GROUP BY status", args))
    finally:
        conn.close()
    a = np.asarray(rows, dtype=float).reshape(-1, 2 + len(PARAM_NAMES) + len(OUTPUTS))
    return Table(x=a[:, 2:9], y=a[:, 9:], speed=a[:, 0], idx=a[:, 1].astype(int),
                 n_diverged=count.get("diverged", 0), n_unsettled=count.get("unsettled", 0))


def speeds_in(path: str | Path) -> list[float]:
    conn = open_dataset(path)
    try:
        return [r[0] / 1000.0 for r in conn.execute(
            "SELECT DISTINCT CAST(round(speed*1000) AS INTEGER) FROM samples WHERE status='ok' ORDER BY 1")]
    finally:
        conn.close()


# --------------------------------------------------------------------------------------------- generation


@dataclass(frozen=True)
class GenerationResult:
    path: str
    samples: int
    new: int
    diverged: int
    wall_time_s: float
    samples_per_s: float
    unsettled: int = 0


def generate(path: str | Path, speed: float, n: int, *, seed: int = 0, resolution: Resolution,
             scheduler: str | None = None, workers: int | None = None, progress=None) -> GenerationResult:
    """Make samples 0..n-1 of (seed, speed) present in the file, computing only the missing ones.

    scheduler: address of a running Dask scheduler (e.g. dask-jobqueue on SLURM); otherwise a LocalCluster of
    ``workers`` single-threaded processes (default: the machine's cores), each with numba limited to one thread
    so the cores are not oversubscribed. progress(done, total) is called as samples arrive.

    Raises DatasetError for a file that is not a data set of this layout, resolution and version, and OSError (one
    line naming the file, :func:`environment_error`) when the disk is full: the failed commit is rolled back, the
    rows committed before stay, nothing is left beside the file, and a file this run created with no sample in it
    is removed.
    """
    new = diverged = unsettled = 0
    conn = lock = None
    created = False
    t0 = time.perf_counter()
    try:
        lock, created = _writer_lock(path)  # before the file's schema: two writers never both create it
        conn = open_dataset(path, create=True)
        layout = conn.execute("PRAGMA user_version").fetchone()[0]
        if layout != SCHEMA_VERSION:
            raise DatasetError(f"data set {str(path)!r} has layout {layout} (hawksim 0.2.0, without the wingbeat "
                               f"before the label); this hawksim writes layout {SCHEMA_VERSION}: start a new file")
        have_res = stored_resolution(conn, speed, seed)
        if have_res is not None and have_res != resolution:
            raise DatasetError(f"data set {str(path)!r} holds speed {speed} seed {seed} at resolution "
                               f"{have_res.to_dict()}, not {resolution.to_dict()}")
        other = stored_versions(conn, speed, seed) - {__version__}
        if other:  # another version may have another UVLM (e.g. 0.1 -> 0.2 changed the wake's core growth)
            raise DatasetError(f"data set {str(path)!r} holds speed {speed} seed {seed} computed by hawksim "
                               f"{', '.join(sorted(other))}, not {__version__}: continue it with that version or "
                               "start a new file")
        have = stored_indices(conn, speed, seed)  # one query (it ran once per index: issue 53, defect 5)
        todo = [i for i in range(n) if i not in have]
        done0 = n - len(todo)
        if progress:
            progress(done0, n)
        if todo:
            for s in _compute(todo, functools.partial(evaluate_sample, seed, speed, resolution=resolution),
                              scheduler, workers):
                insert_sample(conn, s, resolution)
                new += 1
                diverged += s.status == "diverged"
                unsettled += s.status == "unsettled"
                if progress:
                    progress(done0 + new, n)
        samples = len(stored_indices(conn, speed, seed))
    except BaseException as exc:
        _close_writer(conn, lock, path, created and new == 0)  # nothing half-written: a file this run made
        env = environment_error(path, exc) if isinstance(exc, sqlite3.OperationalError) else None
        if env is not None:
            raise env from None
        raise
    else:
        conn.close()
        lock.close()
    wall = time.perf_counter() - t0
    return GenerationResult(str(path), samples, new, diverged, wall, new / wall if wall > 0 else 0.0, unsettled)


def environment_error(path, exc: sqlite3.Error, writing: bool = True) -> OSError | None:
    """The one-line OSError naming ``path`` for a SQLite failure of the environment (SQLITE_FULL: the disk is
    full; SQLITE_IOERR*: a write or sync failed, e.g. at a file-size limit, or a reader could not make a WAL file's
    -shm; SQLITE_READONLY*; SQLITE_CANTOPEN), None for other errors."""
    name = getattr(exc, "sqlite_errorname", "") or ""
    if not name.startswith(("SQLITE_FULL", "SQLITE_IOERR", "SQLITE_READONLY", "SQLITE_CANTOPEN")):
        return None
    code = errno.ENOSPC if name == "SQLITE_FULL" else errno.EIO
    if not writing:
        return OSError(code, f"cannot read data set {path}: {exc} ({name}); is its disk full or read-only?")
    return OSError(code, f"cannot write data set {path}: {exc} ({name}); the samples stored before are kept and the "
                         "same command continues once the disk has room")


def _remove_unfilled(path, created: bool) -> None:
    """Remove a data-set file this run created (and its journals) when it holds no sample."""
    if created:
        for suffix in ("", "-journal", "-wal", "-shm"):
            Path(str(path) + suffix).unlink(missing_ok=True)


def _close_writer(conn, lock, path, remove: bool) -> None:
    """After a failure: roll back (a failed commit is undone from the journal) and close ``conn``, remove the file
    if ``remove`` (:func:`_remove_unfilled`: this run created it and stored nothing) while the writer's lock is still
    held, so that no second writer can have opened it meanwhile, then release ``lock``."""
    for close in (conn and conn.rollback, conn and conn.close):
        try:
            if close:
                close()
        except sqlite3.Error:
            pass
    if lock is not None:
        _remove_unfilled(path, remove)
        lock.close()


WRITER_LOCK_TRIES = 3
"""Tries to lock the data-set file when the file locked was removed or replaced under its name meanwhile (its
previous writer removed the file it had made without a sample): then the file now under the name is locked."""


def _writer_lock(path):
    """The exclusive flock held while this process writes the data-set file ``path``, taken before SQLite opens
    it: the file is created here if absent (``O_EXCL``, at a link's target), so that its schema is only ever written
    under the lock. Returns (the locked file object, whether this call created the file or found it empty).

    A second writer is refused (DatasetError) instead of computing the same samples again, or, when both created
    the file at once, instead of both writing the schema: the second failed (``table samples already exists``) and
    deleted the first's file (issue 53, defect 4). flock is independent of SQLite's own fcntl locks, so readers are
    unaffected."""
    import fcntl
    import os

    target = os.path.realpath(path)
    for _ in range(WRITER_LOCK_TRIES):
        created = False
        try:
            fd = os.open(target, os.O_RDONLY)
        except FileNotFoundError:
            try:
                fd = os.open(target, os.O_RDONLY | os.O_CREAT | os.O_EXCL, 0o666)
                created = True
            except FileExistsError:  # another writer created it just now: lock that one
                continue
        fh = os.fdopen(fd, "rb")
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.close()
            raise DatasetError(f"data set {str(path)!r} is being written by another hawksim dataset: wait for it, "
                               "or write to another file") from None
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(target))
        except FileNotFoundError:
            same = False
        if same:
            return fh, created or os.fstat(fd).st_size == 0
        fh.close()  # the file locked is no longer the one under the name: lock the new one
    raise DatasetError(f"data set {str(path)!r} was removed or replaced {WRITER_LOCK_TRIES} times while this "
                       "hawksim dataset tried to lock it: is another program writing it?")


def _compute(todo, evaluate, scheduler, workers):
    """Yield ``evaluate(i)`` for the indices ``todo`` as they finish (any order), on Dask workers. ``evaluate`` is
    a picklable callable of the index (a module-level function bound by functools.partial): the held-body samples
    (:func:`evaluate_sample`) and the per-step flights (:func:`hawksim.surrogate.flights.evaluate_flight`)."""
    from dask.distributed import as_completed

    from hawksim.cluster import dask_client

    with dask_client(scheduler, workers) as client:
        # Submit in a bounded window: results stream back and are committed one by one.
        window = 4 * max(1, len(client.scheduler_info()["workers"]))
        it = iter(todo)
        futures = [client.submit(evaluate, i, pure=False)
                   for i in itertools.islice(it, window)]
        ac = as_completed(futures)
        for fut in ac:
            yield fut.result()
            fut.release()
            nxt = next(it, None)
            if nxt is not None:
                ac.add(client.submit(evaluate, nxt, pure=False))


def file_sha256(path: str | Path, speed: float | None = None, seed: int | None = None) -> str:
    """SHA-256 of the data-set rows' content (speed, seed, idx, inputs, outputs, status), optionally of one speed
    and/or seed, independent of the SQLite page layout: the identity of the data a network was trained on."""
    import hashlib

    w, args = _where(speed, seed)
    conn = open_dataset(path)
    h = hashlib.sha256()
    try:
        for row in conn.execute(f"SELECT speed, seed, idx, {', '.join(PARAM_NAMES)}, {', '.join(OUTPUTS)}, status "
                                f"FROM samples WHERE {w} ORDER BY speed, seed, idx", args):
            h.update(repr(row).encode())
    finally:
        conn.close()
    return h.hexdigest()
