"""aero.lattice_lanes: the targets-in-lanes lattice kernel, in every lane configuration this host runs, against the
per-segment kernel (which tests/aero/test_biot_savart.py checks against Katz & Plotkin's Eq. 10.115); its two
1/sqrt routes to a few ulp; its bits independent of threads, chunks and a target's place among the others."""

import numpy as np
import pytest
from numba import njit

from aero import scheduling
from aero.biot_savart import RSQRT_MIN, lattice_chunks
from aero.lattice import stacked_lattices
from aero.lattice_lanes import (GROUP, _lanes_chunks, chunks_kernel, config_group, inverse_sqrt_intrinsic,
                                lane_config, lattice_induced_velocity, supported_configs, transpose_targets)
from aero.vector_width import vector_bits
from tests.aero.test_lattice import ULP_TOL, _lattice, _segments_velocity

LANES_RTOL = 1e-13
"""Lanes kernel against the per-segment kernel, relative to the largest velocity: both are float64 evaluations of
the same formula, differing by rounding only (measured 2e-15-6e-15 here, 2026-12-04)."""

BASELINE_RTOL = 2e-14
"""Lanes kernel against the corner-block kernel it replaced (:func:`aero.biot_savart.lattice_chunks`): the same
arithmetic summed in another order (measured 4.0e-15 at stride 17 and 5.1e-15 at stride 9,
scripts/studies/lanes_kernel.py, 2026-12-04)."""

CONFIGS = supported_configs()


def _arrays(lats):
    """{stride: (vx, vy, vz, sg, sr, cg, cr)} contiguous, as aero.lattice.lattice_velocity passes them."""
    return {s: tuple(np.ascontiguousarray(a) for a in arr) for s, arr in stacked_lattices(lats).items()}


def _velocity(kernel, p, lats, group=GROUP):
    """The velocity at p of all lattices through one chunk kernel of aero.lattice_lanes' signature (groups of
    ``group`` targets)."""
    out = np.zeros((p.shape[0], 3))
    T = transpose_targets(p, group)
    for stride, (vx, vy, vz, sg, sr, cg, cr) in _arrays(lats).items():
        kernel(T, p.shape[0], vx, vy, vz, stride, sg, sr, cg, cr, out, np.zeros(1, np.int64), 1)
    return out


def _targets(a, b, seed=3):
    rng = np.random.default_rng(seed)
    return np.ascontiguousarray(np.concatenate([rng.normal(size=(151, 3)) * [0.02, 0.03, 0.005] + [-0.02, 0.02, 0],
                                                a.G.reshape(-1, 3)[::7],   # on corners: the corner's edges give 0
                                                b.G[1]]))


@pytest.fixture(scope="module")
def kernels():
    return {c: (_lanes_chunks if c == lane_config() else chunks_kernel(c)) for c in CONFIGS}


INTERLEAVE_RTOL = 1e-15
"""Two lane vectors per pass over the corners against one (the study option of aero.lattice_lanes.group_intrinsic):
the same sums in the same order, but LLVM may fuse other multiply-adds in the larger block (measured 4.6e-17 of
the largest velocity at 8 lanes on AMD Zen 4, 2026-12-06)."""


@pytest.mark.parametrize("lanes", [4, 8])
def test_interleaved_passes_give_the_same_velocities(lanes):
    route = lane_config()[1] if (lanes, lane_config()[1]) in CONFIGS else "float32"
    a, b = _lattice(40, 16, 0), _lattice(3, 16, 1)
    p = _targets(a, b)
    one = _velocity(chunks_kernel((lanes, route, 1)), p, [a, b])
    cfg = (lanes, route, 2)
    assert config_group(cfg) == max(GROUP, 2 * lanes)
    two = _velocity(chunks_kernel(cfg), p, [a, b], config_group(cfg))
    np.testing.assert_allclose(two, one, rtol=0, atol=INTERLEAVE_RTOL * np.abs(one).max())


@pytest.mark.parametrize("config", CONFIGS, ids=[f"{n}x{r}" for n, r in CONFIGS])
def test_inverse_sqrt_within_a_few_ulp_over_its_range(config):
    f = inverse_sqrt_intrinsic(config)

    @njit
    def run(s, out):
        f(s, out)

    s = np.concatenate([np.geomspace(RSQRT_MIN, 1e36, 200000), np.random.default_rng(0).random(10000) + 0.5])
    out = np.empty_like(s)
    run(s, out)
    exact = 1.0 / np.sqrt(s)  # correctly rounded sqrt, then one rounding of the division: within 1 ulp
    assert np.all(np.abs(out - exact) <= ULP_TOL * np.spacing(exact))


