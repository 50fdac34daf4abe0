"""Floquet analysis of the free body's periodic orbit, beside the cycle-averaged A matrices of the same model.

Monodromy. The Jacobian of the one-wingbeat map (:mod:`hawksim.flight.orbit`) about the orbit's state at phase 0, by
central differences over the 8 body states (u, v, w, p, q, r, phi, theta) of :data:`hawksim.flight.orbit.STATE_NAMES`
(heading/stability axes: x forward horizontal, y right, z down; position and the heading psi are neutral: the
map's velocities are expressed in the heading axes, so the reduced map does not depend on psi, and psi's own
multiplier 1 is dropped). The matrix is NONDIMENSIONAL: velocities / U (U = 2 phi_a f r2), rates x T, angles
in rad, so it is the linearized map of the paper's variables (Eq. 8) from t+ = k to t+ = k + 1. It is split
into the longitudinal (u, w, q, theta) and lateral (v, p, r, phi) blocks, the orders of
:func:`hawksim.stability.system.a_long` / ``a_lat``; for a left/right symmetric orbit the coupling blocks vanish
(their norm is reported). Multipliers mu = eigenvalues; exponents ln(mu) per wingbeat (principal branch),
comparable with the eigenvalues of the nondimensional A matrices (t+ = t / T): a cycle-averaged model
predicts mu = exp(lambda+).

Cycle-averaged A matrices of the quasi-steady backend (:func:`quasi_steady_system`): stability derivatives by
central differences of held-body runs (:func:`hawksim.backends.held.held_flight`, body on the trim path at chi) in which
the wings move relative to the air with an extra rigid body motion (v_d + omega_d x (x - x_cg)): the wing
velocities and angular velocities the backend sees get the disturbance added (the quasi-steady backend takes
each wing's rigid motion and a uniform air velocity, so this is exactly the body translating/rotating relative
to still air, with the attitude frozen, the meaning of Eq. 15's derivatives). Then
:func:`hawksim.stability.system.nondimensional_system` with the mass properties of
:func:`hawksim.stability.derivatives.mass_properties`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import mujoco
import numpy as np

from hawksim.backends.held import held_flight
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.morphology import Morphology
from hawksim.insect.kinematics import Kinematics
from hawksim.backends.builtin import QUASI_STEADY
from hawksim.backends.registry import descriptor
from hawksim.flight.orbit import S, Orbit, orbit_flight, scales
from hawksim.frames import cross
from hawksim.stability.linear_model import LinearModel

FLOQUET_STATES = (0, 1, 2, 3, 4, 5, 6, 7)
"""Indices (into STATE_NAMES) of the monodromy's states: u, v, w, p, q, r, phi, theta."""

FLOQUET_NAMES = ("u", "v", "w", "p", "q", "r", "phi", "theta")
"""The monodromy's states by name (:data:`FLOQUET_STATES`)."""

LONG = (0, 2, 4, 7)
"""Longitudinal (u, w, q, theta) indices into the 8 Floquet states."""

LAT = (1, 3, 5, 6)
"""Lateral (v, p, r, phi) indices into the 8 Floquet states."""

REACH_MIN = 0.1
"""A Floquet mode of a UVLM orbit is RESOLVED when its REACH is at least this (tuned: it decides which modes the
validation compares, not their values). The UVLM's launches are perturbed before the warm-up beats (the wake cannot
be set), so the monodromy is B A^-1 with A = d x(w)/d x0 over the warm-up beats; reach(v) = (|v| / |A^-1 v|) /
sigma_max(A) is how strongly the launch family reaches the mode's direction v at the periodic beat, relative to
its best-reached direction. A mode reached only through a small singular value of A is the launch family's
extrapolation (its wake is not the one a continued flight carries), not a mode of the flight. Measured
(shipped orbits, step 1e-3; results/free_flight/validation.json): every mode the perturbed flights confirm has
reach >= 0.12 (1 m/s: 0.37 longitudinal, 0.48 lateral; 2 m/s: 0.64, 0.20, 0.12 longitudinal, 0.29 lateral), every
one they do not has reach <= 0.042 (1 m/s: -0.176+-0.234i 0.026, 1.185+-2.589i 0.042; 2 m/s: -1.299 0.005,
1.559 0.0003, -1.376 0.020). A quasi-steady orbit (state settable, A = I) has reach 1 for every mode."""


