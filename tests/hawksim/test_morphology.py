"""Table 1 of Nguyen et al. (2020) and the beta-distributed planform (Ellington 1984)."""

import numpy as np
import pytest

from hawksim.insect.morphology import HAWKMOTH, beta_planform

TABLE1_RTOL = 2e-4
"""Relative: area and mean chord of the planform (trapezoid rule, 200001 points) vs Table 1's S = 815.33 mm^2 and
cbar = 16.81 mm. Covers Table 1's own rounding (S = R cbar only to 6e-5) and the quadrature; the round value's
source is not recorded. Measured 5.5e-5 (area: that 6e-5), 7.5e-8 (cbar)."""

R2_QUADRATURE_TOL = 1e-4
"""Dimensionless: r2/R of the planform by quadrature vs the 0.53 it is built with (Table 1). Bounds the trapezoid
rule's error at the root and tip; source of the value not recorded; measured 1.6e-8."""

R2_EXACT_TOL = 1e-12
"""Dimensionless: the planform's stored r2_hat vs 0.53: float64 round-off; measured 1.1e-16."""

ELLINGTON_RTOL = 1e-3
"""Relative: r2 vs Ellington's (1984) r2 = 0.929 r1^0.732, which the beta planform satisfies by construction, so
only the quadrature error of r1 and r2 is left; measured 1.8e-8 (the round value's source is not recorded)."""

EDGE_ATOL = 1e-15
"""m: leading minus trailing edge vs chord (~0.02 m): round-off; measured: exact (0)."""

INERTIA_TRIANGLE_RTOL = 1e-9
"""Relative slack in the triangle inequality of the wing's principal moments (I1 + I2 >= I3; equality for a flat
plate, the perpendicular-axis theorem): round-off allowance. Measured: I1 + I2 - I3 = +9.2e-6 I3, so the slack is
not needed here."""

BETA_FN_RTOL = 1e-14
"""Relative: _beta_fn vs scipy.special.beta over 1 < p, q < 6 (the range stated by the test). Float64 evaluation
of the same function by another method; measured 1.6e-15 at worst over the 23 x 23 grid."""


def test_table1_planform_matches():
    pl = HAWKMOTH.planform
    r = np.linspace(0, pl.R, 200001)
    c = pl.chord(r)
    area = np.trapezoid(c, r)
    # Table 1: R = 48.50 mm, cbar = 16.81 mm, S = 815.33 mm^2 (= R cbar to 0.006 %), r2/R = 0.53
    assert pl.R == pytest.approx(48.50e-3)
    assert area == pytest.approx(815.33e-6, rel=TABLE1_RTOL)
    assert area / pl.R == pytest.approx(16.81e-3, rel=TABLE1_RTOL)
    r2 = np.sqrt(np.trapezoid(c * r**2, r) / area) / pl.R
    assert r2 == pytest.approx(0.53, abs=R2_QUADRATURE_TOL)
    assert pl.r2_hat == pytest.approx(0.53, abs=R2_EXACT_TOL)
    # Ellington (1984): r2 = 0.929 r1^0.732
    r1 = np.trapezoid(c * r, r) / area / pl.R
    assert r2 == pytest.approx(0.929 * r1**0.732, rel=ELLINGTON_RTOL)


def test_leading_and_trailing_edges_span_the_chord():
    pl = HAWKMOTH.planform
    r = np.linspace(0, pl.R, 11)
    np.testing.assert_allclose(pl.leading_edge(r) - pl.trailing_edge(r), pl.chord(r), atol=EDGE_ATOL)


