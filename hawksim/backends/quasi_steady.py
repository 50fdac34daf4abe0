"""Quasi-steady blade-element backend (:mod:`aero.quasi_steady`) for the hawkmoth's two wings."""

from __future__ import annotations

import numpy as np

from aero.quasi_steady import BladeElements, QuasiSteadyConfig, wing_loads
from hawksim.backends.base import FlightState, WingLoads
from hawksim.insect.folder import default_insect
from hawksim.insect.morphology import RHO_AIR, Morphology

N_STRIPS = 20
"""Blade elements per wing (L+ changes < 0.5 % from 20 to 80 strips for Table 3's hover kinematics)."""


class QuasiSteadyBackend:
    """Quasi-steady loads (Dickinson et al. 1999 translational, Sane & Dickinson 2002 rotational, added mass)
    on the morphology's beta-distributed planform; the right wing is the mirror image of the left."""

    name = "quasi-steady"

    def __init__(self, morph: Morphology | None = None, n_strips: int = N_STRIPS,
                 config: QuasiSteadyConfig = QuasiSteadyConfig(rho=RHO_AIR)):
        morph = default_insect().morphology if morph is None else morph  # None: the default insect's
        pl = morph.planform
        self.elements = tuple(
            BladeElements.from_planform(morph.R, pl.chord, pl.leading_edge, n_strips, side) for side in (1.0, -1.0)
        )
        self.config = config
        self._vn: list[np.ndarray | None] = [None, None]

    def reset(self, state: FlightState) -> None:
        self._vn = [None, None]

    def prime(self, previous: FlightState) -> None:
        """The previous-call memory protocol (:class:`hawksim.backends.memory.PrimedMemory`): remember a call at
        ``previous`` (one update interval before the flight's start) as a continuous flight would have: the strip
        normal velocities that the added-mass term differences (the loads of that call are discarded)."""
        self.loads(previous)

    def loads(self, state: FlightState) -> WingLoads:
        force, moment, power = np.zeros((2, 3)), np.zeros((2, 3)), 0.0
        carrier = (state.body_v, state.body_omega, state.body_pos)
        for i, el in enumerate(self.elements):
            res = wing_loads(el, state.wing_R[i], state.wing_origin[i], state.wing_v[i], state.wing_omega[i],
                             state.air_v, self._vn[i], state.dt, carrier, self.config)
            self._vn[i] = res.vn_mid
            force[i], moment[i] = res.force, res.moment
            power += res.power
        return WingLoads(force=force, moment=moment, power=power)
