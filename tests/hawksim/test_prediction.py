"""`hawksim.stability.prediction`: the linear predictions of a perturbed flight (pure functions on synthetic data)
and, once, against a perturbed nonlinear flight from the 1 m/s quasi-steady orbit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.linalg import expm

from hawksim.flight.orbit import state_to_world
from hawksim.flight.result import FlightResult
from hawksim.frames import quat_from_matrices
from hawksim.stability import prediction as P
from hawksim.stability.validation import chart_map

EXACT_ATOL = 1e-12
"""Pure linear algebra against its closed form: round-off only."""

LINEAR_REL = 0.05
"""Relative (max-norm, normalized states) difference of the Floquet prediction from the nonlinear flight's
per-beat deviation over 3 beats (w = 0.01 m/s, phi = 0.5 deg at 1 m/s), relative to the largest deviation;
measured 3.4e-3 (nonlinearity and the quasi-steady load switch, docs/free_flight.md); the bound leaves room for
other platforms' round-off in the switch."""

GHOST_GAIN = 0.1
"""The ghost's largest position error from the nonlinear body, as a fraction of the unperturbed flight's; measured
0.027 over the same 3 beats."""


def test_launch_deviation_units():
    d = P.launch_deviation({"u": 0.1, "q": 90.0, "phi": 180.0})
    assert d[P.FLOQUET_NAMES.index("u")] == 0.1
    assert d[P.FLOQUET_NAMES.index("q")] == pytest.approx(np.pi / 2)
    assert d[P.FLOQUET_NAMES.index("phi")] == pytest.approx(np.pi)
    with pytest.raises(ValueError):
        P.launch_deviation({"psi": 1.0})


def test_floquet_prediction_scales():
    mu = np.linspace(0.5, 1.2, 8)
    scale = np.arange(1.0, 9.0)
    d0 = np.ones(8)
    out = P.floquet_prediction(np.diag(mu), d0, scale, 3)
    np.testing.assert_allclose(out, d0 * mu[None, :] ** np.arange(4)[:, None], atol=EXACT_ATOL)
    # a coupling entry acts on the normalized states: d_1[0] = s0 M01 d0[1] / s1
    M = np.eye(8)
    M[0, 1] = 2.0
    assert P.floquet_prediction(M, np.eye(8)[1], scale, 1)[1, 0] == pytest.approx(2.0 * scale[0] / scale[1])


def test_averaged_prediction_chart_and_expm():
    rng = np.random.default_rng(1)
    A_long, A_lat = 0.3 * rng.normal(size=(4, 4)), 0.3 * rng.normal(size=(4, 4))
    scale = np.array([2.0, 2.0, 2.0, 30.0, 30.0, 30.0, 1.0, 1.0])
    d0 = rng.normal(size=8) * scale
    V_over_U = 0.4
    out = P.averaged_prediction(A_long, A_lat, d0, scale, 4, V_over_U)
    for name, A, idx in (("longitudinal", A_long, P.LONG), ("lateral", A_lat, P.LAT)):
        T = chart_map(name, V_over_U)
        for k in range(5):
            want = np.linalg.solve(T, expm(A * k) @ T @ (d0[list(idx)] / scale[list(idx)])) * scale[list(idx)]
            np.testing.assert_allclose(out[k, list(idx)], want, atol=1e-10)
    np.testing.assert_allclose(P.averaged_prediction(0 * A_long, 0 * A_lat, d0, scale, 2, V_over_U),
                               np.tile(d0, (3, 1)), atol=EXACT_ATOL)


def test_neutral_prediction_accumulates():
    J = np.zeros((4, 8))
    J[0, 5] = 2.0  # heading change per beat per normalized r
    J[3, 2] = -1.0  # world z displacement per beat per normalized w (down)
    scale = np.ones(8)
    d = np.zeros((4, 8))
    d[:, 5] = [0.1, 0.2, 0.3, 0.4]
    d[:, 2] = 0.5
    n = P.neutral_prediction(J, d, scale)
    np.testing.assert_allclose(n[:, 0], [0.0, 0.2, 0.6, 1.2], atol=EXACT_ATOL)
    np.testing.assert_allclose(n[:, 3], [0.0, -0.5, -1.0, -1.5], atol=EXACT_ATOL)


