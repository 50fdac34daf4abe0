"""The LQR's commands on the controlled plant: the seven channels (:data:`INPUTS`) and how they become each wing's
Eq. 1 parameters.

Commands. A command is the deviation ``du`` (7,) of :data:`INPUTS` from a base kinematics (the orbit's):
symmetric f (as the ratio f / f_base - 1), phi0, alpha0, theta0 [rad] added to both wings, and antisymmetric
(left minus right) phi_a, phi0, alpha0 [rad], added half to the left wing and subtracted half from the right
(:func:`wing_kinematics`). Each wing's parameters saturate at the Table 2 bounds (:func:`saturate`).

The plant itself (per-wing kinematics blended at phase 0, a uniform wind) is :class:`hawksim.flight.plant.
ControlledSimulator`, built by :func:`hawksim.flight.plant.controlled_plant`; both are importable from here too.
"""

from __future__ import annotations

import numpy as np

from hawksim.flight.plant import ControlledSimulator, controlled_plant, saturate
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics

__all__ = ["INPUTS", "SYM_INPUTS", "ANTI_INPUTS", "wing_kinematics", "command_of", "saturate", "ControlledSimulator",
           "controlled_plant"]

INPUTS = ("f", "phi0", "alpha0", "theta0", "dphi_a", "dphi0", "dalpha0")
"""Command channels: symmetric f (relative: f / f_base - 1), phi0, alpha0, theta0 [rad]; antisymmetric
(left minus right) phi_a, phi0, alpha0 [rad]."""

SYM_INPUTS = (0, 1, 2, 3)
"""Indices of the symmetric (longitudinal) channels in :data:`INPUTS`."""

ANTI_INPUTS = (4, 5, 6)
"""Indices of the antisymmetric (lateral) channels."""

_P = {k: i for i, k in enumerate(PARAM_NAMES)}


def wing_kinematics(base: Kinematics, du: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(left, right) parameter vectors (7,) SI in PARAM_NAMES order for the command ``du`` (7,), unsaturated."""
    du = np.asarray(du, float)
    p = base.as_array()
    sym = np.zeros(7)
    sym[_P["f"]] = du[0] * base.f
    sym[_P["phi0"]], sym[_P["alpha0"]], sym[_P["theta0"]] = du[1], du[2], du[3]
    anti = np.zeros(7)
    anti[_P["phi_a"]], anti[_P["phi0"]], anti[_P["alpha0"]] = du[4], du[5], du[6]
    return p + sym + anti / 2, p + sym - anti / 2


def command_of(base: Kinematics, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Inverse of :func:`wing_kinematics` for the seven channels (the command actually applied after
    saturation): sym = (left + right) / 2, anti = left - right, relative to ``base``."""
    p = base.as_array()
    s, a = (left + right) / 2 - p, left - right
    return np.array([s[_P["f"]] / base.f, s[_P["phi0"]], s[_P["alpha0"]], s[_P["theta0"]],
                     a[_P["phi_a"]], a[_P["phi0"]], a[_P["alpha0"]]])
