"""Constrained LQR: the wingbeat-to-wingbeat LQR that plans within Table 2, for orbits that sit on its bounds.

Why. The per-step surrogate's orbits (like the UVLM's) sit on two Table 2 bounds, phi_a = 60 deg and
theta0 = 25 deg. The LQR of :mod:`hawksim.control.lqr` commands symmetric and antisymmetric channels
(:data:`hawksim.control.plant.INPUTS`) that each wing then clips at Table 2: at phi_a = 60 deg an antisymmetric
amplitude command can only lower one wing, which also lowers the mean amplitude by a quarter of the command, a
lift and pitch disturbance the linear design does not see; theta0 passes commands of one sign only. Small
disturbances live with that (theta0 is left out of that design); a 0.5 m/s lateral gust does not: the
surrogate's (and the UVLM's) roll response to it is 3-6 times the quasi-steady model's, the LQR asks for 10-25 deg
of antisymmetric amplitude, and the clipped flight departs (docs/control.md, "The per-step surrogate in the loop").

What. The same cost (Bryson's weights of :mod:`hawksim.control.lqr` on the states and on the symmetric and
antisymmetric commands), minimised over a receding horizon of :data:`HORIZON` beats subject to each wing's
parameters staying inside Table 2, with the infinite-horizon LQR's cost-to-go as the terminal cost:

* channels (:data:`WING_INPUTS`): f (both wings), each wing's phi0, alpha0 and phi_a, and theta0 (both wings),
  deviations from the reference kinematics (f relative, angles in rad). Table 2 is then a box on them
  (:func:`channel_bounds`), and the symmetric amplitude is a channel too: an antisymmetric amplitude can be
  flown about a lowered mean with f making up the lift, a trade the optimiser sees;
* the plant: the controlled one-beat map x_{k+1} = A x_k + B0 v_{k-1} + B1 v_k of :mod:`hawksim.control.
  derivatives` over the whole 11-state xi, with B0, B1 differenced in these channels, unclipped, about the orbit
  (:func:`linearize_wings`), augmented for the sensing delay as :func:`hawksim.control.lqr.augment`;
* the problem: z_1..z_N = Phi z_0 + Gamma V over the horizon, cost sum z' Q z + v' R v + z_N' P z_N (P from
  ``scipy.linalg.solve_discrete_are``), condensed into a bounded linear least-squares problem solved by
  ``scipy.optimize.lsq_linear`` (bounded-variable least squares). Only the first beat's channels are flown
  (receding horizon).

When no bound is active over the horizon the optimum is the unconstrained one, whose first move is exactly the
LQR's u = -K z (tested): the controller is the LQR wherever the LQR stays inside Table 2, and the plan respecting
Table 2 where it would not. Longitudinal and lateral are one problem here (the per-wing channels act on both; R
is Bryson's diagonal weight of the symmetric/antisymmetric channels carried to the per-wing ones, so without
bounds it is the decoupled design plus the symmetric-amplitude and theta0 channels).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import mujoco
import numpy as np
from scipy.linalg import solve_discrete_are, solve_triangular
from scipy.optimize import lsq_linear

from hawksim.backends.record import record_scale
from hawksim.backends.registry import descriptor
from hawksim.control.derivatives import (XI_NAMES, Snapshot, central_jacobians, normalized_xi, one_beat,
                                         record_jacobians, xi_scale)
from hawksim.control.lqr import U_MAX, X_MAX, augment
from hawksim.control.schedule import Schedule
from hawksim.flight.orbit import Orbit
from hawksim.trim.registry import point_key
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics
from hawksim.insect.model import load_model
from hawksim.stability.linear_model import LinearModel, record_names

WING_INPUTS = ("f", "phi0_l", "phi0_r", "alpha0_l", "alpha0_r", "theta0", "phi_a_l", "phi_a_r")
"""Channels of the constrained controller: f (both wings; relative, f / f_ref - 1), each wing's (left, right)
phi0 and alpha0, theta0 (both wings), each wing's phi_a [rad], as deviations from the reference kinematics."""