FD_DELTA = QUASI_STEADY.fd.monodromy
"""Central-difference step in the normalized states (u/U, q T, rad) of a settable map: the quasi-steady backend's
(:data:`hawksim.backends.builtin.FD_DELTA`; each backend's is its descriptor's ``fd.monodromy``)."""


@dataclass(frozen=True)
class Floquet:
    """Monodromy (8, 8) nondimensional (rows/cols u, v, w, p, q, r, phi, theta; velocities / U, rates x T, angles
    in radians: :func:`state_scale`), its blocks long (4, 4) in
    (u, w, q, theta) order and lat (4, 4) in (v, p, r, phi) order, coupling: Frobenius norm of the two
    off-diagonal blocks (max), multipliers_long/lat (4,) complex sorted by ``|mu|`` descending, exponents_long/lat
    ln(mu) per wingbeat, eigenvectors_long/lat (4, 4) columns (normalized states)."""

    monodromy: np.ndarray
    long: np.ndarray
    lat: np.ndarray
    coupling: float
    multipliers_long: np.ndarray
    multipliers_lat: np.ndarray
    exponents_long: np.ndarray
    exponents_lat: np.ndarray
    eigenvectors_long: np.ndarray
    eigenvectors_lat: np.ndarray
    delta: float
    wall_time_s: float
    reach_long: tuple[float, ...] = (1.0, 1.0, 1.0, 1.0)
    reach_lat: tuple[float, ...] = (1.0, 1.0, 1.0, 1.0)
    linear: LinearModel | None = field(default=None, repr=False, compare=False)
    """The linear model this is the eigen-analysis of (``map="monodromy"``; :func:`floquet_analysis`)."""

    @property
    def resolved_long(self) -> tuple[bool, ...]:
        """Per longitudinal mode: reach >= :data:`REACH_MIN`."""
        return tuple(r >= REACH_MIN for r in self.reach_long)

    @property
    def resolved_lat(self) -> tuple[bool, ...]:
        """Per lateral mode: reach >= :data:`REACH_MIN`."""
        return tuple(r >= REACH_MIN for r in self.reach_lat)

    @property
    def max_multiplier(self) -> float:
        return float(max(np.abs(self.multipliers_long).max(), np.abs(self.multipliers_lat).max()))

    @property
    def max_resolved_multiplier(self) -> float:
        """Largest ``|mu|`` among the resolved modes (all modes for a settable-state backend)."""
        m = [abs(mu) for mu, ok in zip(np.concatenate([self.multipliers_long, self.multipliers_lat]),
                                       self.resolved_long + self.resolved_lat) if ok]
        return float(max(m)) if m else float("nan")


def state_scale(kin: Kinematics, morph: Morphology | None = None) -> np.ndarray:
    """(8,) SI per normalized unit of the Floquet states: U for velocities, 1/T for rates, 1 for angles (U the
    reference speed with the wing of ``morph``, the insect's: :func:`hawksim.flight.orbit.scales`)."""
    U, T = scales(kin, morph)
    return np.array([U, U, U, 1 / T, 1 / T, 1 / T, 1.0, 1.0])


def _eig(M):
    w, V = np.linalg.eig(M)
    order = np.argsort(-np.abs(w), kind="stable")
    return w[order], V[:, order]


