"""Discrete-time LQR on the controlled one-beat map, with a sensing delay, gain-scheduled over the ascent speed.

Plant (per subsystem, :meth:`hawksim.stability.linear_model.LinearModel.block`): x_{k+1} = A x_k + B0 u_{k-1} + B1 u_k
(normalized deviations from the orbit; u_{k-1} enters because beat k blends the previous command into the new
one). With a sensing delay of d wingbeats the command of beat k can use x_{k-d} and the commands already sent;
the augmented state

    z_k = (x_{k-d}, u_{k-d-1}, u_{k-d}, ..., u_{k-1})        (n + (d + 1) m)

is known at beat k and obeys z_{k+1} = Az z_k + Bz u_k exactly (x advances by the plant, the command slots
shift, u_k enters the last). The gain is the infinite-horizon LQR of (Az, Bz) for the cost
sum z' Q z + u' R u with Q = diag(1 / x_max^2) on the x block (zero on the command slots) and
R = diag(1 / u_max^2) (Bryson's rule, :data:`X_MAX`, :data:`U_MAX`), from scipy.linalg.solve_discrete_are:
u_k = -K z_k. Closed-loop multipliers: eig(Az - Bz K).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_discrete_are

from hawksim.control.derivatives import LAT_X, LONG_X, XI_NAMES
from hawksim.control.plant import ANTI_INPUTS, INPUTS, SYM_INPUTS
from hawksim.stability.history_floquet import RECORD_LAT, RECORD_LONG
from hawksim.stability.linear_model import LinearModel

X_MAX = {"u": 0.01, "v": 0.01, "w": 0.01, "p": 0.05, "q": 0.05, "r": 0.05, "phi": np.deg2rad(1.0),
         "theta": np.deg2rad(1.0), "psi": np.deg2rad(2.0), "X": 0.3, "Y": 0.3}
"""Bryson's acceptable deviations of the normalized states (velocities / U, rates x T, rad, positions / (U T))."""

U_MAX = {"f": 0.03, "phi0": np.deg2rad(3.0), "alpha0": np.deg2rad(3.0), "theta0": np.deg2rad(3.0),
         "dphi_a": np.deg2rad(3.0), "dphi0": np.deg2rad(3.0), "dalpha0": np.deg2rad(3.0)}
"""Bryson's acceptable commands (f relative, angles in rad)."""


def augment(A: np.ndarray, B0: np.ndarray, B1: np.ndarray, delay: int) -> tuple[np.ndarray, np.ndarray]:
    """(Az, Bz) of the delay-augmented state (module docstring)."""
    if delay < 0 or int(delay) != delay:
        raise ValueError(f"sensing delay must be a non-negative integer of wingbeats, got {delay}")
    n, m = B1.shape
    s = delay + 1  # command slots u_{k-d-1} .. u_{k-1}
    N = n + s * m
    Az, Bz = np.zeros((N, N)), np.zeros((N, m))
    Az[:n, :n] = A
    Az[:n, n:n + m] = B0  # u_{k-d-1}
    if delay == 0:
        Bz[:n] = B1  # u_{k-d} = u_k
    else:
        Az[:n, n + m:n + 2 * m] = B1  # u_{k-d}
    for j in range(s - 1):  # shift the slots
        Az[n + j * m:n + (j + 1) * m, n + (j + 1) * m:n + (j + 2) * m] = np.eye(m)
    Bz[n + (s - 1) * m:] = np.eye(m)
    return Az, Bz


@dataclass(frozen=True)
class Gain:
    """One subsystem's LQR: K (m, n + (d + 1) m) on z (module docstring), the closed-loop multipliers (sorted
    by ``|mu|`` descending), the open-loop ones of A, and the indices of its states / inputs."""

    K: np.ndarray
    multipliers: np.ndarray
    open_loop: np.ndarray
    states: tuple[int, ...]
    inputs: tuple[int, ...]
    delay: int
    record: tuple[int, ...] = ()
    """The record components (:data:`hawksim.stability.history_floquet.RECORD_LONG` or ``RECORD_LAT``) whose values
    follow the states in z, record-major (a history network's half-stroke design; empty otherwise)."""

    @property
    def spectral_radius(self) -> float:
        return float(np.abs(self.multipliers).max())


def _sorted(w):
    return w[np.argsort(-np.abs(w), kind="stable")]


def lqr_gain(lin: LinearModel, which: str, delay: int = 0, x_max: dict | None = None,
             u_max: dict | None = None, inputs: tuple[int, ...] | None = None) -> Gain:
    """LQR of the 'long' or 'lat' subsystem of the per-beat ``lin`` (a :class:`LinearModel`) with a sensing delay
    of ``delay`` wingbeats; ``inputs``: the channels (indices in :data:`INPUTS`) of the subsystem it may use (default
    all; the others stay at the reference). A model on a history network's augmented state (``lin.records``): the
    record's values carry no weight and are fed back."""
    A, B0, B1 = lin.block(which)
    xs, us = (LONG_X, SYM_INPUTS) if which == "long" else (LAT_X, ANTI_INPUTS)
    if inputs is not None:
        if not set(inputs) <= set(us) or not inputs:
            raise ValueError(f"inputs {inputs} are not a non-empty subset of the {which} channels {us}")
        cols = [us.index(i) for i in inputs]
        B0, B1, us = B0[:, cols], B1[:, cols], tuple(inputs)
    xm, um = {**X_MAX, **(x_max or {})}, {**U_MAX, **(u_max or {})}
    Az, Bz = augment(A, B0, B1, delay)
    Q = np.zeros_like(Az)  # the body states weighted; a history network's record values (after them) not
    Q[:len(xs), :len(xs)] = np.diag([1 / xm[XI_NAMES[i]] ** 2 for i in xs])
    R = np.diag([1 / um[INPUTS[i]] ** 2 for i in us])
    P = solve_discrete_are(Az, Bz, Q, R)
    K = np.linalg.solve(R + Bz.T @ P @ Bz, Bz.T @ P @ Az)
    record = (RECORD_LONG if which == "long" else RECORD_LAT) if lin.records else ()
    return Gain(K=K, multipliers=_sorted(np.linalg.eigvals(Az - Bz @ K)), open_loop=_sorted(np.linalg.eigvals(A)),
                states=xs, inputs=us, delay=int(delay), record=record)


