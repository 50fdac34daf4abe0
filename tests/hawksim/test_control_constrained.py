"""The constrained LQR (hawksim.control.constrained; docs/control.md "Gusts: the constrained LQR, the surrogate's
envelope and the UVLM"): its channels and Table 2 box, its per-wing derivatives against the seven-channel model, the
plan equal to the LQR where no bound is active and no worse than the clipped LQR where one is, and the gust it
rejects with the per-step surrogate where the per-beat LQR does not."""

import subprocess
import sys

import numpy as np
import pytest

from hawksim.control.closed_loop import Gust, body_length, fly_closed_loop
from hawksim.control.constrained import (WING_INPUTS, ConstrainedSchedule, channel_bounds, constrained_gain,
                                         linearize_wings, wing_channels, wing_params)
from hawksim.control.plant import INPUTS
from hawksim.control.schedule import Schedule
from hawksim.flight.orbit import shipped_orbit
from hawksim.insect.kinematics import bounds_si

FD_TOL = 5e-3
"""Per-wing against seven-channel derivatives (normalized entries up to ~1.4): both are central differences of
step 1e-3 of the float32 network, whose round-off and truncation are ~4e-4 and ~2e-4 per entry
(hawksim.control.derivatives.SURROGATE_FD_DELTA); sums of two columns double that."""

L = body_length()


@pytest.fixture(scope="module")
def sched2():
    return ConstrainedSchedule(2.0, 2.0, aero="surrogate", speeds=(2.0,))


def test_channels_round_trip_and_keep_the_wings_inside_table2():
    kin = shipped_orbit(1.0, "surrogate").kinematics
    v = np.array([0.02, 0.01, -0.03, 0.02, 0.005, -0.01, -0.02, -0.04])
    left, right = wing_params(kin, v)
    assert np.allclose(wing_channels(kin, left, right), v, rtol=0, atol=1e-15)
    lo, hi = bounds_si()
    lb, ub = channel_bounds(kin)
    assert abs(ub[6]) < 1e-6 and abs(ub[7]) < 1e-6 and lb[6] < -0.1  # phi_a on 60 deg: each wing can only lower it
    for corner in (lb, ub):
        for p in wing_params(kin, corner):
            assert np.all(p >= lo - 1e-12) and np.all(p <= hi + 1e-12)
    lb, ub = channel_bounds(kin, held=("theta0",), envelope=0.025)
    assert lb[5] == ub[5] == 0
    assert ub[1] == pytest.approx(0.025 * np.deg2rad(50.0))


def test_per_wing_derivatives_match_the_seven_channel_model(sched2):
    """A symmetric command moves both wings (B_sym = B_left + B_right), an antisymmetric one half each way
    (B_anti = (B_left - B_right) / 2): the per-wing columns, differenced anew, reproduce the shipped seven-channel
    columns of the parameters off the bounds (f, phi0, alpha0 and their differences)."""
    p = sched2.points[0]
    w = sched2.wing_models[2.0]
    i = {k: j for j, k in enumerate(WING_INPUTS)}
    for B7, Bw in ((p.model.B1, w.B1), (p.model.B0, w.B0)):
        pairs = {"f": Bw[:, i["f"]], "phi0": Bw[:, i["phi0_l"]] + Bw[:, i["phi0_r"]],
                 "alpha0": Bw[:, i["alpha0_l"]] + Bw[:, i["alpha0_r"]],
                 "dphi0": (Bw[:, i["phi0_l"]] - Bw[:, i["phi0_r"]]) / 2,
                 "dalpha0": (Bw[:, i["alpha0_l"]] - Bw[:, i["alpha0_r"]]) / 2}
        for name, col in pairs.items():
            ref = B7[:, INPUTS.index(name)]
            assert np.abs(col - ref).max() < FD_TOL, name
            assert np.abs(ref).max() > 10 * FD_TOL  # a column that matters


PLAN_LQR_TOL = 1e-6
"""The condensed horizon's unconstrained first move against the LQR's -K z, relative to the largest entry of K z: the
same optimum by two routes (a Cholesky-condensed least squares with cond ~7e4 and the DARE), equal to round-off.
Measured on hawksim 0.3.0's 2 m/s model 4e-8 (one BLAS thread) and 1e-7 (several; per entry up to 1.2e-6 of the
smallest, 5 % of the largest, which is why the bound is on the vector's scale, not per entry)."""


def test_the_plan_is_the_lqr_where_no_bound_is_active(sched2):
    g = sched2.constrained[2.0]
    rng = np.random.default_rng(0)
    z = np.zeros(g.Az.shape[0])
    z[:11] = 0.01 * rng.standard_normal(11)
    wide = np.full(8, 10.0)
    v, active = g.command(z, -wide, wide)
    assert not active
    assert np.allclose(v, -g.K @ z, rtol=0, atol=1e-14)
    # the condensed problem's unconstrained optimum starts with the LQR's move (terminal cost P from the DARE)
    V = np.linalg.solve(g.M, -g.Mz @ z)
    assert np.abs(V[:8] + g.K @ z).max() <= PLAN_LQR_TOL * np.abs(g.K @ z).max()