@pytest.mark.parametrize("config", CONFIGS, ids=[f"{n}x{r}" for n, r in CONFIGS])
def test_matches_segment_kernel_with_stacked_lattices_and_targets_on_corners(kernels, config):
    a, b, c = _lattice(40, 16, 0), _lattice(3, 16, 1), _lattice(5, 7, 2)  # b stacks onto a; c: another stride
    p = _targets(a, b)
    assert p.shape[0] % GROUP != 0  # the last group is padded
    v = _velocity(kernels[config], p, [a, b, c])
    ref = _segments_velocity(p, [a, b, c])
    assert np.all(np.isfinite(v))
    np.testing.assert_allclose(v, ref, rtol=0, atol=LANES_RTOL * np.abs(ref).max())


def test_close_to_the_corner_block_kernel_it_replaced():
    a = _lattice(40, 16, 0)
    p = _targets(a, _lattice(3, 16, 1))
    (stride, arrays), = _arrays([a]).items()
    base = np.zeros((p.shape[0], 3))
    lattice_chunks(p, *arrays[:3], stride, *arrays[3:], base, np.zeros(1, np.int64), 1)
    v = np.zeros_like(base)
    lattice_induced_velocity(p, *arrays[:3], stride, *arrays[3:], v, threads=1)
    np.testing.assert_allclose(v, base, rtol=0, atol=BASELINE_RTOL * np.abs(base).max())


def test_bits_do_not_depend_on_threads_chunks_or_a_targets_place():
    """A target's velocity is the same, bit for bit, on 1-3 threads, and whether it sits first or last in a group,
    alone or among others (the padding of the last group changes nothing)."""
    a = _lattice(30, 8, 5)
    p = _targets(a, _lattice(3, 8, 6), seed=7)
    (stride, arrays), = _arrays([a]).items()

    def run(q, threads=1):
        out = np.zeros((q.shape[0], 3))
        lattice_induced_velocity(np.ascontiguousarray(q), *arrays[:3], stride, *arrays[3:], out, threads=threads)
        return out

    ref = run(p)
    old = scheduling.MIN_PARALLEL_WORK
    scheduling.MIN_PARALLEL_WORK = 0
    try:
        for threads in (2, 3):
            assert np.array_equal(run(p, threads), ref), threads
    finally:
        scheduling.MIN_PARALLEL_WORK = old
    perm = np.random.default_rng(8).permutation(p.shape[0])
    assert np.array_equal(run(p[perm]), ref[perm])
    for k in (1, 7, 8, 9, 17):
        assert np.array_equal(run(p[-k:]), ref[-k:]), k


@pytest.mark.parametrize("config", CONFIGS, ids=[f"{n}x{r}" for n, r in CONFIGS])
def test_partial_row_and_empty_inputs(kernels, config):
    """Fewer corners than a row (no chordwise edge at all), no corners, no targets."""
    a = _lattice(2, 9, 9)
    (stride, arrays), = _arrays([a]).items()
    vx, vy, vz, sg, sr, cg, cr = (np.ascontiguousarray(x[:7]) for x in arrays)
    sg[-1], sr[-1] = 0.0, 1.0  # the 7th corner's spanwise edge leads out of the partial row
    p = np.random.default_rng(10).normal(size=(13, 3)) * 0.02
    out = np.zeros((13, 3))
    kernels[config](transpose_targets(p), 13, vx, vy, vz, stride, sg, sr, cg, cr, out, np.zeros(1, np.int64), 1)
    G = np.stack([vx, vy, vz], axis=1)
    from aero.biot_savart import segment_velocity

    rc2 = sr[:6] / ((G[1:] - G[:-1]) ** 2).sum(1)
    ref = segment_velocity(p, G[:6], G[1:], sg[:6], rc2)
    assert np.abs(ref).max() > 0
    np.testing.assert_allclose(out, ref, rtol=0, atol=LANES_RTOL * np.abs(ref).max())
    empty = np.zeros(0)
    out = np.ones((13, 3))
    lattice_induced_velocity(p, empty, empty, empty, stride, empty, empty, empty, empty, out)
    assert np.array_equal(out, np.ones((13, 3)))
    lattice_induced_velocity(np.zeros((0, 3)), vx, vy, vz, stride, sg, sr, cg, cr, np.zeros((0, 3)))


def test_lane_configuration_follows_the_vector_width():
    lanes, inverse_sqrt = lane_config()
    assert lanes == (8 if vector_bits() >= 512 else 4)
    assert (lanes, inverse_sqrt) in CONFIGS
    assert inverse_sqrt == ("rsqrt14" if any(r == "rsqrt14" and n == lanes for n, r in CONFIGS) else "float32")
