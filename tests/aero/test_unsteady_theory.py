"""The classical references themselves (aero.unsteady_theory) against tabulated values and limits."""

import numpy as np
import pytest

from aero.unsteady_theory import garrick_thrust, heave_lift, pitch_lift, theodorsen, wagner, wagner_jones

THEODORSEN_TABLE = {0.1: 0.8319 - 0.1723j, 0.5: 0.5979 - 0.1507j, 1.0: 0.5394 - 0.1003j}
"""C(k) = F + iG to four decimals, the values tabulated for Theodorsen's function (Theodorsen 1935, NACA Rep. 496;
reprinted e.g. in Bisplinghoff, Ashley & Halfman 1955)."""

TABLE_ATOL = 6e-5
"""Half a unit in the table's last place, plus its rounding."""

JONES_ATOL = 0.01
"""R. T. Jones' (1938) two-exponential fit of Wagner's function: within 0.01 over s = 0-20 semichords (its stated
accuracy; the exact function was computed here from Theodorsen's function)."""


@pytest.mark.parametrize("k", sorted(THEODORSEN_TABLE))
def test_theodorsen_against_table(k):
    assert abs(theodorsen(k) - THEODORSEN_TABLE[k]) < TABLE_ATOL


def test_theodorsen_limits_and_bad_input():
    assert abs(theodorsen(1e-6) - 1.0) < 1e-4
    assert abs(theodorsen(1e4) - 0.5) < 1e-4
    with pytest.raises(ValueError, match="reduced frequency"):
        theodorsen(0.0)


def test_quasi_steady_limits():
    """k -> 0: heave lift -> -2 pi i k (the lift slope at the heave-induced angle), pitch lift -> 2 pi; Garrick's
    thrust -> pi k^2 (h0/b)^2 (the quasi-steady suction of a plate at angle -h'/U)."""
    k = 1e-4
    assert abs(heave_lift(k) / (-2j * np.pi * k) - 1) < 1e-3
    assert abs(pitch_lift(k) / (2 * np.pi) - 1) < 1e-3
    assert garrick_thrust(k, 0.1) == pytest.approx(np.pi * k**2 * 0.01, rel=1e-3)


def test_wagner_against_jones_and_limits():
    s = np.array([0.5, 1, 2, 3, 5, 10, 15, 20])
    assert np.max(np.abs(wagner(s) - wagner_jones(s))) < JONES_ATOL
    assert wagner(0.0) == 0.5
    assert wagner(200.0) > 0.994  # 1 - phi falls as ~1/s
    assert np.all(np.diff(wagner(np.linspace(0, 30, 31))) > 0)
    with pytest.raises(ValueError, match="reduced time"):
        wagner(-1.0)