SA_INPUTS = ("f", "phi0", "alpha0", "theta0", "phi_a", "dphi_a", "dphi0", "dalpha0")
"""The same channels as symmetric means and left-minus-right differences (:data:`SA_FROM_WING`): f, phi0, alpha0,
theta0, phi_a, then the antisymmetric phi_a, phi0, alpha0 of :data:`hawksim.control.plant.INPUTS`."""

SA_FROM_WING = np.array([
    [1, 0, 0, 0, 0, 0, 0, 0],
    [0, 0.5, 0.5, 0, 0, 0, 0, 0],
    [0, 0, 0, 0.5, 0.5, 0, 0, 0],
    [0, 0, 0, 0, 0, 1, 0, 0],
    [0, 0, 0, 0, 0, 0, 0.5, 0.5],
    [0, 0, 0, 0, 0, 0, 1, -1],
    [0, 1, -1, 0, 0, 0, 0, 0],
    [0, 0, 0, 1, -1, 0, 0, 0]], float)
"""s = SA_FROM_WING @ v: the symmetric/antisymmetric channels (:data:`SA_INPUTS`) of the per-wing ones."""

SYM_PHI_A_MAX = np.deg2rad(3.0)
"""Bryson's acceptable symmetric amplitude command [rad], as :data:`hawksim.control.lqr.U_MAX`'s other angles
(the per-beat LQR has no such channel)."""

HORIZON = 10
"""Beats of the receding horizon. Tuned: long enough for the plan to see a saturated beat's consequences (the
closed loop's fast modes decay within ~5 beats, docs/control.md); what it moves: the solve's size (8 x HORIZON
channels) and, when bounds are active, how far ahead the plan trades them."""

HELD_AT_BOUND = ("theta0",)
"""Parameters whose channel is held at the reference where the reference sits on a Table 2 bound (the surrogate's
and the UVLM's theta0 = 25 deg). Measured (scripts/studies/control_constrained.py): with theta0 free to move below
its bound the plans lean on it (theta0 down to 7 deg in a 0.5 m/s gust at 1 m/s), far outside the +-1.25 deg the
surrogate's network was trained on, and the flights depart; held, they recover. phi_a, on its bound too, stays
free: the per-wing amplitudes are the lateral authority."""

FIXED_WIDTH = 1e-12
"""A channel whose bounds are closer than this [normalized] is held at its bound, not optimised."""

_P = {k: i for i, k in enumerate(PARAM_NAMES)}


