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

ANGLE_ATOL = 1e-12
"""rad: Eq. 1's angles (sweep over two beats; rotation at reversal and mid-stroke) vs their closed form. The same
expression evaluated twice: round-off of sin at arguments up to ~17 rad (~17 eps = 4e-15); measured 2.0e-15."""

AOA_TOL_DEG = 1e-9
"""deg: geometric angle of attack at mid-stroke vs 90 - alpha_a +- alpha0 (docs/conventions.md). Exact in theory;
arccos of a float64 dot product, round-off; measured 3.2e-14."""

RATE_FD_ATOL = 1e-4
"""rad/s: KIN.rates vs a central difference with h = 1e-7 s. Round-off of the difference, eps |angle| / h
~ 3e-9, plus truncation h^2 |d3 angle/dt3| / 6 ~ 1e-8 (rates up to 194 rad/s); measured 1.2e-8: a wide bound."""

ACCEL_FD_ATOL = 1
"""rad/s^2: KIN.accelerations vs a central difference of the rates with h = 1e-7 s (accelerations up to 3.2e4).
Round-off eps |rate| / h ~ 4e-7 plus truncation h^2 |d4 angle/dt4| / 6 ~ 1e-6; measured 2.1e-6: a wide bound."""

ROTATION_ATOL = 1e-14
"""Right wing's rotation matrices vs MIRROR RL MIRROR (entries of order 1): the same products with signs flipped,
so round-off at most; measured: exact (0)."""


def test_eq1_sweep_and_rotation_phases():
    # Eq. 1 as printed for phi: phi_a sin(2 pi f t + 3 pi/2) + phi_0
    t = np.linspace(0, 2 * T, 101)
    phi, theta, alpha = KIN.angles(t)
    np.testing.assert_allclose(phi, KIN.phi_a * np.sin(2 * np.pi * KIN.f * t + 1.5 * np.pi) + KIN.phi0, atol=ANGLE_ATOL)
    np.testing.assert_allclose(theta, KIN.theta0)
    # rotation: 90 deg (+ alpha0) at stroke reversal (t = 0, T/2), extremes at mid-stroke (T/4, 3T/4)
    rev = KIN.angles(np.array([0.0, T / 2]))[2]
    np.testing.assert_allclose(rev, np.pi / 2 + KIN.alpha0, atol=ANGLE_ATOL)
    mid = KIN.angles(np.array([T / 4, 3 * T / 4]))[2]
    np.testing.assert_allclose(mid, np.pi / 2 + KIN.alpha0 + np.array([-1, 1]) * KIN.alpha_a, atol=ANGLE_ATOL)


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
    assert _geometric_aoa(T / 4) == pytest.approx(90 - a_deg + a0, abs=AOA_TOL_DEG)
    assert _geometric_aoa(3 * T / 4) == pytest.approx(90 - a_deg - a0, abs=AOA_TOL_DEG)
    assert KIN.rates(T / 4)[0] > 0 > KIN.rates(3 * T / 4)[0]  # downstroke sweeps toward the head


def test_rates_and_accelerations_are_derivatives():
    t = np.linspace(0, T, 37)
    h = 1e-7
    np.testing.assert_allclose(KIN.rates(t), (KIN.angles(t + h) - KIN.angles(t - h)) / (2 * h), atol=RATE_FD_ATOL)
    np.testing.assert_allclose(KIN.accelerations(t), (KIN.rates(t + h) - KIN.rates(t - h)) / (2 * h),
                               atol=ACCEL_FD_ATOL)


def test_motion_is_angles_rates_and_accelerations_bit_for_bit():
    """Kinematics.motion (the held-body loop's one call per step) equals the three array methods exactly, so the
    shipped held-body results do not change; a wrong row or sign fails it."""
    kin = table3_kinematics(1.0)
    for t in np.linspace(0.0, 3 * kin.period, 241):
        m = kin.motion(t)
        assert m.shape == (3, 3)
        assert np.array_equal(m[0], kin.angles(t))
        assert np.array_equal(m[1], kin.rates(t))
        assert np.array_equal(m[2], kin.accelerations(t))


def test_body_angle_and_stroke_plane():
    assert np.degrees(KIN.chi) == pytest.approx(58.5)  # Table 3: chi = 58.5 deg at beta = 1.5 deg
    # with the body pitched nose-up by chi, the stroke plane normal is tilted forward by beta
    from hawksim.frames import rot_y

    normal_world = rot_y(-KIN.chi) @ R_BODY_STROKE[:, 2]
    assert np.degrees(np.arctan2(normal_world[0], normal_world[2])) == pytest.approx(np.degrees(KIN.beta))


def test_left_and_right_wings_are_mirror_images():
    t = np.linspace(0, T, 13)
    RL, RR = wing_rotation_body(KIN, t, "left"), wing_rotation_body(KIN, t, "right")
    np.testing.assert_allclose(RR, MIRROR @ RL @ MIRROR, atol=ROTATION_ATOL)
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
