"""Perturbed nonlinear flights against the Floquet exponents (hawksim.stability.validation), quasi-steady, 1 m/s.

Measured (`hawksim reproduce --only validation`, results/free_flight/validation.json, docs/free_flight.md
"Perturbed nonlinear flights"): at 1 m/s the unstable longitudinal oscillation's fitted exponent is
0.3895+0.2299i against the Floquet 0.3888+0.2298i (0.15 %), at half the amplitude 0.3902+0.2301i (0.15 %
change); the stable longitudinal modes agree to < 1e-4. The issue's target is 5 %.
"""

import numpy as np
import pytest

from hawksim.flight.orbit import periodic_orbit
from hawksim.stability.floquet import monodromy
from hawksim.stability.validation import chart_map, fit_rate, validate_speed

TARGET = 0.05
"""Relative error |lambda_nl - lambda_floquet| / |lambda_floquet| of issue 19 (item 4)."""

HALVING_TOL = 0.01
"""Relative change of the fitted exponent when the amplitude is halved (measured 0.15 %)."""


def test_fit_rate_recovers_an_exponential():
    lam = complex(0.3, 0.2)
    a = 0.5 * np.exp(lam * np.arange(10))
    assert abs(fit_rate(a) - lam) < 1e-12


def test_chart_map_is_identity_at_hover():
    assert np.array_equal(chart_map("lateral", 0.0), np.eye(4))
    assert chart_map("longitudinal", 0.5)[0, 3] == 0.5 and chart_map("lateral", 0.5)[0, 3] == -0.5


def test_unstable_modes_match_floquet_at_1m_s():
    o = periodic_orbit(1.0)
    fq = monodromy(o, lateral=False)
    A = {"longitudinal": np.zeros((4, 4))}  # the averaged model is not under test here
    r = validate_speed(o, fq, A, systems=("longitudinal",), modes="unstable", state_flights=False)
    modes = r["systems"]["longitudinal"]["modes"]
    assert modes and all(m["abs_multiplier"] > 1 for m in modes)
    for m in modes:
        assert m["rel_error_nonlinear_vs_floquet"] < TARGET, m
        assert m["rel_error_imag_part_vs_floquet"] < TARGET, m
        assert m["halving"]["rel_change"] < HALVING_TOL, m
        assert m["fit_beats"] >= 10, m


def test_reach_separates_a_direction_the_launches_barely_reach():
    from hawksim.stability.floquet import REACH_MIN, reach

    A = np.diag([2.0, 1.0, 0.5, 1e-3])  # the warm-up beats damp the 4th direction 2000x
    V = np.eye(4, dtype=complex)
    V[:, 1] = (np.eye(4)[1] + 1j * np.eye(4)[2]) / np.sqrt(2)
    r = reach(A, V)
    assert r[0] == 1.0 and r[3] == 5e-4 and REACH_MIN < r[1] < 1.0
    assert [x >= REACH_MIN for x in r] == [True, True, True, False]


UVLM_LATERAL_2MS = 0.1186
"""Per wingbeat: the UVLM's unstable lateral exponent at 2 m/s (a divergence on the sourced hawkmoth) fitted from the
perturbed nonlinear flights (results/free_flight/validation.json, `hawksim reproduce --only validation_uvlm` on
hawksim 0.3: 0.11857; the monodromy gave 0.1185). hawksim 0.2's hawkmoth had an oscillation, 0.2296+0.1010i."""


@pytest.mark.slow
def test_uvlm_floquet_flags_the_wake_mode_and_keeps_the_flight_mode():
    """UVLM, 2 m/s: the lateral block has a real exponent 1.23 (|mu| 3.4) that no perturbed flight shows
    (the flights' fit there is the phase-locked 1.01+0.94i of a beat-to-beat oscillation, not this mode) beside the
    divergence the flights confirm (0.1185 against 0.1186); the reach test flags the first unresolved and keeps the
    second, within issue 19's 5 % of the flights."""
    from hawksim.flight.orbit import shipped_orbit

    o = shipped_orbit(2.0, "uvlm")
    if o is None or not o.converged:
        pytest.skip("no converged shipped UVLM orbit at 2 m/s")
    fq = monodromy(o)
    ex, ok = fq.exponents_lat, fq.resolved_lat
    kept = [i for i in range(4) if ok[i] and ex[i].real > 0]
    assert kept, (ex, ok)
    assert min(abs(ex[i] - UVLM_LATERAL_2MS) for i in kept) <= TARGET * abs(UVLM_LATERAL_2MS)
    assert not all(ok), "the wake mode should be flagged unresolved"
    assert all(abs(ex[i]) < 1.0 for i in range(4) if ok[i])  # no resolved exponent near the spurious 1.23
    assert all(fq.resolved_long[:2])  # the two unstable longitudinal modes (0.926, 0.182) are resolved
