"""The free body's state at a wing phase, as data: the names of its nine components and the frozen
:class:`BodyState` (an operating point, :class:`hawksim.trim.point.OperatingPoint`, holds it; the trim layer below the
flight layer reads it). Its chart (heading axes, Euler angles about a reference body angle) and how it is written
into and read from a simulator: :mod:`hawksim.flight.body_state`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

STATE_NAMES = ("u", "v", "w", "p", "q", "r", "phi", "theta", "psi")
"""Body state at phase 0, the chart of :mod:`hawksim.flight.body_state` (m/s, rad/s, rad)."""

SYM_STATE = (0, 2, 4, 7)
"""Indices of the symmetric (longitudinal) state (u, w, q, theta) in :data:`STATE_NAMES`."""


@dataclass(frozen=True)
class BodyState:
    """The map's state (the chart of :mod:`hawksim.flight.body_state`): u, v, w [m/s] and p, q, r [rad/s] in the
    heading axes (x forward horizontal, y right, z down), Euler angles phi (bank), theta (body pitch), psi (heading)
    [rad]."""

    u: float = 0.0
    v: float = 0.0
    w: float = 0.0
    p: float = 0.0
    q: float = 0.0
    r: float = 0.0
    phi: float = 0.0
    theta: float = 0.0
    psi: float = 0.0

    def as_array(self) -> np.ndarray:
        """(9,) in :data:`STATE_NAMES` order."""
        return np.array([getattr(self, k) for k in STATE_NAMES])

    @classmethod
    def from_array(cls, x) -> BodyState:
        return cls(*map(float, x))

    def to_dict(self) -> dict[str, float]:
        return {k: float(getattr(self, k)) for k in STATE_NAMES}
