"""Per-step UVLM training data: free flights with the UVLM in the loop, recorded at every UVLM update.

The second kind of data set (beside the held-body cycle averages of :mod:`hawksim.surrogate.dataset`, in the same
machinery: one SQLite file with hawksim's application id, a single flock-locked writer, Dask workers that only
compute, one row committed per finished flight, INSERT OR IGNORE on the key, so a killed run resumes without
duplicates). Table ``flights``, keyed by (seed, idx).

Why free flights and not prescribed body paths: the loads the surrogate must reproduce are those of the states
free and controlled flights visit, above all the within-beat recoil of the body (pitch rate +-30 rad/s, body
velocity +-0.25 m/s at every speed, measured below) phase-locked to the wings, and the perturbations that grow
along the orbit's unstable modes. A flight of the free body with the UVLM in the loop visits exactly these, with
the wake its own motion shed; a random path would spend the data budget on states no flight reaches. The price,
correlation between phase and recoil in the data, is broken by the random launch states and kinematics.

Flight ``i`` of seed ``s`` (:func:`sample_flight`, a pure function of (s, i) by
``numpy.random.default_rng([s, FLIGHT_STREAM, i])``):

- ascent speed V uniform in [0, 2] m/s; launch state and kinematics interpolated linearly in V between the shipped
  UVLM orbits (``insects/hawkmoth/data/orbit_table_uvlm.json``: 0, 1, 1.5, 2 m/s; the hover row is not converged
  but is a launch state of the right kind);
- kinematics: each of the seven parameters moved uniformly by +-:data:`KIN_SPREAD` of Table 2's width (f +-0.625 Hz,
  the angles +-1.25 deg), clipped to Table 2;
- launched on the (interpolated) orbit's launch state; after :data:`WARM_BEATS` beats, which develop the wake, the
  body state is kicked at phase 0 by a perturbation uniform within :data:`LAUNCH_SPREAD` (u, w +-0.3 m/s, q +-2
  rad/s, theta +-0.05 rad), written on the free joint with the wake kept; one flight in :data:`LATERAL_EVERY` is
  lateral as well (v, p, r, phi likewise) and solves both wings, the others are left/right symmetric (the UVLM
  solves one wing and mirrors it: 3.7x cheaper, measured);
- :data:`FLIGHT_BEATS` beats at `hawksim fly --aero uvlm`'s settings (:data:`hawksim.backends.resolution.FLY_UVLM`,
  wake of the last 3 beats, MuJoCo 200 RK4 steps per beat, loads held between the 40 UVLM updates per beat), cut at
  the first update where the flight leaves the range (:data:`CUT_SPEED`, :data:`CUT_ANGLE`).

Stored per flight: the spec (speed, kinematics, launch perturbation, symmetric), the rows as one float32 blob of
shape (n, :data:`N_COLUMNS`) in :data:`COLUMNS` order (SI; body axes x head, y left, z dorsal; wing axes the wing
body's frame), the cut reason, status ('ok', or 'diverged' when the UVLM blew up or its peak force coefficient
exceeded :data:`hawksim.surrogate.dataset.PEAK_FORCE_CEILING`), resolution, version, wall time.
"""

from __future__ import annotations

import functools
import json
import math
import sqlite3
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hawksim import __version__
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE, FLY_UVLM, FLY_WAKE_CYCLES
from hawksim.insect.folder import default_insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics
from hawksim.surrogate.dataset import (
    PEAK_FORCE_CEILING,
    DatasetError,
    _compute,
    _close_writer,
    _writer_lock,
    environment_error,
    open_dataset,
)

FLIGHT_STREAM = 21
"""Second component of the flights' random stream (keeps it apart from the held-body samples' (seed, speed, i))."""

KIN_SPREAD = 0.025
"""Half-width of the kinematic perturbation about the interpolated orbit, as a fraction of Table 2's range."""

