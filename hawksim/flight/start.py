"""The start of a free flight: the initial body state on the trim's periodic path, and the perturbations a user
may add to it.

Frames: world (z up, heading +x); perturbations in stability axes (docs/conventions.md: x forward horizontal, y right,
z down), mapped to world by :data:`hawksim.frames.STABILITY_TO_WORLD`.
"""

from __future__ import annotations

import numpy as np

from hawksim.flight.simulator import Simulator
from hawksim.frames import pitch_of, quat_from_matrix, rot_y
from hawksim.insect.kinematics import Kinematics

PERTURBATIONS = {
    "u": "forward velocity disturbance [m/s] (stability axes)",
    "v": "rightward velocity disturbance [m/s]",
    "w": "downward velocity disturbance [m/s]",
    "p": "roll rate [deg/s] (right wing down positive)",
    "q": "pitch rate [deg/s] (nose up positive)",
    "r": "yaw rate [deg/s] (nose right positive)",
    "theta": "initial pitch offset [deg] (nose up positive)",
    "phi": "initial roll offset [deg] (right wing down positive)",
}
"""Names accepted by ``--perturb NAME=VALUE``."""

LATERAL_PERTURBATIONS = ("v", "p", "r", "phi")
"""Perturbations that break the left/right symmetry (the UVLM must then solve both wings)."""


def parse_perturbations(perturb: dict[str, float]) -> dict[str, float]:
    """Validate perturbation names and values (ValueError naming the bad one)."""
    for k, v in perturb.items():
        if k not in PERTURBATIONS:
            raise ValueError(f"unknown perturbation {k!r}; choose from {', '.join(PERTURBATIONS)}")
        if not np.isfinite(v):
            raise ValueError(f"perturbation {k}={v} is not finite")
    return perturb


def is_lateral(perturb: dict[str, float]) -> bool:
    """Whether ``perturb`` breaks the left/right symmetry."""
    return any(perturb.get(k, 0.0) != 0.0 for k in LATERAL_PERTURBATIONS)


def inertial_pitch_offset(sim: Simulator, kin: Kinematics) -> float:
    """Mean minus initial body pitch [rad] over one wingbeat in vacuum, from a start at pitch chi.

    The wings' inertia makes the body pitch oscillate within each beat (several degrees for a hawkmoth);
    the paper's body angle chi is the cycle mean, so the flight starts at chi minus this offset. Runs on
    ``sim``'s model in vacuum (:meth:`Simulator.vacuum`), leaving it as it was.
    """
    with sim.vacuum():
        sim.reset()
        pitch = [float(pitch_of(sim.step().state.body_R)) for _ in range(sim.steps_per_cycle)]
    return float(np.mean(pitch) - kin.chi)


def start_on_orbit(sim: Simulator, kin: Kinematics, speed: float, pitch_guess: float):
    """(pitch0 [rad], velocity (3,) [m/s], nose-up pitch rate q0 [rad/s]) so that the first wingbeat's mean
    pitch is chi, its mean pitch rate zero and its mean velocity straight up at ``speed``.

    The aerodynamic and inertial loads oscillate within each beat; starting from rest in pitch rate at t = 0
    leaves the oscillation's integral as a mean rate (the body drifts by ~15 deg in the first beat). One
    calibration beat from the guess measures the means; the start is corrected by them (removing a mean rate q
    also lowers the mean pitch by q T / 2).
    """
    up = np.array([0.0, 0.0, speed])
    sim.reset(velocity=up, quat=quat_from_matrix(rot_y(-pitch_guess)))
    pitch, q, v = [], [], []
    for _ in range(sim.steps_per_cycle):
        st = sim.step().state
        pitch.append(pitch_of(st.body_R))
        q.append(-st.body_omega[1])
        v.append(st.body_v)
    q_mean = float(np.mean(q))
    v_mean = np.mean(v, axis=0)
    pitch0 = pitch_guess - (float(np.mean(pitch)) - kin.chi) + q_mean * kin.period / 2
    v0 = up - (v_mean - up)
    v0[1] = 0.0
    return pitch0, v0, -q_mean
