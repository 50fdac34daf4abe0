"""Floquet analysis of an orbit flown with a per-step surrogate that has history inputs (a delay system).

A network with history lags reads the body state at t - lag T from its backend's record of calls
(:func:`hawksim.backends.step_surrogate.lagged_states`), so the state of its one-beat map is the body state AND that
record: with lags up to L beats and N calls per beat, the ceil(L N) records before the beat's first call, six
body-axes values each (velocity relative to the air [m/s], angular velocity [rad/s]). The warm-up chain of
:func:`hawksim.stability.floquet.monodromy` takes the record as a function of the launch state (the family of
launches: the record a perturbed launch builds during its warm-up beat), which is one particular record per body
state, not the map's state. Here the monodromy is taken on the augmented state, by central differences: each column
one beat flown from the orbit's state and record at phase 0 with one component changed (the record written into the
backend's ring), each row the body state or a record value one beat later.

Normalised as :func:`hawksim.stability.floquet.state_scale` (velocities / U, rates x T, angles in rad; a record's
velocities / U and rates x T). For a left/right symmetric orbit the augmented map splits into a longitudinal block
(u, w, q, theta and each record's v_x, v_z, omega_y) and a lateral one (v, p, r, phi and v_y, omega_x, omega_z); the
coupling blocks' norm is reported. The multipliers are each block's eigenvalues; the record alone is a shift register
(eigenvalues 0), so the network's dependence on its history moves them off 0, and the body's modes are the ones that
the body-state rows of their eigenvectors carry (:attr:`HistoryFloquet.body_share`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import mujoco
import numpy as np

from hawksim.backends.record import history_rows, record_scale, record_size, set_history_rows
from hawksim.backends.step_surrogate import StepSurrogateBackend
from hawksim.flight.orbit import (STEPS_PER_CYCLE, SURROGATE_FD_STEP, Orbit, make_orbit_backend, read_body_state,
                                  set_body_state)
from hawksim.flight.simulator import Simulator, aero_every_for
from hawksim.insect.model import load_model
from hawksim.stability.floquet import FLOQUET_NAMES, FLOQUET_STATES, LAT, LONG, state_scale
from hawksim.stability.linear_model import LinearModel, record_names

RECORD_LONG, RECORD_LAT = (0, 2, 4), (1, 3, 5)
"""A record's longitudinal (v_x, v_z, omega_y) and lateral (v_y, omega_x, omega_z) components (body axes)."""


@dataclass(frozen=True)
class HistoryFloquet:
    """The augmented monodromy's blocks long, lat (n, n) nondimensional (the 4 body states in
    :data:`hawksim.stability.floquet.LONG` / ``LAT`` order, then the records' 3 components, oldest record first),
    their coupling (Frobenius norm of the off-diagonal blocks, max), multipliers_long/lat (n,) complex sorted by
    ``|mu|`` descending, body_share_long/lat (n,): the fraction of each eigenvector's norm in the 4 body states,
    records: the records of history in the state, delta: the difference step."""

    long: np.ndarray
    lat: np.ndarray
    coupling: float
    multipliers_long: np.ndarray
    multipliers_lat: np.ndarray
    body_share_long: np.ndarray
    body_share_lat: np.ndarray
    records: int
    delta: float
    residual: float
    """max ``|z' - z|`` of the augmented state (normalized) one beat after the linearization point: how far the point
    (the orbit's state and its periodic beat's record) is from periodic in the augmented state."""
    record_mismatch: float
    """max ``|difference|`` (normalized) of that record and the one the periodic beat started with, which the orbit
    was solved with (its :attr:`hawksim.flight.orbit.Orbit.record`, or the warm-up beat's calls; nan: an orbit with
    neither)."""
    wall_time_s: float
    linear: LinearModel | None = field(default=None, repr=False, compare=False)
    """The linear model this is the eigen-analysis of (``map="history"``; :func:`history_floquet_analysis`)."""

    def body_modes(self, system: str, share: float = 0.05, count: int = 4) -> np.ndarray:
        """The ``count`` largest multipliers of ``system`` ('long' or 'lat') whose eigenvectors put at least
        ``share`` of their norm in the body states (the record's own modes carry almost none)."""
        mu = self.multipliers_long if system == "long" else self.multipliers_lat
        sh = self.body_share_long if system == "long" else self.body_share_lat
        return mu[sh >= share][:count]


