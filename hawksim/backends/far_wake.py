"""The UVLM's prescribed far wake: the definition of its periodic orbit at hover and 0.5 m/s (issue 49, item 4).

At low ascent speeds the UVLM's free wake stays under the wings and is met again by them; a 1e-5 change of the
flight grows ~300-fold within three beats, so the one-beat map of the free body has no derivative a Newton solver
can use and its orbit does not converge (docs/free_flight.md, "A periodic orbit at hover"). With a wake that is free
only while younger than :data:`FREE_BEATS` wingbeats (``aero.uvlm.UVLMConfig.free_wake_age``) and moves with the
air plus a uniform downwash after that (``far_wake_drift``), the map is smooth to ~1e-3 and the orbit converges.

The downwash is momentum theory's for an actuator disk of the stroke's swept area carrying the insect's weight
(:func:`momentum_downwash`): a model of the far wake's mean motion, not a measurement. Where the free wake's map is
smooth (1 m/s and faster, measured) the orbits keep the whole wake free (:func:`far_wake_for` gives None).

Model choices (each measured by ``python -m scripts.studies.hover_far_wake``, docs/free_flight.md):

* :data:`FREE_BEATS` = 0.5: the free wake's map at hover scatters by 3e-2 (normalized q periodicity, RMS about a
  line over relative frequency changes of +-2e-3), at 1 beat by 1.4e-2, at 0.5 and 0.25 beats by 5e-4 - 9e-4;
  the longest smooth one was kept. Its cost at 1 and 2 m/s: L+ -0.8 % and -0.4 %, P+ -0.3 % and -0.1 % against
  the whole wake free (held body, reference lattice).
* :data:`PRESCRIBED_BELOW` = 0.75 m/s: the free-wake orbits converge at 1, 1.5 and 2 m/s and not at 0 and 0.5 m/s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from hawksim.insect.kinematics import Kinematics
from hawksim.insect.morphology import RHO_AIR, Morphology

FREE_BEATS = 0.5
"""Wingbeats a wake corner stays free before it drifts with the prescribed downwash (a model choice, module
docstring)."""

PRESCRIBED_BELOW = 0.75
"""Ascent speed [m/s] below which the UVLM's periodic orbits use the prescribed far wake (module docstring)."""


def momentum_downwash(speed: float, kin: Kinematics, morph: Morphology) -> float:
    """Momentum theory's induced velocity [m/s] at an actuator disk carrying the insect's weight in a climb at
    ``speed`` [m/s]: w = -V/2 + sqrt(V^2/4 + W / (2 rho A)), A = 2 phi_a R^2 the area the two wings sweep (two
    sectors of angle 2 phi_a, radius R); Ellington (1984, Phil. Trans. R. Soc. B 305:145)'s estimate for hovering
    insects, here the far wake's mean motion (a model, not a measurement)."""
    if not (math.isfinite(speed) and speed >= 0.0):
        raise ValueError(f"speed must be a finite ascent speed >= 0 m/s, got {speed!r}")
    area = 2.0 * kin.phi_a * morph.R**2
    return -speed / 2.0 + math.sqrt(speed**2 / 4.0 + morph.weight / (2.0 * RHO_AIR * area))


@dataclass(frozen=True)
class FarWake:
    """A prescribed far wake: corners older than ``free_beats`` wingbeats move with the air plus ``downwash`` [m/s]
    straight down (world -z)."""

    free_beats: float
    downwash: float

    def __post_init__(self):
        if not (math.isfinite(self.free_beats) and self.free_beats >= 0.0):
            raise ValueError(f"free_beats must be a finite number of wingbeats >= 0, got {self.free_beats!r}")
        if not math.isfinite(self.downwash):
            raise ValueError(f"downwash must be finite [m/s], got {self.downwash!r}")

    def apply(self, backend, kin: Kinematics):
        """Set this far wake on a UVLM backend (its ``config``, an ``aero.uvlm.UVLMConfig``) flying ``kin``;
        ValueError for a backend without a wake."""
        cfg = getattr(backend, "config", None)
        if cfg is None or not hasattr(cfg, "free_wake_age"):
            raise ValueError(f"a prescribed far wake needs a UVLM backend, got {type(backend).__name__}")
        backend.config = dataclasses.replace(cfg, free_wake_age=self.free_beats / kin.f,
                                             far_wake_drift=(0.0, 0.0, -self.downwash))
        solver = getattr(backend, "solver", None)
        if solver is not None:  # already reset by a simulator: the solver reads its config at every step
            if solver.step_count:
                raise ValueError("a prescribed far wake must be set before the backend's first step")
            solver.config = backend.config
        return backend

    def to_json(self) -> dict:
        return {"free_beats": self.free_beats, "downwash": self.downwash}

    @staticmethod
    def from_json(d: dict | None) -> FarWake | None:
        return None if d is None else FarWake(float(d["free_beats"]), float(d["downwash"]))


def far_wake_for(speed: float, kin: Kinematics, morph: Morphology) -> FarWake | None:
    """The far wake of the UVLM's periodic orbit at ascent ``speed`` [m/s]: prescribed (:data:`FREE_BEATS`, the
    momentum downwash of ``kin`` and ``morph``) below :data:`PRESCRIBED_BELOW`, None (the whole wake free) above."""
    if speed >= PRESCRIBED_BELOW:
        return None
    return FarWake(FREE_BEATS, momentum_downwash(speed, kin, morph))


__all__ = ["FarWake", "far_wake_for", "momentum_downwash", "FREE_BEATS", "PRESCRIBED_BELOW"]
