"""The UVLM against classical 2D unsteady theory (issue 48): flat rectangular plates at AR 10, 20, 40, 80,
extrapolated to AR -> infinity (a quadratic in 1/AR), against Theodorsen (heave; pitch about the quarter chord),
Garrick's plunging thrust and Wagner's indicial lift (:mod:`aero.unsteady_theory`).

The time step convects the wake one chordwise panel per step (:func:`aero.plate.consistent_steps`). CI runs 8
chordwise rings at k = 1, where that resolution meets the targets (k = 0.5 at 8 rings costs 4x as much and is
within 0.3 %); the slow tests run the converged
resolution of docs/validation.md (:data:`CONVERGED`) at every k <= 2. The whole table, with the figures:
scripts/studies/classical_cases.py.
"""

from dataclasses import replace

import numpy as np
import pytest

from aero import plate
from aero.unsteady_theory import garrick_thrust, heave_lift, pitch_lift, wagner
from aero.uvlm import LEGACY_0_2

ASPECT_RATIOS = (10.0, 20.0, 40.0, 80.0)
N_SPAN = 24

AMPLITUDE_RTOL = 0.03
"""Issue 48's target: the first harmonic's amplitude within 3 % of Theodorsen's in the 2D limit (k <= 2)."""
PHASE_TOL_DEG = 3.0
"""Issue 48's target: its phase within 3 deg."""
WAGNER_RTOL = 0.03
"""Issue 48's target: C_L(s) / (2 pi alpha) within 3 % of Wagner's function for s >= 1."""
GARRICK_RTOL = 0.03
"""Garrick's mean thrust within 3 % (k <= 1; the amplitude target applied to the thrust, which goes with the
square of the load)."""
GARRICK_RTOL_K2 = 0.06
"""At k = 2 the 16-ring resolution gives 25 steps a period; measured 0.962 of Garrick there (the thrust is
quadratic in the load, whose amplitude is 2.2 % high there)."""
GARRICK_RTOL_8_RINGS = 0.04
"""CI's coarser lattice (8 chordwise rings) at k = 1: measured 0.971 of Garrick (16 rings: 0.982)."""
LEGACY_EXCESS_MIN = 0.08
"""hawksim 0.2's UVLM exceeds the 2D heave lift at k = 1 already at AR 20 (8 rings, 80 steps a period: measured
1.20 with the linear-theory wake core, 1.23 with its own 0.05 c; above the 2D theory where a finite wing must be
below it: scripts/studies/theodorsen_candidates.py): the defect the new unsteady term and shedding
remove. The test holds the old configuration to it, so that it shows what the others would catch."""


def _grid(ar, nc, k):
    return plate.PlateGrid(ar, nc, N_SPAN, plate.consistent_steps(k, nc))


def harmonic_2d(motion, k, nc):
    hs = [plate.harmonic_response(_grid(ar, nc, k), motion, k) for ar in ASPECT_RATIOS]
    H, _ = plate.extrapolate_aspect_ratio(ASPECT_RATIOS, np.array([h.H for h in hs]))
    ct, _ = plate.extrapolate_aspect_ratio(ASPECT_RATIOS, np.array([h.c_t for h in hs]))
    return H, float(ct), [h.H for h in hs]


def check_theodorsen(motion, k, nc):
    H, ct, by_ar = harmonic_2d(motion, k, nc)
    ref = complex((heave_lift if motion == "heave" else pitch_lift)(k))
    assert abs(H) / abs(ref) == pytest.approx(1.0, abs=AMPLITUDE_RTOL), (abs(H) / abs(ref))
    assert abs(np.degrees(np.angle(H / ref))) < PHASE_TOL_DEG
    # a finite wing lies below the 2D amplitude, and closer to it the longer it is
    amps = np.abs(by_ar)
    assert np.all(np.diff(amps) > 0)
    return ct


@pytest.mark.parametrize("motion", ["heave", "pitch"])
def test_theodorsen_8_rings(motion):
    k = 1.0
    ct = check_theodorsen(motion, k, 8)
    if motion == "heave":
        assert ct / garrick_thrust(k, plate.HEAVE_AMPLITUDE / 0.5) == pytest.approx(1.0, abs=GARRICK_RTOL_8_RINGS)


def test_wagner_8_rings():
    s = np.array([1.0, 2.0, 5.0, 10.0, 20.0])
    phi = [plate.indicial_lift(_grid(ar, 8, 1.0), s) for ar in ASPECT_RATIOS]
    lim = np.array([plate.extrapolate_aspect_ratio(ASPECT_RATIOS, np.array(phi)[:, i])[0] for i in range(s.size)])
    np.testing.assert_allclose(lim / wagner(s), 1.0, atol=WAGNER_RTOL)


def test_legacy_unsteady_term_exceeds_theodorsen():
    cfg = replace(plate.PLAIN_CONFIG, **LEGACY_0_2)
    h = plate.harmonic_response(plate.PlateGrid(20.0, 8, N_SPAN, 80), "heave", 1.0, config=cfg)
    assert abs(h.H) / abs(heave_lift(1.0)) > 1 + LEGACY_EXCESS_MIN


CONVERGED = [(0.1, 8), (0.25, 8), (0.5, 16), (1.0, 16), (2.0, 16)]
"""(k, chordwise rings) of the converged resolution: 16 rings from k = 0.5 up; below, 8 (16 would need 200-500
steps a period at U dt = c / 16, and the chordwise error falls with k: 8 rings are within 0.5 % at k <= 0.25,
scripts/studies/classical_cases.py)."""


@pytest.mark.slow
@pytest.mark.parametrize("motion", ["heave", "pitch"])
@pytest.mark.parametrize("k,nc", CONVERGED)
def test_theodorsen_converged(motion, k, nc):
    ct = check_theodorsen(motion, k, nc)
    if motion == "heave":
        tol = GARRICK_RTOL if k <= 1 else GARRICK_RTOL_K2
        assert ct / garrick_thrust(k, plate.HEAVE_AMPLITUDE / 0.5) == pytest.approx(1.0, abs=tol)


@pytest.mark.slow
def test_wagner_converged():
    s = np.array([1.0, 2.0, 3.0, 5.0, 10.0, 15.0, 20.0])
    phi = [plate.indicial_lift(_grid(ar, 16, 1.0), s) for ar in ASPECT_RATIOS]
    lim = np.array([plate.extrapolate_aspect_ratio(ASPECT_RATIOS, np.array(phi)[:, i])[0] for i in range(s.size)])
    np.testing.assert_allclose(lim / wagner(s), 1.0, atol=WAGNER_RTOL)
