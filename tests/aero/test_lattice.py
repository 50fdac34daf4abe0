"""The lattice Biot-Savart kernel (shared corners, divider-free 1/sqrt) against the per-segment kernel, which
tests/aero/test_biot_savart.py checks against Katz & Plotkin's Eq. 10.115."""

import numpy as np
from numba import njit

from aero.biot_savart import LATTICE_BLOCK, RSQRT_MIN, rsqrt, segment_velocity
from aero.lattice import Lattice, _fill, lattice_velocity, ring_lattice

ULP_TOL = 4
"""rsqrt's allowed error in units of the last place of the correctly rounded value. The Householder step takes the
float32 guess's ~1e-7 relative error to ~(5/2) d^3 ~ 3e-21, below float64 rounding, so only the roundings of the
step's few float64 operations are left (aero/biot_savart.py, rsqrt); measured 1 ulp over the test's range."""

KERNEL_RTOL = 1e-12
"""Lattice kernel against the segment kernel, relative to the largest velocity (both are float64 evaluations of
the same formula; they differ by rounding, ~1e-14 measured)."""


@njit(fastmath=True, error_model="numpy")
def _rsqrt_loop(s, out):
    for k in range(s.shape[0]):  # vectorised, as in the kernel
        out[k] = rsqrt(s[k])


def _segments_velocity(p, lats):
    out = np.zeros((len(p), 3))
    for lat in lats:
        s = lat.segments()
        out += segment_velocity(p, s.a, s.b, s.gamma, s.rc2)
    return out


def _lattice(rows, ns, seed, chord_step=1e-3, rc2=1e-8):
    rng = np.random.default_rng(seed)
    G = np.zeros((rows + 1, ns + 1, 3))
    G[..., 0] = -np.arange(rows + 1)[:, None] * chord_step
    G[..., 1] = np.arange(ns + 1)[None, :] * 3e-3
    G[..., 2] = 1e-3 * np.sin(np.arange(rows + 1))[:, None]
    G += 0.2 * chord_step * rng.normal(size=G.shape)
    return ring_lattice(G, 1e-3 * rng.normal(size=(rows, ns)), rc2, 4 * rc2)


def test_rsqrt_within_a_few_ulp_over_its_range():
    s = np.concatenate([np.geomspace(RSQRT_MIN, 1e36, 200001), np.random.default_rng(0).random(10000) + 0.5])
    out = np.empty_like(s)
    _rsqrt_loop(s, out)
    exact = 1.0 / np.sqrt(s)  # correctly rounded sqrt, then one rounding of the division: within 1 ulp
    assert np.all(np.abs(out - exact) <= ULP_TOL * np.spacing(exact))


def test_lattice_kernel_matches_segment_kernel_across_blocks_and_stacked_lattices():
    a = _lattice(40, 16, 0)          # 697 corners: several blocks and a remainder
    b = _lattice(3, 16, 1)           # same stride: stacked into one kernel call
    c = _lattice(5, 7, 2)            # another stride: a second call
    assert a.G.shape[0] * a.G.shape[1] > 3 * LATTICE_BLOCK
    rng = np.random.default_rng(3)
    p = np.concatenate([rng.normal(size=(150, 3)) * [0.02, 0.03, 0.005] + [-0.02, 0.02, 0.0],
                        a.G.reshape(-1, 3)[::7],      # on corners: finite, the corner's own edges give zero
                        b.G[1]])
    v = lattice_velocity(p, [a, b, c])
    ref = _segments_velocity(p, [a, b, c])
    assert np.all(np.isfinite(v))
    np.testing.assert_allclose(v, ref, rtol=0, atol=KERNEL_RTOL * np.abs(ref).max())


def test_short_edges_keep_their_precision():
    """A freshly shed wake row has chordwise edges far shorter than the distance to the targets: the velocity
    they induce must keep the segment kernel's precision. (The scalar form |r1| + |r2| - (r1.r2)(1/|r1| + 1/|r2|)
    of K, whose rounding is not scaled by |r0|, is off by 1.4e-11-2.8e-11 of the largest velocity here, measured,
    and fails; inside the UVLM it gave errors of O(1).)"""
    p = np.random.default_rng(5).normal(size=(50, 3)) * 0.05
    for step in (1e-9, 1e-7, 1e-5):
        lat = _lattice(1, 16, 4, chord_step=step, rc2=1e-4)
        lat = Lattice(lat.G, np.zeros_like(lat.span_gamma), lat.span_rc2, lat.chord_gamma, lat.chord_rc2)
        v = lattice_velocity(p, [lat])
        ref = _segments_velocity(p, [lat])
        np.testing.assert_allclose(v, ref, rtol=0, atol=KERNEL_RTOL * np.abs(ref).max())


def test_no_edges_no_velocity():
    lat = ring_lattice(np.zeros((1, 5, 3)), np.zeros((0, 4)), 1e-8, 1e-8)
    assert np.array_equal(lattice_velocity(np.ones((3, 3)), [lat]), np.zeros((3, 3)))
    assert np.array_equal(lattice_velocity(np.ones((3, 3)), []), np.zeros((3, 3)))


def test_fill_writes_corners_and_padded_edges_bit_for_bit():
    """The kernel arrays of two stacked lattices (one with scalar cores broadcast, one with per-edge cores, as the
    wake has) equal numpy's ((b - a) ** 2).sum(-1) * rc2 exactly, with gamma 0 and rr 1 on the missing edges."""
    lats = [_lattice(3, 5, 6), _lattice(4, 5, 7)]
    rng = np.random.default_rng(8)
    w = lats[1]
    lats[1] = Lattice(w.G, w.span_gamma, rng.random(w.span_gamma.shape) * 1e-8, w.chord_gamma,
                      rng.random(w.chord_gamma.shape) * 1e-8)
    n = sum(lat.G.shape[0] * lat.G.shape[1] for lat in lats)
    arrays = np.full((7, n), np.nan)
    off = 0
    for lat in lats:
        _fill(lat.G, lat.span_gamma, lat.span_rc2, lat.chord_gamma, lat.chord_rc2, off, *arrays)
        off += lat.G.shape[0] * lat.G.shape[1]
    parts = []
    for lat in lats:
        G = lat.G
        shape = G.shape[:2]
        sg, sr, cg, cr = np.zeros(shape), np.ones(shape), np.zeros(shape), np.ones(shape)
        sg[:, :-1] = lat.span_gamma
        sr[:, :-1] = ((G[:, 1:] - G[:, :-1]) ** 2).sum(-1) * lat.span_rc2
        cg[:-1] = lat.chord_gamma
        cr[:-1] = ((G[1:] - G[:-1]) ** 2).sum(-1) * lat.chord_rc2
        parts.append(np.stack([*G.reshape(-1, 3).T, sg.ravel(), sr.ravel(), cg.ravel(), cr.ravel()]))
    assert np.array_equal(arrays, np.concatenate(parts, axis=1))
