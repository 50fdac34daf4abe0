"""The balance step of the trim (hawksim.trim.balance), exercised on the fast quasi-steady model."""

import pytest

from hawksim.backends.held import evaluate
from hawksim.backends.resolution import Resolution
from hawksim.insect.kinematics import table3_kinematics
from hawksim.trim.balance import balance_on_uvlm

QS = Resolution(aero="quasi-steady", steps_per_cycle=60, cycles=2)

BALANCE_TOL = 0.005
"""|L+ - 1|, |D+|, |M+|: the tolerance the balance is asked for, and that an independent re-evaluation must meet
(the same deterministic computation). The value is a choice of the test; its source is not recorded."""


def test_balance_reaches_the_tolerance_and_keeps_the_other_parameters():
    kin0 = table3_kinematics(1.0)
    r = balance_on_uvlm(kin0, 1.0, QS, tol=BALANCE_TOL)
    assert r.converged and r.evaluations <= 20
    a = evaluate(r.kinematics, 1.0, QS)  # independent re-evaluation
    assert abs(a.L_plus - 1) <= BALANCE_TOL and abs(a.D_plus) <= BALANCE_TOL and abs(a.M_plus) <= BALANCE_TOL
    # the quasi-steady model lifts 1.21 W at Table 3 (test_held): the balance lowers f
    assert r.kinematics.f < kin0.f
    for k in ("theta0", "phi_a", "alpha_a"):
        assert getattr(r.kinematics, k) == pytest.approx(getattr(kin0, k))


def test_a_stalled_balance_restarts_from_its_best_point():
    """With too few evaluations for the first pass (max_evals=6: the 4-run Jacobian and 1 step), the restart from
    the best point reaches the tolerance; the result counts both passes and keeps the original start."""
    kin0 = table3_kinematics(1.0)
    no_restart = balance_on_uvlm(kin0, 1.0, QS, tol=BALANCE_TOL, max_evals=6, restarts=0)
    assert not no_restart.converged and no_restart.evaluations == 6
    r = balance_on_uvlm(kin0, 1.0, QS, tol=BALANCE_TOL, max_evals=6)
    assert r.converged and 6 < r.evaluations <= 26
    assert r.start.kinematics == kin0
    a = evaluate(r.kinematics, 1.0, QS)
    assert max(abs(a.L_plus - 1), abs(a.D_plus), abs(a.M_plus)) <= BALANCE_TOL