LAUNCH_SPREAD = {"u": 0.3, "v": 0.3, "w": 0.3, "p": 2.0, "q": 2.0, "r": 2.0, "phi": 0.05, "theta": 0.05}
"""Half-widths of the uniform kick at t = WARM_BEATS T (m/s, rad/s, rad) in the orbit's state chart
(:data:`hawksim.flight.orbit.STATE_NAMES`); v, p, r, phi only in lateral flights."""

LATERAL_EVERY = 4
"""Flight i is lateral (asymmetric, both wings solved) when i % LATERAL_EVERY == LATERAL_EVERY - 1."""

FLIGHT_BEATS = 8
"""Wingbeats per flight: :data:`WARM_BEATS` that develop the wake from none (kept, flagged by time) + 6."""

WARM_BEATS = 2
"""Rows before this many wingbeats carry the wake's start-up and are not used for training (t < WARM_BEATS T)."""

CUT_SPEED = 1.0
"""A flight is cut when its body velocity differs from (0, 0, V) by more than this [m/s] ..."""

CUT_ANGLE = math.radians(45.0)
"""... or its bank or pitch differ from the launch attitude's by more than this [rad]."""

@dataclass(frozen=True)
class FlightFamily:
    """How a family of training flights is drawn (:func:`sample_flight`): the kinematic spread ``kin_spread``
    (fraction of Table 2's width about the interpolated orbit), the kick's half-widths ``launch_spread`` (m/s,
    rad/s, rad; v, p, r, phi only in lateral flights), one flight in ``lateral_every`` lateral, the random
    stream (second component of the seed sequence), and where a flight is cut (``cut_speed`` [m/s] from
    (0, 0, V), ``cut_angle`` [rad] of bank or pitch from the attitude after the kick; with ``cut_by_rotation``, of
    the rotation from that attitude: the bank atan2(R12, R22) is ill-conditioned with the body axis near the
    vertical, where it jumped 50-100 deg between updates in wide flights pitched 82-86 deg)."""

    name: str
    kin_spread: float
    launch_spread: dict
    lateral_every: int
    stream: int
    cut_speed: float
    cut_angle: float
    cut_by_rotation: bool = False


FAMILIES = {
    "orbit": FlightFamily("orbit", KIN_SPREAD, LAUNCH_SPREAD, LATERAL_EVERY, FLIGHT_STREAM, CUT_SPEED, CUT_ANGLE),
    "wide": FlightFamily("wide", 0.15, {"u": 0.5, "v": 0.6, "w": 0.5, "p": 6.0, "q": 4.0, "r": 6.0, "phi": 0.15,
                                        "theta": 0.1}, 1, FLIGHT_STREAM + 1, cut_speed=2.0,
                         cut_angle=math.radians(90.0), cut_by_rotation=True),
}
"""Flight families. ``orbit`` (the shipped data set, data/uvlm_flights_0.2.0.sqlite): small kinematic changes and
kicks about the orbits, the states free flights and small-signal control visit. ``wide``: the states a controlled
flight visits in a 0.5 m/s lateral gust (the UVLM under its LQR at 1-2 m/s, scripts/studies/control_constrained.py:
antisymmetric phi0 commands up to 38 deg, dphi_a 10 deg, theta0 5 deg below its bound, roll rates ~10 rad/s,
sideslip 0.5 m/s), where the orbit family's network extrapolates (docs/control.md, "Gusts"): kinematics within
+-15 % of Table 2's width (f +-3.75 Hz, angles +-7.5 deg, phi_a +-4.5 deg; clipped to Table 2), every flight lateral
(both wings solved), kicks up to 0.6 m/s sideslip and 6 rad/s roll and yaw rate, cut at 2 m/s or 90 deg (at
the orbit family's 1 m/s and 45 deg most wide flights ended within a fifth of a beat of the kick, all at the same
phase). Its flights go in their own file (a file holds one family; :func:`generate_flights`)."""

COLUMNS = ("t", "vx", "vy", "vz", "wx", "wy", "wz", *(f"R{i}{j}" for i in range(3) for j in range(3)),
           "FLx", "FLy", "FLz", "FRx", "FRy", "FRz", "MLx", "MLy", "MLz", "MRx", "MRy", "MRz",
           "power_aero", "power_joint")
