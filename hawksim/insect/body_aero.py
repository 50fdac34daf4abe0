"""The body's own aerodynamic loads: drag and lift of head, thorax and abdomen (issue 51, item 2).

Model (a model choice: no measured *Manduca* body coefficients were reachable; Willmott & Ellington 1997b's abstract
says only that "the hawkmoth body is amongst the most streamlined for any insect"): the body is a slender body of
revolution in the viscous-crossflow model of Allen & Perkins (1951, NACA Rep. 1048), without its potential-flow
term (slender-body theory gives no net normal force on a body closed at both ends). With w the velocity of the air
relative to the body in body axes (x toward the head, y left, z dorsal; :mod:`hawksim.insect.morphology`), split
into its axial part w_x and its crossflow part w_n = (0, w_y, w_z):

    F_axial = 1/2 rho CD0 S_front |w_x| w_x e_x,        F_cross = 1/2 rho ETA CD_CROSS S_plan |w_n| w_n,

both along the air's motion relative to the body (a drag: the body is pushed the way the air goes). In terms of the
body's angle of attack a (between the body axis and the relative wind) and q = 1/2 rho |w|^2 these are the axial
force q CD0 S_front cos^2 a and the normal force q ETA CD_CROSS S_plan sin^2 a of the crossflow model. Both act at
the centroid of the body's side (planform) area, so that they pitch the body about its centre of mass.

Geometry (derived from the insect's segments, :class:`hawksim.insect.morphology.Morphology`): S_front is the largest
segment cross-section pi b c (the thorax's for the hawkmoth: 86 mm^2); S_plan = sum over segments of pi a sqrt(b c)
(the side area of the equivalent round body; the segments' slight overlaps are counted twice: a model choice,
< 3 % of S_plan for the hawkmoth); the centroid is the S_plan-weighted mean of the segment centres.

Constants (one home; each says its class and the rule that chose it): :data:`CD0`, :data:`CD_CROSS`, :data:`ETA`.
Pure functions of the relative air velocity: the body's own motion enters through w only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawksim.insect.morphology import RHO_AIR, Morphology

CD0 = 0.25
"""Axial (zero-incidence) drag coefficient of the body on its frontal area S_front. Class: model choice (derived from
a formula, not a measurement). Rule: Hoerner's streamlined-body estimate (Fluid-Dynamic Drag, 1965, ch. 6; recalled,
not re-read in this session) C_D = C_f (3 L/d + 4.5 (d/L)^0.5 + 21 (d/L)^2) with laminar (Blasius) friction
C_f = 1.328 / sqrt(Re_L), for the hawkmoth model's fineness ratio L/d = 42.5 mm / 10.5 mm = 4.05, at the middle of
the forward-speed range (U = 2.5 m/s, Re_L = 7.1e3): 0.247, rounded to 0.25. The same formula gives 0.39 at 1 m/s
and 0.17 at 5 m/s; a constant is kept (the body's share of the force balance is a few per cent,
docs/forward_flight.md). Kinematic viscosity 1.5e-5 m^2/s."""

CD_CROSS = 1.2
"""Crossflow drag coefficient of a circular cylinder at subcritical Reynolds number (Re_d ~ 1e3 to 2e5; the body's
crossflow Re_d is 3e2 to 3.5e3 from 0.5 to 5 m/s). Class: quoted, a textbook value (Hoerner 1965, ch. 3; the value
Allen & Perkins 1951 use), not a hawkmoth measurement."""

ETA = 0.6
"""Allen & Perkins's finite-length factor of the crossflow drag (the ratio of a finite cylinder's crossflow drag to an
infinite one's). Class: model choice. Rule: the value their tabulation gives near fineness ratio 4-5 (the hawkmoth
model's 4.05), recalled, not re-read in this session."""


@dataclass(frozen=True)
class BodyAero:
    """The body load model of one insect (module docstring). ``s_front`` [m^2]: frontal area; ``s_plan`` [m^2]: side
    (planform) area; ``centre`` (3,) [m]: where the loads act, body frame relative to the body's centre of mass;
    ``length``, ``diameter`` [m]: the segments' extent along x and the equivalent diameter of the largest section
    (documentation); ``cd0``, ``cd_cross``, ``eta``: the coefficients; ``rho`` [kg/m^3]: air density."""

    s_front: float
    s_plan: float
    centre: tuple[float, float, float]
    length: float
    diameter: float
    cd0: float = CD0
    cd_cross: float = CD_CROSS
    eta: float = ETA
    rho: float = RHO_AIR

    @staticmethod
    def of(morph: Morphology) -> BodyAero:
        """The model of ``morph``'s body segments (module docstring, "Geometry")."""
        segs = morph.segments
        centres = morph.segment_centres()
        front = [math.pi * s.semi_axes[1] * s.semi_axes[2] for s in segs]
        plan = np.array([math.pi * s.semi_axes[0] * math.sqrt(s.semi_axes[1] * s.semi_axes[2]) for s in segs])
        centre = sum(p * centres[s.name] for p, s in zip(plan, segs)) / plan.sum()
        x_lo = min(s.centre[0] - s.semi_axes[0] for s in segs)
        x_hi = max(s.centre[0] + s.semi_axes[0] for s in segs)
        return BodyAero(s_front=float(max(front)), s_plan=float(plan.sum()),
                        centre=tuple(float(c) for c in centre), length=float(x_hi - x_lo),
                        diameter=float(2.0 * math.sqrt(max(front) / math.pi)))

    def force(self, w_body: np.ndarray) -> np.ndarray:
        """Force (3,) [N] on the body, body axes, for the air velocity relative to the body ``w_body`` (3,) [m/s],
        body axes."""
        w = np.asarray(w_body, dtype=float)
        wn = np.array([0.0, w[1], w[2]])
        axial = 0.5 * self.rho * self.cd0 * self.s_front * abs(w[0]) * w[0]
        return np.array([axial, 0.0, 0.0]) + 0.5 * self.rho * self.eta * self.cd_cross * self.s_plan * \
            float(np.linalg.norm(wn)) * wn

    def loads(self, w_body: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(force (3,) [N], moment (3,) [N m] about the body's centre of mass), body axes, for ``w_body`` (3,) [m/s]
        (:meth:`force` acting at :attr:`centre`)."""
        f = self.force(w_body)
        return f, np.cross(np.asarray(self.centre), f)


def angle_of_attack(w_body: np.ndarray) -> float:
    """The body's angle of attack [rad] in its symmetry plane: atan2(w_z, -w_x) for ``w_body`` (3,) the air's
    velocity relative to the body, body axes: zero for air coming head-on, positive with the air coming from below
    (ventral side), pi/2 for air rising along the dorsal axis."""
    w = np.asarray(w_body, dtype=float)
    return math.atan2(w[2], -w[0])