def monodromy(orbit: Orbit, *, delta: float | None = None, model: mujoco.MjModel | None = None,
              lateral: bool = True) -> Floquet:
    """Monodromy of the one-beat map about ``orbit`` by central differences (16 flights; 8 without ``lateral``, whose
    lateral block is then the identity), in normalized states (angles in radians: :class:`Floquet`). UVLM: the
    symmetric perturbations use the mirrored lattice, the lateral ones both wings; each evaluation is a launch from
    an empty wake with the orbit's warm-up beats (:mod:`hawksim.flight.orbit`), the perturbation applied at the
    launch and the map measured over the periodic beat (the perturbation's evolution over the warm-up beats is
    included: the Jacobian is then that of ``warm_beats + 1`` beats relative to ``warm_beats``, see :func:`_chain`).
    Each UVLM mode gets its ``reach`` and is ``resolved`` or not (:data:`REACH_MIN`): an unresolved exponent is the
    launch family's extrapolation, not a mode of the flight. An orbit with a record (a history network's,
    :attr:`hawksim.flight.orbit.Orbit.record`) is flown from its record, which is held: the body block of the
    augmented map; its modes are :func:`hawksim.stability.history_floquet.history_monodromy`'s."""
    import time

    t0 = time.perf_counter()
    if delta is None:  # the backend's: the UVLM's free wake amplifies round-off (docs/free_flight.md)
        delta = descriptor(orbit.aero).fd.monodromy
    M, A = _monodromy_matrix(orbit, delta, model, lateral)
    lin = LinearModel(point=orbit, map="monodromy", states=FLOQUET_NAMES, inputs=(), A=M,
                      scale=state_scale(orbit.kinematics, orbit.insect.morphology), dt=orbit.kinematics.period,
                      delta=delta, wall_time_s=time.perf_counter() - t0, launch=A if orbit.warm_beats else None)
    fl = floquet_analysis(lin)
    return fl if lateral or not orbit.warm_beats else replace(fl, reach_lat=(1.0,) * 4)


def floquet_analysis(lin: LinearModel) -> Floquet:
    """The Floquet analysis of a monodromy (``lin.map == "monodromy"``, :func:`monodromy`): the eigen-analysis of its
    A per longitudinal and lateral block, and for a UVLM orbit (``lin.launch``, the launches' d x(w) / d x0) each
    mode's reach (:data:`REACH_MIN`)."""
    if lin.map != "monodromy":
        raise ValueError(f"floquet_analysis takes a monodromy (map='monodromy'), got map={lin.map!r}")
    fl = replace(_floquet(lin.A, lin.delta, lin.wall_time_s), linear=lin)
    if lin.launch is None:
        return fl
    A = lin.launch
    return replace(fl, reach_long=reach(A[np.ix_(LONG, LONG)], fl.eigenvectors_long),
                   reach_lat=reach(A[np.ix_(LAT, LAT)], fl.eigenvectors_lat))


def reach(A: np.ndarray, V: np.ndarray) -> tuple[float, ...]:
    """Per column v of ``V`` (eigenvectors, complex): (|v| / |A^-1 v|) / sigma_max(A), in (0, 1]
    (:data:`REACH_MIN`)."""
    smax = np.linalg.svd(A, compute_uv=False)[0]
    return tuple(float(np.linalg.norm(v) / np.linalg.norm(np.linalg.solve(A, v)) / smax) for v in V.T)


def _monodromy_matrix(orbit: Orbit, delta: float, model, lateral: bool) -> np.ndarray:
    """(M, A): the (8, 8) normalized monodromy at central-difference step ``delta`` (see :func:`monodromy`) and
    the launch Jacobian A = d x(w) / d x0 (identity without warm-up beats)."""
    kin = orbit.kinematics
    sc = state_scale(kin, orbit.insect.morphology)
    x0 = orbit.launch_state.as_array()
    w = orbit.warm_beats
    fl = {s: orbit_flight(orbit, s, model) for s in (True, False)}
    cols = FLOQUET_STATES if lateral else LONG
    # states at the start (k = w) and end (k = w + 1) of the periodic beat, per perturbed launch
    A = np.zeros((8, 8))   # d x(w) / d x0, normalized (identity when w = 0)
    B = np.zeros((8, 8))   # d x(w+1) / d x0
    for j in cols:
        sym = j in LONG
        outs = []
        for s in (1, -1):
            x = x0.copy()
            x[FLOQUET_STATES[j]] += s * delta * sc[j]
            st = fl[sym].fly(kin, x, w + 1, orbit.chi_ref, record=orbit.record).states
            outs.append((st[w][:8] / sc, st[w + 1][:8] / sc))
        A[:, j] = (outs[0][0] - outs[1][0]) / (2 * delta)
        B[:, j] = (outs[0][1] - outs[1][1]) / (2 * delta)
    if not lateral:
        for j in LAT:
            A[j, j] = B[j, j] = 1.0
    return _chain(A, B, w), (A if w else np.eye(8))


