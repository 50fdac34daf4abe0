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
* Chord distribution: Ellington (1984), Phil. Trans. R. Soc. B 305:17-40 ("The aerodynamics of hovering
  insect flight. II. Morphological parameters"): the chord follows a beta distribution in r/R whose
  first moment r1 relates to the second by r2 = 0.929 r1^0.732.
* Feathering-axis position and wing mass distribution: ``Morphology()`` (the default, every shipped table,
  network and test) keeps the model choices of hawksim 0.2 (axis at 25 % of the local chord, uniform areal
  density); :meth:`Morphology.sourced` is the named alternative of issue 22 (axis on the leading edge, areal
  density falling toward the tip and the trailing edge). What the literature search found for each, and which
  of the alternative's values are sourced and which are still provisional: docs/fidelity.md.
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


@dataclass(frozen=True)
class WingMassModel:
    """Areal density of a wing over its planform (the mass itself is ``Morphology.wing_mass``).

    rho_A(r, s) proportional to exp(-span_decay r/R) exp(-chord_decay s), with r the spanwise position and s in
    [0, 1] the fraction of the local chord behind the leading edge. ``span_decay = chord_decay = 0`` is a wing of
    uniform areal density (the default model). Positive decays put the mass toward the root and the leading edge,
    where insect wings carry their veins: Ellington (1984, Phil. Trans. R. Soc. B 305:17-40) treats the moments of
    wing mass apart from those of wing area; Combes & Daniel (2003, "Flexural stiffness in insect wings II",
    J. Exp. Biol. 206) find the Manduca forewing's flexural stiffness (vein material) falling from the base to the
    tip and from the leading to the trailing edge (their abstract, as recalled; the stored text of the search held
    only the introduction: docs/fidelity.md). ``name`` labels the model in tables and reports.
    """

    name: str = "uniform"
    span_decay: float = 0.0
    chord_decay: float = 0.0

    def __post_init__(self):
        for k in ("span_decay", "chord_decay"):
            v = getattr(self, k)
            if not math.isfinite(v):
                raise ValueError(f"WingMassModel.{k} must be finite, got {v!r}")

    def density(self, r_hat: np.ndarray, s: np.ndarray) -> np.ndarray:
        """Relative areal density (dimensionless, 1 at the leading edge of the root) at r/R and chord fraction s
        (broadcast shapes)."""
        if self.span_decay == 0.0 and self.chord_decay == 0.0:
            return np.ones(np.broadcast(r_hat, s).shape)
        return np.exp(-self.span_decay * np.asarray(r_hat) - self.chord_decay * np.asarray(s))


UNIFORM_WING = WingMassModel()
"""Uniform areal density: hawksim 0.2's wing (centre of mass at 0.465 R, the planform's r1)."""

VEINED_WING = WingMassModel("veined", span_decay=1.0, chord_decay=1.0)
"""PROVISIONAL areal density of :meth:`Morphology.sourced`: e times denser at the root than at the tip and at
the leading than at the trailing edge. The direction is sourced (see :class:`WingMassModel`); the two decay
constants are NOT: the measured Manduca forewing centre of mass and moments of inertia (O'Hara & Palazotto 2012,
Bioinspir. Biomim. 7:046011; Ellington 1984) were not available to this session, and these constants are to be
replaced by a fit to them before the alternative becomes the default (docs/fidelity.md). On the hawkmoth
planform: centre of mass at 0.401 R (uniform: 0.465 R), the mass on average 42 % of the local chord behind the
leading edge (uniform: 50 %), radius of the second moment of wing mass 0.471 R (uniform: 0.530 R, the area's)."""


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
    axis_fraction: float = 0.25
    """Feathering (pitching) axis as a fraction of the local chord behind the leading edge (0: on the leading
    edge). 0.25 is hawksim 0.2's model choice (issue 22: it sets L+ and P+ by up to 10 %; docs/fidelity.md)."""
    wing_mass_model: WingMassModel = UNIFORM_WING
    """Areal density of the wing mass (:class:`WingMassModel`; default uniform)."""
    name: str = "default"
    """Label of the variant (tables, reports, :data:`MORPHOLOGIES`)."""

    def __post_init__(self):
        if not (math.isfinite(self.axis_fraction) and 0.0 <= self.axis_fraction <= 1.0):
            raise ValueError(f"axis_fraction must lie in [0, 1] (fraction of the chord behind the leading edge), "
                             f"got {self.axis_fraction!r}")
        if not (math.isfinite(self.wing_mass) and 0.0 < 2 * self.wing_mass < self.total_mass):
            raise ValueError(f"wing_mass must be positive and the two wings lighter than total_mass, "
                             f"got {self.wing_mass!r}")

    @classmethod
    def sourced(cls) -> Morphology:
        """Issue 22's alternative: the feathering axis on the leading edge and the :data:`VEINED_WING` mass
        distribution; everything else as the default. NOT the default: every shipped table, network and test is
        built on ``Morphology()``; switching needs the pipeline regenerated (issue 22, item 4).

        Sources: the axis on the leading edge follows the hawkmoth wing's structure, whose leading-edge veins form
        the spar about which the wing pronates and supinates, with the centre of mass behind the torsional axis
        (Wootton 1993, J. Exp. Biol. 180:105, on Lepidoptera forewings: "its centre of mass is commonly located
        behind the torsional axis"); the axis positions of the paper's UVLM (Nguyen et al. 2016) and the other
        hawkmoth models could not be read in this session's sources (docs/fidelity.md). The mass distribution's
        constants are provisional (:data:`VEINED_WING`). Wing mass 47 mg as the default (Berman & Wang 2007)."""
        return cls(axis_fraction=0.0, wing_mass_model=VEINED_WING, name="sourced")

    @cached_property
    def planform(self) -> Planform:
        return beta_planform(self.R, self.cbar, self.r2_hat, self.axis_fraction)

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
        dA = dA * self.wing_mass_model.density(r[:, None] / self.R, s[None, :])
        pts = np.stack([x, np.broadcast_to(r[:, None], x.shape), np.zeros_like(x)], -1).reshape(-1, 3)
        w = dA.reshape(-1)
        return pts, self.wing_mass * w / w.sum()

    @cached_property
    def wing_com(self) -> np.ndarray:
        """Centre of mass (3,) of the left wing in its wing frame [m] (areal density: ``wing_mass_model``)."""
        pts, m = self._wing_mass_grid
        return (m[:, None] * pts).sum(0) / m.sum()

    @cached_property
    def wing_inertia(self) -> np.ndarray:
        """Inertia (3, 3) of the left wing about its centre of mass, wing-frame axes [kg m^2].

        A flat plate of areal density ``wing_mass_model`` and thickness ``wing_thickness`` (which only keeps the
        tensor strictly positive definite): the out-of-plane inertia is Ixx + Iyy + m t^2 / 6.
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

MORPHOLOGIES = ("default", "sourced")
"""Named variants (:func:`morphology`)."""


def morphology(name: str = "default") -> Morphology:
    """The named variant: "default" (:data:`HAWKMOTH`) or "sourced" (:meth:`Morphology.sourced`)."""
    if name == "default":
        return HAWKMOTH
    if name == "sourced":
        return Morphology.sourced()
    raise ValueError(f"unknown morphology {name!r}; choose one of {', '.join(MORPHOLOGIES)}")
