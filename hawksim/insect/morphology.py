"""Hawkmoth (*Manduca sexta*) morphology: mass, wing planform, body segments, wing hinge.

All quantities SI (kg, m). Frames:

* body frame: origin at the centre of mass of the body segments (head + thorax + abdomen; the wings are
  separate bodies), x toward the head, y to the left, z dorsal;
* wing frame (left wing): origin at the wing hinge, x toward the leading edge, y along the span toward the
  tip, z = x cross y (dorsal surface at zero rotation). The right wing's frame is the mirror image
  (see :mod:`hawksim.insect.kinematics`); its geometry is the left one with y -> -y.

Sources
-------
* Table 1 of Nguyen et al. (2020), "Study of vertically ascending flight of a hawkmoth model", Acta Mech.
  Sin. 36: total mass m = 1578.70 mg, wing length R = 48.50 mm, mean chord 16.81 mm, wing area
  S = 815.33 mm^2 (one wing), r2/R = 0.53.
* Wing mass 47 mg each: Berman & Wang (2007), J. Fluid Mech. 582:153-168, Table 1 (hawkmoth).
* Chord distribution: Ellington (1984), Phil. Trans. R. Soc. B 305:1-15 ("The aerodynamics of hovering
  insect flight. II. Morphological parameters"): the chord follows a beta distribution in r/R whose
  first moment r1 relates to the second by r2 = 0.929 r1^0.732.
* Body segments (head, thorax, abdomen) and the hinge position are the paper's "left out" quantities.
  Lengths and diameters are representative of adult *M. sexta* (body length ~ 45-50 mm, thorax ~ 10 mm
  wide; Willmott & Ellington 1997, J. Exp. Biol. 200:2693-2704; O'Hara & Palazotto 2012,
  Arthropod Struct. Dev. 41:101-110). The mass split between segments is a model choice (documented in
  models/hawkmoth/README.md); it sets the body inertia, not the cycle-averaged aerodynamics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

G = 9.81
"""Gravitational acceleration [m/s^2]."""

RHO_AIR = 1.225
"""Air density [kg/m^3] (ISA sea level), used by all aerodynamic models."""

P0_W = 84.2e-3
"""Reference power P0 [W]: required power of a hovering hawkmoth, Nguyen et al. (2020) Sec. 3.1."""

STROKE_PLANE_TO_BODY = np.deg2rad(60.0)
"""Angle chi + beta [rad]: the stroke plane is fixed at 120 deg from the body axis (Willmott & Ellington
1997 via Nguyen et al. 2020 Sec. 2), so the body angle is chi = 60 deg - beta."""


@dataclass(frozen=True)
class Ellipsoid:
    """A body segment: a solid ellipsoid of uniform density aligned with the body axes.

    Attributes: mass [kg]; centre (3,) in the body frame [m] (before the whole body is shifted so that its
    centre of mass is the origin); semi_axes (3,) along body x, y, z [m].
    """

    name: str
    mass: float
    centre: tuple[float, float, float]
    semi_axes: tuple[float, float, float]

    def inertia_about_centre(self) -> np.ndarray:
        """Inertia tensor (3, 3) about the segment's own centre, body axes [kg m^2]."""
        a, b, c = self.semi_axes
        m = self.mass
        return np.diag([m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5])


def _beta_fn(p: float, q: float) -> float:
    """Euler's beta function B(p, q) = Gamma(p) Gamma(q) / Gamma(p + q) for the planform's 1 < p, q (no
    overflow below p + q ~ 170). Equal to the bit to scipy.special.beta at the hawkmoth's (p, q), without
    importing scipy.special (0.2 s of every command's start-up)."""
    return math.gamma(p) * math.gamma(q) / math.gamma(p + q)


