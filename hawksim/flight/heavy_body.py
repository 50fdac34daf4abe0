"""The heavy-body check of the flight loop: a free flight whose body is so heavy that it barely moves, against the
held body of :mod:`hawksim.backends.held` (same kinematics, same backend). What the loop applies (loads in the
world frame, the moment about the body's centre of mass) and the power it samples must then agree with the held
body's cycle averages (tests/hawksim/test_heavy_body.py; scripts/studies/held_power_bias.py, docs/free_flight.md).
"""

from __future__ import annotations

import mujoco
import numpy as np

from hawksim.flight.power import P_plus
from hawksim.flight.simulator import Simulator
from hawksim.frames import quat_from_matrix, rot_y
from hawksim.insect.model import load_model
from hawksim.insect.folder import default_insect

HEAVY = 1e4
"""Body mass and inertia factor of the heavy-body flights."""

CYCLES = 3
"""Wingbeats flown; the last one is compared (the UVLM's wake develops over the first two)."""


def heavy_free_flight(kin, speed: float, backend, *, steps_per_cycle: int, aero_every: int,
                      cycles: int = CYCLES) -> dict:
    """The last wingbeat of a free flight of a body :data:`HEAVY` times heavier, gravity off, started at pitch chi
    moving straight up at ``speed`` [m/s]: {"L", "D", "M"} (L+, D+, M+ of the loads as applied by the loop: world
    frame, the pitching moment about the body's centre of mass, nose up) and {"P_updates", "P_steps"} (P+ of the
    joint power, :func:`hawksim.flight.power.P_plus` with either sampling). The hawkmoth's model and scales."""
    m = load_model()
    b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "body")
    m.body_mass[b] *= HEAVY
    m.body_inertia[b] *= HEAVY
    sim = Simulator(m, kin, backend, steps_per_cycle=steps_per_cycle, gravity=False, aero_every=aero_every)
    sim.reset(velocity=np.array([0.0, 0.0, speed]), quat=quat_from_matrix(rot_y(-kin.chi)))
    sim.advance((cycles - 1) * steps_per_cycle)
    r = sim.advance(steps_per_cycle)
    F = r.force.sum(1)
    insect = default_insect()
    W = insect.weight
    pitching = -(r.moment_about_body() * r.body_R[:, :, 1]).sum(1)
    return {"L": F[:, 2].mean() / W, "D": -F[:, 0].mean() / W, "M": pitching.mean() / (W * insect.cbar),
            **{f"P_{s}": P_plus(r.power_joint, aero_every, first=r.first, sampling=s) for s in ("updates", "steps")}}
