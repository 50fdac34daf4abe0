"""Held-body cycle averages (the paper's setting) with the quasi-steady backend."""

import numpy as np
import pytest

from hawksim.backends.base import NoAero
from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import HAWKMOTH

INERTIAL_MEAN_TOL = 1e-9
"""Cycle mean of the wings' inertial power in vacuum as a fraction of its peak: zero for periodic kinetic energy;
what is left is the quadrature of the 400-step beat and round-off. Source of 1e-9 not recorded; measured
5.4e-17."""

VACUUM_POWER_RTOL = 1e-12
"""Relative: P+ in vacuum vs the mean positive part of the inertial power / 84.2 mW: the same float64 sum;
measured: exact (0)."""

NEAR_TRIM_TOL = 0.1
"""|D+| and |M+| of Table 3's kinematics (the paper's UVLM trim) on the quasi-steady model: 'nearly a trim'. A
round bound, not derived; measured at most 0.059 (M+ at hover)."""

QS_LIFT_RANGE = (1.0, 1.6)
"""L+ of Table 3's kinematics on the quasi-steady model: above the paper's UVLM value (0.97 at hover, Table 4),
since Dickinson et al.'s coefficients lift more than a UVLM; the upper end is a round bound.
Measured 1.38 (2 m/s) to 1.46 (hover) on the sourced hawkmoth (feathering axis 0.06 of the chord: more rotational
lift than hawksim 0.2's quarter-chord axis, which gave 1.15 to 1.26)."""

CYCLE_RTOL = 1e-2
"""Relative: L+ of beat 1 vs beat 2 (quasi-steady: periodic after the first step); measured 7.9e-6."""

HOLD_SPEED_TOL = 0.1
"""m/s: beat-mean ascent speed vs 1 m/s over 3 free beats from the shipped quasi-steady trim (the free body's
recoil costs lift, docs/free_flight.md). Measured largest deviation 0.040 m/s (hawksim 0.2: 0.072)."""

HOLD_PITCH_TOL_DEG = 2.5
"""deg: beat-mean body angle vs chi over the first 2 beats; measured 0.48 and 2.09 deg on the sourced hawkmoth (the
third beat 5.26 deg: the held-body trim is not the free body's orbit and the pitch mode is unstable, |mu| 1.55 a beat;
hawksim 0.2's hawkmoth stayed within 0.49 deg for 3 beats)."""


def test_inertial_power_is_periodic_and_aero_power_positive():
    kin = table3_kinematics(0.0)
    r = held_flight(kin, 0.0, NoAero(), cycles=1, steps_per_cycle=400)
    # the wings' kinetic energy is periodic: the cycle mean of the inertial power vanishes
    peak = np.abs(r.power_inertial).max()
    assert peak > 1e-3  # tens of mW peak: hawkmoth wings are heavy (Berman & Wang 2007)
    assert abs(r.power_inertial.mean()) < INERTIAL_MEAN_TOL * peak
    # in vacuum, the required power is the positive part of the inertial power
    assert r.averages.P_plus == pytest.approx(np.maximum(r.power_inertial, 0).mean() / 84.2e-3, rel=VACUUM_POWER_RTOL)
    assert r.averages.L_plus == 0


def test_table3_is_nearly_a_trim_for_the_quasi_steady_model():
    """Table 3 (the paper's UVLM trim) flown on our quasi-steady model: D+ and M+ near zero, L+ above the
    paper's UVLM value (0.97 at hover, Table 4): Dickinson et al.'s coefficients give more lift than a UVLM."""
    for V in (0.0, 1.0, 2.0):
        r = held_flight(table3_kinematics(V), V, QuasiSteadyBackend(), cycles=2, steps_per_cycle=100)
        a = r.averages
        assert abs(a.D_plus) < NEAR_TRIM_TOL and abs(a.M_plus) < NEAR_TRIM_TOL
        assert QS_LIFT_RANGE[0] < a.L_plus < QS_LIFT_RANGE[1]
        # the two cycles agree (quasi-steady: periodic after the first step)
        assert r.per_cycle[0].L_plus == pytest.approx(r.per_cycle[1].L_plus, rel=CYCLE_RTOL)
    # P+ grows with the ascent speed (Table 4: 0.86 -> 1.34 from 0 to 2 m/s)
    P = [held_flight(table3_kinematics(V), V, QuasiSteadyBackend(), cycles=1, steps_per_cycle=100).averages.P_plus
         for V in (0.0, 1.0, 2.0)]
    assert P[0] < P[1] < P[2]


def test_lift_and_weight_scales():
    assert HAWKMOTH.weight == pytest.approx(1578.7e-6 * 9.81)
    with pytest.raises(ValueError, match="speed"):
        held_flight(table3_kinematics(0.0), -1.0, NoAero())


def test_quasi_steady_trim_holds_over_three_wingbeats():
    """From the shipped quasi-steady trim (insects/hawkmoth/data/trim_table_quasi_steady.json, balanced held-body to
    |L+ - 1|, |D+|, |M+| <= 0.01) the free flight keeps its ascent speed within 0.1 m/s for 3 beats and its
    cycle-mean body angle within 2.5 deg of chi for 2. (The free body's recoil costs lift: the speed falls ~0.02 m/s
    per beat, see docs/free_flight.md; a free flight that holds for many beats starts from the periodic orbit.)"""
    from hawksim.cli.fly import fly_named

    r = fly_named(1.0, 3, start="trim")
    assert "quasi-steady balance" in r.trim_source
    n = r.steps_per_cycle
    z, pitch = r.body_pos[:, 2], np.degrees(r.pitch())
    for c in range(3):
        s = slice(c * n, (c + 1) * n)
        assert (z[s][-1] - z[s][0]) / (r.t[s][-1] - r.t[s][0]) == pytest.approx(1.0, abs=HOLD_SPEED_TOL)
        if c < 2:
            assert pitch[s].mean() == pytest.approx(np.degrees(r.kinematics.chi), abs=HOLD_PITCH_TOL_DEG)