@dataclass(frozen=True)
class Planform:
    """Wing planform: beta-distributed chord (Ellington 1984) with a straight feathering axis.

    The chord is c(r) = cbar * rhat^(p-1) (1-rhat)^(q-1) / B(p, q), rhat = r/R, so that the mean chord is
    exactly cbar and the area R cbar. The feathering (rotation) axis is the wing-frame y axis and lies at
    ``axis_fraction`` of the local chord behind the leading edge: x_le = axis_fraction c, x_te = -(1 -
    axis_fraction) c.
    """

    R: float
    cbar: float
    p: float
    q: float
    axis_fraction: float = 0.25

    def chord(self, r: np.ndarray) -> np.ndarray:
        """Local chord [m] at spanwise positions r [m] (any shape), zero outside [0, R]."""
        rh = np.clip(np.asarray(r, dtype=float) / self.R, 0.0, 1.0)
        return self.cbar * rh ** (self.p - 1) * (1 - rh) ** (self.q - 1) / _beta_fn(self.p, self.q)

    def leading_edge(self, r: np.ndarray) -> np.ndarray:
        """x of the leading edge [m] in the wing frame."""
        return self.axis_fraction * self.chord(r)

    def trailing_edge(self, r: np.ndarray) -> np.ndarray:
        """x of the trailing edge [m] in the wing frame."""
        return -(1.0 - self.axis_fraction) * self.chord(r)

    @property
    def area(self) -> float:
        """Exact area of one wing [m^2]: R cbar."""
        return self.R * self.cbar

    @property
    def r2_hat(self) -> float:
        """Exact nondimensional radius of the second moment of area, sqrt(E[rhat^2])."""
        p, q = self.p, self.q
        return float(np.sqrt(p * (p + 1) / ((p + q) * (p + q + 1))))

    @property
    def r1_hat(self) -> float:
        """Exact nondimensional radius of the first moment of area."""
        return self.p / (self.p + self.q)


def beta_planform(R: float, cbar: float, r2_hat: float, axis_fraction: float = 0.25) -> Planform:
    """Planform whose R, mean chord and r2/R match the targets exactly.

    r1 follows from Ellington's (1984) empirical relation r2 = 0.929 r1^0.732; then the beta parameters are
    the method-of-moments solution p = r1 [r1 (1 - r1) / (r2^2 - r1^2) - 1], q = p (1 - r1) / r1.
    """
    r1 = (r2_hat / 0.929) ** (1.0 / 0.732)
    p = r1 * (r1 * (1 - r1) / (r2_hat**2 - r1**2) - 1)
    q = p * (1 - r1) / r1
    if not (p > 1 and q > 1):
        raise ValueError(f"r2_hat={r2_hat} gives a chord distribution with p={p:.3f}, q={q:.3f}; need > 1")
    return Planform(R=R, cbar=cbar, p=p, q=q, axis_fraction=axis_fraction)


def _default_segments() -> tuple[Ellipsoid, ...]:
    """Head, thorax, abdomen of a 1.48 g body (model choice; see the module docstring).

    Positions along the body axis (x, toward the head) are measured from the wing-hinge line; the abdomen
    hangs slightly below the thorax axis.
    """
    return (
        Ellipsoid("head", 0.06 * 1.4847e-3, (0.0105, 0.0, 0.0), (0.0030, 0.0035, 0.0035)),
        Ellipsoid("thorax", 0.40 * 1.4847e-3, (0.0020, 0.0, 0.0), (0.0075, 0.0050, 0.0055)),
        Ellipsoid("abdomen", 0.54 * 1.4847e-3, (-0.0165, 0.0, -0.0010), (0.0125, 0.0048, 0.0048)),
    )