"""Row layout: t [s] from the launch (phase = f t); v (3) [m/s] and omega (3) [rad/s] of the body in body axes
(relative to the air, which is still); the body's attitude R (body -> world, row-major); force (left, right) [N]
and moment about the hinge [N m] (left, right) of each wing in its own wing axes; the UVLM's aerodynamic power
of both wings [W]; the joint power of the six wing joints [W] (at the update's step)."""

N_COLUMNS = len(COLUMNS)

_SCHEMA = f"""
CREATE TABLE IF NOT EXISTS flights (
    seed INTEGER NOT NULL,
    idx INTEGER NOT NULL,
    speed REAL NOT NULL,
    {", ".join(f"{n} REAL NOT NULL" for n in PARAM_NAMES)},
    perturbation TEXT NOT NULL,
    symmetric INTEGER NOT NULL,
    n_rows INTEGER NOT NULL,
    cut TEXT,
    status TEXT NOT NULL,
    resolution TEXT NOT NULL,
    version TEXT NOT NULL,
    wall_s REAL NOT NULL,
    data BLOB NOT NULL,
    PRIMARY KEY (seed, idx)
);
"""


@dataclass(frozen=True)
class FlightSpec:
    """One training flight: speed V [m/s], kinematics (SI), launch state x0 (9,) and chart chi_ref [rad] (the
    orbit's, :func:`hawksim.flight.orbit.set_body_state`), the kick (9,) added to the state at t = WARM_BEATS T,
    symmetric."""

    speed: float
    kinematics: Kinematics
    x0: tuple[float, ...]
    chi_ref: float
    perturbation: tuple[float, ...]
    symmetric: bool


@dataclass(frozen=True)
class FlightSample:
    """An evaluated flight: its spec, seed, idx, rows (n, N_COLUMNS) float32, cut reason (None: flown to the end),
    status ('ok' / 'diverged'), wall time [s]."""

    spec: FlightSpec
    seed: int
    idx: int
    rows: np.ndarray
    cut: str | None
    status: str
    wall_s: float


