"""A backend's record of its past calls: the memory of a network with history inputs.

A history network (the per-step surrogate with lags, :mod:`hawksim.backends.step_surrogate`) reads its inputs at
t - lag T from a ring of its own calls. The ring is one float64 array (:func:`new_history`) so that the Python backend
and the flight loop's native callback (:mod:`hawksim.flight.native`) read and write the same record through
:func:`lagged_states`. A record row: t [s], then the body's velocity relative to the air [m/s] and angular velocity
[rad/s] in body axes. The memory protocol that sets and reads it (seed, snapshot, restore) is
:mod:`hawksim.backends.memory`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hawksim.insect.kinematics import Kinematics

HISTORY_ROW = 7
"""A history record's row: t [s], then the body's velocity relative to the air and angular velocity in body axes
(m/s, rad/s)."""
HISTORY_ROWS_PER_BEAT = 1024
"""Rows kept per wingbeat of the longest lag: more than any flight's calls per beat (one per RK4 step at most,
200 by default), so the ring never drops a row a lag still reads."""
MAX_NATIVE_LAGS = 4
"""History lags the native callback evaluates (its ctx slots)."""


def new_history(lags) -> np.ndarray:
    """An empty record for these lags [wingbeats]: float64 [capacity, count, newest row, then capacity rows of
    :data:`HISTORY_ROW`]."""
    cap = HISTORY_ROWS_PER_BEAT * max(1, math.ceil(max(lags, default=0.0) - 1e-9)) + 8
    h = np.zeros(3 + HISTORY_ROW * cap)
    h[0] = cap
    return h


def _newest(hist: np.ndarray, n: int) -> list[int]:
    """Ring positions of the newest n records of ``hist``, oldest first."""
    cap, count, head = int(hist[0]), int(hist[1]), int(hist[2])
    if count < n:
        raise RuntimeError(f"the record holds {count} calls, fewer than the {n} asked for")
    return [(head - n + 1 + k) % cap for k in range(n)]


def history_rows(hist: np.ndarray, n: int) -> np.ndarray:
    """The newest n records of the ring ``hist`` (:func:`new_history`) as (n, 6), oldest first."""
    return np.array([hist[3 + HISTORY_ROW * i + 1:3 + HISTORY_ROW * (i + 1)] for i in _newest(hist, n)])


def set_history_rows(hist: np.ndarray, rows: np.ndarray, t0: float, dt: float) -> None:
    """Make the ring ``hist`` hold exactly ``rows`` (n, 6), oldest first, as calls at t0 - n dt, ..., t0 - dt
    (in place: the native callback holds the array's address)."""
    n = len(rows)
    if n > int(hist[0]):
        raise ValueError(f"{n} rows do not fit a record of {int(hist[0])}")
    for k in range(n):
        r = 3 + HISTORY_ROW * k
        hist[r] = t0 - (n - k) * dt
        hist[r + 1:r + HISTORY_ROW] = rows[k]
    hist[1], hist[2] = n, n - 1


def set_history_values(hist: np.ndarray, rows: np.ndarray) -> None:
    """Overwrite the values of the newest len(rows) records of the ring ``hist`` with ``rows`` (n, 6), oldest
    first, keeping their times (in place)."""
    for k, i in enumerate(_newest(hist, len(rows))):
        hist[3 + HISTORY_ROW * i + 1:3 + HISTORY_ROW * (i + 1)] = rows[k]


@njit(cache=True)
def lagged_states(hist, t, s, lags, period, out):
    """Record the state s (6,) at time t [s] in the ring ``hist`` (:func:`new_history`), then write into out
    (n_lags, 6) the recorded state at t - lag period for each lag [wingbeats]: linear in time between the two
    records around that instant (np.interp's rule), the oldest record before the first one (before the flight's
    start: the first call's state). The Python backend and the native callback both call this, so a flight's
    history inputs are the same whichever runs a step. No allocation."""
    cap, n, head = int(hist[0]), int(hist[1]), int(hist[2])
    head = 0 if n == 0 else (head + 1) % cap
    r = 3 + HISTORY_ROW * head
    hist[r] = t
    for j in range(6):
        hist[r + 1 + j] = s[j]
    n = min(n + 1, cap)
    hist[1], hist[2] = n, head
    for k in range(lags.shape[0]):
        tau = t - lags[k] * period
        i, newer, found = head, -1, False
        for _ in range(n):
            if hist[3 + HISTORY_ROW * i] <= tau:
                found = True
                break
            newer = i
            i = (i - 1) % cap
        if not found:  # before the oldest record: the oldest
            i, newer = newer, -1
        ri = 3 + HISTORY_ROW * i
        if newer < 0 or hist[ri] == tau:
            for j in range(6):
                out[k, j] = hist[ri + 1 + j]
            continue
        rn = 3 + HISTORY_ROW * newer
        w = (tau - hist[ri]) / (hist[rn] - hist[ri])
        for j in range(6):
            out[k, j] = hist[ri + 1 + j] + w * (hist[rn + 1 + j] - hist[ri + 1 + j])


def record_scale(kin: Kinematics) -> np.ndarray:
    """(6,) SI per normalized unit of a record row's values, as the Floquet states are normalized
    (:func:`hawksim.stability.floquet.state_scale`): velocities by U (Eq. 8, :func:`hawksim.insect.kinematics.
    reference_speed`), angular velocities by 1 / T."""
    from hawksim.insect.kinematics import reference_speed

    return np.array([reference_speed(kin)] * 3 + [kin.f] * 3)


def record_size(lags, calls: int) -> int:
    """Records of the calls before a beat's start that the beat's history inputs read: ceil(max lag x calls per
    beat) (0 without lags), the record part of a history network's state (:attr:`hawksim.flight.orbit.Orbit.record`,
    :mod:`hawksim.stability.history_floquet`)."""
    return int(math.ceil(max(lags, default=0.0) * calls - 1e-9))