def synthetic_flight(chi=1.0, n=40, spc=10, dt=1e-3) -> FlightResult:
    """A body climbing at 1 m/s with a pitch oscillation, states set through the orbit's chart."""
    t = dt * np.arange(n)
    x = np.zeros((n, 9))
    x[:, 2] = -1.0
    x[:, 7] = chi + 0.1 * np.sin(2 * np.pi * t / (spc * dt))
    R = np.array([state_to_world(xx, chi)[0] for xx in x])
    v = np.array([state_to_world(xx, chi)[1] for xx in x])
    pos = np.stack([0 * t, 0 * t, t], axis=1)
    z = np.zeros((n, 2, 3))
    return FlightResult(speed_target=1.0, cycles=n // spc, aero="quasi-steady", kinematics=None,
                        steps_per_cycle=spc, t=t, body_pos=pos, body_quat=quat_from_matrices(R), body_v=v,
                        body_omega=np.zeros((n, 3)), wing_R=np.tile(np.eye(3), (n, 2, 1, 1)), wing_origin=z,
                        force=z, moment=np.zeros((n, 3)), power_aero=np.zeros(n), power_joint=np.zeros(n),
                        wall_time_s=0.0)


def test_ghost_pose_adds_the_deviation():
    chi = 1.0
    ref = synthetic_flight(chi)
    nb = len(ref.t) // ref.steps_per_cycle
    zero = np.zeros((nb + 1, 8))
    pos, quat = P.ghost_pose(ref, zero, np.zeros((nb + 1, 4)), chi)
    np.testing.assert_allclose(pos, ref.body_pos, atol=EXACT_ATOL)
    np.testing.assert_allclose(np.abs((quat * ref.body_quat).sum(1)), 1.0, atol=1e-12)
    # theta and phi deviations growing linearly per beat, heading and position from the neutral part
    d = zero.copy()
    d[:, 7] = 0.01 * np.arange(nb + 1)
    d[:, 6] = 0.02 * np.arange(nb + 1)
    neutral = np.zeros((nb + 1, 4))
    neutral[:, 0] = 0.03 * np.arange(nb + 1)
    neutral[:, 2] = 0.001 * np.arange(nb + 1)
    pos, quat = P.ghost_pose(ref, d, neutral, chi)
    ghost = dataclasses.replace(ref, body_pos=pos, body_quat=quat)
    xg, xr = P.flight_states(ghost, chi), P.flight_states(ref, chi)
    k = ref.t / (ref.steps_per_cycle * (ref.t[1] - ref.t[0]))  # beats, fractional
    np.testing.assert_allclose(xg[:, 7] - xr[:, 7], 0.01 * k, atol=1e-9)
    np.testing.assert_allclose(xg[:, 6] - xr[:, 6], 0.02 * k, atol=1e-9)
    np.testing.assert_allclose(xg[:, 8] - xr[:, 8], 0.03 * k, atol=1e-9)
    np.testing.assert_allclose(pos[:, 1] - ref.body_pos[:, 1], 0.001 * k, atol=1e-12)


@pytest.fixture(scope="module")
def perturbed():
    from hawksim.cli.fly import fly_named
    from hawksim.flight.orbit import shipped_orbit

    perturb = {"w": 0.01, "phi": 0.5}
    orbit = shipped_orbit(1.0, "quasi-steady")
    res = fly_named(1.0, 3, perturb=perturb)
    return res, perturb, orbit, P.predict_flight(res, perturb, orbit)


def test_prediction_follows_the_nonlinear_flight(perturbed):
    from hawksim.stability.floquet import state_scale

    res, perturb, orbit, pred = perturbed
    sc = state_scale(orbit.kinematics)
    assert pred.nonlinear.shape == (3, 8) and pred.floquet.shape == (4, 8) and pred.averaged.shape == (4, 8)
    np.testing.assert_allclose(pred.nonlinear[0], P.launch_deviation(perturb), atol=1e-12)
    nl, fq = pred.nonlinear / sc, pred.floquet[:3] / sc
    rel = np.abs(nl - fq).max() / np.abs(nl).max()
    assert rel < LINEAR_REL, rel
    # the ghost stands closer to the nonlinear body than the unperturbed flight does
    err_ghost = np.abs(pred.ghost_pos - res.body_pos).max()
    err_ref = np.abs(pred.reference.body_pos - res.body_pos).max()
    assert err_ghost < GHOST_GAIN * err_ref, (err_ghost, err_ref)


def test_no_prediction_reasons(perturbed):
    res = perturbed[0]
    with pytest.raises(P.NoPrediction, match="uvlm"):
        P.predict_cli_flight(res, {"w": 0.01}, speed=1.0, aero="uvlm")
    with pytest.raises(P.NoPrediction, match="periodic orbit"):
        P.predict_cli_flight(dataclasses.replace(res, trim_source="given"), {"w": 0.01}, speed=1.0,
                             aero="quasi-steady")
    with pytest.raises(P.NoPrediction, match="no perturbation"):
        P.predict_cli_flight(res, {"w": 0.0}, speed=1.0, aero="quasi-steady")
