"""Eq. 1 kinematics, the rotation-angle reading of docs/conventions.md, Table 2/3 data and the wing frames."""

import numpy as np
import pytest

from hawksim.insect.kinematics import (
    MIRROR,
    PARAM_NAMES,
    R_BODY_STROKE,
    TABLE2_BOUNDS_DEG,
    Kinematics,
    bounds_si,
    table3_kinematics,
    wing_rotation_body,
    wing_rotation_stroke,
)

KIN = Kinematics.from_edge(dict(f=26.5, beta=1.5, phi0=-5.5, theta0=15.8, alpha0=0.7, phi_a=60, alpha_a=66.9))
T = KIN.period


def test_eq1_sweep_and_rotation_phases():
    # Eq. 1 as printed for phi: phi_a sin(2 pi f t + 3 pi/2) + phi_0
    t = np.linspace(0, 2 * T, 101)
    phi, theta, alpha = KIN.angles(t)
    np.testing.assert_allclose(phi, KIN.phi_a * np.sin(2 * np.pi * KIN.f * t + 1.5 * np.pi) + KIN.phi0, atol=1e-12)
    np.testing.assert_allclose(theta, KIN.theta0)
    # rotation: 90 deg (+ alpha0) at stroke reversal (t = 0, T/2), extremes at mid-stroke (T/4, 3T/4)
    rev = KIN.angles(np.array([0.0, T / 2]))[2]
    np.testing.assert_allclose(rev, np.pi / 2 + KIN.alpha0, atol=1e-12)
    mid = KIN.angles(np.array([T / 4, 3 * T / 4]))[2]
    np.testing.assert_allclose(mid, np.pi / 2 + KIN.alpha0 + np.array([-1, 1]) * KIN.alpha_a, atol=1e-12)


def _geometric_aoa(t):
    """Angle between the chord (toward the leading edge) and the velocity of the span axis, stroke frame."""
    from hawksim.frames import cross

    phi, theta, alpha = KIN.angles(t)
    R = wing_rotation_stroke(phi, theta, alpha, side="left")
    omega = -KIN.rates(t)[0] * np.array([0.0, 0.0, 1.0])  # left-wing sweep is a rotation about -z_s
    v = cross(omega, R[:, 1])
    return np.degrees(np.arccos(R[:, 0] @ v / np.linalg.norm(v)))


def test_mid_stroke_angle_of_attack_is_90_minus_alpha_a():
    # docs/conventions.md: geometric AoA at mid-stroke = 90 deg - alpha_a; alpha0 raises it on the downstroke and
    # lowers it on the upstroke. The wing leads with its leading edge on both half strokes.
    a_deg, a0 = np.degrees(KIN.alpha_a), np.degrees(KIN.alpha0)
    assert _geometric_aoa(T / 4) == pytest.approx(90 - a_deg + a0, abs=1e-9)
    assert _geometric_aoa(3 * T / 4) == pytest.approx(90 - a_deg - a0, abs=1e-9)
    assert KIN.rates(T / 4)[0] > 0 > KIN.rates(3 * T / 4)[0]  # downstroke sweeps toward the head


def test_rates_and_accelerations_are_derivatives():
    t = np.linspace(0, T, 37)
    h = 1e-7
    np.testing.assert_allclose(KIN.rates(t), (KIN.angles(t + h) - KIN.angles(t - h)) / (2 * h), atol=1e-4)
    np.testing.assert_allclose(KIN.accelerations(t), (KIN.rates(t + h) - KIN.rates(t - h)) / (2 * h), atol=1)


def test_body_angle_and_stroke_plane():
    assert np.degrees(KIN.chi) == pytest.approx(58.5)  # Table 3: chi = 58.5 deg at beta = 1.5 deg
    # with the body pitched nose-up by chi, the stroke plane normal is tilted forward by beta
    from hawksim.frames import rot_y

    normal_world = rot_y(-KIN.chi) @ R_BODY_STROKE[:, 2]
    assert np.degrees(np.arctan2(normal_world[0], normal_world[2])) == pytest.approx(np.degrees(KIN.beta))


def test_left_and_right_wings_are_mirror_images():
    t = np.linspace(0, T, 13)
    RL, RR = wing_rotation_body(KIN, t, "left"), wing_rotation_body(KIN, t, "right")
    np.testing.assert_allclose(RR, MIRROR @ RL @ MIRROR, atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(RR), 1.0)
    # spans point to either side: left tip at +y, right tip (local -y) at -y
    assert np.all((RL @ [0, 1, 0])[:, 1] > 0) and np.all((RR @ [0, -1, 0])[:, 1] < 0)


def test_table2_bounds_and_errors():
    lo, hi = bounds_si()
    assert lo.shape == (7,) and np.all(lo < hi)
    assert lo[0] == 15 and hi[0] == 40 and hi[5] == pytest.approx(np.radians(60))
    good = {k: (a + b) / 2 for k, (a, b) in TABLE2_BOUNDS_DEG.items()}
    assert Kinematics.from_edge(good).to_edge() == pytest.approx(good)
    with pytest.raises(ValueError, match="alpha_a=80"):
        Kinematics.from_edge({**good, "alpha_a": 80})
    with pytest.raises(ValueError, match="unknown"):
        Kinematics.from_edge({**good, "gamma": 1})
    with pytest.raises(ValueError, match="missing"):
        Kinematics.from_edge({k: v for k, v in good.items() if k != "f"})
    with pytest.raises(ValueError, match="not finite"):
        Kinematics(*([float("nan")] + [0.0] * 6))
    assert list(PARAM_NAMES) == list(Kinematics.__dataclass_fields__)


def test_table3_interpolation():
    k = table3_kinematics(0.75)  # halfway between 0.5 and 1.0 m/s (Table 3: 27.9 and 29.4 Hz)
    assert k.f == pytest.approx(28.65)
    assert np.degrees(k.alpha_a) == pytest.approx((66.5 + 65.0) / 2)
    with pytest.raises(ValueError, match="speed 2.5"):
        table3_kinematics(2.5)