def periodic_lqr_gains(blocks: list[tuple[np.ndarray, np.ndarray, np.ndarray]], xs: tuple[int, ...],
                       us: tuple[int, ...], delay: int = 0, x_max: dict | None = None,
                       u_max: dict | None = None, record: tuple[int, ...] = ()) -> tuple[Gain, ...]:
    """LQR of a periodic plant sampled p times per wingbeat (the half-stroke maps: p = 2): ``blocks`` [(A_j,
    B0_j, B1_j)] of each phase j of one subsystem (states ``xs``, inputs ``us``), a sensing delay of ``delay``
    SAMPLES, the same Bryson weights at every sample. One Gain per phase, u = -K_j z at phase j. States of the
    blocks beyond ``xs`` (a history network's record values, components ``record``) carry no weight: the cost is
    the body's, and the gain feeds the record back.

    Method: each phase augmented as :func:`augment` ((Az_j, Bz_j)); the plant lifted over one beat from phase 0,
    z_p = Phi z_0 + Gamma (u_0, ..., u_{p-1}), with the cost of every sample folded into the lifted weights
    (Q_L = sum Phi_j' Q Phi_j, R_L = diag(R) + sum Gamma_j' Q Gamma_j, cross term S_L = sum Phi_j' Q Gamma_j);
    scipy's solve_discrete_are(A_L, B_L, Q_L, R_L, s=S_L) gives the phase-0 cost-to-go P_0 of the periodic
    problem, and the per-phase gains follow by the Riccati recursion backward from it over one beat,
    K_j = (R + Bz_j' P_{j+1} Bz_j)^-1 Bz_j' P_{j+1} Az_j (P_p = P_0). Closed loop: the multipliers per beat are
    eig(prod_j (Az_j - Bz_j K_j)) (every Gain carries them); ``open_loop``: eig(prod_j A_j)."""
    xm, um = {**X_MAX, **(x_max or {})}, {**U_MAX, **(u_max or {})}
    aug = [augment(A, B0, B1, delay) for A, B0, B1 in blocks]
    n, m = blocks[0][2].shape
    N, p = aug[0][0].shape[0], len(blocks)
    Q = np.zeros((N, N))
    Q[:len(xs), :len(xs)] = np.diag([1 / xm[XI_NAMES[i]] ** 2 for i in xs])
    R = np.diag([1 / um[INPUTS[i]] ** 2 for i in us])
    Phi, Gam = np.eye(N), np.zeros((N, p * m))
    QL, RL, SL = np.zeros((N, N)), np.kron(np.eye(p), R), np.zeros((N, p * m))
    for j, (Az, Bz) in enumerate(aug):
        QL += Phi.T @ Q @ Phi
        RL += Gam.T @ Q @ Gam
        SL += Phi.T @ Q @ Gam
        Gam = Az @ Gam
        Gam[:, j * m:(j + 1) * m] += Bz
        Phi = Az @ Phi
    P0 = solve_discrete_are(Phi, Gam, QL, RL, s=SL)
    P, Ks = P0, [None] * p
    for j in reversed(range(p)):
        Az, Bz = aug[j]
        Ks[j] = np.linalg.solve(R + Bz.T @ P @ Bz, Bz.T @ P @ Az)
        P = Q + Az.T @ P @ (Az - Bz @ Ks[j])
    M = np.eye(N)
    for (Az, Bz), K in zip(aug, Ks):
        M = (Az - Bz @ K) @ M
    A_beat = np.eye(n)
    for A, _, _ in blocks:
        A_beat = A @ A_beat
    mu, ol = _sorted(np.linalg.eigvals(M)), _sorted(np.linalg.eigvals(A_beat))
    return tuple(Gain(K=K, multipliers=mu, open_loop=ol, states=tuple(xs), inputs=tuple(us), delay=int(delay),
                      record=tuple(record)) for K in Ks)


def periodic_lqr_gain(lin: LinearModel, which: str, delay: int = 0, x_max: dict | None = None,
                      u_max: dict | None = None, inputs: tuple[int, ...] | None = None) -> tuple[Gain, ...]:
    """:func:`periodic_lqr_gains` of the 'long' or 'lat' subsystem of a periodic ``lin`` (the half-stroke map, a
    :class:`LinearModel` with phases), a sensing delay of ``delay`` SAMPLES; ``inputs``: the subsystem's channels it
    may use (indices in :data:`INPUTS`, default all). A model on a history network's augmented state feeds its
    record values back (unweighted)."""
    xs, us = (LONG_X, SYM_INPUTS) if which == "long" else (LAT_X, ANTI_INPUTS)
    blocks = [lin.block(which, j) for j in range(lin.phases)]
    if inputs is not None:
        if not set(inputs) <= set(us) or not inputs:
            raise ValueError(f"inputs {inputs} are not a non-empty subset of the {which} channels {us}")
        cols = [us.index(i) for i in inputs]
        blocks, us = [(A, B0[:, cols], B1[:, cols]) for A, B0, B1 in blocks], tuple(inputs)
    record = (RECORD_LONG if which == "long" else RECORD_LAT) if lin.records else ()
    return periodic_lqr_gains(blocks, xs, us, delay, x_max, u_max, record)