def test_masses():
    m = HAWKMOTH
    assert m.total_mass == pytest.approx(1578.70e-6)
    assert m.body_mass + 2 * m.wing_mass == pytest.approx(1578.70e-6)
    # Berman & Wang (2007): 47 mg wings of a 1648 mg moth, the same fraction of Table 1's 1578.70 mg
    assert m.wing_mass == pytest.approx(47e-6 * 1578.70 / 1648)
    I = m.body_inertia
    assert np.all(np.linalg.eigvalsh(I) > 0) and np.allclose(I, I.T)
    Iw = m.wing_inertia
    ev = np.linalg.eigvalsh(Iw)
    assert np.all(ev > 0) and ev[0] + ev[1] >= ev[2] * (1 - INERTIA_TRIANGLE_RTOL)
    assert 0 < m.wing_com[1] < m.R and m.wing_com[0] < 0  # centroid behind the quarter-chord axis


def test_bad_r2_rejected():
    with pytest.raises(ValueError, match="r2_hat"):
        beta_planform(0.05, 0.017, 0.9)


def test_beta_function_matches_scipy():
    """The planform's B(p, q) without scipy.special: bit-equal at the hawkmoth's (p, q) (so every chord, and
    every UVLM result, is unchanged), and to 1e-14 relative over the planforms' range 1 < p, q < 6."""
    from scipy.special import beta

    from hawksim.insect.morphology import _beta_fn

    p, q = HAWKMOTH.planform.p, HAWKMOTH.planform.q
    assert _beta_fn(p, q) == beta(p, q)
    grid = np.linspace(1.01, 6.0, 23)
    for a in grid:
        for b in grid:
            assert _beta_fn(a, b) == pytest.approx(beta(a, b), rel=BETA_FN_RTOL)


# ---- issue 22: the feathering axis and the wing mass distribution as parameters -----------------------------

VARIANT_RTOL = 1e-3
"""Relative: the centre of mass, r2 of mass and mean chord position of the wing mass models vs the values their
docstrings state (3 digits). The quadrature (400 x 60 midpoints) is converged far below that: measured 2e-4 at
worst (rounding of the stated digits)."""
GYRATION_FIT_ATOL = 2e-4
"""The fitted span decay (4 decimals) reproduces the measured radius of gyration 0.381 R to this (in R)."""


def _mass_moments(m):
    pts, w = m._wing_mass_grid
    pl = m.planform
    s = (pl.leading_edge(pts[:, 1]) - pts[:, 0]) / pl.chord(pts[:, 1])
    r2 = np.sqrt((w * pts[:, 1] ** 2).sum() / w.sum()) / m.R
    return m.wing_com[1] / m.R, r2, (w * s).sum() / w.sum()


def test_hawksim_0_2s_wing():
    """hawksim 0.2's hawkmoth: the quarter-chord axis and the uniform density, 47 mg wings 8 mm apart."""
    from hawksim.insect.morphology import UNIFORM_WING, Morphology, morphology
    m = Morphology.hawksim_0_2()
    assert m.axis_fraction == 0.25 and m.wing_mass_model == UNIFORM_WING and morphology("hawksim-0.2") == m
    assert m.wing_mass == 47e-6 and m.hinge_from_thorax[1] == 0.004 and m.name == "hawksim-0.2"
    com, r2, s = _mass_moments(m)
    # uniform density: the centre of mass is the planform's r1 = 0.465 R, r2 of mass the area's 0.53
    assert com == pytest.approx(m.planform.r1_hat, rel=VARIANT_RTOL)
    assert r2 == pytest.approx(0.53, rel=VARIANT_RTOL)
    assert s == pytest.approx(0.5, rel=VARIANT_RTOL)


