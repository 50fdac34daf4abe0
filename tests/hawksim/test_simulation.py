"""The flight loop: exact tracking of Eq. 1, momentum conservation in vacuum, xfrc_applied semantics."""

import mujoco
import numpy as np
import pytest

from hawksim.backends.base import FlightState, NoAero, WingLoads
from hawksim.flight.simulator import Simulator
from hawksim.insect.kinematics import MIRROR, table3_kinematics
from hawksim.insect.model import load_model

KIN = table3_kinematics(1.0)
TRACK_TOL_DEG = 0.01
"""deg: largest joint-angle error against Eq. 1 over 10 beats (issue 2's requirement: track Eq. 1 to < 0.01 deg)."""

MOMENTUM_TOL = 1e-6
"""Momentum error (linear, angular) relative to the wings' own peak momentum (issue 2's requirement). Met by RK4 at
MOMENTUM_STEPS_PER_CYCLE: the error falls as dt^4, 8e-6 at 200 steps per beat, 5e-7 at 400 (measured).
Measured at 400: 5.0e-7 (linear) and 6.0e-8 (angular) in vacuum, 4.2e-8 and 3.3e-7 under a constant load, 5.3e-8
under gravity."""

MOMENTUM_STEPS_PER_CYCLE = 400
"""Steps per beat of the momentum tests: the coarsest of 200, 400 that meets MOMENTUM_TOL (see there)."""

COM_DRIFT_TOL_M = 1e-7
"""m: largest displacement of the system's centre of mass over 10 beats in vacuum (the body itself moves ~2 mm).
Source of the value not recorded; measured 1.2e-8 m."""

MIRROR_ATOL = 1e-12
"""Symmetric flapping: right wing origin vs the mirrored left one (m, absolute; origins ~0.02 m), and right wing
force vs the mirrored left one (as a fraction of the largest force component). The quasi-steady model evaluates
the two wings with the same operations on mirrored data: round-off; measured 6.1e-18 m and 2.4e-14 of the
largest force."""

SIDE_FORCE_TOL = 1e-12
"""Total side force of the symmetric pair as a fraction of the largest force component: round-off; measured
8.1e-14."""

LATERAL_DRIFT_TOL_M = 1e-12
"""m: the body's lateral position after two beats of symmetric flapping: round-off; measured 4.8e-18 m."""

ROLL_YAW_RATE_TOL = 1e-9
"""rad/s: the body's roll and yaw rates after two beats of symmetric flapping: round-off; measured 1.2e-14 rad/s."""


def _wing_peak_momentum(sim, n):
    """Peak linear and angular momentum of one wing moving on Eq. 1 with the body held (body frame)."""
    m, d = sim.m, mujoco.MjData(sim.m)
    b = sim.wing_ids[0]
    p_max = L_max = 0.0
    for t in np.linspace(0, KIN.period, n):
        q, qd, _ = sim.desired(t)
        d.qpos[:] = 0
        d.qpos[3] = 1
        d.qpos[sim.wing_qpos] = q
        d.qvel[:] = 0
        d.qvel[sim.wing_dof] = qd
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        p_max = max(p_max, np.linalg.norm(m.body_subtreemass[b] * d.subtree_linvel[b]))
        # about the body origin: spin about the wing's COM + the COM's moment of momentum
        L = d.subtree_angmom[b] + m.body_subtreemass[b] * np.cross(d.subtree_com[b], d.subtree_linvel[b])
        L_max = max(L_max, np.linalg.norm(L))
    return p_max, L_max


def test_joints_track_eq1():
    sim = Simulator(load_model(), KIN, NoAero())
    sim.reset()
    err = 0.0
    for _ in range(10 * sim.steps_per_cycle):
        sim.step()
        err = max(err, np.abs(sim.wing_angles() - sim.desired(sim.d.time)[0]).max())
    assert np.degrees(err) < TRACK_TOL_DEG


@pytest.mark.parametrize("spc", [MOMENTUM_STEPS_PER_CYCLE])
def test_momentum_conserved_in_vacuum(spc):
    sim = Simulator(load_model(), KIN, NoAero(), gravity=False, steps_per_cycle=spc)
    sim.reset()
    p_wing, L_wing = _wing_peak_momentum(sim, 201)
    com0 = sim.d.subtree_com[sim.body_id].copy()
    p_max = L_max = com_max = 0.0
    pitch = []
    for _ in range(10 * spc):
        sim.step()
        p, L = sim.momentum()
        p_max, L_max = max(p_max, np.linalg.norm(p)), max(L_max, np.linalg.norm(L))
        com_max = max(com_max, np.linalg.norm(sim.d.subtree_com[sim.body_id] - com0))
        pitch.append(np.arcsin(sim.d.xmat[sim.body_id][6]))
    assert p_max < MOMENTUM_TOL * p_wing
    assert L_max < MOMENTUM_TOL * L_wing
    # the body oscillates (several degrees of pitch) while the system's centre of mass stays put
    assert np.degrees(np.ptp(pitch)) > 5
    assert com_max < COM_DRIFT_TOL_M


