"""Steady limit and Wagner build-up of impulsively started flat rectangular wings (plain UVLM)."""

import numpy as np
import pytest

from aero.mesh import wing_mesh
from steady_vlm_reference import steady_lift_coefficient
from aero.uvlm import UVLM, FreeStream, UVLMConfig

PLAIN = UVLMConfig(le_suction=False, core_growth=False, free_wake=False)

VLM_RTOL = 0.02
"""Relative: the UVLM's C_L after 100 steps (wake ~17 spans long) vs the steady horseshoe VLM on the same lattice
(steady_vlm_reference.py). Also the bound the 'can fail' check shows a 10 % error exceeds. Source of 2 %: not
found (a round value); measured 3.0e-4 at AR 6, alpha 5 deg."""

SETTLED_RTOL = 2e-3
"""Relative change of C_L over the last 9 steps that counts as settled. Source: not found (a round value);
measured 5.3e-4."""

HELMBOLD_RTOL = 0.05
"""Relative: lift slope vs Helmbold's (1942) lifting-line estimate (Anderson, Eq. 5.81), which lies ~4.5 % above
converged lifting-surface values at AR 6; measured 4.6 % here: a margin of only 0.4 %."""

WAGNER_TOL = 0.05
"""Absolute, in C_L / C_L(steady): the build-up vs R. T. Jones' (1938) approximation of Wagner's function at
s = 2, 4, 6, 10. Finite AR 100 (Jones 1940, NACA Rep. 681: the gap shrinks from 0.08 at AR 24 to 0.04 at AR 100
for s = 2) plus the one-step shedding lag (ds = 0.25, ~0.015 in Phi at s = 2). Measured max 0.047."""


def _pitch(alpha):
    """Wing frame -> world, nose up by alpha: wing x = (cos a, 0, sin a)."""
    c, s = np.cos(alpha), np.sin(alpha)
    return np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])


def impulsive_start(ar, nc, ns, alpha, steps, cfg=PLAIN, U=1.0, chord=1.0):
    """C_L history (lift normal to the stream / (q S)) of a rectangular wing started at t = 0, dt = panel / U."""
    m = wing_mesh(np.linspace(0, ar * chord, ns + 1), np.zeros(ns + 1), -chord * np.ones(ns + 1), nc)
    s = UVLM([m], cfg)
    fs = FreeStream(v0=np.array([-U, 0.0, 0.0]))
    R = _pitch(alpha)[None]
    z = np.zeros((1, 3))
    q = 0.5 * cfg.rho * U ** 2 * ar * chord ** 2
    return m, np.array([s.step(chord / nc / U, R, z, z, z, fs).force[0, 2] / q for _ in range(steps)])


def helmbold(ar):
    """Helmbold (1942) lift slope of a flat unswept wing [1/rad] (Anderson, Fundamentals of Aerodynamics,
    Eq. 5.81): 2 pi AR / (2 + sqrt(AR^2 + 4))."""
    return 2 * np.pi * ar / (2 + np.sqrt(ar ** 2 + 4))


def test_steady_limit_matches_vlm_and_helmbold():
    alpha = np.radians(5.0)
    m, cl = impulsive_start(6.0, 6, 24, alpha, 100)
    cl_vlm = steady_lift_coefficient(m, alpha)
    assert cl[-1] == pytest.approx(cl_vlm, rel=VLM_RTOL)
    assert abs(cl[-1] - cl[-10]) < SETTLED_RTOL * cl[-1]
    assert cl[-1] / alpha == pytest.approx(helmbold(6.0), rel=HELMBOLD_RTOL)
    # the test can fail: a 10 % wrong answer is rejected
    assert not 0.9 * cl_vlm == pytest.approx(cl[-1], rel=VLM_RTOL)


def wagner_jones(s):
    """R. T. Jones' (1938) approximation of Wagner's function (NACA Rep. 681)."""
    return 1 - 0.165 * np.exp(-0.0455 * s) - 0.335 * np.exp(-0.3 * s)


def test_wagner_build_up_high_aspect_ratio():
    nc = 8
    alpha = np.radians(3.0)
    m, cl = impulsive_start(100.0, nc, 20, alpha, 41)
    s = 2.0 * np.arange(41) / nc            # s = U t / (c/2) at the end of each step (wake length)
    cl_inf = steady_lift_coefficient(m, alpha)
    ratio = cl / cl_inf
    for sk in (2.0, 4.0, 6.0, 10.0):
        k = int(round(sk * nc / 2))
        # finite AR and the shedding lag: WAGNER_TOL
        assert ratio[k] == pytest.approx(wagner_jones(s[k]), abs=WAGNER_TOL), (sk, ratio[k], wagner_jones(s[k]))
    gap = ratio - wagner_jones(s)
    assert gap[8] > gap[16] > gap[40] > 0          # the finite-AR lead decays as the starting vortex recedes