class _DelayMap:
    """One simulator and backend for the orbit's kinematics; :meth:`beat` flies one beat from a body state and a
    record."""

    def __init__(self, orbit: Orbit, model: mujoco.MjModel | None, network=None):
        self.orbit = orbit
        if network is None:
            backend, every = make_orbit_backend(orbit.aero, symmetric=False, kinematics=orbit.kinematics,
                                                insect=orbit.insect)
        else:
            backend = StepSurrogateBackend(orbit.kinematics, network)
            every = aero_every_for(backend, STEPS_PER_CYCLE)
        if not getattr(backend, "lags", ()):
            raise ValueError("history_monodromy needs a per-step surrogate with history lags (this backend has none)")
        orbit.seed(backend)  # an orbit solved on the augmented state starts with its record
        self.backend = backend
        model = model if model is not None else load_model(morph=orbit.insect.morphology)
        self.sim = Simulator(model, orbit.kinematics, backend,
                             steps_per_cycle=STEPS_PER_CYCLE, gravity=True, aero_every=every)
        self.calls = STEPS_PER_CYCLE // aero_every_for(backend, STEPS_PER_CYCLE)
        self.records = record_size(backend.lags, self.calls)
        self.period = orbit.kinematics.period

    def _read(self, n: int) -> np.ndarray:
        return history_rows(self.backend.history, n)

    def _write(self, rows: np.ndarray, t0: float) -> None:
        set_history_rows(self.backend.history, rows, t0, self.period / self.calls)

    def start(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The orbit's phase-0 state (9,) and a record (records, 6) for it: the launch (with the orbit's record,
        if it has one) flown through its warm-up beats, then the periodic beat, whose own calls are the record.
        Also the record the periodic beat started with (records, 6; None for an orbit with neither warm-up beats
        nor a record), for the mismatch of the two: 0 up to :data:`hawksim.flight.orbit.RECORD_TOL` for an orbit
        solved on the augmented state; for one solved with a warm-up beat, whose lagged inputs reach before the
        launch, not."""
        o = self.orbit
        set_body_state(self.sim, o.launch_state.as_array(), o.chi_ref)
        if o.warm_beats:
            self.sim.advance(o.warm_beats * STEPS_PER_CYCLE)
        x = read_body_state(self.sim, o.chi_ref)
        before = self._read(self.records) if o.has_memory else None
        self.sim.advance(STEPS_PER_CYCLE)
        return x, self._read(self.records), before

    def beat(self, x: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """State (9,) and record one beat after starting at phase 0 in state x with the record ``rows``."""
        set_body_state(self.sim, x, self.orbit.chi_ref)
        self._write(rows, float(self.sim.d.time))
        self.sim.advance(STEPS_PER_CYCLE)
        return read_body_state(self.sim, self.orbit.chi_ref), self._read(self.records)


def history_monodromy(orbit: Orbit, *, delta: float = SURROGATE_FD_STEP, model: mujoco.MjModel | None = None,
                      network=None) -> HistoryFloquet:
    """The augmented monodromy of ``orbit`` (a per-step surrogate with history lags; module docstring) by central
    differences with the normalized step ``delta``: 2 (8 + 6 n) one-beat flights for n records. ``network``: a
    :class:`hawksim.backends.step_network.StepNetwork` to fly instead of the orbit backend's (default: the
    shipped one)."""
    t_start = time.perf_counter()
    dm = _DelayMap(orbit, model, network)
    x0, r0, r_warm = dm.start()
    U_T = state_scale(orbit.kinematics, orbit.insect.morphology)
    rec_scale = record_scale(orbit.kinematics)
    n = dm.records

    def pack(x, rows):
        return np.concatenate([x[list(FLOQUET_STATES)] / U_T, (rows / rec_scale).ravel()])

    z0 = pack(x0, r0)
    residual = float(np.abs(pack(*dm.beat(x0, r0)) - z0).max())
    mismatch = float(np.abs((r0 - r_warm) / rec_scale).max()) if r_warm is not None else float("nan")

    dim = 8 + 6 * n
    J = np.zeros((dim, dim))
    for j in range(dim):
        outs = []
        for s in (1.0, -1.0):
            x, rows = x0.copy(), r0.copy()
            if j < 8:
                x[FLOQUET_STATES[j]] += s * delta * U_T[j]
            else:
                k, c = divmod(j - 8, 6)
                rows[k, c] += s * delta * rec_scale[c]
            outs.append(pack(*dm.beat(x, rows)))
        J[:, j] = (outs[0] - outs[1]) / (2 * delta)
    lin = LinearModel(point=orbit, map="history", states=FLOQUET_NAMES + record_names(n), inputs=(), A=J,
                      scale=np.concatenate([U_T, np.tile(rec_scale, n)]), dt=orbit.kinematics.period, delta=delta,
                      wall_time_s=time.perf_counter() - t_start, records=n, record_ref=r0, record_scale=rec_scale,
                      residual=residual, record_mismatch=mismatch)
    return history_floquet_analysis(lin)


def history_floquet_analysis(lin: LinearModel) -> HistoryFloquet:
    """The eigen-analysis of an augmented monodromy (``lin.map == "history"``, :func:`history_monodromy`): its
    longitudinal and lateral blocks (the body's 4 states, then each record's 3 values), their multipliers and how
    much of each eigenvector lies in the body states."""
    if lin.map != "history":
        raise ValueError(f"history_floquet_analysis takes an augmented monodromy (map='history'), got map={lin.map!r}")
    J, n = lin.A, lin.records
    long_ix = list(LONG) + [8 + 6 * k + c for k in range(n) for c in RECORD_LONG]
    lat_ix = list(LAT) + [8 + 6 * k + c for k in range(n) for c in RECORD_LAT]
    L, Lt = J[np.ix_(long_ix, long_ix)], J[np.ix_(lat_ix, lat_ix)]
    coupling = max(np.linalg.norm(J[np.ix_(long_ix, lat_ix)]), np.linalg.norm(J[np.ix_(lat_ix, long_ix)]))
    (wl, sl), (wt, st) = _modes(L), _modes(Lt)
    return HistoryFloquet(long=L, lat=Lt, coupling=float(coupling), multipliers_long=wl, multipliers_lat=wt,
                          body_share_long=sl, body_share_lat=st, records=n, delta=lin.delta,
                          residual=lin.residual, record_mismatch=lin.record_mismatch,
                          wall_time_s=lin.wall_time_s, linear=lin)


def _modes(M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues sorted by ``|mu|`` descending and each eigenvector's norm fraction in the first 4 (body) states."""
    w, V = np.linalg.eig(M)
    order = np.argsort(-np.abs(w), kind="stable")
    w, V = w[order], V[:, order]
    share = np.linalg.norm(V[:4], axis=0) / np.linalg.norm(V, axis=0)
    return w, share