def _chain(A: np.ndarray, B: np.ndarray, warm: int) -> np.ndarray:
    """The one-beat monodromy from d x(w)/d x0 (A) and d x(w+1)/d x0 (B): M = B A^-1 (for w = 0, A = I).
    For the UVLM this is the map of the periodic beat's start state to its end state along the family of
    launches, i.e. with the wake developed from each perturbed launch."""
    if warm == 0:
        return B
    return B @ np.linalg.inv(A)


def _floquet(M, delta, wall) -> Floquet:
    L = M[np.ix_(LONG, LONG)]
    Lt = M[np.ix_(LAT, LAT)]
    c = max(np.linalg.norm(M[np.ix_(LONG, LAT)]), np.linalg.norm(M[np.ix_(LAT, LONG)]))
    wl, Vl = _eig(L)
    wt, Vt = _eig(Lt)
    return Floquet(monodromy=M, long=L, lat=Lt, coupling=float(c), multipliers_long=wl, multipliers_lat=wt,
                   exponents_long=np.log(wl.astype(complex)), exponents_lat=np.log(wt.astype(complex)),
                   eigenvectors_long=Vl, eigenvectors_lat=Vt, delta=delta, wall_time_s=wall)


# ---- cycle-averaged A matrices of the quasi-steady backend -----------------------------------------------
class _RelativeMotion:
    """A quasi-steady backend whose wings move relative to the air with an extra rigid motion of the body:
    velocity v_d (world) and angular velocity omega_d (world) about the body's centre of mass."""

    name = "quasi-steady"

    def __init__(self, v_d: np.ndarray, omega_d: np.ndarray, morph=None):
        from hawksim.backends.quasi_steady import QuasiSteadyBackend

        self.inner = QuasiSteadyBackend(default_insect().morphology if morph is None else morph)
        self.v_d, self.omega_d = np.asarray(v_d, float), np.asarray(omega_d, float)

    def reset(self, state):
        self.inner.reset(state)

    def prime(self, previous):
        """The quasi-steady model's previous-call memory (:class:`hawksim.backends.memory.PrimedMemory`)."""
        self.loads(previous)

    def loads(self, st):
        c = st.body_pos
        st2 = replace(st, wing_v=st.wing_v + self.v_d + cross(self.omega_d, st.wing_origin - c),
                      wing_omega=st.wing_omega + self.omega_d, body_v=st.body_v + self.v_d,
                      body_omega=st.body_omega + self.omega_d)
        return self.inner.loads(st2)


DERIV_DELTA_VELOCITY = 0.05
"""Translational disturbance / U (as hawksim.stability.derivatives.DELTA_VELOCITY)."""

DERIV_DELTA_RATE = 0.05
"""Rotational disturbance x T (as hawksim.stability.derivatives.DELTA_RATE)."""

QS_HELD_CYCLES = 2
"""Held-body wingbeats (the last is averaged; the quasi-steady model has no wake, the first beat only starts its
added-mass memory)."""


@dataclass(frozen=True)
class AveragedSystem:
    """Cycle-averaged linear model: dimensional derivatives (stability axes, SI, about the system's centre of mass:
    :func:`hawksim.stability.system.about_centre_of_mass`), nondimensional A_long (4, 4),
    A_lat (4, 4) (t+ = t/T), their eigenvalues (complex, sorted by real part descending), and Eq. 8's scalars."""

    derivatives: dict
    nondimensional: dict
    A_long: np.ndarray
    A_lat: np.ndarray
    eig_long: np.ndarray
    eig_lat: np.ndarray
    scalars: dict


