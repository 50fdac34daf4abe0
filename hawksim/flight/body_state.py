"""The free body's state at a wing phase: its chart (heading axes, Euler angles about a reference body angle),
and how it is written into and read from a :class:`hawksim.flight.simulator.Simulator`.

State (9,), SI, documented exactly (``BodyState``, :mod:`hawksim.state`):

* u, v, w [m/s]: velocity of the body's centre of mass (the free joint's linear qvel; the body frame's origin
  is its centre of mass) in the HEADING axes H: the stability axes (x forward horizontal, y right, z down)
  turned about the vertical by the yaw psi. At psi = 0, H is the fixed stability frame: u = vx_world,
  v = -vy_world, w = -vz_world (an ascent at V has w = -V).
* p, q, r [rad/s]: the body's angular velocity in the heading axes H (roll right-wing-down, pitch nose-up, yaw
  nose-right positive).
* phi, theta, psi [rad]: Euler angles Z-Y-X (Etkin) of the body-fixed stability frame F relative to the
  stability axes: F is the body's aircraft frame (x toward the head, y right, z ventral) pitched nose-down by the
  reference body angle ``chi_ref`` (= kin.chi), so that F's x is horizontal when the body's pitch is chi_ref;
  F = Rz(psi) Ry(theta - chi_ref) Rx(phi). So theta is the body pitch (elevation of the body x axis above the
  horizontal, nose up; for phi = 0 exactly ``arcsin(R_world_body[2, 0])``), phi the bank about the horizontal
  F x axis (right wing down), psi the heading (nose right). Position and psi are neutral: the dynamics do not
  depend on them, and velocities in H make the reduced map independent of psi.

The state is SET by writing the free joint's qpos/qvel directly (:func:`set_body_state`, no momentum adjustment as
in ``Simulator.reset``) and READ back the same way (:func:`read_body_state`), so that iterating the map is the
flight up to the two approximations below.

Backend memory. The quasi-steady backend keeps the previous call's strip normal velocities (its added-mass term is a
backward difference); at the section it is primed from the state x by one call at t = -aero_every dt with the body
state there extrapolated to second order from x and a probe step (:func:`_prime_previous_call`), so P is a function
of x alone. The difference to a continuous flight (whose memory holds the true previous step) is the extrapolation's
error in one step's added-mass impulse (see :func:`hawksim.flight.orbit.fly_orbit`). The wing joints are reset to
their exact prescribed phase-0 pose and rates (the continuous flight tracks them to < 1e-6 rad).
"""

from __future__ import annotations

import mujoco
import numpy as np

from hawksim.backends.base import read_state
from hawksim.backends.memory import PREVIOUS_CALL
from hawksim.backends.registry import descriptor_of
from hawksim.flight.simulator import Simulator
from hawksim.frames import STABILITY_TO_WORLD, pitch_of, quat_from_matrix, quat_to_matrix, rot_x, rot_y, rot_z
from hawksim.state import STATE_NAMES, SYM_STATE, BodyState  # noqa: F401 (their home: hawksim.state)

S = STABILITY_TO_WORLD
"""World (z up, heading +x) <-> stability axes (x forward, y right, z down): a rotation by pi about x."""


