"""The mean lift coefficient that weight support requires, in the blade-element sense of Ellington (1984) and of
Willmott & Ellington (1997, J. Exp. Biol. 200:2723) for forward flight (issue 51, item 3).

Definition used (the paper's body was not reachable, only its abstract: "mean lift coefficients ... exceed the
maximum steady-state value of 0.71 at all except the very fastest speeds, peaking at 2.0 or greater between 1 and
2 m/s"; this is the standard form of that calculation, stated here so that a reader can check it against the paper):
every blade element of both wings is given the same lift coefficient C_L, its lift is 1/2 rho C_L c dr |u_n|^2
perpendicular to u_n and to the span, where u_n is the element's velocity relative to the air less its spanwise
component, and lift is taken upward on both half-strokes (the vertical component's magnitude: circulation reversed
at each stroke reversal, as Ellington assumed for hovering). C_L is the value for which the beat-mean vertical
force of that lift equals the weight W:

    C_L = W / mean_t sum_wings sum_strips 1/2 rho c dr |u_n|^2 |(s x u_n / |u_n|) . e_z|,

s the span axis and e_z world up. The wing motion is the held-body path of :func:`hawksim.backends.held.held_flight`
(the same MuJoCo model and state as the aerodynamic runs; the strips are the quasi-steady backend's), at ascent
``speed`` V and ``forward_speed`` U (the air at (-U, 0, -V)). Neither the body's lift nor drag (thrust) enters: C_L
measures what the wings' flapping must achieve for weight support alone.

:func:`mid_downstroke_incidence` gives the other quantity the abstract quotes ("the mid-downstroke angle of incidence
is constant at 30-40 deg across the speed range"): the angle between the chord (wing x axis) and u_n at the strip
nearest r2 (the radius of the second moment of area), at mid-downstroke (t = T/4, :mod:`hawksim.insect.kinematics`),
in [0, 90] deg.
"""

from __future__ import annotations

import numpy as np

from hawksim.backends.base import WingLoads
from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.morphology import RHO_AIR

STEPS_PER_CYCLE = 200
"""Samples of the beat (the mean changes < 1e-4 relative from 200 to 400 at the hover trim)."""


class _Probe:
    """A backend that exerts no loads and accumulates the denominator of C_L (module docstring) over its calls."""

    name = "lift-coefficient probe"

    def __init__(self, morph):
        self.elements = QuasiSteadyBackend(morph).elements
        self.terms: list[float] = []
        self.incidence: list[float] = []
        k = int(np.argmin(np.abs(np.abs(self.elements[0].y) - morph.r2_hat * morph.R)))
        self.r2_strip = k

    def reset(self, state) -> None:
        self.terms, self.incidence = [], []

    def loads(self, st) -> WingLoads:
        total = 0.0
        for i, el in enumerate(self.elements):
            R = st.wing_R[i]
            arm = np.outer(el.y, R[:, 1])  # strip centres on the rotation axis, from the hinge (n, 3)
            u = st.wing_v[i] + np.cross(st.wing_omega[i], arm) - st.air_v
            s = R[:, 1]
            un = u - np.outer(u @ s, s)
            speed = np.linalg.norm(un, axis=1)
            lift_dir = np.cross(s, un) / np.maximum(speed, 1e-300)[:, None]
            total += float(np.sum(0.5 * RHO_AIR * el.chord * el.dy * speed**2 * np.abs(lift_dir[:, 2])))
            if i == 0:
                k = self.r2_strip
                cos = abs(un[k] @ R[:, 0]) / max(speed[k], 1e-300)
                self.incidence.append(float(np.arccos(min(cos, 1.0))))
        self.terms.append(total)
        return WingLoads(force=np.zeros((2, 3)), moment=np.zeros((2, 3)), power=0.0)


def mean_lift_coefficient(kin: Kinematics, speed: float = 0.0, forward_speed: float = 0.0,
                          insect: Insect | None = None, steps_per_cycle: int = STEPS_PER_CYCLE) -> float:
    """C_L of the module docstring for ``kin`` (SI) at ascent ``speed`` and ``forward_speed`` [m/s], of ``insect``
    (default :func:`hawksim.insect.folder.default_insect`: its wings and weight)."""
    ins = default_insect() if insect is None else insect
    return float(ins.weight / np.mean(_probe(kin, speed, forward_speed, ins, steps_per_cycle).terms))


def mid_downstroke_incidence(kin: Kinematics, speed: float = 0.0, forward_speed: float = 0.0,
                             insect: Insect | None = None, steps_per_cycle: int = STEPS_PER_CYCLE) -> float:
    """The angle of incidence [rad] at r2 at mid-downstroke (module docstring) for ``kin`` at ascent ``speed`` and
    ``forward_speed`` [m/s]."""
    ins = default_insect() if insect is None else insect
    return _probe(kin, speed, forward_speed, ins, 4 * (steps_per_cycle // 4)).incidence[steps_per_cycle // 4]


def _probe(kin, speed, forward_speed, insect, steps_per_cycle) -> _Probe:
    """The probe after one beat of the held path (t = 0 to T - dt)."""
    probe = _Probe(insect.morphology)
    held_flight(kin, speed, probe, cycles=1, steps_per_cycle=steps_per_cycle, insect=insect,
                forward_speed=forward_speed, body_loads=False)
    return probe
