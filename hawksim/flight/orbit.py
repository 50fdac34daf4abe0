"""The periodic orbit of the free body: the one-wingbeat stroboscopic map and its Newton shooting solve.

The map. The free flight of :class:`hawksim.flight.simulator.Simulator` (MuJoCo free body, wings on their prescribed
motion Eq. 1, body recoil included, gravity on) is strobed at wing phase 0 (t = k T): the wings are then at their
prescribed phase-0 pose and rates, so the body state alone fixes the mechanical state, and the map is

    x_{k+1} = P(x_k; kin),   x = the body state of :data:`STATE_NAMES` at t = k T.

The state (9,), SI (u, v, w, p, q, r, phi, theta, psi; ``BodyState``), its chart and how it is set and read
(the quasi-steady backend's memory primed from it): :mod:`hawksim.flight.body_state`.

A history network (the per-step surrogate with history inputs) also keeps a record of its last calls; its orbit is
periodic in that record too (:attr:`Orbit.record`, :func:`periodic_orbit`).

UVLM: the wake is part of the state and cannot be set from x. The UVLM orbit is a free flight LAUNCHED at
t = 0 from x0 with no wake; the map's residual is measured on beat ``warm_beats + 1`` (default 2 warm-up beats
develop the wake on the orbit guess): periodicity x((w + 1) T) = x(w T), and the mean velocity of that beat.
This is well defined (a smooth function of x0 and the kinematics) but only approximately a periodic orbit of the
full system: the residual floor is the wake's beat-to-beat variation, measured by one more beat
(:attr:`Orbit.floor`).

Forward flight (issue 51; ``forward_speed`` U > 0, :mod:`hawksim.condition`): the air is still and the body's
mean velocity over the periodic beat is (U, 0, V) (world); the state is the same chart (velocities in the level
heading axes, so the orbit's u is about U), periodic in (u, w, q, theta) while the position drifts at (U, 0, V);
the body's own loads (:class:`hawksim.insect.body_aero.BodyAero`) act on the free body
(:attr:`hawksim.flight.simulator.Simulator.body_aero`) where U > 0, as they count in the held-body trims, and the
UVLM's wake is free (no prescribed far wake: the forward stream carries it away). U = 0 is vertical flight, computed
exactly as before.

Newton shooting (:func:`periodic_orbit`), symmetric flight: unknowns (u, w, q, theta) at phase 0 plus the
kinematic parameters f and phi0 (beta, alpha0 and the rest at the held-body trim): f sets the mean lift,
phi0 (the mean sweep, i.e. where the centre of pressure sits along the body) the mean pitching moment, and the
phase-0 pitch theta tilts the stroke plane and thereby the mean horizontal force. Equations: 4 periodicity
residuals and 2 mean-velocity residuals (mean horizontal velocity U, mean vertical velocity V). Normalized:
velocities by U = 2 phi_a f r2, the rate by 1/T (q T), angles in rad. Finite-difference Jacobian, Newton with
backtracking line search.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from hawksim.backends.base import AeroBackend
from hawksim.backends.builtin import (FD_STEP, QUASI_STEADY, SURROGATE_FD_STEP,  # noqa: F401 (re-exported)
                                      SURROGATE_ORBIT_TOL, UVLM_FD_STEP, UVLM_TOL_RATE, UVLM_TOL_VELOCITY,
                                      UVLM_WARM_BEATS)
from hawksim.backends.far_wake import FarWake, far_wake_for
from hawksim.backends.memory import RECORD, WAKE
from hawksim.backends.registry import descriptor, descriptor_of
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import Kinematics, reference_speed
from hawksim.insect.morphology import Morphology
from hawksim.insect.model import load_model
from hawksim.backends import flight_backend
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE
from hawksim.frames import pitch_of
from hawksim.flight.body_state import (S, STATE_NAMES, SYM_STATE, BodyState, read_body_state,  # noqa: F401
                                       set_body_state, state_to_world, world_to_state)
from hawksim.flight.power import P_plus
from hawksim.flight.simulator import Simulator, aero_every_for
from hawksim.trim.point import OperatingPoint
from hawksim.trim.registry import shipped_point
from hawksim.trim.tables import trim_kinematics

STEPS_PER_CYCLE = FLY_STEPS_PER_CYCLE
"""Integrator steps per wingbeat (the quasi-steady trim table's resolution)."""

MAX_STEP = 0.2
"""Largest Newton step in any normalized unknown (u/U, w/U, q T, theta [rad], f/f_trim, phi0 [rad])."""

RECORD_TOL = 1e-6
"""A history network's orbit (:attr:`Orbit.record`) counts as converged when its record changes by at most this
over the periodic beat (normalized as the state: velocities / U, rates x T), besides the body's residual."""

MAX_RECORD_ITER = 30
"""Updates of the record (each followed by the body's Newton solve) before a delay orbit gives up."""

# The per-backend steps and tolerances live in the backends' descriptors (``descriptor(aero).fd.orbit``,
# ``.orbit_tolerance``, ``.warm_beats``: :mod:`hawksim.backends.builtin`); these names are theirs.
ORBIT_TOL = QUASI_STEADY.orbit_tolerance.residual
"""The default orbit tolerance (max abs normalized residual, :data:`hawksim.backends.builtin.ORBIT_TOL`)."""


def make_orbit_backend(aero: str, *, symmetric: bool = True, kinematics: Kinematics | None = None,
                       insect: Insect | None = None, far_wake: FarWake | None = None) -> tuple[AeroBackend, int]:
    """(backend, aero_every) of `hawksim fly --aero NAME` (:func:`hawksim.backends.flight_backend`) for
    ``STEPS_PER_CYCLE`` integrator steps per beat, at its descriptor's update interval (quasi-steady every step, the
    UVLM and the surrogate at ``FLY_UVLM``'s rate), with ``insect``'s wings (None: the default insect's).
    ``far_wake``: the UVLM's prescribed far wake (:class:`hawksim.backends.far_wake.FarWake`, an orbit's
    :attr:`Orbit.far_wake`; needs ``kinematics``); None: the whole wake free.
    ValueError for a backend without periodic orbits."""
    descriptor(aero).orbits.require("a periodic orbit", aero)
    backend = flight_backend(aero, symmetric=symmetric, kinematics=kinematics,
                             morphology=None if insect is None else insect.morphology)
    if far_wake is not None:
        if kinematics is None:
            raise ValueError("a prescribed far wake (far_wake) needs the kinematics flown")
        far_wake.apply(backend, kinematics)
    return backend, aero_every_for(backend, STEPS_PER_CYCLE)


@dataclass(frozen=True)
class Beats:
    """A free flight strobed at phase 0, nb beats. states (nb + 1, 9): the state at t = k T; mean_velocity
    (nb, 3): each beat's mean centre-of-mass velocity of the body (displacement / T), world frame [m/s];
    mean_pitch (nb,) [rad]; P_plus (nb,): cycle mean of max(0, joint power) / P0 (the insect's) over the
    backend-update steps (:func:`hawksim.flight.power.P_plus`); wall_time_s."""

    states: np.ndarray
    mean_velocity: np.ndarray
    mean_pitch: np.ndarray
    P_plus: np.ndarray
    wall_time_s: float
    record: np.ndarray | None = None
    """A history network's record (n, 6) at the flight's end (:func:`hawksim.backends.step_surrogate.history_rows`,
    n = :func:`hawksim.backends.step_surrogate.record_size`); None for a backend without one."""


def backend_record(backend, every: int) -> np.ndarray | None:
    """The newest records (n, 6) of a history network's backend that a beat's history inputs read (its
    :meth:`~hawksim.backends.memory.RecordMemory.snapshot` at ``STEPS_PER_CYCLE // every`` calls per beat), None
    without lags or for a backend without a record."""
    if descriptor_of(backend).memory != RECORD:
        return None
    return backend.snapshot(STEPS_PER_CYCLE // every)


class OrbitFlight:
    """Free flights of the orbit solver from phase 0: one reusable MjModel, a Simulator per kinematics (aero: the
    name of a registered backend that supports periodic orbits, :mod:`hawksim.backends.registry`) of ``insect``
    (default :func:`hawksim.insect.folder.default_insect`): its wings in the backend, its MJCF unless ``model`` is
    given, its P0 in :attr:`Beats.P_plus`; ``far_wake``: the UVLM's prescribed far wake (:func:`make_orbit_backend`);
    ``forward_speed`` [m/s]: the flight condition's U (:mod:`hawksim.condition`): where > 0 the body's own loads act
    on the free body (:attr:`hawksim.flight.simulator.Simulator.body_aero`)."""

    def __init__(self, aero: str, symmetric: bool = True, model: mujoco.MjModel | None = None,
                 insect: Insect | None = None, far_wake: FarWake | None = None, forward_speed: float = 0.0):
        from hawksim.condition import check_forward_speed

        self.aero = aero
        self.symmetric = symmetric
        self.far_wake = far_wake
        self.forward_speed = check_forward_speed(forward_speed)
        self.insect = default_insect() if insect is None else insect
        self.model = model if model is not None else load_model(morph=self.insect.morphology)

    def fly(self, kin: Kinematics, x0: np.ndarray, beats: int, chi_ref: float, backend=None,
            record: np.ndarray | None = None) -> Beats:
        """``beats`` beats from x0 at phase 0; ``record`` (n, 6): a history network's record of the calls before
        the start (:attr:`Orbit.record`; default none)."""
        if backend is None:
            backend, _ = make_orbit_backend(self.aero, symmetric=self.symmetric, kinematics=kin, insect=self.insect,
                                            far_wake=self.far_wake)
        every = aero_every_for(backend, STEPS_PER_CYCLE)
        if record is not None:
            backend.seed(np.asarray(record, float), kin.period * every / STEPS_PER_CYCLE)
        sim = Simulator(self.model, kin, backend, steps_per_cycle=STEPS_PER_CYCLE, gravity=True, aero_every=every)
        if self.forward_speed > 0:
            from hawksim.insect.body_aero import BodyAero

            sim.body_aero = BodyAero.of(self.insect.morphology)
        set_body_state(sim, x0, chi_ref)
        t0 = time.perf_counter()
        n = STEPS_PER_CYCLE
        states, vel, pitch, pp = [read_body_state(sim, chi_ref)], [], [], []
        states[0] = np.asarray(x0, float).copy()
        pos = sim.d.qpos[:3].copy()
        for _ in range(beats):
            b = sim.advance(n)
            pw, th = b.power_joint, pitch_of(b.body_R)
            if not np.all(np.isfinite(sim.d.qpos)):
                raise FloatingPointError("free flight diverged (non-finite state)")
            states.append(read_body_state(sim, chi_ref))
            new = sim.d.qpos[:3].copy()
            vel.append((new - pos) / kin.period)
            pos = new
            pitch.append(th.mean())
            pp.append(P_plus(pw, every, first=b.first, P0=self.insect.P0))
        return Beats(np.array(states), np.array(vel), np.array(pitch), np.array(pp), time.perf_counter() - t0,
                     backend_record(backend, every))


def orbit_flight(orbit: OperatingPoint, symmetric: bool = True, model: mujoco.MjModel | None = None) -> OrbitFlight:
    """The :class:`OrbitFlight` of ``orbit``'s flights: its backend, insect, far wake and forward speed."""
    return OrbitFlight(orbit.aero, symmetric=symmetric, model=model, insect=orbit.insect, far_wake=orbit.far_wake,
                       forward_speed=orbit.forward_speed)


Orbit = OperatingPoint
"""The free-body name of :class:`hawksim.trim.point.OperatingPoint` (the same type; :func:`periodic_orbit` returns
one with ``body="free"``)."""


def orbit_within_uvlm_tolerance(r: np.ndarray, kin: Kinematics, morph: Morphology | None = None) -> bool:
    """Whether a normalized 6-residual (u, w, q, theta periodicity; mean horizontal and vertical velocity) meets
    the UVLM's orbit tolerance (:data:`UVLM_TOL_VELOCITY` and :data:`UVLM_TOL_RATE` in SI); ``morph``: the insect's
    morphology of :func:`scales`."""
    return descriptor("uvlm").orbit_tolerance.met(r, *scales(kin, morph))


def shipped_orbit(speed: float, aero: str, *, insect: Insect | None = None,
                  model: mujoco.MjModel | None = None) -> Orbit | None:
    """The shipped orbit of ``aero`` at exactly ``speed`` [m/s] (its descriptor's ``orbit_table``) for ``insect`` on
    ``model`` (default: the default insect on its generated MJCF), None if absent (or if the table does not hold for
    the backend as built now: the surrogate's orbits hold for the network they were solved with only); SI
    (kinematics and launch state angles in radians). The registry of :mod:`hawksim.trim.registry` (each table read
    once per process)."""
    return shipped_point(speed, aero, insect=insect, model=model)


def orbit_table(orbits: list[Orbit], command: str) -> dict:
    """The layout of a shipped orbit table (one row per speed, :meth:`Orbit.to_json`), with its command."""
    from hawksim import __version__

    return {"source": "Newton shooting on the one-wingbeat map of the free body (hawksim.flight.orbit)",
            "command": command, "hawksim_version": __version__, "aero": orbits[0].aero if orbits else None,
            "steps_per_cycle": STEPS_PER_CYCLE, "rows": [o.to_json() for o in orbits]}


def scales(kin: Kinematics, morph: Morphology | None = None) -> tuple[float, float]:
    """(U [m/s], T [s]): the reference speed of Eq. 8 (:func:`hawksim.insect.kinematics.reference_speed`, with the
    wing of ``morph``, the flying insect's morphology: default :func:`hawksim.insect.folder.default_insect`'s) and
    the wingbeat period, the units of the normalized states."""
    return reference_speed(kin, default_insect().morphology if morph is None else morph), kin.period


def orbit_residual(kin: Kinematics, speed: float, b: Beats, warm: int, morph: Morphology | None = None,
                   forward_speed: float = 0.0) -> np.ndarray:
    """Normalized 6-residual of a flight whose beat ``warm`` (0-based) is the candidate periodic beat (``morph``: the
    insect's morphology of :func:`scales`): periodicity of (u, w, q, theta) and the beat's mean velocity less
    (``forward_speed``, ``speed``) (world x and z)."""
    U, T = scales(kin, morph)
    xa, xb = b.states[warm], b.states[warm + 1]
    dx = xb - xa
    mv = b.mean_velocity[warm]
    mx = mv[0] - forward_speed if forward_speed else mv[0]
    return np.array([dx[0] / U, dx[2] / U, dx[4] * T, dx[7], mx / U, (mv[2] - speed) / U])


MOMENT_PARAMETERS = ("phi0", "alpha0", "theta0")
"""The kinematic parameters a periodic-orbit solve may balance the mean pitching moment with (its sixth unknown,
radians): phi0 (the mean sweep, the default) or, where phi0 is wanted elsewhere (e.g. off a Table 2 bound), the
mean feathering alpha0 or the mean deviation theta0."""


def unpack_unknowns(z: np.ndarray, base: Kinematics, f_ref: float,
                    morph: Morphology | None = None, moment_parameter: str = "phi0") -> tuple[Kinematics, np.ndarray]:
    """Normalized unknowns z = (u/U, w/U, q T, theta, f/f_ref, phi0 (or ``moment_parameter``)) -> (kinematics,
    launch state (9,)) (``morph``: the insect's morphology of :func:`scales`)."""
    kin = replace(base, f=float(z[4] * f_ref), **{moment_parameter: float(z[5])})
    U, T = scales(kin, morph)
    x = np.zeros(9)
    x[0], x[2], x[4], x[7] = z[0] * U, z[1] * U, z[2] / T, z[3]
    return kin, x


def initial_guess(kin: Kinematics, speed: float, flight: OrbitFlight, warm: int = 0,
                  forward_speed: float = 0.0) -> np.ndarray:
    """Launch state (9,) from the held-body trim, by ``hawksim.flight.fly._start_on_orbit``'s logic: one calibration
    beat from (straight up at V, pitch chi, no rotation) measures the beat-mean pitch, pitch rate and velocity,
    and the start is corrected by them (removing a mean rate q also lowers the mean pitch by q T / 2). The
    Newton solve calibrates on the first beat (warm = 0) also for the UVLM: after warm-up beats from an
    uncorrected start the body has drifted too far for a one-beat correction. Forward flight: the start moves at
    (``forward_speed``, 0, ``speed``) and the horizontal velocity is corrected toward ``forward_speed``."""
    x = np.zeros(9)
    x[2], x[7] = -speed, kin.chi
    if forward_speed:
        x[0] = forward_speed
    b = flight.fly(kin, x, warm + 1, kin.chi)
    # the calibration beat's means (the beat mean of q is (theta(T) - theta(0)) / T)
    q_mean = (b.states[warm + 1, 7] - b.states[warm, 7]) / kin.period
    mv = b.mean_velocity[warm]
    x0 = x.copy()
    x0[7] = kin.chi - (b.mean_pitch[warm] - kin.chi) + q_mean * kin.period / 2
    x0[4] = -q_mean
    x0[0] = forward_speed - (mv[0] - forward_speed) if forward_speed else -mv[0]
    x0[2] = -speed - (-mv[2] + speed)
    return x0


def periodic_orbit(speed: float, aero: str = "quasi-steady", *, kinematics: Kinematics | None = None,
                   tol: float | None = None, max_iter: int = 20, warm_beats: int | None = None,
                   model: mujoco.MjModel | None = None, x0: np.ndarray | None = None, log=None,
                   fd_step: float | None = None, insect: Insect | None = None,
                   far_wake: FarWake | None | str = "auto", forward_speed: float = 0.0,
                   moment_parameter: str = "phi0") -> Orbit:
    """Newton shooting for the symmetric periodic orbit at ascent ``speed`` [m/s] and ``forward_speed`` [m/s]
    (:mod:`hawksim.condition`; default 0, vertical flight).

    SI throughout: u, w [m/s], q [rad/s], theta [rad], f [Hz], phi0 [rad].

    Unknowns: (u, w, q, theta) at the launch and the kinematic parameters f, phi0 (start: the held-body trim
    ``trim_kinematics(speed, aero)`` or ``kinematics``; the other five parameters stay fixed). Equations:
    periodicity of (u, w, q, theta) over the measured beat and its mean velocity (0, 0, V) (world). Forward-
    difference Jacobian (6 extra flights per iteration), full Newton step with backtracking (halving while the
    residual's max norm does not fall, at most 10 times). A solve that does not converge returns the point of smallest
    residual it evaluated, with that residual (``converged`` False). ``warm_beats``: beats before the measured one
    (default: the backend's ``warm_beats``: 0 for the quasi-steady backend and the surrogate,
    :data:`UVLM_WARM_BEATS` for the UVLM). ``tol``: the max abs normalized residual (default: the backend's
    ``orbit_tolerance``, :class:`hawksim.backends.registry.OrbitTolerance`). ``fd_step``: the Jacobian's step
    (default: the backend's ``fd.orbit``). ``log``: called with a line per iteration. ``insect``: the insect flown
    (default :func:`hawksim.insect.folder.default_insect`): its wings in the backend, its MJCF unless ``model`` is
    given (then the two must describe the same insect), its P0 in :attr:`Orbit.P_plus`; without ``kinematics`` the
    start is the default insect's held-body trim, or another insect's reference kinematics at ``speed``
    (:meth:`hawksim.insect.insect.Insect.reference_kinematics`; the default insect's trim if it has none: a variant
    of the default insect given by the fields that differ).

    ``far_wake``: the UVLM's wake ("auto": :func:`hawksim.backends.far_wake.far_wake_for`, prescribed after half a
    beat below 0.75 m/s, where the whole free wake's map is not smooth enough for Newton, docs/free_flight.md; a
    :class:`~hawksim.backends.far_wake.FarWake`; or None: the whole wake free); the orbit keeps it
    (:attr:`Orbit.far_wake`) and every flight from it flies it. Ignored (None) for a backend without a wake.

    A per-step surrogate with history inputs (and ``warm_beats`` not given) is a delay system: its state is the
    body state and the record of its last calls (:mod:`hawksim.stability.history_floquet`). Its orbit is solved on
    that augmented state: the Newton solve above from a record, then the record replaced by the periodic beat's
    own calls and the body solved again, until the record repeats to :data:`RECORD_TOL` (a fixed-point
    iteration: the record is a shift register whose every entry is overwritten in one beat, so it enters its own
    update only through the network's history inputs). The orbit keeps that record (:attr:`Orbit.record`) and
    every flight from it starts with it.

    Forward flight (``forward_speed`` > 0, the module docstring): the mean-velocity residual is (U, 0, V), the body's
    loads act, the wake is free (``far_wake`` "auto" gives None); without ``kinematics`` the start is the default
    insect's shipped forward trims in level flight (:func:`hawksim.trim.tables.forward_start`, 0-4 m/s; ValueError
    naming ``forward_speed`` elsewhere: give kinematics, e.g. a trim of
    :func:`hawksim.trim.model_search.trim_on_model`), and a network backend (trained on vertical flight only) is
    refused (:func:`hawksim.condition.check_forward_backend`). The orbit carries ``forward_speed``.

    ``moment_parameter`` (:data:`MOMENT_PARAMETERS`): the parameter solved with f instead of phi0 (then phi0
    stays at the start's); ValueError naming it otherwise.
    """
    if moment_parameter not in MOMENT_PARAMETERS:
        raise ValueError(f"moment_parameter {moment_parameter!r}: choose one of {', '.join(MOMENT_PARAMETERS)}")
    from hawksim.condition import check_forward_backend, check_forward_speed

    t_start = time.perf_counter()
    desc = descriptor(aero)
    desc.orbits.require("a periodic orbit", aero)
    forward_speed = check_forward_speed(forward_speed)
    check_forward_backend(aero, forward_speed)
    if forward_speed > 0 and kinematics is None:  # the shipped forward trims (ValueError outside them)
        from hawksim.trim.tables import forward_start

        kinematics = forward_start(forward_speed, speed, insect)
    insect = default_insect() if insect is None else insect
    guess = (shipped_orbit(speed, desc.orbit_guess, insect=insect)  # the surrogate mimics the UVLM
             if desc.orbit_guess and not forward_speed else None)
    if kinematics is None and guess is not None:
        kinematics = guess.kinematics
        x0 = guess.initial_state.as_array() if x0 is None else x0
    if kinematics is None and insect != default_insect():  # another insect: from its own reference kinematics
        kinematics = insect.reference_kinematics(speed)  # (None: the default insect's trim, as for a variant of it)
    base = kinematics if kinematics is not None else trim_kinematics(speed, aero)
    chi = base.chi
    delay = (desc.memory == RECORD and warm_beats is None  # the orbit of a delay system
             and desc.make(kinematics=base, morphology=insect.morphology).memory_beats() > 0)
    if warm_beats is None:  # beats before the measured one: the UVLM's wake (a history network's: its record)
        warm_beats = desc.warm_beats
    warm = warm_beats
    if desc.memory != WAKE:
        far_wake = None
    elif isinstance(far_wake, str):
        if far_wake != "auto":
            raise ValueError(f"far_wake must be 'auto', a FarWake or None, got {far_wake!r}")
        far_wake = None if forward_speed else far_wake_for(speed, base, insect.morphology)
    fl = OrbitFlight(aero, symmetric=True, model=model, insect=insect, far_wake=far_wake,
                     forward_speed=forward_speed)
    h_fd = fd_step if fd_step is not None else desc.fd.orbit
    f_ref = base.f
    if x0 is None:
        x0 = initial_guess(base, speed, fl, 0, forward_speed)
    morph = insect.morphology  # the velocity unit is this insect's wing speed
    U, T = scales(base, morph)
    z = np.array([x0[0] / U, x0[2] / U, x0[4] * T, x0[7], 1.0, getattr(base, moment_parameter)])
    rec = None  # the record the flights start with (a delay orbit's; None: no record)

    def F(zz):
        kin, x = unpack_unknowns(zz, base, f_ref, morph, moment_parameter)
        b = fl.fly(kin, x, warm + 1, chi, record=rec)
        return orbit_residual(kin, speed, b, warm, morph, forward_speed), b

    def met(rr, zz) -> bool:
        if tol is not None:
            return float(np.abs(rr).max()) <= tol
        kin_, _ = unpack_unknowns(zz, base, f_ref, morph, moment_parameter)
        return desc.orbit_tolerance.met(rr, *scales(kin_, morph))

    hist: list[float] = []

    def newton(z, it):  # at most max_iter iterations per solve; ``it`` counts them all
        r, b = F(z)
        hist.append(float(np.abs(r).max()))
        best = (z, r, b)  # the point of smallest residual evaluated: the answer of a solve that does not converge
        if log is not None:
            log(f"start: max|residual| {hist[-1]:.3e}" if len(hist) == 1 else
                f"record updated: max|residual| {hist[-1]:.3e}")
        k = 0
        while not met(r, z) and k < max_iter:
            it, k = it + 1, k + 1
            J = np.empty((6, 6))
            for j in range(6):
                zj = z.copy()
                zj[j] += h_fd
                J[:, j] = (F(zj)[0] - r) / h_fd
            dz = np.linalg.solve(J, -r)
            lam = min(1.0, MAX_STEP / np.abs(dz).max())
            for halvings in range(11):
                if halvings:
                    lam /= 2
                try:
                    rn, bn = F(z + lam * dz)
                except (ValueError, FloatingPointError):  # e.g. the UVLM refuses a far-off flight
                    rn, bn = np.full(6, np.inf), None
                if np.abs(rn).max() < hist[-1]:
                    break
            if bn is None:
                break
            # the step evaluated last, with its own residual (when every halving fails, the last, smallest one)
            z, r, b = z + lam * dz, rn, bn
            hist.append(float(np.abs(r).max()))
            if np.abs(r).max() < np.abs(best[1]).max():
                best = (z, r, b)
            if log is not None:
                log(f"iteration {it}: max|residual| {hist[-1]:.3e} (step {lam:g})")
        if not met(r, z):  # stalled: the best point it went through, with its own residual and flight
            z, r, b = best
        return z, r, b, it

    z, r, b, it = newton(z, 0)
    change = 0.0
    if delay:  # the record's fixed point: fly from the last periodic beat's own calls until they repeat
        from hawksim.backends.record import record_scale

        rec_scale = record_scale(base)  # the normalization of the body state's U, T
        for _ in range(MAX_RECORD_ITER):
            change = float("inf") if rec is None else float(np.abs((b.record - rec) / rec_scale).max())
            if change <= RECORD_TOL:
                break
            rec = b.record
            z, r, b, it = newton(z, it)
        if log is not None:
            log(f"record: max change over the periodic beat {change:.2e}")
    kin, x_launch = unpack_unknowns(z, base, f_ref, morph, moment_parameter)
    floor = 0.0
    if warm > 0:
        bf = fl.fly(kin, x_launch, warm + 2, chi)
        rf = orbit_residual(kin, speed, Beats(bf.states[1:], bf.mean_velocity[1:], bf.mean_pitch[1:], bf.P_plus[1:],
                                         0.0), warm, morph, forward_speed)
        floor = float(np.abs(rf[:4]).max())
    extra = {}
    if rec is not None:
        _, every = make_orbit_backend(aero, kinematics=kin, insect=insect)
        extra = {"record": rec, "record_dt": kin.period * every / STEPS_PER_CYCLE, "record_change": change}
    return OperatingPoint(speed=float(speed), aero=aero, kinematics=kin, body="free",
                 source=f"Newton shooting on the one-wingbeat map of the free body ({aero})",
                 initial_state=BodyState.from_array(b.states[warm]),
                 launch_state=BodyState.from_array(x_launch), warm_beats=warm, residual=float(np.abs(r).max()),
                 residuals=r,
                 mean_velocity=b.mean_velocity[warm], mean_pitch=float(b.mean_pitch[warm]),
                 P_plus=float(b.P_plus[warm]), iterations=it, converged=met(r, z) and change <= RECORD_TOL,
                 floor=floor, history=tuple(hist), wall_time_s=time.perf_counter() - t_start, chi_ref=chi,
                 insect=insect, far_wake=far_wake, forward_speed=forward_speed, **extra)


def fly_orbit(orbit: Orbit, beats: int, *, perturbation: np.ndarray | None = None,
              model: mujoco.MjModel | None = None, symmetric: bool | None = None, backend=None,
              iterate_map: bool = False) -> Beats:
    """Open-loop free flight of ``beats`` wingbeats from the orbit (one continuous flight: no resets, the backend
    keeps its memory and the wings their tracking error), strobed at phase 0. With ``iterate_map`` the flight is
    restarted from the read state at every section instead (x_{k+1} = P(x_k) exactly). The two differ by the
    state the map does not carry: the quasi-steady memory (primed, 1e-3 m/s error in the strip normal velocities)
    and the wing-rate tracking error at phase 0 (5e-4 rad/s): measured 4.5e-4 rad/s in q (q T = 1.6e-5) and 8e-6
    m/s in u after one beat at 1 m/s, then amplified by the multipliers.
    ``perturbation`` (9,) is added to the launch state (SI, state order).
    For the UVLM the flight includes the orbit's ``warm_beats`` (the returned rows start at the periodic beat); an
    orbit with a record (a history network's) starts with it.
    symmetric: mirror the UVLM (default: unless the perturbation is lateral). The insect flown is the orbit's
    (:attr:`Orbit.insect`; its MJCF unless ``model`` is given)."""
    x = orbit.launch_state.as_array()
    if perturbation is not None:
        x = x + np.asarray(perturbation, float)
    if symmetric is None:
        symmetric = perturbation is None or not np.any(np.asarray(perturbation)[[1, 3, 5, 6, 8]])
    fl = orbit_flight(orbit, symmetric, model)
    w = orbit.warm_beats
    if iterate_map:
        if orbit.has_memory:
            raise ValueError("iterate_map needs a settable state (quasi-steady orbit); the UVLM's wake and a history "
                             "network's record are not")
        rows = [fl.fly(orbit.kinematics, x, 1, orbit.chi_ref, backend=backend, record=orbit.record)]
        for _ in range(beats - 1):
            rows.append(fl.fly(orbit.kinematics, rows[-1].states[-1], 1, orbit.chi_ref, backend=backend))
        return Beats(np.array([rows[0].states[0]] + [r.states[-1] for r in rows]),
                     np.concatenate([r.mean_velocity for r in rows]), np.concatenate([r.mean_pitch for r in rows]),
                     np.concatenate([r.P_plus for r in rows]), sum(r.wall_time_s for r in rows))
    b = fl.fly(orbit.kinematics, x, w + beats, orbit.chi_ref, backend=backend, record=orbit.record)
    return Beats(b.states[w:], b.mean_velocity[w:], b.mean_pitch[w:], b.P_plus[w:], b.wall_time_s, b.record)


def beat_map(orbit: Orbit, x: np.ndarray, *, model: mujoco.MjModel | None = None, symmetric: bool = True,
             beats: int = 1) -> np.ndarray:
    """The one-beat map at the orbit's kinematics: state (9,) at the launch -> state (9,) ``beats`` beats after
    the measured beat starts (for the UVLM the launch is ``warm_beats`` earlier, from an empty wake); the orbit's
    insect."""
    fl = orbit_flight(orbit, symmetric, model)
    return fl.fly(orbit.kinematics, np.asarray(x, float), orbit.warm_beats + beats, orbit.chi_ref,
                  record=orbit.record).states[-1]
