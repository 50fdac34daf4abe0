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
* Wing mass 47 mg each, the wing's moment of inertia about its root, the wing-base spacing and the body length:
  the rows of ../shared/sources/insect-morphology.md (Berman & Wang 2007, J. Fluid Mech. 582:153-168, Table 2;
  Palaoro et al.'s hemolymph data set), the constants below (BW2007_*, PALAORO_*).
* Chord distribution: Ellington (1984), Phil. Trans. R. Soc. B 305:17-40 ("The aerodynamics of hovering
  insect flight. II. Morphological parameters"): the chord follows a beta distribution in r/R whose
  first moment r1 relates to the second by r2 = 0.929 r1^0.732.
* Feathering-axis position and wing mass distribution: ``Morphology()`` (the default, every shipped table,
  network and test until the pipeline is regenerated) keeps the model choices of hawksim 0.2 (axis at 25 % of
  the local chord, uniform areal density, 47 mg wings); :meth:`Morphology.sourced` is issue 49's hawkmoth (wing
  mass and its radius of gyration from Berman & Wang 2007, the wing-base spacing from Palaoro et al., the axis
  calibrated to the seed paper's Table 4 lift).

Every number says its source class: quoted (from a cited table), measured (class (a) of the sources file: read in
the measuring authors' data), derived (arithmetic on those), model choice (no source), or calibrated (fitted to a
result of the seed paper, with the rule and the residual).
* Body segments (head, thorax, abdomen) and the hinge position are the paper's "left out" quantities.
  Lengths and diameters are representative of adult *M. sexta* (body length ~ 45-50 mm, thorax ~ 10 mm
  wide; Willmott & Ellington 1997, J. Exp. Biol. 200:2693-2704; O'Hara & Palazotto 2012,
  Arthropod Struct. Dev. 41:101-110). The mass split between segments is a model choice (documented in
  hawksim/insects/hawkmoth/README.md); it sets the body inertia, not the cycle-averaged aerodynamics.
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

BW2007_WING_MASS = 47e-6
"""Mass of one forewing [kg] of Berman & Wang's (2007, J. Fluid Mech. 582:153-168, Table 2) hawkmoth; source class
(b): quoted with that citation by public code (../shared/sources/insect-morphology.md)."""

BW2007_TOTAL_MASS = 1648e-6
"""Total mass [kg] of the same individual; class (b), same source."""

BW2007_R = 51.9e-3
"""Wing length [m] of the same individual; class (b), same source."""

BW2007_WING_INERTIA = 1.84e-8
"""Moment of inertia [kg m^2] of one forewing about its root, the flapping axis (0.184 g cm^2); class (b), same
source. Read here as the moment about the wing-frame x axis through the hinge, the integral of r^2 dm (see
:data:`WING_GYRATION_HAT`)."""

WING_GYRATION_HAT = math.sqrt(BW2007_WING_INERTIA / BW2007_WING_MASS) / BW2007_R
"""Mass radius of gyration of the wing about its root in units of R: sqrt(I / m) / R = 0.381; class (c), derived
from the three rows above (a uniform-areal-density wing of the hawkmoth planform gives 0.530: the measured wing is
root-heavy). Carried over to the seed paper's individual in units of R (:meth:`Morphology.sourced`)."""

WING_MASS_FRACTION = 2 * BW2007_WING_MASS / BW2007_TOTAL_MASS
"""Two forewings' share of the total mass, 0.0570; class (c), from Berman & Wang's individual. The rule that carries
the 47 mg over to the seed paper's lighter individual (1578.70 mg): same fraction, 45.02 mg a wing (a wing scales
with the body; the absolute 47 mg would make the lighter moth's wings relatively heavier)."""

ROOT_HEAVY_SPAN_DECAY = 2.6347
"""span_decay of :data:`ROOT_HEAVY_WING`, class (c): the value for which the seed planform's mass radius of gyration
about the root (wing-frame x through the hinge) is :data:`WING_GYRATION_HAT` (fitted by bisection; the test
tests/hawksim/test_morphology.py recomputes it to 1e-4). About the axis normal to the wing plane the same fit would
give about 3.2 (the chordwise extent adds x^2 dm): the flapping-axis reading is the model's."""

ROOT_HEAVY_WING = WingMassModel("root-heavy", span_decay=ROOT_HEAVY_SPAN_DECAY, chord_decay=0.0)
"""The wing of :meth:`Morphology.sourced`: areal density exp(-2.635 r/R), fitted to the measured radius of gyration
(:data:`ROOT_HEAVY_SPAN_DECAY`): centre of mass at 0.310 R (uniform: 0.465 R), radius of gyration 0.381 R. The
chordwise distribution is a model choice: uniform across the chord (no source gives the Manduca forewing's
chordwise centre of mass; ../shared/sources/insect-morphology.md)."""

PALAORO_WING_BASE_SPACING = 11.08e-3
"""Distance between the two forewing bases [m] of *M. sexta*, mean of N = 19 (SD 0.61 mm); class (a): Palaoro et al.,
hemolymph-viscosity data set (``data/hemolymph_data.csv``, column ``body.width``)."""

PALAORO_FOREWING = 52.8e-3
"""Forewing length [m] of the same 19 moths (SD 5.2 mm); class (a), same data set."""

PALAORO_BODY_LENGTH = 45.5e-3
"""Body length [m], head to abdomen tip, of the same 19 moths (SD 4.9 mm); class (a), same data set. Scaled to the
seed paper's wing (R / :data:`PALAORO_FOREWING`): 41.8 mm; the model's segments span 42.5 mm (a model choice,
:func:`_default_segments`, within 2 %)."""


CALIBRATED_AXIS_FRACTION = 0.06
"""Feathering axis of :meth:`Morphology.sourced`, as a fraction of the local chord behind the leading edge: a
CALIBRATED model parameter (no reachable source gives it; the seed paper does not state it). Rule: the least-squares
fit of the current UVLM's held-body L+ at Table 3's kinematics to Table 4's L+ at 0, 1 and 2 m/s (the seed paper's
own UVLM lift; one parameter, three targets), at `hawksim aero`'s default resolution (6 x 12 rings, 40 steps, the
resolution of the reference labels), rounded to 0.005 (fit 0.0585). It moves L+ by about -0.5 per unit of chord
fraction (so 0.02 of the chord is 1 % of L+) and P+, the trims and the stability results with it; those are
predictions, not fits. Command, residuals and the check at 8 x 16 rings / 80 steps (where the same rule gives 0.03):
``python scripts/studies/axis_calibration.py --out results/axis_calibration.json``, docs/results.md."""


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


SEED_TOTAL_MASS = 1578.70e-6
"""Total mass [kg] of the seed paper's individual, wings included; class (b): Nguyen et al. 2020, Table 1."""

SEED_R = 48.50e-3
"""Wing length [m] of the seed paper's individual; class (b): Nguyen et al. 2020, Table 1."""

SEED_WING_MASS = WING_MASS_FRACTION * SEED_TOTAL_MASS / 2
"""Mass of one wing [kg] of the seed paper's individual, 45.02 mg; class (c): :data:`WING_MASS_FRACTION` of
:data:`SEED_TOTAL_MASS` (the rule is stated there)."""

SEED_HINGE_FROM_THORAX = (0.0010, PALAORO_WING_BASE_SPACING * SEED_R / PALAORO_FOREWING / 2, 0.0035)
"""Left wing hinge relative to the thorax centre [m]: lateral offset half the measured wing-base spacing scaled to the
seed wing (class (c): :data:`PALAORO_WING_BASE_SPACING` x R / :data:`PALAORO_FOREWING`, 10.18 mm apart); fore-aft
1.0 mm and height 3.5 mm, near the front of the thorax on its dorsolateral edge, are model choices."""


@dataclass(frozen=True)
class Morphology:
    """The hawkmoth model's mass properties and geometry (SI).

    The defaults are the sourced hawkmoth of hawksim 0.3 (issue 49): the seed paper's individual (Table 1: mass, R,
    mean chord, r2) with every other number sourced or derived where the literature allows and labelled where it does
    not (each field's docstring gives its class: (a) measured, (b) quoted, (c) derived, model choice, calibrated).
    :meth:`hawksim_0_2` is hawksim 0.2's hawkmoth. total_mass includes both wings. ``hinge_left`` is the left wing
    hinge in the body frame; the right hinge is its mirror image (y -> -y).
    """

    total_mass: float = SEED_TOTAL_MASS
    """Total mass [kg], wings included; quoted: Nguyen et al. 2020, Table 1 (the seed paper's individual)."""
    wing_mass: float = SEED_WING_MASS
    """Mass of one wing [kg]; derived: :data:`SEED_WING_MASS` (Berman & Wang 2007's wing-mass fraction)."""
    R: float = SEED_R
    """Wing length [m]; quoted: Nguyen et al. 2020, Table 1."""
    cbar: float = 16.81e-3
    """Mean chord [m]; quoted: Nguyen et al. 2020, Table 1."""
    r2_hat: float = 0.53
    """Radius of the second moment of wing area / R; quoted: Nguyen et al. 2020, Table 1."""
    wing_thickness: float = 0.1e-3
    """Wing thickness [m]; model choice (it only keeps the wing's inertia tensor positive definite)."""
    segments: tuple[Ellipsoid, ...] = field(default_factory=_default_segments)
    """Head, thorax, abdomen; model choice (:func:`_default_segments`; 42.5 mm long, :data:`PALAORO_BODY_LENGTH`)."""
    hinge_from_thorax: tuple[float, float, float] = SEED_HINGE_FROM_THORAX
    """Left hinge relative to the thorax centre [m]; lateral offset derived, the rest model choice
    (:data:`SEED_HINGE_FROM_THORAX`)."""
    axis_fraction: float = CALIBRATED_AXIS_FRACTION
    """Feathering (pitching) axis as a fraction of the local chord behind the leading edge (0: on the leading
    edge); calibrated: :data:`CALIBRATED_AXIS_FRACTION` (the rule and what it moves are stated there)."""
    wing_mass_model: WingMassModel = ROOT_HEAVY_WING
    """Areal density of the wing mass (:class:`WingMassModel`): :data:`ROOT_HEAVY_WING`, fitted to the measured
    radius of gyration (derived; uniform across the chord, a model choice)."""
    name: str = "sourced"
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
        """Issue 49's sourced hawkmoth, the default since hawksim 0.3: ``Morphology()`` (kept so that code written
        against hawksim 0.2, where it was a variant, runs unchanged)."""
        return cls()

    @classmethod
    def hawksim_0_2(cls) -> Morphology:
        """hawksim 0.2's hawkmoth, for reproducing its results: Berman & Wang's 47 mg wing taken as is, of uniform areal
        density (:data:`UNIFORM_WING`), hinges 8.00 mm apart and the quarter-chord feathering axis (all model
        choices then). Differs from the default in those four numbers and its name."""
        return cls(wing_mass=BW2007_WING_MASS, wing_mass_model=UNIFORM_WING, hinge_from_thorax=(0.0010, 0.0040, 0.0035),
                   axis_fraction=0.25, name="hawksim-0.2")

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
"""The default hawkmoth (the sourced one, :class:`Morphology`'s defaults)."""

MORPHOLOGIES = ("sourced", "hawksim-0.2")
"""Named variants (:func:`morphology`): the default, and hawksim 0.2's (:meth:`Morphology.hawksim_0_2`)."""


def morphology(name: str = "sourced") -> Morphology:
    """The named variant: "sourced" (:data:`HAWKMOTH`, also under its old name "default") or "hawksim-0.2"
    (:meth:`Morphology.hawksim_0_2`)."""
    if name in ("sourced", "default"):
        return HAWKMOTH
    if name == "hawksim-0.2":
        return Morphology.hawksim_0_2()
    raise ValueError(f"unknown morphology {name!r}; choose one of {', '.join(MORPHOLOGIES)}")