def state_to_world(x: np.ndarray, chi_ref: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(R_world_body (3, 3), v_world (3,) [m/s], omega_world (3,) [rad/s]) of a state x (9,)."""
    u, v, w, p, q, r, phi, theta, psi = x
    H = rot_z(psi)
    A = H @ rot_y(theta - chi_ref) @ rot_x(phi) @ rot_y(chi_ref)  # aircraft body frame -> stability axes
    return S @ A @ S, S @ H @ np.array([u, v, w]), S @ H @ np.array([p, q, r])


def world_to_state(R: np.ndarray, v_world: np.ndarray, omega_world: np.ndarray, chi_ref: float) -> np.ndarray:
    """Inverse of :func:`state_to_world`: the state (9,) of a body attitude R (body -> world) and world-frame
    velocity and angular velocity."""
    F = S @ R @ S @ rot_y(-chi_ref)
    theta = chi_ref - pitch_of(F)
    phi = np.arctan2(F[2, 1], F[2, 2])
    psi = np.arctan2(F[1, 0], F[0, 0])
    Ht = rot_z(psi).T
    return np.concatenate([Ht @ S @ v_world, Ht @ S @ omega_world, [phi, theta, psi]])


def read_body_state(sim: Simulator, chi_ref: float) -> np.ndarray:
    """The state (9,) of the simulator's body now, from the free joint's qpos/qvel."""
    d = sim.d
    R = quat_to_matrix(d.qpos[3:7])
    return world_to_state(R, d.qvel[:3].copy(), R @ d.qvel[3:6], chi_ref)


def _rodrigues(rv: np.ndarray) -> np.ndarray:
    a = float(np.linalg.norm(rv))
    if a == 0.0:
        return np.eye(3)
    k = rv / a
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def set_body_state(sim: Simulator, x: np.ndarray, chi_ref: float, position=(0.0, 0.0, 0.0), t: float = 0.0) -> None:
    """Start ``sim`` at time t (default 0) in state x (9,): wings at their prescribed pose and rates at t
    (``sim.desired(t)``; phase 0 at t = 0), the free joint's qpos/qvel written directly (no momentum adjustment),
    backend reset; a quasi-steady backend's added-mass memory is primed by one call at t - aero_every dt
    (:func:`_prime_previous_call`). A t other than 0 starts the flight mid-beat (the half-stroke map of
    :mod:`hawksim.control.halfstroke` starts at phase 0.5)."""
    R, v_w, om_w = state_to_world(np.asarray(x, float), chi_ref)
    sim.reset(velocity=v_w, quat=quat_from_matrix(R), omega_body=R.T @ om_w, position=np.asarray(position, float))
    m, d = sim.m, sim.d
    if t != 0.0:
        d.time = t
        q, qd, _ = sim.desired(t)
        d.qpos[sim.wing_qpos] = q
        d.qvel[sim.wing_dof] = qd
    d.qpos[3:7] = quat_from_matrix(R)
    d.qvel[:3] = v_w
    d.qvel[3:6] = R.T @ om_w
    mujoco.mj_forward(m, d)
    sim.backend.reset(sim.state())
    if descriptor_of(sim.backend).memory == PREVIOUS_CALL:
        _prime_previous_call(sim, t)


def _prime_previous_call(sim: Simulator, t: float = 0.0) -> None:
    """Give a backend of previous-call memory (:class:`hawksim.backends.memory.PrimedMemory`: the quasi-steady
    model's strip normal velocities) the memory of a call at t - h, h = aero_every dt, as a continuous flight would
    have: the body state at t - h is extrapolated to second order from t and a
    probe step to t + h (v(t - h) = 2 v(t) - v(t + h), likewise the body-frame angular velocity; position and
    attitude with the acceleration (v(t + h) - v(t)) / h), the wings at their prescribed pose at t - h."""
    m, d = sim.m, sim.d
    h = sim.dt * sim.aero_every
    qpos0, qvel0 = d.qpos.copy(), d.qvel.copy()
    for _ in range(sim.aero_every):
        sim.step()
    v_h, w_h = d.qvel[:3].copy(), d.qvel[3:6].copy()
    d.time = t
    d.qpos[:], d.qvel[:] = qpos0, qvel0
    d.qacc_warmstart[:] = 0.0
    mujoco.mj_forward(m, d)
    sim._i = 0
    sim.backend.reset(sim.state())
    v0, w0 = qvel0[:3], qvel0[3:6]
    d2 = mujoco.MjData(m)
    d2.time = t - h
    d2.qpos[:], d2.qvel[:] = qpos0, qvel0
    d2.qpos[:3] = qpos0[:3] - h * v0 + 0.5 * h * (v_h - v0)
    R0 = quat_to_matrix(qpos0[3:7])
    d2.qpos[3:7] = quat_from_matrix(R0 @ _rodrigues(-h * w0 + 0.5 * h * (w_h - w0)))
    d2.qvel[:3], d2.qvel[3:6] = 2 * v0 - v_h, 2 * w0 - w_h
    q, qd, _ = sim.desired(t - h)
    d2.qpos[sim.wing_qpos] = q
    d2.qvel[sim.wing_dof] = qd
    mujoco.mj_forward(m, d2)
    sim.backend.prime(read_state(m, d2, sim.body_id, sim.wing_ids, h))
