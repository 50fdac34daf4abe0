"""The UVLM's unsteady load term (issue 48): the panel's potential jump from its two bounding rings, the
second-order backward difference in time with unequal steps, and the opt-in lumped near wake."""

import numpy as np
import pytest

from aero.lattice import ring_lattice
from aero.mesh import wing_mesh
from aero.uvlm import UVLM, UVLMConfig
from aero.wake import lump_near_wake

EXACT_RTOL = 1e-12
"""The backward difference on three samples is exact for a quadratic in time (round-off only)."""


def _solver(**kw):
    y = np.linspace(0.0, 1.0, 3)
    return UVLM([wing_mesh(y, np.full(3, 0.25), np.full(3, -0.75), 3)], UVLMConfig(**kw))


def _quadratic(t):
    """Ring circulations (3, 2) that are quadratic in t, different per ring."""
    a = np.arange(6.0).reshape(3, 2)
    return 1.0 + a * t + (a + 1.0) * t**2, a + 2 * (a + 1.0) * t


@pytest.mark.parametrize("h1,h2", [(1e-3, 1e-3), (1e-3, 2.5e-3), (3e-3, 1e-3)])
def test_bdf2_is_exact_for_a_quadratic_with_unequal_steps(h1, h2):
    s = _solver(potential_jump="ring")
    t = 0.7
    g, dg = _quadratic(t)
    s._gamma_prev, s._gamma_prev2 = [_quadratic(t - h1)[0]], [_quadratic(t - h1 - h2)[0]]
    s._dt_prev, s._dt_prev2 = h1, h2
    np.testing.assert_allclose(s._jump_rate(0, g), dg, rtol=EXACT_RTOL)


def test_panel_jump_is_the_mean_of_the_bounding_rings():
    s = _solver(time_derivative="euler")
    g1 = np.zeros((3, 2))
    s._gamma_prev, s._dt_prev = [g1], 0.5
    g = np.array([[1.0, 2.0], [3.0, 5.0], [4.0, 9.0]])
    rate = g / 0.5
    expect = 0.5 * (rate + np.vstack([np.zeros((1, 2)), rate[:-1]]))
    np.testing.assert_allclose(s._jump_rate(0, g), expect, rtol=EXACT_RTOL)
    # its chordwise sum is the trapezoid rule: the ring sum less half the trailing-edge ring
    np.testing.assert_allclose(expect.sum(0), rate.sum(0) - 0.5 * rate[-1], rtol=EXACT_RTOL)


def test_first_step_has_no_unsteady_term():
    s = _solver()
    assert np.all(s._jump_rate(0, np.ones((3, 2))) == 0)


def test_lump_near_wake_moves_corners_zone_by_zone():
    x = np.array([0.0, 0.3, 0.6, 1.2, 1.5, 2.4])  # corner rows' distance from the attached row [m]
    G = np.zeros((x.size, 2, 3))
    G[..., 0] = x[:, None]
    G[:, 1, 1] = 1.0
    lat = ring_lattice(G, np.ones((x.size - 1, 1)), 0.01, 0.01)
    out = lump_near_wake(lat, np.ones(2), 1e-6, zones=2)
    np.testing.assert_array_equal(out.G[:, 0, 0], [0.0, 0.0, 0.0, 1.2, 1.2, 2.4])
    assert np.all(out.span_rc2[1:3] == 1e-6) and np.all(out.span_rc2[3:] == 0.01)
    np.testing.assert_array_equal(lat.G[:, 0, 0], x)  # the wake itself is untouched
    one = lump_near_wake(lat, np.ones(2), 1e-6, zones=1)
    np.testing.assert_array_equal(one.G[:, 0, 0], [0.0, 0.0, 0.0, 1.2, 1.5, 2.4])


def test_bad_settings():
    for kw, match in ((dict(potential_jump="node"), "potential_jump"), (dict(time_derivative="rk4"), "time_derivative"),
                      (dict(near_wake_zones=-1), "near_wake_zones"), (dict(near_wake_zones=1.5), "near_wake_zones")):
        with pytest.raises(ValueError, match=match):
            UVLMConfig(**kw)
