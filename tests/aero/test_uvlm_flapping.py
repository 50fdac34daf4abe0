"""Flapping wings: mirror symmetry, power definition, hover lift, error handling."""

import numpy as np
import pytest

from aero.mesh import mirror_mesh, wing_mesh
from aero.uvlm import UVLM, FreeStream, UVLMConfig, run_prescribed
from aero.uvlm_kinematics import two_wing_motion

FREQ = 25.0

MIRROR_RTOL = 1e-9
"""Relative, per component: the mirrored one-wing solve vs the explicit two-wing solve (forces, circulations),
over the 0.4 beat before the wing meets its own wake. Mathematically identical solves, so round-off; margin for
its growth through the free wake (the reason the test stops before stroke reversal). Measured 4.6e-15."""

MIRROR_ATOL = 1e-12
"""Same comparison, absolute part as a fraction of the largest |force| (|circulation|): for components that
vanish. Measured 1.1e-15 of the largest."""

SYMMETRY_TOL = 1e-10
"""Total side force of the symmetric pair as a fraction of the peak |Fz|; roll and yaw moments as a fraction of
peak |Fz| x 0.05 m (the span). Vanish to round-off; measured 5.8e-16 (side force), 4.5e-16 (roll), 6.4e-16
(yaw)."""

POWER_RTOL = 1e-12
"""Relative: UVLM power vs -sum F . v of the load points from the prescribed motion, with and without a carrier
velocity. The same float64 sum (eps 2.2e-16 over ~32 elements); measured: exact (0)."""

HOVER_LIFT_RANGE_N = (1e-3, 5e-2)
"""N: last-cycle mean lift of the 25 Hz, 50 mm wing in hover must lie in this range: order 10 mN by the scale of
the wing (an order-of-magnitude plausibility band, not a measured bound). Measured 9.3e-3 N."""


def small_wing(nc=4, ns=8):
    """Elliptic-ish wing, 50 mm span, 20 mm max chord (hawkmoth-like scale)."""
    y = np.linspace(0, 0.05, ns + 1)
    c = 0.02 * np.sqrt(np.clip(1 - (y / 0.05) ** 2, 0, 1)) + 0.004
    return wing_mesh(y, 0.25 * c, -0.75 * c, nc)


def motion(steps_per_cycle=40, cycles=1.5):
    t = np.arange(int(steps_per_cycle * cycles) + 1) / (steps_per_cycle * FREQ)
    return (t,) + two_wing_motion(t, freq=FREQ)


PLANE = (np.zeros(3), np.array([0.0, 1.0, 0.0]))


def test_mirror_mode_equals_explicit_two_wings_and_symmetry():
    left = small_wing()
    # 16 steps (0.4 cycle): before stroke reversal, where the wing meets its own free wake and round-off
    # differences between the two (mathematically identical) solves grow chaotically
    t, R, o, v, w = motion(cycles=0.4)
    both = UVLM([left, mirror_mesh(left)], UVLMConfig())
    half = UVLM([left], UVLMConfig())
    dt = t[1] - t[0]
    fy, mx, mz, fz = [], [], [], []
    for k in range(t.size):
        a = both.step(dt, R[k], o[k], v[k], w[k])
        b = half.step(dt, R[k, :1], o[k, :1], v[k, :1], w[k, :1], mirror_plane=PLANE)
        assert np.allclose(b.force[0], a.force[0], rtol=MIRROR_RTOL, atol=MIRROR_ATOL * np.abs(a.force).max())
        assert np.allclose(b.gamma[0], a.gamma[0], rtol=MIRROR_RTOL, atol=MIRROR_ATOL * np.abs(a.gamma).max())
        tot = a.force.sum(0)
        mom = a.moment(np.zeros(3)).sum(0)
        fy.append(tot[1])
        mx.append(mom[0])
        mz.append(mom[2])
        fz.append(abs(tot[2]))
    scale = max(fz)
    # total side force, roll and yaw moment of a symmetric pair vanish to round-off
    assert np.abs(fy).max() < SYMMETRY_TOL * scale
    assert np.abs(mx).max() < SYMMETRY_TOL * scale * 0.05 and np.abs(mz).max() < SYMMETRY_TOL * scale * 0.05


def test_power_is_minus_force_dot_panel_velocity():
    left = small_wing()
    t, R, o, v, w = motion(cycles=0.5)
    s = UVLM([left], UVLMConfig())
    dt = t[1] - t[0]
    powers = []
    for k in range(t.size - 1):  # stop just before stroke reversal
        r = s.step(dt, R[k, :1], o[k, :1], v[k, :1], w[k, :1], mirror_plane=PLANE)
        powers.append(r.power())
    assert np.mean(powers) > 0  # over the half stroke the flapping wing works on the air
    # independent velocities of the load points from the motion (rigid rotation about the hinge)
    p = r.element_point
    vel = np.cross(w[k, 0], p - o[k, 0])
    expected = -(r.element_force * vel).sum()
    assert r.power() == pytest.approx(expected, rel=POWER_RTOL)
    # relative to a carrier moving with v_ref the power changes by F . v_ref
    vref = np.array([0.3, -0.2, 1.0])
    assert r.power(v_ref=vref) == pytest.approx(expected + r.force[0] @ vref, rel=POWER_RTOL)


def test_hover_gives_positive_finite_lift():
    left = small_wing()
    t, R, o, v, w = motion(cycles=2.0)
    res = run_prescribed([left], UVLMConfig(), t, R[:, :1], o[:, :1], v[:, :1], w[:, :1],
                         mirror_plane=PLANE)
    assert np.all(np.isfinite(res.force))
    lift = res.force[-40:, 0, 2].mean()          # last cycle
    assert HOVER_LIFT_RANGE_N[0] < lift < HOVER_LIFT_RANGE_N[1]
    assert res.power[-40:].mean() > 0


def test_invalid_inputs_raise_value_error():
    left = small_wing()
    t, R, o, v, w = motion(cycles=0.25)
    s = UVLM([left], UVLMConfig())
    bad = v[0, :1].copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        s.step(t[1], R[0, :1], o[0, :1], bad, w[0, :1])
    with pytest.raises(ValueError, match="dt"):
        s.step(-1.0, R[0, :1], o[0, :1], v[0, :1], w[0, :1])
    with pytest.raises(ValueError, match="too coarse"):
        s.step(10 * (t[1] - t[0]) * 8, R[10, :1], o[10, :1], v[10, :1], w[10, :1])
    with pytest.raises(ValueError, match="too coarse"):
        run_prescribed([left], UVLMConfig(), t[::8], R[::8, :1], o[::8, :1], v[::8, :1], w[::8, :1])
    with pytest.raises(ValueError, match="non-finite"):
        run_prescribed([left], UVLMConfig(), t, R[:, :1], o[:, :1], v[:, :1] + np.inf, w[:, :1])
    with pytest.raises(ValueError):
        FreeStream(v0=np.array([np.nan, 0, 0]))


def test_injected_nan_raises_floating_point_error_naming_step():
    left = small_wing()
    t, R, o, v, w = motion(cycles=0.25)
    s = UVLM([left], UVLMConfig())
    dt = t[1] - t[0]
    for k in range(3):
        s.step(dt, R[k, :1], o[k, :1], v[k, :1], w[k, :1], mirror_plane=PLANE)
    s.wakes[0].gamma[1, 3] = np.nan              # corrupt the wake state
    with pytest.raises(FloatingPointError, match="step 3"):
        s.step(dt, R[3, :1], o[3, :1], v[3, :1], w[3, :1], mirror_plane=PLANE)