def wing_params(base: Kinematics, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(left, right) parameter vectors (7,) SI in PARAM_NAMES order for the channels ``v`` (8,) of
    :data:`WING_INPUTS` about ``base``, unsaturated."""
    v = np.asarray(v, float)
    p = base.as_array()
    left, right = p.copy(), p.copy()
    left[_P["f"]] = right[_P["f"]] = base.f * (1 + v[0])
    left[_P["phi0"]] += v[1]
    right[_P["phi0"]] += v[2]
    left[_P["alpha0"]] += v[3]
    right[_P["alpha0"]] += v[4]
    left[_P["theta0"]] += v[5]
    right[_P["theta0"]] += v[5]
    left[_P["phi_a"]] += v[6]
    right[_P["phi_a"]] += v[7]
    return left, right


def wing_channels(base: Kinematics, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Inverse of :func:`wing_params` (8,): f and theta0 from the mean of the wings."""
    p = base.as_array()
    dl, dr = np.asarray(left, float) - p, np.asarray(right, float) - p
    return np.array([(dl[_P["f"]] + dr[_P["f"]]) / 2 / base.f, dl[_P["phi0"]], dr[_P["phi0"]], dl[_P["alpha0"]],
                     dr[_P["alpha0"]], (dl[_P["theta0"]] + dr[_P["theta0"]]) / 2, dl[_P["phi_a"]], dr[_P["phi_a"]]])


_CHANNEL_PARAM = [_P[k] for k in ("f", "phi0", "phi0", "alpha0", "alpha0", "theta0", "phi_a", "phi_a")]


def channel_bounds(base: Kinematics, *, envelope: float | None = None, held: tuple[str, ...] = (),
                   insect: Insect | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) (8,) of the channels about ``base`` that keep both wings inside Table 2, and with
    ``envelope`` (a fraction of Table 2's width) within +-envelope x width of ``base`` per parameter (the
    surrogate's training envelope: :data:`hawksim.surrogate.flights.KIN_SPREAD`); the channels of the
    parameters in ``held`` (PARAM_NAMES) are held at the reference (both bounds 0). Table 2 is ``insect``'s
    kinematic bounds (default :func:`hawksim.insect.folder.default_insect`'s)."""
    lo, hi = (default_insect() if insect is None else insect).bounds_si()
    p = base.as_array()
    idx = _CHANNEL_PARAM
    lb, ub = lo[idx] - p[idx], hi[idx] - p[idx]
    if envelope is not None:
        w = envelope * (hi[idx] - lo[idx])
        lb, ub = np.maximum(lb, -w), np.minimum(ub, w)
    lb[0], ub[0] = lb[0] / base.f, ub[0] / base.f  # f relative
    lb, ub = np.minimum(lb, 0.0), np.maximum(ub, 0.0)
    for k in held:
        m = np.array([PARAM_NAMES[i] == k for i in idx])
        lb[m] = ub[m] = 0.0
    return lb, ub


WingMapModel = LinearModel
"""The per-wing model's name of :class:`hawksim.stability.linear_model.LinearModel` (``map="wings"``): the controlled
one-beat map in the per-wing channels, normalized as the per-beat model: A (11, 11), B0 and B1 (11, 8) over
:data:`WING_INPUTS`; on a history network's augmented state (``records`` n > 0) (11 + 6 n) rows."""


def _wing_model(orbit: Orbit, A, B0, B1, delta: float, wall: float, records: int = 0) -> LinearModel:
    return LinearModel(point=orbit, map="wings", states=XI_NAMES + record_names(records), inputs=WING_INPUTS, A=A,
                       B0=B0, B1=B1, scale=xi_scale(orbit.kinematics, orbit.insect.morphology),
                       dt=orbit.kinematics.period, delta=delta, wall_time_s=wall, records=records)


def linearize_wings(orbit: Orbit, *, A: np.ndarray | None = None, delta: float | None = None,
                    model: mujoco.MjModel | None = None) -> WingMapModel:
    """:class:`WingMapModel` about ``orbit`` (settable state: quasi-steady or surrogate) by central differences
    (:func:`hawksim.control.derivatives.central_jacobians`, unclipped: at a bound the difference reaches
    ``delta`` past it, where the surrogate's network extrapolates smoothly); ``A``: the state block if known
    (a :class:`BeatMapModel`'s: the zero-command beats are the same), else differenced too. 32 one-beat
    flights (+16 for A). A history network's orbit (:attr:`hawksim.flight.orbit.Orbit.record`): each beat branches
    from the orbit's flight (:class:`hawksim.control.derivatives.Snapshot`); given an ``A`` on the augmented state
    (a :class:`BeatMapModel` with ``records``), B0 and B1 get the record's rows too, else the record is held."""
    descriptor(orbit.aero).constrained_control.require("the constrained LQR's per-wing derivatives", orbit.aero)
    if orbit.has_memory and orbit.record is None:
        raise ValueError("per-wing derivatives need an orbit with a settable state or a record (quasi-steady or "
                         "surrogate); the UVLM's wake is neither")
    t0 = time.perf_counter()
    model = model if model is not None else load_model(morph=orbit.insect.morphology)
    if delta is None:
        delta = descriptor(orbit.aero).fd.control
    sc = xi_scale(orbit.kinematics, orbit.insect.morphology)
    if orbit.record is not None:
        snap = Snapshot(orbit, model)
        x0 = orbit.initial_state.as_array()
        if A is not None and A.shape[0] > 11:  # the augmented state: the commands' effect on the record too
            _, B0, B1 = record_jacobians(lambda x, vp, v, r: snap.beat(x, vp, v, record=r, wings=wing_params), x0,
                                         snap.record, orbit.kinematics, delta, 0, len(WING_INPUTS), states=False)
            return _wing_model(orbit, np.array(A, float), B0, B1, delta, time.perf_counter() - t0,
                               records=len(snap.record))

        def beat(x, v_prev, v):
            return snap.beat(x, v_prev, v, wings=wing_params)
    else:
        x0 = orbit.launch_state.as_array()

        def beat(x, v_prev, v):
            return one_beat(orbit, x, v_prev, v, model=model, wings=wing_params)

    A_, B0, B1 = central_jacobians(beat, normalized_xi(sc), x0, sc, delta, 0 if A is not None else 8,
                                   len(WING_INPUTS))
    return _wing_model(orbit, np.array(A if A is not None else A_, float), B0, B1, delta, time.perf_counter() - t0)


def wing_weights(u_max: dict | None = None) -> np.ndarray:
    """R (8, 8) on :data:`WING_INPUTS`: Bryson's diagonal weight of the symmetric/antisymmetric channels
    (:data:`hawksim.control.lqr.U_MAX`, :data:`SYM_PHI_A_MAX`) carried through :data:`SA_FROM_WING`."""
    um = {**U_MAX, **(u_max or {})}
    s_max = [um["f"], um["phi0"], um["alpha0"], um["theta0"], um.get("phi_a", SYM_PHI_A_MAX), um["dphi_a"],
             um["dphi0"], um["dalpha0"]]
    Rs = np.diag([1 / m ** 2 for m in s_max])
    return SA_FROM_WING.T @ Rs @ SA_FROM_WING


def _sqrt_psd(M: np.ndarray) -> np.ndarray:
    """S with S' S = M for a symmetric positive semi-definite M."""
    w, V = np.linalg.eigh((M + M.T) / 2)
    return (V * np.sqrt(np.clip(w, 0, None))).T


@dataclass(frozen=True)
class ConstrainedGain:
    """The constrained LQR about one orbit (module docstring) for a sensing delay of ``delay`` beats: the
    augmented plant (Az, Bz), the infinite-horizon gain K and cost-to-go P, and the condensed horizon as the
    least-squares problem |M V + Mz z_0|^2 (the horizon cost less a constant of z_0) in the horizon's channels V
    (N m,): M (N m, N m) upper triangular (the Cholesky factor of the condensed cost's Hessian), Mz (N m, nz).
    ``multipliers``: eig(Az - Bz K) (the loop with no bound active)."""

    Az: np.ndarray
    Bz: np.ndarray
    K: np.ndarray
    P: np.ndarray
    M: np.ndarray
    Mz: np.ndarray
    horizon: int
    delay: int
    multipliers: np.ndarray
    open_loop: np.ndarray

    @property
    def spectral_radius(self) -> float:
        return float(np.abs(self.multipliers).max())

    def command(self, z0: np.ndarray, lb: np.ndarray, ub: np.ndarray) -> tuple[np.ndarray, bool]:
        """(first beat's channels (8,), whether a bound was active) for the augmented state z0 and channel
        bounds (8,) held over the horizon."""
        m = self.Bz.shape[1]
        rhs = -self.Mz @ z0
        V = solve_triangular(self.M, rhs)
        L, U = np.tile(lb, self.horizon), np.tile(ub, self.horizon)
        if np.all(V >= L) and np.all(V <= U):
            return -self.K @ z0, False
        free = U - L > FIXED_WIDTH  # a channel with no room (both bounds at the reference) is held there
        Vf = np.clip(np.zeros_like(L), L, U)
        if free.any():
            sol = lsq_linear(self.M[:, free], rhs - self.M[:, ~free] @ Vf[~free], bounds=(L[free], U[free]),
                             method="bvls")
            Vf[free] = sol.x
        return np.clip(Vf[:m], lb, ub), True


def constrained_gain(lin: WingMapModel, delay: int = 0, *, x_max: dict | None = None, u_max: dict | None = None,
                     horizon: int = HORIZON) -> ConstrainedGain:
    """:class:`ConstrainedGain` of ``lin`` (module docstring)."""
    Az, Bz = augment(lin.A, lin.B0, lin.B1, delay)
    n, m = lin.B1.shape
    nz = Az.shape[0]
    xm = {**X_MAX, **(x_max or {})}
    Q = np.zeros((nz, nz))  # the 11 states of xi weighted; a history network's record values (after them) not
    Q[:len(XI_NAMES), :len(XI_NAMES)] = np.diag([1 / xm[k] ** 2 for k in XI_NAMES])
    R = wing_weights(u_max)
    P = solve_discrete_are(Az, Bz, Q, R)
    K = np.linalg.solve(R + Bz.T @ P @ Bz, Bz.T @ P @ Az)
    N = int(horizon)
    Phi = np.zeros((N * nz, nz))
    Gam = np.zeros((N * nz, N * m))
    Ak = np.eye(nz)
    for k in range(N):  # z_{k+1} = Az^(k+1) z0 + sum_j Az^(k-j) Bz v_j
        Ak = Az @ Ak
        Phi[k * nz:(k + 1) * nz] = Ak
        for j in range(k + 1):
            Gam[k * nz:(k + 1) * nz, j * m:(j + 1) * m] = np.linalg.matrix_power(Az, k - j) @ Bz
    Sq = _sqrt_psd(Q)
    Sp = _sqrt_psd(P)
    rows_x = np.vstack([Sq @ Gam[k * nz:(k + 1) * nz] for k in range(N - 1)] + [Sp @ Gam[(N - 1) * nz:]])
    rows_z = np.vstack([Sq @ Phi[k * nz:(k + 1) * nz] for k in range(N - 1)] + [Sp @ Phi[(N - 1) * nz:]])
    Sr = _sqrt_psd(R)
    M_full = np.vstack([rows_x, np.kron(np.eye(N), Sr)])
    Mz_full = np.vstack([rows_z, np.zeros((N * m, nz))])
    # the same minimiser from a square system: M' M = C' C (Cholesky; R > 0 makes it positive definite), so
    # |M V + Mz z|^2 = |C V + C^-T M' Mz z|^2 + const (4x fewer rows for every solve)
    C = np.linalg.cholesky(M_full.T @ M_full).T
    M = C
    Mz = np.linalg.solve(C.T, M_full.T @ Mz_full)
    mu = np.linalg.eigvals(Az - Bz @ K)
    ol = np.linalg.eigvals(lin.A)
    return ConstrainedGain(Az=Az, Bz=Bz, K=K, P=P, M=M, Mz=Mz, horizon=N, delay=int(delay),
                           multipliers=mu[np.argsort(-np.abs(mu), kind="stable")],
                           open_loop=ol[np.argsort(-np.abs(ol), kind="stable")])


class ConstrainedSchedule(Schedule):
    """A :class:`hawksim.control.schedule.Schedule` (orbits, one-beat models and LQR gains at the grid speeds,
    per beat only) whose commands come from the constrained LQR of each grid point (:func:`constrained_gain` of
    :func:`linearize_wings`), blended with the interpolation weights (a convex blend of plans inside the same
    Table 2 box stays inside it). ``bound_active``: how many commands so far had a bound active in their plan."""

    def __init__(self, v_lo: float, v_hi: float, *, horizon: int = HORIZON, envelope: float | None = None,
                 held: tuple[str, ...] | None = None, **kw):
        if kw.get("rate", "beat") != "beat":
            raise ValueError("the constrained LQR updates once per wingbeat (--control-rate beat)")
        insect = kw.get("insect")
        if insect is not None and insect != default_insect():  # its wing models and plans use Table 2's box
            raise ValueError(f"insect {insect.name!r}: the constrained LQR is designed for the default hawkmoth only "
                             "(control another insect with control='lqr')")
        if kw.get("axis", "vertical") != "vertical":
            raise ValueError("axis: the constrained LQR flies vertical ascent only (a forward-flight schedule takes "
                             "the LQR, Schedule(axis='forward'))")
        super().__init__(v_lo, v_hi, **kw)
        self.horizon = int(horizon)
        self.envelope = envelope
        self.held = HELD_AT_BOUND if held is None else tuple(held)
        self.wing_models, self.constrained = {}, {}
        for p in self.points:
            key = point_key(p.speed, p.orbit.aero, p.orbit.insect, kw.get("model"), "wings")
            if key not in _WING_MODELS:
                _WING_MODELS[key] = linearize_wings(p.orbit, A=p.model.A, model=kw.get("model"))
            self.wing_models[p.speed] = _WING_MODELS[key]
            self.constrained[p.speed] = constrained_gain(_WING_MODELS[key], self.delay, x_max=kw.get("x_max"),
                                                         u_max=kw.get("u_max"), horizon=horizon)
        self.bound_active = 0

    def wings(self, v: float, x_sensed: np.ndarray, pos_sensed: np.ndarray, past: list,
              phase: int = 0, record: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(left, right) parameter vectors (7,) SI for the next beat (the arguments as :meth:`Schedule.command`),
        inside Table 2."""
        kin, x_ref, _, _ = self.reference(v, phase)
        pos_ref = sum(w * pt.reference_state(phase)[1] for w, pt in self.weights(v))
        xi = np.concatenate([x_sensed - x_ref, pos_sensed - pos_ref])
        lb, ub = channel_bounds(kin, envelope=self.envelope, held=self._held(kin), insect=self.insect)
        past_v = [wing_channels(kin, left, right) for left, right in past]
        out, active = np.zeros(len(WING_INPUTS)), False
        rec_dev = None if record is None or not self.feeds_record else record - self.reference_record(v, phase)
        for w, pt in self.weights(v):
            sc = xi_scale(pt.orbit.kinematics, pt.orbit.insect.morphology)
            parts = [xi / sc] if rec_dev is None else [xi / sc, (rec_dev / record_scale(pt.orbit.kinematics)).ravel()]
            z = np.concatenate(parts + past_v)
            vk, a = self.constrained[pt.speed].command(z, lb, ub)
            out += w * vk
            active |= a
        self.bound_active += int(active)
        return wing_params(kin, out)

    def to_json_constrained(self) -> dict:
        """The constrained design's settings and how often a bound shaped the plan (for the flight's JSON)."""
        return {"horizon_beats": self.horizon, "channels": list(WING_INPUTS),
                "envelope_fraction_of_table2": self.envelope, "held_at_bound": list(self.held),
                "commands_with_a_bound_active": self.bound_active,
                "closed_loop_spectral_radius_unconstrained": {f"{v:g}": g.spectral_radius
                                                              for v, g in self.constrained.items()}}

    def _held(self, kin: Kinematics) -> tuple[str, ...]:
        """The parameters of :attr:`held` that sit on a Table 2 bound at ``kin``
        (:data:`hawksim.control.schedule.BOUND_TOL`)."""
        from hawksim.control.schedule import BOUND_TOL

        lo, hi = self.insect.bounds_si()
        p = kin.as_array()
        return tuple(k for k in self.held if min(p[_P[k]] - lo[_P[k]], hi[_P[k]] - p[_P[k]]) <= BOUND_TOL)


_WING_MODELS: dict = {}
"""The process's per-wing models, keyed by :func:`hawksim.flight.points.point_key` (insect, backend, speed, MJCF)."""