def test_the_plan_respects_the_bounds_and_costs_no_more_than_the_clipped_lqr(sched2):
    """A gust-sized state (roll rate and bank of the 0.5 m/s gust's first beat): the plan stays in the box and its
    horizon cost is below that of flying the LQR clipped at the box (the per-beat LQR's way)."""
    g = sched2.constrained[2.0]
    kin = sched2.points[0].orbit.kinematics
    lb, ub = channel_bounds(kin, held=("theta0",))
    z = np.zeros(g.Az.shape[0])
    z[[1, 3, 5, 6]] = [-0.04, -0.15, 0.1, -0.03]  # v / U, p T, r T, phi
    v, active = g.command(z, lb, ub)
    assert active and np.all(v >= lb - 1e-12) and np.all(v <= ub + 1e-12)

    def cost(V):  # the horizon cost less a constant of z (hawksim.control.constrained.ConstrainedGain)
        return float(np.sum((g.M @ V + g.Mz @ z) ** 2))

    Vc, zk = [], z.copy()
    for _ in range(g.horizon):
        u = np.clip(-g.K @ zk, lb, ub)
        Vc.append(u)
        zk = g.Az @ zk + g.Bz @ u
    from scipy.optimize import lsq_linear

    free = ub - lb > 0
    Lb, Ub = np.tile(lb, g.horizon), np.tile(ub, g.horizon)
    f = np.tile(free, g.horizon)
    plan = np.zeros_like(Lb)
    plan[f] = lsq_linear(g.M[:, f], -g.Mz @ z, bounds=(Lb[f], Ub[f]), method="bvls").x
    assert np.allclose(plan[:8], v, atol=1e-12)
    clipped = np.concatenate(Vc)
    assert cost(plan) < cost(clipped) and np.abs(plan - clipped).max() > 1e-3  # the same cost up to a constant


def _recovered_after(beats, end):
    ok = [abs(b["speed_error"]) <= 0.02 and abs(b["pitch_error_deg"]) <= 2 and abs(b["roll_deg"]) <= 2
          and b["horizontal_drift_m"] < L for b in beats]
    k = next((beats[i]["beat"] for i in range(len(ok)) if all(ok[i:])), None)
    return None if k is None else max(0, k - end)


def test_the_constrained_lqr_rejects_a_gust_the_lqr_does_not(sched2):
    """0.15 m/s lateral gust over beats 5-6 at 2 m/s with the per-step surrogate: the constrained LQR stays within
    the bounds throughout (measured: roll at most 1.7 deg), the per-beat LQR departs (measured: speed error -0.11 m/s at
    beat 20, -2.5 at 30). hawksim 0.3.0's network at 2 m/s is less forgiving than 0.2's, whose 0.2 m/s gust this test
    flew (the per-beat LQR recovered it after 22 beats, the constrained one after 7, scripts/studies/
    control_constrained.py, 2026-12-02): now the per-beat LQR departs from a 0.1 m/s gust (0.05 m/s: recovered) and
    the constrained LQR from the 0.2 m/s one (next test)."""
    gust = [Gust(np.array([0.0, 0.15, 0.0]), 5, 2)]
    c = fly_closed_loop(2.0, 30, aero="surrogate", schedule=sched2, gusts=gust, control="clqr")
    lqr = fly_closed_loop(2.0, 30, aero="surrogate", schedule=Schedule(2.0, 2.0, aero="surrogate", speeds=(2.0,)),
                          gusts=gust)
    assert _recovered_after(c.beats, 6) <= 10
    k = _recovered_after(lqr.beats, 6)
    assert k is None or k > 10


@pytest.mark.xfail(strict=True, reason="hawksim 0.3.0 regression, measured 2026-12-07: the constrained LQR does not "
                   "recover the 0.2 m/s lateral gust at 2 m/s (pitch and roll errors of 2-6 deg through beat 35, "
                   "departs at beat ~45; holding theta0 at the orbit's value it recovers after 20 beats), which it "
                   "recovered after 7 with hawksim 0.2's network")
def test_the_constrained_lqr_rejects_the_0_2_m_s_gust(sched2):
    """Issue 20's constrained-LQR result of hawksim 0.2 (0.2 m/s lateral gust over beats 5-6 at 2 m/s, recovered
    within 10 beats after it), kept as the target the regenerated network misses."""
    gust = [Gust(np.array([0.0, 0.2, 0.0]), 5, 2)]
    c = fly_closed_loop(2.0, 30, aero="surrogate", schedule=sched2, gusts=gust, control="clqr")
    k = _recovered_after(c.beats, 6)
    assert k is not None and k <= 10


def test_clqr_on_the_cli_is_refused_with_the_uvlm():
    r = subprocess.run([sys.executable, "-m", "hawksim", "fly", "--aero", "uvlm", "--speed", "1", "--cycles", "2",
                        "--control", "clqr"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1 and "--control clqr" in r.stderr


def test_linearize_wings_refuses_a_uvlm_orbit():
    with pytest.raises(ValueError, match="settable state"):
        linearize_wings(shipped_orbit(1.0, "uvlm"))


def test_constrained_gain_with_a_delay_has_the_same_multipliers(sched2):
    """The delay-augmented state is exact, so the one-beat delay only adds zero multipliers (as the LQR's)."""
    w = sched2.wing_models[2.0]
    g0, g1 = constrained_gain(w, 0), constrained_gain(w, 1)
    big = lambda g: np.sort(np.abs(g.multipliers[np.abs(g.multipliers) > 1e-6]))  # noqa: E731
    assert g0.spectral_radius < 1 and g1.spectral_radius < 1
    assert g1.spectral_radius == pytest.approx(g0.spectral_radius, abs=0.05)
    assert len(big(g1)) >= len(big(g0))