@functools.lru_cache(maxsize=1)
def _orbit_rows() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(speeds (k,), kinematics (k, 7) SI, launch states (k, 9), chi_ref (k,)) of the shipped UVLM orbits."""
    from hawksim.flight.orbit import Orbit
    from hawksim.insect.folder import default_insect
    from hawksim.insect.tables import table_path

    rows = json.loads(table_path(default_insect(), "orbit", "uvlm").read_text())["rows"]
    orbits = sorted((Orbit.from_json(r) for r in rows), key=lambda o: o.speed)
    return (np.array([o.speed for o in orbits]), np.array([o.kinematics.as_array() for o in orbits]),
            np.array([o.launch_state.as_array() for o in orbits]), np.array([o.chi_ref for o in orbits]))


def orbit_at(speed: float) -> tuple[Kinematics, np.ndarray, float]:
    """Kinematics, launch state (9,) and chi_ref of the shipped UVLM orbits interpolated linearly at ``speed``."""
    v, kin, x0, chi = _orbit_rows()
    k = np.array([np.interp(speed, v, kin[:, j]) for j in range(kin.shape[1])])
    x = np.array([np.interp(speed, v, x0[:, j]) for j in range(x0.shape[1])])
    return Kinematics.from_array(k), x, float(np.interp(speed, v, chi))


def sample_flight(seed: int, i: int, family: str = "orbit") -> FlightSpec:
    """The spec of flight i of ``seed`` in ``family`` (:data:`FAMILIES`; module docstring): a pure function of
    (seed, i, family)."""
    from hawksim.flight.orbit import STATE_NAMES

    if seed < 0 or i < 0:
        raise ValueError(f"seed and flight index must be >= 0, got seed={seed}, i={i}")
    fam = FAMILIES[family]
    rng = np.random.default_rng([int(seed), fam.stream, int(i)])
    speed = float(rng.uniform(0.0, 2.0))
    kin0, x0, chi = orbit_at(speed)
    lo, hi = default_insect().bounds_si()
    k = np.clip(kin0.as_array() + fam.kin_spread * (hi - lo) * rng.uniform(-1, 1, len(PARAM_NAMES)), lo, hi)
    symmetric = i % fam.lateral_every != fam.lateral_every - 1
    u = rng.uniform(-1, 1, len(STATE_NAMES))
    pert = np.array([fam.launch_spread.get(n, 0.0) * u[j] for j, n in enumerate(STATE_NAMES)])
    if symmetric:
        pert[[1, 3, 5, 6, 8]] = 0.0
    return FlightSpec(speed, Kinematics.from_array(k), tuple(map(float, x0)), chi,
                      tuple(map(float, pert)), symmetric)


def evaluate_flight(seed: int, i: int, beats: int = FLIGHT_BEATS, family: str = "orbit", *,
                    history_kick: np.ndarray | None = None, state_at_kick: np.ndarray | None = None,
                    kick_log: list | None = None) -> FlightSample:
    """Fly flight i of ``family`` (UVLM in the loop, `hawksim fly --aero uvlm`'s settings) and record every UVLM
    update (:func:`fly_spec` of :func:`sample_flight`'s spec)."""
    return fly_spec(sample_flight(seed, i, family), seed, i, beats, family, history_kick=history_kick,
                    state_at_kick=state_at_kick, kick_log=kick_log)


def fly_spec(spec: FlightSpec, seed: int = -1, i: int = -1, beats: int = FLIGHT_BEATS, family: str = "orbit", *,
             kick: bool = True, history_kick: np.ndarray | None = None, state_at_kick: np.ndarray | None = None,
             kick_log: list | None = None) -> FlightSample:
    """Fly the flight ``spec`` (UVLM in the loop, `hawksim fly --aero uvlm`'s settings; cut as ``family``'s) and
    record every UVLM update; seed and i label the sample. ``kick`` False: no kick at t = WARM_BEATS T (a free flight
    from the launch state, e.g. the launch study, scripts/studies/step_surrogate_launch.py).

    For the memory study (``scripts/studies/step_surrogate_memory.py``; the data sets use none of these):
    history_kick (9,) is added to the body state one beat before the kick; state_at_kick (9,) is written at the
    kick instead of the state flown + the spec's perturbation, so that two flights leave the kick in the same body
    state with different wakes; kick_log, a list, receives the body state just before the kick."""
    from hawksim.backends import flight_backend
    from hawksim.flight.orbit import read_body_state, set_body_state
    from hawksim.flight.simulator import Simulator, aero_every_for
    from hawksim.frames import pitch_of
    from hawksim.insect.model import load_model
    from hawksim.insect.morphology import RHO_AIR

    morph = default_insect().morphology

    fam = FAMILIES[family]
    t0 = time.perf_counter()
    kin = spec.kinematics
    backend = flight_backend("uvlm", symmetric=spec.symmetric)
    every = aero_every_for(backend, FLY_STEPS_PER_CYCLE)
    sim = Simulator(load_model(), kin, backend, steps_per_cycle=FLY_STEPS_PER_CYCLE, aero_every=every)
    set_body_state(sim, np.asarray(spec.x0), spec.chi_ref)
    u_tip = 2.0 * math.pi * kin.f * kin.phi_a * morph.R
    f_ceiling = PEAK_FORCE_CEILING * 0.5 * RHO_AIR * u_tip**2 * morph.wing_area  # per wing
    v_ref = np.array([0.0, 0.0, spec.speed])
    rows, cut, status, att0 = [], None, "ok", None
    try:
        for step in range(beats * FLY_STEPS_PER_CYCLE):
            if history_kick is not None and step == (WARM_BEATS - 1) * FLY_STEPS_PER_CYCLE:
                _kick(sim, read_body_state(sim, spec.chi_ref) + np.asarray(history_kick), spec.chi_ref)
            if kick and step == WARM_BEATS * FLY_STEPS_PER_CYCLE:
                before = read_body_state(sim, spec.chi_ref)
                if kick_log is not None:
                    kick_log.append(before)
                x = before + np.asarray(spec.perturbation) if state_at_kick is None else np.asarray(state_at_kick)
                _kick(sim, x, spec.chi_ref)
            rec = sim.step()
            if step % every:
                continue
            st, ld = rec.state, rec.loads
            R = st.body_R
            pitch, roll = pitch_of(R), math.atan2(R[1, 2], R[2, 2])
            if att0 is None and step >= WARM_BEATS * FLY_STEPS_PER_CYCLE:
                att0, R0 = (pitch, roll), R.copy()
            Fw = np.einsum("kji,kj->ki", st.wing_R, ld.force)
            Mw = np.einsum("kji,kj->ki", st.wing_R, ld.moment)
            if not (np.all(np.isfinite(Fw)) and np.all(np.isfinite(Mw))):
                raise FloatingPointError("non-finite UVLM loads")
            if np.linalg.norm(ld.force, axis=1).max() > f_ceiling:
                status, cut = "diverged", f"peak force coefficient above {PEAK_FORCE_CEILING:g} at t={st.t:.5f} s"
                break
            if np.linalg.norm(st.body_v - v_ref) > fam.cut_speed:
                cut = f"speed left the range at t={st.t:.5f} s"
                break
            if att0 is not None and (
                    math.acos(min(1.0, max(-1.0, (np.trace(R0.T @ R) - 1) / 2))) > fam.cut_angle
                    if fam.cut_by_rotation else
                    abs(pitch - att0[0]) > fam.cut_angle or abs(roll - att0[1]) > fam.cut_angle):
                cut = f"attitude left the range at t={st.t:.5f} s"
                break
            rows.append([st.t, *(R.T @ st.body_v), *(R.T @ st.body_omega), *R.ravel(), *Fw.ravel(),
                         *Mw.ravel(), ld.power, rec.joint_power])
    except FloatingPointError as exc:
        status, cut = "diverged", f"blew up: {exc}"
    data = np.asarray(rows, dtype=np.float32).reshape(-1, N_COLUMNS)
    return FlightSample(spec, int(seed), int(i), data, cut, status, time.perf_counter() - t0)


def _kick(sim, x: np.ndarray, chi_ref: float) -> None:
    """Write the body state x (9,) on the free joint (attitude, velocity, rates; position kept), keeping the
    backend's wake and the wings' motion: the perturbation of a flight in progress."""
    import mujoco

    from hawksim.flight.orbit import state_to_world
    from hawksim.frames import quat_from_matrix

    R, v_w, om_w = state_to_world(x, chi_ref)
    d = sim.d
    d.qpos[3:7] = quat_from_matrix(R)
    d.qvel[:3] = v_w
    d.qvel[3:6] = R.T @ om_w
    mujoco.mj_forward(sim.m, d)


# --------------------------------------------------------------------------------------------- the file


def ensure_flight_table(conn, family: str = "orbit") -> None:
    """Add the ``flights`` table to a data-set file (a no-op when it has one) for flights of ``family``
    (:data:`FAMILIES`): a file holds one family, recorded in its ``flight_family`` table (absent: ``orbit``, the
    shipped file's); DatasetError when the file holds another."""
    if family not in FAMILIES:
        raise DatasetError(f"flight family {family!r}: choose {', '.join(FAMILIES)}")
    with conn:
        conn.executescript(_SCHEMA)
    have = stored_family(conn)
    n = conn.execute("SELECT count(*) FROM flights").fetchone()[0]
    if have != family and (n or have != "orbit"):
        raise DatasetError(f"the data set holds {have!r} flights, not {family!r}: start a new file")
    if family != "orbit":
        with conn:
            conn.execute("CREATE TABLE IF NOT EXISTS flight_family (family TEXT NOT NULL)")
            if conn.execute("SELECT count(*) FROM flight_family").fetchone()[0] == 0:
                conn.execute("INSERT INTO flight_family (family) VALUES (?)", (family,))


def stored_family(conn) -> str:
    """The flight family of a data-set file (``orbit`` when it records none)."""
    if not conn.execute("SELECT count(*) FROM sqlite_master WHERE name='flight_family'").fetchone()[0]:
        return "orbit"
    r = conn.execute("SELECT family FROM flight_family").fetchone()
    return "orbit" if r is None else str(r[0])


def stored_flights(conn, seed: int) -> set[int]:
    return {r[0] for r in conn.execute("SELECT idx FROM flights WHERE seed=?", (int(seed),))}


def insert_flight(conn, s: FlightSample) -> None:
    """Store one flight and commit (INSERT OR IGNORE: never a duplicate)."""
    cols = ("seed", "idx", "speed", *PARAM_NAMES, "perturbation", "symmetric", "n_rows", "cut", "status",
            "resolution", "version", "wall_s", "data")
    res = {**FLY_UVLM.to_dict(), "wake_cycles": FLY_WAKE_CYCLES, "mujoco_steps_per_cycle": FLY_STEPS_PER_CYCLE}
    vals = (s.seed, s.idx, s.spec.speed, *(float(v) for v in s.spec.kinematics.as_array()),
            json.dumps(list(s.spec.perturbation)), int(s.spec.symmetric), int(s.rows.shape[0]), s.cut, s.status,
            json.dumps(res, sort_keys=True), __version__, s.wall_s,
            np.ascontiguousarray(s.rows, dtype="<f4").tobytes())
    with conn:
        conn.execute(f"INSERT OR IGNORE INTO flights ({', '.join(cols)}) VALUES ({', '.join('?' * len(cols))})", vals)


@dataclass(frozen=True)
class StoredFlight:
    """A flight read back: seed, idx, speed [m/s], kinematics (7,) SI, symmetric, rows (n, N_COLUMNS) float64,
    cut, status."""

    seed: int
    idx: int
    speed: float
    kinematics: np.ndarray
    symmetric: bool
    rows: np.ndarray
    cut: str | None
    status: str

    @classmethod
    def from_sample(cls, sample: FlightSample) -> StoredFlight:
        """The flight as a data set stores and reads it back (rows in float64), without writing it."""
        sp = sample.spec
        return cls(sample.seed, sample.idx, sp.speed, sp.kinematics.as_array(), sp.symmetric,
                   sample.rows.astype(np.float64), sample.cut, sample.status)


def read_flights(path: str | Path, seed: int | None = None, *, status: str | None = "ok") -> list[StoredFlight]:
    """The flights of a data-set file (optionally one seed; by default the 'ok' ones), ordered by (seed, idx)."""
    conn = open_dataset(path)
    try:
        if not conn.execute("SELECT count(*) FROM sqlite_master WHERE name='flights'").fetchone()[0]:
            raise DatasetError(f"data set {str(path)!r} holds no flights table (a held-body sample set?)")
        where, args = ["1"], []
        if seed is not None:
            where.append("seed=?")
            args.append(int(seed))
        if status is not None:
            where.append("status=?")
            args.append(status)
        q = (f"SELECT seed, idx, speed, {', '.join(PARAM_NAMES)}, symmetric, n_rows, cut, status, data FROM flights "
             f"WHERE {' AND '.join(where)} ORDER BY seed, idx")
        out = []
        for r in conn.execute(q, args):
            n = int(r[11])
            rows = np.frombuffer(r[14], dtype="<f4")
            if rows.size != n * N_COLUMNS:
                raise DatasetError(f"data set {str(path)!r}: flight ({r[0]}, {r[1]}) holds {rows.size} values, "
                                   f"expected {n} x {N_COLUMNS}")
            out.append(StoredFlight(int(r[0]), int(r[1]), float(r[2]), np.array(r[3:10], dtype=float),
                                    bool(r[10]), rows.reshape(n, N_COLUMNS).astype(np.float64), r[12], r[13]))
    finally:
        conn.close()
    return out


def copy_flights(src: str | Path, dst: str | Path, keys: list[tuple[int, int]]) -> int:
    """Copy the flights (seed, idx) ``keys`` of ``src`` into the data-set file ``dst`` (created if needed; rows
    already there are kept), e.g. a small held-out set for CI. Returns the number of flights in ``dst``."""
    conn = open_dataset(dst, create=True)
    try:
        ensure_flight_table(conn)
        s = open_dataset(src)
        try:
            cols = [r[1] for r in s.execute("PRAGMA table_info(flights)")]
            for seed, idx in keys:
                row = s.execute(f"SELECT {', '.join(cols)} FROM flights WHERE seed=? AND idx=?",
                                (int(seed), int(idx))).fetchone()
                if row is None:
                    raise DatasetError(f"{str(src)!r} holds no flight ({seed}, {idx})")
                with conn:
                    conn.execute(f"INSERT OR IGNORE INTO flights ({', '.join(cols)}) VALUES "
                                 f"({', '.join('?' * len(cols))})", row)
        finally:
            s.close()
        return conn.execute("SELECT count(*) FROM flights").fetchone()[0]
    finally:
        conn.close()


@dataclass(frozen=True)
class FlightGenerationResult:
    path: str
    flights: int
    new: int
    diverged: int
    rows_new: int
    wall_time_s: float


def generate_flights(path: str | Path, n: int, *, seed: int = 0, scheduler: str | None = None,
                     workers: int | None = None, progress=None, log=None, beats: int = FLIGHT_BEATS,
                     family: str = "orbit") -> FlightGenerationResult:
    """Make flights 0..n-1 of ``seed`` in ``family`` (:data:`FAMILIES`; a file holds one) present in the file,
    computing only the missing ones (the machinery of :func:`hawksim.surrogate.dataset.generate`: one locked
    writer, Dask workers, a commit per flight). ``log(text)`` gets one line per stored flight; ``beats`` (tests
    only) shortens the flights."""
    conn = lock = None
    created = False
    t0 = time.perf_counter()
    new = diverged = rows_new = 0
    try:
        lock, created = _writer_lock(path)  # before the schema: two writers never both create the file
        conn = open_dataset(path, create=True)  # inside: a full disk while the schema is written is reported too
        ensure_flight_table(conn, family)
        other = {r[0] for r in conn.execute("SELECT DISTINCT version FROM flights WHERE seed=?", (int(seed),))}
        other -= {__version__}
        if other:
            raise DatasetError(f"data set {str(path)!r} holds flights of seed {seed} computed by hawksim "
                               f"{', '.join(sorted(other))}, not {__version__}: start a new file")
        have = stored_flights(conn, seed)
        todo = [i for i in range(n) if i not in have]
        if progress:
            progress(n - len(todo), n)
        if todo:
            for s in _compute(todo, functools.partial(evaluate_flight, seed, beats=beats, family=family), scheduler,
                              workers):
                insert_flight(conn, s)
                new += 1
                diverged += s.status == "diverged"
                rows_new += s.rows.shape[0]
                if progress:
                    progress(n - len(todo) + new, n)
                if log:
                    log(f"{time.strftime('%H:%M:%S')} flight {s.idx}: V={s.spec.speed:.3f} m/s "
                        f"{'sym' if s.spec.symmetric else 'lateral'} rows={s.rows.shape[0]} {s.status} "
                        f"cut={s.cut} wall={s.wall_s:.1f} s; stored {n - len(todo) + new}/{n}")
        total = len(stored_flights(conn, seed))
    except BaseException as exc:  # as dataset.generate: a full disk is one line, the committed flights stay
        _close_writer(conn, lock, path, created and new == 0)  # a file this run made without a flight goes
        env = environment_error(path, exc) if isinstance(exc, sqlite3.OperationalError) else None
        if env is not None:  # "database or disk is full", "disk I/O error" (a file-size limit)
            raise env from None
        raise
    conn.close()
    lock.close()
    return FlightGenerationResult(str(path), total, new, diverged, rows_new, time.perf_counter() - t0)
