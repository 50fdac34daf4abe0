"""The flight condition: the insect's velocity through still air in its symmetry plane (issue 51, item 1).

A condition is two numbers: the vertical speed V [m/s] (``speed``, climb positive: the ascent speed of the paper,
Nguyen et al. 2020, which keeps its meaning) and the forward speed U [m/s] (``forward_speed``, along world +x, the
body's heading; default 0). World axes: x forward, y left, z up (docs/conventions.md). A body held on its
equilibrium path at (U, V) sees the air stream at (-U, 0, -V) (:func:`air_velocity`). U = 0 is vertical ascent,
computed exactly as before the forward speed existed (bit for bit).
"""

from __future__ import annotations

import math

import numpy as np

FORWARD_SPEED_RANGE = (0.0, 5.0)
"""Forward speeds [m/s] of the study: hover to 5 m/s, the range Willmott & Ellington (1997, J. Exp. Biol.
200:2705 and 200:2723) filmed free-flying *Manduca sexta* over (the CLI's bounds; the library takes any U >= 0)."""


def check_forward_speed(forward_speed: float) -> float:
    """``forward_speed`` as a float; ValueError naming it unless finite and >= 0 m/s (backward flight is not
    modelled)."""
    u = float(forward_speed)
    if not (math.isfinite(u) and u >= 0.0):
        raise ValueError(f"forward_speed must be a finite forward speed >= 0 m/s, got {forward_speed}")
    return u


def air_velocity(speed: float, forward_speed: float = 0.0) -> np.ndarray:
    """The air's velocity (3,) [m/s], world axes, seen by a body held at vertical speed ``speed`` and forward speed
    ``forward_speed``: (-U, 0, -V); the x entry is +0.0 (not -0.0) at U = 0, as before U existed."""
    return np.array([-forward_speed if forward_speed else 0.0, 0.0, -speed])