@dataclass(frozen=True)
class Morphology:
    """The hawkmoth model's mass properties and geometry (SI).

    total_mass includes both wings (Table 1 of Nguyen et al. 2020). ``hinge_left`` is the left wing hinge in
    the body frame; the right hinge is its mirror image (y -> -y).
    """

    total_mass: float = 1578.70e-6
    wing_mass: float = 47e-6
    R: float = 48.50e-3
    cbar: float = 16.81e-3
    r2_hat: float = 0.53
    wing_thickness: float = 0.1e-3
    segments: tuple[Ellipsoid, ...] = field(default_factory=_default_segments)
    hinge_from_thorax: tuple[float, float, float] = (0.0010, 0.0040, 0.0035)
    """Left hinge relative to the thorax centre [m]: near the front of the thorax, on its dorsolateral edge."""

    @cached_property
    def planform(self) -> Planform:
        return beta_planform(self.R, self.cbar, self.r2_hat)

    @property
    def body_mass(self) -> float:
        """Mass of head + thorax + abdomen [kg] = total - 2 wings."""
        return self.total_mass - 2 * self.wing_mass

    @property
    def weight(self) -> float:
        """W = m g [N], the force scale of L+ and D+."""
        return self.total_mass * G

    @property
    def wing_area(self) -> float:
        """S, one wing [m^2]."""
        return self.planform.area

    @cached_property
    def _segment_com(self) -> np.ndarray:
        m = np.array([s.mass for s in self.segments])
        c = np.array([s.centre for s in self.segments])
        return (m[:, None] * c).sum(0) / m.sum()

    @cached_property
    def body_inertia(self) -> np.ndarray:
        """Inertia (3, 3) of the body segments about their centre of mass, body axes [kg m^2]."""
        scale = self.body_mass / sum(s.mass for s in self.segments)
        inertia = np.zeros((3, 3))
        for s in self.segments:
            d = np.asarray(s.centre) - self._segment_com
            inertia += scale * (s.inertia_about_centre() + s.mass * (d @ d * np.eye(3) - np.outer(d, d)))
        return inertia

    def segment_centres(self) -> dict[str, np.ndarray]:
        """Segment centres in the body frame [m] (relative to the body centre of mass)."""
        return {s.name: np.asarray(s.centre) - self._segment_com for s in self.segments}

    @property
    def hinge_left(self) -> np.ndarray:
        """Left wing hinge in the body frame [m]."""
        thorax = next(s for s in self.segments if s.name == "thorax")
        return np.asarray(thorax.centre) + np.asarray(self.hinge_from_thorax) - self._segment_com

    @cached_property
    def _wing_mass_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """Fine quadrature of the planform: points (n, 3) in the wing frame and their masses (n,)."""
        pl = self.planform
        nr, nx = 400, 60
        r = (np.arange(nr) + 0.5) / nr * self.R
        c = pl.chord(r)
        s = (np.arange(nx) + 0.5) / nx  # fraction of chord from the leading edge
        x = pl.leading_edge(r)[:, None] - s[None, :] * c[:, None]
        dA = (self.R / nr) * c[:, None] / nx * np.ones_like(x)
        pts = np.stack([x, np.broadcast_to(r[:, None], x.shape), np.zeros_like(x)], -1).reshape(-1, 3)
        w = dA.reshape(-1)
        return pts, self.wing_mass * w / w.sum()

    @cached_property
    def wing_com(self) -> np.ndarray:
        """Centre of mass (3,) of the left wing in its wing frame [m] (uniform areal density)."""
        pts, m = self._wing_mass_grid
        return (m[:, None] * pts).sum(0) / m.sum()

    @cached_property
    def wing_inertia(self) -> np.ndarray:
        """Inertia (3, 3) of the left wing about its centre of mass, wing-frame axes [kg m^2].

        A uniform plate of thickness ``wing_thickness`` (which only keeps the tensor strictly positive
        definite): the out-of-plane inertia is Ixx + Iyy + m t^2 / 6.
        """
        pts, m = self._wing_mass_grid
        d = pts - self.wing_com
        inertia = np.einsum("n,nij->ij", m, (d * d).sum(1)[:, None, None] * np.eye(3) - d[:, :, None] * d[:, None, :])
        t2 = self.wing_thickness**2 / 12 * self.wing_mass
        inertia += np.diag([t2, t2, 0.0])
        return inertia

    @property
    def r2(self) -> float:
        """Dimensional radius of the second moment of wing area [m] (the U of the paper's Eq. 8 uses it)."""
        return self.r2_hat * self.R


HAWKMOTH = Morphology()
"""The default hawkmoth."""