def _mean_loads_stability(kin, speed, v_d_s, w_d_s, steps_per_cycle, insect=None, model=None, forward_speed=0.0):
    if not forward_speed:  # vertical flight: as before the forward speed existed (bit for bit)
        r = held_flight(kin, speed, _RelativeMotion(S @ v_d_s, S @ w_d_s, None if insect is None else
                                                    insect.morphology),
                        cycles=QS_HELD_CYCLES, steps_per_cycle=steps_per_cycle, insect=insect, model=model)
        F, M = r.mean_loads(1)
        return np.concatenate([S @ F, S @ M])
    from hawksim.backends.held import body_loads_world
    from hawksim.condition import air_velocity
    from hawksim.frames import rot_y

    insect = default_insect() if insect is None else insect
    r = held_flight(kin, speed, _RelativeMotion(S @ v_d_s, S @ w_d_s, insect.morphology), cycles=QS_HELD_CYCLES,
                    steps_per_cycle=steps_per_cycle, insect=insect, model=model, forward_speed=forward_speed,
                    body_loads=False)
    F, M = r.mean_loads(1)
    # the body's own loads in the disturbed stream (its translation; the model takes no rotation, as in free flight)
    fb, mb = body_loads_world(rot_y(-kin.chi), air_velocity(speed, forward_speed) - S @ v_d_s, insect)
    return np.concatenate([S @ (F + fb), S @ (M + mb)])


def quasi_steady_system(kin: Kinematics, speed: float, *, steps_per_cycle: int = 200,
                        insect: Insect | None = None, forward_speed: float = 0.0) -> AveragedSystem:
    """Stability derivatives of the quasi-steady backend at ``kin`` on the held trim path (ascent ``speed``,
    forward speed ``forward_speed`` [m/s], :mod:`hawksim.condition`; body at chi), and the nondimensional A matrices
    (hawksim.stability.system). ``insect`` (default :func:`hawksim.insect.folder.default_insect`): its wings in the
    backend, its MJCF for the held flights and the mass and inertia, its morphology for Eq. 8's scales. In forward
    flight the body's own loads (:class:`hawksim.insect.body_aero.BodyAero`) count, in the disturbed stream, as on
    the free body."""
    from hawksim.insect.kinematics import reference_speed
    from hawksim.insect.model import load_model
    from hawksim.stability.derivatives import mass_properties
    from hawksim.stability.system import about_centre_of_mass, nondimensional_system

    insect = default_insect() if insect is None else insect
    model = load_model(morph=insect.morphology)
    U, T = reference_speed(kin, insect.morphology), kin.period
    dv, dw = DERIV_DELTA_VELOCITY * U, DERIV_DELTA_RATE / T
    e = np.eye(3)
    z = np.zeros(3)
    out = {}
    comp = dict(X=0, Y=1, Z=2, L=3, M=4, N=5)
    for var, i, trans, forces in (("u", 0, True, "XZM"), ("w", 2, True, "XZM"), ("q", 1, False, "XZM"),
                                  ("v", 1, True, "YLN"), ("p", 0, False, "YLN"), ("r", 2, False, "YLN")):
        h = dv if trans else dw
        ys = []
        for s in (1, -1):
            vd, wd = (s * h * e[i], z) if trans else (z, s * h * e[i])
            ys.append(_mean_loads_stability(kin, speed, vd, wd, steps_per_cycle, insect, model, forward_speed))
        diff = (ys[0] - ys[1]) / (2 * h)
        for f in forces:
            out[f + var] = float(diff[comp[f]])
    mp = mass_properties(kin, model)
    # moved to the system's centre of mass
    d, Al, At, scalars = nondimensional_system(kin, speed, out, mp, insect.morphology, forward_speed=forward_speed)

    def ev(A):
        w = np.linalg.eigvals(A)
        return w[np.argsort(-w.real, kind="stable")]

    return AveragedSystem(derivatives=about_centre_of_mass(out, mp.body_cg), nondimensional=d, A_long=Al, A_lat=At,
                          eig_long=ev(Al), eig_lat=ev(At),
                          scalars=scalars)
