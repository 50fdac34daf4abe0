"""The aerodynamic backend interface: flight state in, wing loads out.

Every aerodynamic model of hawksim (quasi-steady, UVLM, surrogates) implements :class:`AeroBackend`, so the
flight loop (:mod:`hawksim.flight.simulator`) does not know which one it runs. All vectors are in the WORLD frame
(MuJoCo's: z up), SI units. Index 0 of the wing axis is the left wing, 1 the right wing.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import mujoco
import numpy as np

from hawksim.frames import cross


@dataclass(frozen=True)
class FlightState:
    """The insect's kinematic state at time t, as the aerodynamics sees it.

    Attributes:
        t: time [s]; dt: the step the loads will be held over [s].
        body_pos (3,): body centre of mass [m]; body_R (3, 3): body frame -> world;
        body_v (3,): velocity of the centre of mass [m/s]; body_omega (3,): body angular velocity [rad/s].
        wing_R (2, 3, 3): wing frame -> world; wing_origin (2, 3): hinge positions [m];
        wing_v (2, 3): hinge velocities [m/s]; wing_omega (2, 3): wing angular velocities [rad/s].
        air_v (3,): uniform air velocity (wind) [m/s], zero in still air.
    """

    t: float
    dt: float
    body_pos: np.ndarray
    body_R: np.ndarray
    body_v: np.ndarray
    body_omega: np.ndarray
    wing_R: np.ndarray
    wing_origin: np.ndarray
    wing_v: np.ndarray
    wing_omega: np.ndarray
    air_v: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def body_point_velocity(self, p: np.ndarray) -> np.ndarray:
        """Velocity [m/s] of points p (..., 3) moving rigidly with the body."""
        return self.body_v + cross(self.body_omega, p - self.body_pos)


@dataclass(frozen=True)
class WingLoads:
    """Aerodynamic loads on the two wings (world frame).

    Attributes:
        force (2, 3): total aerodynamic force on each wing [N].
        moment (2, 3): moment about each wing's hinge (``FlightState.wing_origin``) [N m].
        power: aerodynamic power the wings spend on the air, relative to the body's rigid motion [W]:
            P = -sum_i F_i . (v_i - v_body(p_i)) over the wing elements.
        extras: backend-specific data for recording (e.g. panel pressure, wake), never used by the loop.
    """

    force: np.ndarray
    moment: np.ndarray
    power: float
    extras: dict[str, Any] = field(default_factory=dict)

    def moment_about(self, state: FlightState, ref: np.ndarray) -> np.ndarray:
        """Total aerodynamic moment (3,) about the point ref [N m]."""
        arm = state.wing_origin - ref
        return (self.moment + cross(arm, self.force)).sum(0)


class AeroBackend(Protocol):
    """What the flight loop needs from an aerodynamic model."""

    name: str

    def reset(self, state: FlightState) -> None:
        """Start a new flight at ``state`` (clears any history such as a wake)."""

    def loads(self, state: FlightState) -> WingLoads:
        """Loads to hold over the next step [state.t, state.t + state.dt]."""


class NoAero:
    """Vacuum: zero loads. For momentum-conservation and inertia tests."""

    name = "none"

    def reset(self, state: FlightState) -> None:
        pass

    def loads(self, state: FlightState) -> WingLoads:
        return WingLoads(np.zeros((2, 3)), np.zeros((2, 3)), 0.0)


def read_state(m: mujoco.MjModel, d: mujoco.MjData, body_id: int, wing_ids, dt: float) -> FlightState:
    """FlightState from MuJoCo data whose kinematics (mj_kinematics, mj_comPos, mj_comVel) are current."""
    v6 = np.zeros(6)
    wing_v, wing_w = np.zeros((2, 3)), np.zeros((2, 3))
    for i, wid in enumerate(wing_ids):
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_XBODY, wid, v6, 0)
        wing_w[i], wing_v[i] = v6[:3], v6[3:]
    R_body = d.xmat[body_id].reshape(3, 3).copy()
    return FlightState(
        t=float(d.time), dt=dt,
        body_pos=d.xipos[body_id].copy(), body_R=R_body,
        body_v=d.qvel[:3].copy(), body_omega=R_body @ d.qvel[3:6],
        wing_R=d.xmat[wing_ids].reshape(2, 3, 3).copy(),
        wing_origin=d.xpos[wing_ids].copy(), wing_v=wing_v, wing_omega=wing_w,
    )