def test_sourced_variant():
    """Issue 49's hawkmoth: the measured radius of gyration (Berman & Wang 2007: I = 1.84e-8 kg m^2, 47 mg,
    R = 51.9 mm, sqrt(I/m)/R = 0.381), the wing-mass fraction 2 x 47 / 1648, the wing-base spacing 11.08 mm scaled
    by 48.5 / 52.8 (Palaoro et al.); ../shared/sources/insect-morphology.md."""
    from hawksim.insect.morphology import (CALIBRATED_AXIS_FRACTION, ROOT_HEAVY_WING, WING_GYRATION_HAT, Morphology,
                                           morphology)
    m = Morphology.sourced()
    assert m.name == "sourced" and morphology("sourced") == m == Morphology() and morphology("default") is HAWKMOTH
    assert m.axis_fraction == CALIBRATED_AXIS_FRACTION and m.wing_mass_model == ROOT_HEAVY_WING
    assert WING_GYRATION_HAT == pytest.approx(0.381, abs=5e-4)
    com, r2, s = _mass_moments(m)
    assert r2 == pytest.approx(WING_GYRATION_HAT, abs=GYRATION_FIT_ATOL)
    assert s == pytest.approx(0.5, rel=VARIANT_RTOL)  # uniform across the chord (model choice)
    assert m.wing_mass == pytest.approx(2 * 47 / 1648 * 1578.70e-6 / 2, rel=1e-12)  # 45.02 mg
    assert 2 * m.hinge_left[1] == pytest.approx(11.08e-3 * 48.5 / 52.8, rel=1e-12)  # 10.18 mm apart
    # the body and the planform's area are the seed paper's
    assert m.total_mass == HAWKMOTH.total_mass and m.wing_area == HAWKMOTH.wing_area
    r = np.linspace(0, m.R, 7)
    np.testing.assert_allclose(m.planform.leading_edge(r), m.axis_fraction * m.planform.chord(r), atol=EDGE_ATOL)
    ev = np.linalg.eigvalsh(m.wing_inertia)
    assert np.all(ev > 0) and ev[0] + ev[1] >= ev[2] * (1 - INERTIA_TRIANGLE_RTOL)


def test_root_heavy_decay_is_the_fit():
    """ROOT_HEAVY_SPAN_DECAY is the bisection root of r_gyration(decay) = 0.381 R on the seed planform, to 1e-4."""
    from dataclasses import replace

    from hawksim.insect.morphology import ROOT_HEAVY_SPAN_DECAY, WING_GYRATION_HAT, Morphology, WingMassModel

    def gyration(decay):
        m = replace(Morphology.sourced(), wing_mass_model=WingMassModel("fit", span_decay=decay))
        return _mass_moments(m)[1]

    lo, hi = 0.0, 10.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gyration(mid) > WING_GYRATION_HAT else (lo, mid)
    assert ROOT_HEAVY_SPAN_DECAY == pytest.approx(0.5 * (lo + hi), abs=1e-4)


def test_mass_model_moves_the_mass_inboard_and_forward():
    from hawksim.insect.morphology import Morphology, WingMassModel
    base = _mass_moments(Morphology(wing_mass_model=WingMassModel()))  # uniform
    span = _mass_moments(Morphology(wing_mass_model=WingMassModel("s", span_decay=1.0)))
    chord = _mass_moments(Morphology(wing_mass_model=WingMassModel("c", chord_decay=1.0)))
    assert span[0] < base[0] and span[1] < base[1] and span[2] == pytest.approx(base[2], rel=VARIANT_RTOL)
    assert chord[2] < base[2] and chord[0] == pytest.approx(base[0], rel=VARIANT_RTOL)
    # chordwise exp(-s): mean s = 1 - 1/(e - 1), exact for the density, to the quadrature's accuracy
    assert chord[2] == pytest.approx(1 - 1 / (np.e - 1), rel=VARIANT_RTOL)


def test_bad_variants_rejected():
    from hawksim.insect.morphology import Morphology, WingMassModel, morphology
    with pytest.raises(ValueError, match="axis_fraction"):
        Morphology(axis_fraction=1.5)
    with pytest.raises(ValueError, match="wing_mass"):
        Morphology(wing_mass=0.0)
    with pytest.raises(ValueError, match="span_decay"):
        WingMassModel(span_decay=float("nan"))
    with pytest.raises(ValueError, match="unknown morphology"):
        morphology("nope")
