"""Biot-Savart kernel against a direct numpy evaluation of the classical straight-segment formula
(Katz & Plotkin 2001, Eq. 10.115) and the core model's far-field limit."""

import numpy as np
import pytest

from aero.biot_savart import aligned_scratch, ring_influence, segment_velocity

CLASSICAL_RTOL = 1e-11
"""Singular kernel vs the direct numpy evaluation of K&P Eq. 10.115, relative per component (dimensionless). Two
float64 evaluations of the same formula in another order: round-off only. Measured: 3.5e-12 at worst, on components
far below the largest (the absolute error is 8.9e-16 of a largest velocity 6.3, i.e. 1.4e-16 relative to it)."""

CLASSICAL_ATOL = 1e-12
"""Same comparison, absolute part as a fraction of the largest velocity (covers components that cancel to near
zero). Float64 round-off (eps 2.2e-16) over ~150 summed segments; measured 1.4e-16 of the largest velocity."""

FAR_FIELD_RTOL = 1e-9
"""Cored kernel (rc = 1e-3) vs the singular one at 50x the sample distance, relative (dimensionless). The Scully
factor there differs from 1 by rc^2/h^2 ~ 1e-10. np.allclose's default atol = 1e-8 also applies, and the velocities
are <= 2.3e-5, so the check is in effect absolute; measured: largest difference 4.4e-14 (5e-9 relative on the
smallest components)."""

SCULLY_RTOL = 1e-12
"""Cored velocity inside the core vs the singular value times the Scully factor h^2/(rc^2+h^2), relative. The
same closed form evaluated two ways: float64 round-off; measured 1.8e-16."""

RING_RTOL = 1e-10
"""ring_influence's normal-velocity coefficients vs the summed segment kernel dotted with the normal, relative.
Same kernel, other summation order: round-off; measured 2.2e-12 at worst (on near-zero coefficients)."""

RING_ATOL = 1e-13
"""Same comparison, absolute (velocity per unit circulation, 1/m; coefficients here are <= 0.06). Measured largest
difference 8e-17."""


def classical(a, b, g, p):
    """K&P Eq. 10.115: v = G/(4 pi) r1xr2/|r1xr2|^2 r0.(r1/|r1| - r2/|r2|), summed over segments."""
    out = np.zeros((len(p), 3))
    for k in range(len(g)):
        r0, r1, r2 = b[k] - a[k], p - a[k], p - b[k]
        c = np.cross(r1, r2)
        k_ = g[k] / (4 * np.pi * (c * c).sum(1)) * (r1 @ r0 / np.linalg.norm(r1, axis=1)
                                                    - r2 @ r0 / np.linalg.norm(r2, axis=1))
        out += k_[:, None] * c
    return out


def _random(n, m, rc, seed=0):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, 3))
    b = a + 0.3 * rng.normal(size=(n, 3))
    g = rng.normal(size=n)
    p = rng.normal(size=(m, 3)) * 2.0
    return (a, b, g, np.full(n, rc * rc)), a, b, g, p


def induced_velocity(seg, p):
    return segment_velocity(p, *seg)


def test_singular_kernel_matches_classical_formula():
    seg, a, b, g, p = _random(150, 203, 0.0)     # 203 targets: several parallel blocks and a remainder
    v = induced_velocity(seg, p)
    ref = classical(a, b, g, p)
    assert np.allclose(v, ref, rtol=CLASSICAL_RTOL, atol=CLASSICAL_ATOL * np.abs(ref).max())


def test_core_tends_to_singular_far_away_and_regularises_near():
    seg, a, b, g, p = _random(40, 50, 1e-3, seed=1)
    far = p * 50.0
    assert np.allclose(induced_velocity(seg, far), classical(a, b, g, far), rtol=FAR_FIELD_RTOL)
    # on the segment's axis (midpoint) and at its ends: zero, not inf/nan
    one = (np.zeros((1, 3)), np.array([[1.0, 0.0, 0.0]]), np.ones(1), np.full(1, 0.1 ** 2))
    pts = np.array([[0.5, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    assert np.array_equal(induced_velocity(one, pts), np.zeros((4, 3)))
    # inside the core the velocity is below the singular value: Scully factor h^2/(rc^2+h^2)
    h = 0.05
    v = induced_velocity(one, np.array([[0.5, 0.0, h]]))[0]
    vs = classical(one[0], one[1], one[2], np.array([[0.5, 0.0, h]]))[0]
    assert np.allclose(v, vs * h * h / (0.1 ** 2 + h ** 2), rtol=SCULLY_RTOL)


def test_zero_length_segment_gives_zero():
    z = np.ones((1, 3))
    seg = (z, z.copy(), np.ones(1), np.zeros(1))
    assert np.array_equal(induced_velocity(seg, np.array([[0.0, 0.3, 2.0], [1.0, 1.0, 1.0]])), np.zeros((2, 3)))


def test_ring_influence_consistent_with_kernel():
    rng = np.random.default_rng(2)
    corners = rng.normal(size=(5, 4, 3))
    p = rng.normal(size=(20, 3)) * 3
    n = rng.normal(size=(20, 3))
    A = np.empty((20, 5))
    ring_influence(p, n, corners, 1e-4, A)
    for l in range(5):
        a, b = corners[l], np.roll(corners[l], -1, axis=0)
        v = segment_velocity(p, a, b, np.ones(4), 1e-4)
        assert np.allclose(A[:, l], (v * n).sum(1), rtol=RING_RTOL, atol=RING_ATOL)


@pytest.mark.parametrize("size", [1, 7, 8, 209])
def test_aligned_scratch_is_six_disjoint_cache_line_aligned_arrays(size):
    arrays = aligned_scratch(size)
    assert len(arrays) == 6
    for j, a in enumerate(arrays):
        assert a.shape == (size,) and a.dtype == np.float64
        assert a.ctypes.data % 64 == 0  # 64-byte boundaries (docstring: 512-bit loads within one cache line)
        a[:] = j
    for j, a in enumerate(arrays):  # no array overwrote another
        assert np.all(a == j)
