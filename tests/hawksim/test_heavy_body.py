"""A free flight with a very heavy body reproduces the held-body cycle averages (the loop's load coupling).

With the body's mass and inertia multiplied by ``HEAVY`` = 1e4 and gravity off, the body barely moves in a few
wingbeats (its velocity changes by ~ (W / (1e4 m)) 3 T ~ 1e-4 m/s, its attitude by ~ 1e-5 rad), so the free
flight started at the held-body attitude chi and ascent speed V sees the same wing motion relative to the air
as :func:`hawksim.backends.held.held_flight`, and its cycle-mean loads must be the held ones. This checks
:meth:`hawksim.flight.simulator.Simulator.step`'s hold of the backend's loads between updates (``aero_every > 1``):
holding them in the WING frame rotates the force with the wing over the hold (a bias of about
(aero_every - 1) dt / 2 mean(omega x F), -4 % in L+ for the UVLM at 1 m/s); holding them in the WORLD frame
reproduces the held run, whose loads are a zero-order hold at the backend's own rate.

Tolerances: L+, D+ within ``REL_TOL`` = 0.5 % of max(|L+|, 1) (D+ and L+ share the scale W: D+ is near zero,
so its error is measured on the weight scale), M+ within ``M_ABS_TOL`` = 0.005 absolute (M+ is near zero at the
trim, so a relative error is meaningless; 0.005 is 0.5 % of W cbar).

The required power P+ (cycle mean of max(0, P_aero + P_inertial) / P0) must match too (issue 48, item 5): with the
loads held between updates, the joint power of the steps in between pairs the update's load with a later wing
motion, and max(0, .) turns that lag into a bias (-2.7 % for the UVLM, -2.8 % quasi-steady); the flight's P+
samples the update steps only (:mod:`hawksim.flight.power`), which removes it. ``P_REL_TOL`` below.
"""

import pytest

from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.flight.heavy_body import CYCLES, heavy_free_flight
from hawksim.trim.tables import trim_kinematics

REL_TOL = 0.005
M_ABS_TOL = 0.005
P_REL_TOL = 0.005
"""Heavy-body free P+ against the held body's, relative: issue 48's 0.5 %. The bias it guards against (the
zero-order hold's lag inside max(0, .), ``sampling="steps"``) measured -2.8 % quasi-steady (0.9206 against 0.9475,
1 m/s, 200 steps, backend every 5) and -2.7 % UVLM (1.1035 against 1.1346); the update sampling gave 4e-5
quasi-steady, so 0.5 % is 5x below the bias and 100x above the fixed estimate's error."""


def heavy_free_averages(kin, speed, backend, *, steps_per_cycle, aero_every, cycles=CYCLES):
    """(L+, D+, M+) of :func:`heavy_free_flight`."""
    r = heavy_free_flight(kin, speed, backend, steps_per_cycle=steps_per_cycle, aero_every=aero_every, cycles=cycles)
    return r["L"], r["D"], r["M"]


def held_averages(kin, speed, backend, *, steps_per_cycle, cycles=CYCLES, power=False):
    """(L+, D+, M+) of the held body's last wingbeat (and P+ after them where ``power``)."""
    a = held_flight(kin, speed, backend, cycles=cycles, steps_per_cycle=steps_per_cycle).averages
    return (a.L_plus, a.D_plus, a.M_plus) + ((a.P_plus,) if power else ())


def _check(free, held):
    (Lf, Df, Mf), (Lh, Dh, Mh) = free, held
    scale = max(abs(Lh), 1.0)
    assert abs(Lf - Lh) <= REL_TOL * scale, (free, held)
    assert abs(Df - Dh) <= REL_TOL * scale, (free, held)
    assert abs(Mf - Mh) <= M_ABS_TOL, (free, held)


@pytest.mark.parametrize("aero_every", [1, 5])
def test_heavy_body_quasi_steady(aero_every):
    """Quasi-steady at 1 m/s: 200 integrator steps per beat, the backend every ``aero_every`` steps, against
    the held run at the backend's rate (200 / aero_every steps per beat)."""
    kin = trim_kinematics(1.0, "quasi-steady")
    free = heavy_free_averages(kin, 1.0, QuasiSteadyBackend(), steps_per_cycle=200, aero_every=aero_every)
    held = held_averages(kin, 1.0, QuasiSteadyBackend(), steps_per_cycle=200 // aero_every)
    _check(free, held)


def _check_power(free, held_P):
    """The update-sampled P+ within P_REL_TOL of the held body's."""
    assert abs(free["P_updates"] - held_P) <= P_REL_TOL * abs(held_P), (free, held_P)


@pytest.mark.parametrize("aero_every", [1, 5])
def test_heavy_body_power_quasi_steady(aero_every):
    """P+ of the heavy free flight (quasi-steady, 1 m/s, 200 steps, backend every ``aero_every``) against the held
    body at the backend's rate; with a hold (5) the every-step estimate must miss the tolerance (the bias this
    test exists for: it shows that the check can fail), without one (1) the two samplings are the same rows."""
    kin = trim_kinematics(1.0, "quasi-steady")
    free = heavy_free_flight(kin, 1.0, QuasiSteadyBackend(), steps_per_cycle=200, aero_every=aero_every)
    *_, held_P = held_averages(kin, 1.0, QuasiSteadyBackend(), steps_per_cycle=200 // aero_every, power=True)
    _check_power(free, held_P)
    if aero_every == 1:
        assert free["P_steps"] == free["P_updates"]
    else:
        assert abs(free["P_steps"] - held_P) > P_REL_TOL * abs(held_P), (free, held_P)


@pytest.mark.slow
def test_heavy_body_uvlm():
    """UVLM at the 1 m/s UVLM trim, `hawksim fly`'s coupling: 6 x 12 rings, 200 steps, backend every 5."""
    from hawksim.backends.uvlm import UVLMBackend

    kin = trim_kinematics(1.0, "uvlm")
    free = heavy_free_flight(kin, 1.0, UVLMBackend(n_chord=6, n_span=12), steps_per_cycle=200, aero_every=5)
    held = held_averages(kin, 1.0, UVLMBackend(n_chord=6, n_span=12), steps_per_cycle=40, power=True)
    _check((free["L"], free["D"], free["M"]), held[:3])
    _check_power(free, held[3])
    assert abs(free["P_steps"] - held[3]) > P_REL_TOL * abs(held[3]), (free, held)  # measured -3.0 %


@pytest.mark.slow
def test_heavy_body_power_surrogate():
    """The per-step surrogate (`hawksim fly --aero surrogate`'s coupling: the network in the native callback every
    5 of 200 steps) at the 1 m/s UVLM trim: its P+ against the held body's at 40 steps, and the every-step
    estimate misses it (measured -1.5 %; the update sampling 1.5e-5)."""
    from hawksim.backends.step_surrogate import StepSurrogateBackend

    kin = trim_kinematics(1.0, "uvlm")
    free = heavy_free_flight(kin, 1.0, StepSurrogateBackend(kin), steps_per_cycle=200, aero_every=5)
    *_, held_P = held_averages(kin, 1.0, StepSurrogateBackend(kin), steps_per_cycle=40, power=True)
    _check_power(free, held_P)
    assert abs(free["P_steps"] - held_P) > P_REL_TOL * abs(held_P), (free, held_P)