class ConstantLoad:
    """A known force and moment (about the hinge) on the left wing."""

    name = "constant"

    def __init__(self, F, M):
        self.F, self.M = np.asarray(F, float), np.asarray(M, float)

    def reset(self, state):
        pass

    def loads(self, state: FlightState) -> WingLoads:
        return WingLoads(np.array([self.F, np.zeros(3)]), np.array([self.M, np.zeros(3)]), 0.0)


def test_xfrc_applied_gives_expected_momentum_rates():
    """Newton-Euler for the whole system: dP/dt = F and dL_O/dt = M_hinge + x_hinge x F about the world origin."""
    F, M = np.array([1e-3, -2e-3, 5e-3]), np.array([2e-6, 1e-6, -3e-6])
    sim = Simulator(load_model(), KIN, ConstantLoad(F, M), gravity=False, steps_per_cycle=400)
    sim.reset()
    d = sim.d

    def L_origin():
        P, L = sim.momentum()
        return P, L + np.cross(d.subtree_com[sim.body_id], P)

    P0, L0 = L_origin()
    impulse_ang = np.zeros(3)
    n = 200
    w = sim.wing_ids[0]
    for _ in range(n):
        # the loop holds the loads over a step as xfrc_applied: the force acts at the wing's moving centre of
        # mass, with the torque M + (hinge - com) x F fixed at the step start
        hinge0, com0 = d.xpos[w].copy(), d.xipos[w].copy()
        sim.step()
        com_mid = 0.5 * (com0 + d.xipos[w])  # midpoint rule
        impulse_ang += (M + np.cross(hinge0 - com0, F) + np.cross(com_mid, F)) * sim.dt
    P1, L1 = L_origin()
    p_wing, L_wing = _wing_peak_momentum(sim, 51)
    # RK4 momentum error, as in vacuum: below MOMENTUM_TOL of the wing's momentum
    np.testing.assert_allclose(P1 - P0, F * n * sim.dt, rtol=0, atol=MOMENTUM_TOL * p_wing)
    np.testing.assert_allclose(L1 - L0, impulse_ang, rtol=0, atol=MOMENTUM_TOL * L_wing)


def test_gravity_alone_accelerates_the_system_at_g():
    sim = Simulator(load_model(), KIN, NoAero(), gravity=True, steps_per_cycle=MOMENTUM_STEPS_PER_CYCLE)
    sim.reset()
    p_wing, _ = _wing_peak_momentum(sim, 51)
    P0, _ = sim.momentum()
    for _ in range(100):
        sim.step()
    P1, _ = sim.momentum()
    mass = sim.m.body_subtreemass[sim.body_id]
    np.testing.assert_allclose(P1 - P0, mass * 100 * sim.dt * np.array([0, 0, -9.81]), rtol=0,
                               atol=MOMENTUM_TOL * p_wing)


def test_symmetric_flapping_stays_in_the_sagittal_plane():
    from hawksim.backends.quasi_steady import QuasiSteadyBackend

    sim = Simulator(load_model(), KIN, QuasiSteadyBackend())
    sim.reset()
    side = []
    for _ in range(2 * sim.steps_per_cycle):
        r = sim.step()
        st, ld = r.state, r.loads
        np.testing.assert_allclose(st.wing_origin[1], MIRROR @ st.wing_origin[0] + [0, 2 * st.body_pos[1], 0],
                                   atol=MIRROR_ATOL)
        np.testing.assert_allclose(ld.force[1], MIRROR @ ld.force[0], atol=MIRROR_ATOL * np.abs(ld.force).max())
        side.append(ld.force.sum(0)[1])
    scale = np.abs(ld.force).max()
    assert np.abs(side).max() < SIDE_FORCE_TOL * scale
    assert abs(sim.d.qpos[1]) < LATERAL_DRIFT_TOL_M  # no lateral drift
    assert np.abs(sim.d.qvel[[3, 5]]).max() < ROLL_YAW_RATE_TOL  # no roll or yaw rate (body frame)


def test_the_last_beat_spans_the_whole_beat():
    """The CLI contract's per-beat mean vertical speed of the LAST beat is measured over the whole beat (to the body
    position after the last step, FlightResult.end_pos), as every other beat is: a 3-beat flight's third beat equals
    the third beat of the same flight flown to 4 beats (deterministic, so to round-off). Before 2026-12-03 it ended
    at the start of the last step, which moved it by 1e-5 m/s here and 4e-5 m/s in the README's controlled
    surrogate flight (beat 20: 0.99996 against 1.0000004 for beats 1-19)."""
    from hawksim.cli.fly import fly_named

    short, long = (fly_named(1.0, c, "quasi-steady").summary() for c in (3, 4))
    for key in ("mean_vertical_speed", "horizontal_speed"):
        assert short["beats"][2][key] == pytest.approx(long["beats"][2][key], abs=1e-12)
    assert short["mean_vertical_speed"] == short["beats"][2]["mean_vertical_speed"]
