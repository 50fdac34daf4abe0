"""Biot-Savart kernels for straight vortex segments with a regularised core (numba, float64).

Velocity induced at a point p by a straight segment from a to b of circulation Gamma (Katz & Plotkin 2001,
Eq. 10.115), regularised with the Scully (Vatistas n = 1) core profile, v_theta = Gamma h / (2 pi (h^2 + r_c^2))
(Scully 1975; the profile Ramasamy & Leishman 2007 pair with their core-growth law):

    v = Gamma / (4 pi) * (r1 x r2) * K / (|r1 x r2|^2 + |r0|^2 r_c^2),   K = r0 . (r1/|r1| - r2/|r2|),

with r1 = p - a, r2 = p - b, r0 = b - a. Since |r1 x r2| = h |r0| (h the distance from the segment's line),
this is the singular formula times h^2 / (h^2 + r_c^2): exact far from the core, zero on the axis. With
r_c = 0 it is the classical formula (a point on the segment's line gets zero).

Segments are passed as structure-of-arrays: start (ax, ay, az), direction r0 = b - a (dx, dy, dz), gamma,
and rr = |r0|^2 r_c^2; targets as (n, 3). The loops run over chunks of targets on all threads
(:func:`aero.scheduling.run_chunked`: nogil kernels on a thread pool, chunks taken on demand) and, with
``fastmath`` (float64 still; only reassociation of the sums changes, ~1e-15 relative) and IEEE division
(``error_model="numpy"``: no Python zero-division checks), vectorised over segments. Cost per evaluation: two
square roots and one division, which bound it at ~0.45 G evaluations/s per core with 256-bit vectors here.

:func:`lattice_chunks` and :func:`_lattice_chunks_mixed` are the corner-block kernels for the edges of a ring
lattice (wing or wake), whose corners each segment shares with its neighbours: per target, the unit vectors r/|r|
are computed once per corner (without the divider: :func:`rsqrt`), and per edge, since r0 = r1 - r2,

    K = (r1 - r2) . (r1/|r1| - r2/|r2|),

which needs no square root and keeps the plain formula's precision for short edges (the scalar form
|r1| + |r2| - (r1 . r2)(1/|r1| + 1/|r2|) loses it: its rounding, eps |r|, is not scaled by |r0|); the one
division left per edge is the core denominator. The corners are processed in blocks of LATTICE_BLOCK, so that a
block's corner distances stay in the L1 cache while its edges use them. The float64 lattice velocity the UVLM uses
comes from the targets-in-lanes kernel of :mod:`aero.lattice_lanes` (1.2-1.3x this one at 512 bits, issue 23);
:func:`lattice_chunks` stays as the baseline the benchmarks time it against, and its pieces
(:func:`corner_vectors`, :func:`edge_sum`) serve the treecode's near field.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.core import cgutils, types
from numba.extending import intrinsic

from aero.scheduling import run_chunked

FOUR_PI = 4.0 * np.pi
TINY = 1e-300
"""Guards divisions by zero (a target on a segment's end point gets zero from it)."""

RSQRT_MIN = 1e-36
"""Smallest squared distance [m^2] :func:`rsqrt` takes (its float32 first guess must not underflow); a target
closer than 1e-18 m to a lattice corner counts as on it (the edges from that corner then give zero, as in
:func:`induced_velocity`)."""

RSQRT_MIN32 = np.float32(1e-30)
"""Smallest squared distance [m^2] of the mixed-precision lattice kernel's float32 1/sqrt (a target closer than
1e-15 m to a corner counts as on it)."""

TINY32 = np.float32(1e-37)
"""The float32 counterpart of TINY (a normal float32, so that no denominator is zero)."""

PRECISIONS = ("float64", "mixed")
"""Pair-evaluation precisions of :func:`aero.lattice_lanes.lattice_induced_velocity`: float64 throughout, or
"mixed": each target-edge evaluation in float32 (after the target-corner differences are formed in float64) and the
sums over edges accumulated in float64."""

LATTICE_BLOCK = 192
"""Corners per block of the corner-block kernels (the block's per-target scratch, 6 x 8 bytes per
corner, and inputs stay in a 48 KiB L1 data cache)."""


@intrinsic
def claim(typingctx, counter):
    """claim(counter) in njit code: atomically add 1 to counter[0] (a 1-D int64 array) and return its previous
    value (sequentially consistent): the next free chunk of a work queue shared by a kernel's tasks
    (:func:`aero.scheduling.run_chunked`)."""
    if not (isinstance(counter, types.Array) and counter.dtype == types.int64 and counter.ndim == 1):
        return None

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, aryty, ary, [context.get_constant(types.intp, 0)])
        return builder.atomic_rmw("add", ptr, context.get_constant(types.int64, 1), "seq_cst")

    return types.int64(counter), codegen


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def rsqrt(s):
    """1/sqrt(s) in float64 for s in [RSQRT_MIN, 3e38], without square root or division instructions.

    A float32 first guess (under fastmath LLVM emits the hardware reciprocal-square-root estimate and one Newton
    step, relative error ~1e-7; without it, the correctly rounded float32 value) refined by one third-order
    Householder step in float64, y <- y (1 + e/2 + 3 e^2/8) with e = 1 - s y^2, which takes a relative error d
    to ~(5/2) d^3: below float64 rounding (checked: <= 4 ulp over 1e-36..1e36 in tests/aero/test_biot_savart.py).
    """
    y = np.float64(np.float32(1.0) / np.sqrt(np.float32(s)))
    e = 1.0 - s * y * y
    return y + y * e * (0.5 + 0.375 * e)


@njit(nogil=True, fastmath=True, error_model="numpy", cache=True)
def _segment_chunks(targets, ax, ay, az, dx, dy, dz, gamma, rr, out, counter, nchunk):
    """One task of :func:`induced_velocity`: chunks q = claim(counter) < nchunk of the targets."""
    n = targets.shape[0]
    m = ax.shape[0]
    q = claim(counter)
    while q < nchunk:
        for i in range(q * n // nchunk, (q + 1) * n // nchunk):
            px, py, pz = targets[i, 0], targets[i, 1], targets[i, 2]
            ux = 0.0
            uy = 0.0
            uz = 0.0
            for k in range(m):
                r0x = dx[k]
                r0y = dy[k]
                r0z = dz[k]
                r1x = px - ax[k]
                r1y = py - ay[k]
                r1z = pz - az[k]
                r2x = r1x - r0x
                r2y = r1y - r0y
                r2z = r1z - r0z
                cx = r1y * r2z - r1z * r2y
                cy = r1z * r2x - r1x * r2z
                cz = r1x * r2y - r1y * r2x
                n1 = np.sqrt(r1x * r1x + r1y * r1y + r1z * r1z)
                n2 = np.sqrt(r2x * r2x + r2y * r2y + r2z * r2z)
                num = (r0x * r1x + r0y * r1y + r0z * r1z) * n2 - (r0x * r2x + r0y * r2y + r0z * r2z) * n1
                f = gamma[k] * num / (n1 * n2 * (cx * cx + cy * cy + cz * cz + rr[k]) + TINY)
                ux += f * cx
                uy += f * cy
                uz += f * cz
            out[i, 0] = ux / FOUR_PI
            out[i, 1] = uy / FOUR_PI
            out[i, 2] = uz / FOUR_PI
        q = claim(counter)


def induced_velocity(targets, ax, ay, az, dx, dy, dz, gamma, rr, out):
    """out[i] = velocity (3,) at targets[i] (n, 3) induced by all segments [m/s]; out (n, 3) is overwritten.
    Segments as structure-of-arrays (:func:`pack`), all contiguous float64."""
    run_chunked(_segment_chunks, (targets, ax, ay, az, dx, dy, dz, gamma, rr, out), targets.shape[0],
                targets.shape[0] * ax.shape[0])


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def edge_sum(m, x1, y1, z1, e1, f1, g1, x2, y2, z2, e2, f2, g2, gamma, rr, ux, uy, uz):
    """Velocity sums (times 4 pi) of edges k < m from corners 1 to corners 2, given the target's distance
    vectors r = (x, y, z) to them and the unit vectors r/|r| = (e, f, g); circulations gamma, rr = |r0|^2 r_c^2."""
    for k in range(m):
        ax, ay, az = x1[k], y1[k], z1[k]
        bx, by, bz = x2[k], y2[k], z2[k]
        cx = ay * bz - az * by
        cy = az * bx - ax * bz
        cz = ax * by - ay * bx
        K = (ax - bx) * (e1[k] - e2[k]) + (ay - by) * (f1[k] - f2[k]) + (az - bz) * (g1[k] - g2[k])
        f = gamma[k] * K / (cx * cx + cy * cy + cz * cz + rr[k] + TINY)
        ux += f * cx
        uy += f * cy
        uz += f * cz
    return ux, uy, uz


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def corner_vectors(px, py, pz, bx, by, bz, m, rx, ry, rz, ex, ey, ez):
    """The lattice kernel's first pass for one target p: r = p - corner and its unit vector e (floored at
    :data:`RSQRT_MIN`) into rx..ez for the corners 0..m-1 of (bx, by, bz); shared by the treecode's near field."""
    for k in range(m):
        x = px - bx[k]
        y = py - by[k]
        z = pz - bz[k]
        inv = rsqrt(max(x * x + y * y + z * z, RSQRT_MIN))
        rx[k] = x
        ry[k] = y
        rz[k] = z
        ex[k] = x * inv
        ey[k] = y * inv
        ez[k] = z * inv


@njit(inline="always", cache=True)
def aligned_buffer(size):
    """A float64 array of ``size`` whose first element lies on a 64-byte (cache-line) boundary. numba's own arrays
    are 32-byte aligned (they began 32 bytes past a cache line in 20 of 20 allocations of 209 elements)."""
    raw = np.empty(size + 8)
    off = ((64 - raw.ctypes.data % 64) % 64) // 8
    return raw[off:off + size]


@njit(inline="always", cache=True)
def aligned_scratch(size):
    """Six float64 arrays of ``size`` whose first elements lie on 64-byte (cache-line) boundaries, carved from one
    :func:`aligned_buffer`: the corner-block kernels' per-target corner vectors. On AMD Zen 5 with 512-bit
    vectors the edge sums otherwise load many vectors across two cache lines: the edge pass alone ran 1.2x faster
    on aligned scratch there (scripts/studies/kernel_variants.py, ``edges_only`` against ``edges_shifted``;
    docs/performance.md). The alignment moves no arithmetic, so no bits."""
    pad = (size + 7) // 8 * 8
    raw = aligned_buffer(6 * pad)
    return (raw[:size], raw[pad:pad + size], raw[2 * pad:2 * pad + size], raw[3 * pad:3 * pad + size],
            raw[4 * pad:4 * pad + size], raw[5 * pad:5 * pad + size])


@njit(nogil=True, fastmath=True, error_model="numpy", cache=True)
def lattice_chunks(targets, vx, vy, vz, stride, span_gamma, span_rr, chord_gamma, chord_rr, out, counter, nchunk):
    """One task of the corner-block float64 lattice kernel (the arguments of
    :func:`aero.lattice_lanes.lattice_induced_velocity`, then the work queue's counter and chunk count): chunks
    q = claim(counter) < nchunk of the targets. The baseline of :mod:`aero.lattice_lanes`'s kernel."""
    n = targets.shape[0]
    nc = vx.shape[0]
    if n == 0 or nc == 0:
        return
    block = LATTICE_BLOCK
    nb = (nc + block - 1) // block
    scale = 1.0 / FOUR_PI
    size = block + stride + 1
    rx, ry, rz, ex, ey, ez = aligned_scratch(size)
    q = claim(counter)
    while q < nchunk:
        i0 = q * n // nchunk
        i1 = (q + 1) * n // nchunk
        for b in range(nb):
            c0 = b * block
            c1 = min(c0 + block, nc)
            m = min(c1 + stride, nc) - c0
            ms = min(c1, nc - 1) - c0
            mc = min(c1, nc - stride) - c0
            bx, by, bz = vx[c0:c0 + m], vy[c0:c0 + m], vz[c0:c0 + m]
            sg, sr, cg, cr = span_gamma[c0:], span_rr[c0:], chord_gamma[c0:], chord_rr[c0:]
            for i in range(i0, i1):
                corner_vectors(targets[i, 0], targets[i, 1], targets[i, 2], bx, by, bz, m, rx, ry, rz, ex, ey, ez)
                ux, uy, uz = edge_sum(ms, rx, ry, rz, ex, ey, ez, rx[1:], ry[1:], rz[1:], ex[1:], ey[1:],
                                       ez[1:], sg, sr, 0.0, 0.0, 0.0)
                if mc > 0:
                    ux, uy, uz = edge_sum(mc, rx, ry, rz, ex, ey, ez, rx[stride:], ry[stride:], rz[stride:],
                                           ex[stride:], ey[stride:], ez[stride:], cg, cr, ux, uy, uz)
                out[i, 0] += ux * scale
                out[i, 1] += uy * scale
                out[i, 2] += uz * scale
        q = claim(counter)


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def _edge_terms_mixed(m, x1, y1, z1, e1, f1, g1, x2, y2, z2, e2, f2, g2, gamma, rr, tx, ty, tz):
    """:func:`edge_sum`'s terms (times 4 pi) on float32 distances, unit vectors, circulations and rr, evaluated
    in float32 and stored in tx, ty, tz [k < m] (float32) for :func:`_sum_terms` to add in float64. (Storing the
    terms and summing them in a second loop lets LLVM vectorise both loops; adding each float32 term straight to
    float64 sums kept the fused loop scalar, slower on the kernel benchmark with 256-bit vectors at the same
    arithmetic: docs/performance.md. Summing the terms in float32 was 1.75x faster but moved the reference case's
    lift by 6.5e-4 and power by 9.6e-4 relative against 1.5e-4 and 9e-6: scripts/studies/mixed_precision.py.)"""
    for k in range(m):
        ax, ay, az = x1[k], y1[k], z1[k]
        bx, by, bz = x2[k], y2[k], z2[k]
        cx = ay * bz - az * by
        cy = az * bx - ax * bz
        cz = ax * by - ay * bx
        K = (ax - bx) * (e1[k] - e2[k]) + (ay - by) * (f1[k] - f2[k]) + (az - bz) * (g1[k] - g2[k])
        f = gamma[k] * K / (cx * cx + cy * cy + cz * cz + rr[k] + TINY32)
        tx[k] = f * cx
        ty[k] = f * cy
        tz[k] = f * cz


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def _sum_terms(m, tx, ty, tz, ux, uy, uz):
    """ux, uy, uz plus the float64 sums of the float32 terms tx, ty, tz [k < m]."""
    for k in range(m):
        ux += np.float64(tx[k])
        uy += np.float64(ty[k])
        uz += np.float64(tz[k])
    return ux, uy, uz


@njit(nogil=True, fastmath=True, error_model="numpy", cache=True)
def _lattice_chunks_mixed(targets, vx, vy, vz, stride, span_gamma, span_rr, chord_gamma, chord_rr, out, counter,
                          nchunk):
    """:func:`lattice_chunks` with float32 pair evaluations (precision "mixed"): the target-corner differences
    are formed in float64 and rounded to float32, 1/sqrt is float32 (hardware estimate and one Newton step under
    fastmath), span/chord gamma and rr are float32 arrays; each edge's term is float32
    (:func:`_edge_terms_mixed`), the per-target sums float64 (:func:`_sum_terms`)."""
    n = targets.shape[0]
    nc = vx.shape[0]
    if n == 0 or nc == 0:
        return
    block = LATTICE_BLOCK
    nb = (nc + block - 1) // block
    scale = 1.0 / FOUR_PI
    size = block + stride + 1
    rx = np.empty(size, np.float32)
    ry = np.empty(size, np.float32)
    rz = np.empty(size, np.float32)
    ex = np.empty(size, np.float32)
    ey = np.empty(size, np.float32)
    ez = np.empty(size, np.float32)
    tx = np.empty(size, np.float32)
    ty = np.empty(size, np.float32)
    tz = np.empty(size, np.float32)
    one = np.float32(1.0)
    q = claim(counter)
    while q < nchunk:
        i0 = q * n // nchunk
        i1 = (q + 1) * n // nchunk
        for b in range(nb):
            c0 = b * block
            c1 = min(c0 + block, nc)
            m = min(c1 + stride, nc) - c0
            ms = min(c1, nc - 1) - c0
            mc = min(c1, nc - stride) - c0
            bx, by, bz = vx[c0:c0 + m], vy[c0:c0 + m], vz[c0:c0 + m]
            sg, sr, cg, cr = span_gamma[c0:], span_rr[c0:], chord_gamma[c0:], chord_rr[c0:]
            for i in range(i0, i1):
                px, py, pz = targets[i, 0], targets[i, 1], targets[i, 2]
                for k in range(m):
                    x = np.float32(px - bx[k])
                    y = np.float32(py - by[k])
                    z = np.float32(pz - bz[k])
                    inv = one / np.sqrt(max(x * x + y * y + z * z, RSQRT_MIN32))
                    rx[k] = x
                    ry[k] = y
                    rz[k] = z
                    ex[k] = x * inv
                    ey[k] = y * inv
                    ez[k] = z * inv
                _edge_terms_mixed(ms, rx, ry, rz, ex, ey, ez, rx[1:], ry[1:], rz[1:], ex[1:], ey[1:], ez[1:], sg,
                                  sr, tx, ty, tz)
                ux, uy, uz = _sum_terms(ms, tx, ty, tz, 0.0, 0.0, 0.0)
                if mc > 0:
                    _edge_terms_mixed(mc, rx, ry, rz, ex, ey, ez, rx[stride:], ry[stride:], rz[stride:],
                                      ex[stride:], ey[stride:], ez[stride:], cg, cr, tx, ty, tz)
                    ux, uy, uz = _sum_terms(mc, tx, ty, tz, ux, uy, uz)
                out[i, 0] += ux * scale
                out[i, 1] += uy * scale
                out[i, 2] += uz * scale
        q = claim(counter)


RING_PAIR_COST = 24
"""Cost of one ring-target evaluation of :func:`ring_influence` in lattice-kernel pair evaluations, the unit of
:data:`aero.scheduling.MIN_PARALLEL_WORK` (four edges, two square roots and two divisions each, not vectorised:
measured on one core: docs/performance.md; so an influence matrix of 144 x 72 rings is split
over the threads). Measured, not tuned; it only decides whether a call is split."""


@njit(nogil=True, fastmath=False, cache=True)
def _ring_chunks(targets, normals, corners, rc2, out, counter, nchunk):
    """One task of :func:`ring_influence`: chunks q = claim(counter) < nchunk of the targets."""
    n = targets.shape[0]
    L = corners.shape[0]
    q = claim(counter)
    while q < nchunk:
        for i in range(q * n // nchunk, (q + 1) * n // nchunk):
            px, py, pz = targets[i, 0], targets[i, 1], targets[i, 2]
            nx, ny, nz = normals[i, 0], normals[i, 1], normals[i, 2]
            for l in range(L):
                vn = 0.0
                for s in range(4):
                    e = (s + 1) % 4
                    r1x = px - corners[l, s, 0]
                    r1y = py - corners[l, s, 1]
                    r1z = pz - corners[l, s, 2]
                    r2x = px - corners[l, e, 0]
                    r2y = py - corners[l, e, 1]
                    r2z = pz - corners[l, e, 2]
                    cx = r1y * r2z - r1z * r2y
                    cy = r1z * r2x - r1x * r2z
                    cz = r1x * r2y - r1y * r2x
                    c2 = cx * cx + cy * cy + cz * cz
                    r0x = r1x - r2x
                    r0y = r1y - r2y
                    r0z = r1z - r2z
                    r0sq = r0x * r0x + r0y * r0y + r0z * r0z
                    den = c2 + r0sq * rc2
                    r1 = np.sqrt(r1x * r1x + r1y * r1y + r1z * r1z)
                    r2 = np.sqrt(r2x * r2x + r2y * r2y + r2z * r2z)
                    if den < TINY or r1 < 1e-15 or r2 < 1e-15:
                        continue
                    K = (r0x * r1x + r0y * r1y + r0z * r1z) / r1 - (r0x * r2x + r0y * r2y + r0z * r2z) / r2
                    vn += K / (FOUR_PI * den) * (cx * nx + cy * ny + cz * nz)
                out[i, l] = vn
        q = claim(counter)


def ring_influence(targets, normals, corners, rc2, out):
    """out[i, l] = normal velocity at targets[i] (along normals[i]) induced by ring l with unit circulation.

    corners (L, 4, 3): each ring's corners in loop order (the circulation runs 0 -> 1 -> 2 -> 3 -> 0).
    All arrays contiguous float64; rc2: squared core radius [m^2] (scalar)."""
    run_chunked(_ring_chunks, (targets, normals, corners, rc2, out), targets.shape[0],
                RING_PAIR_COST * targets.shape[0] * corners.shape[0])


def pack(a: np.ndarray, b: np.ndarray, gamma: np.ndarray, rc2) -> tuple:
    """Structure-of-arrays arguments of :func:`induced_velocity` for segments a -> b (m, 3)."""
    a = np.asarray(a, dtype=float).reshape(-1, 3)
    d = np.asarray(b, dtype=float).reshape(-1, 3) - a
    rc2 = np.broadcast_to(np.asarray(rc2, dtype=float), (a.shape[0],))
    rr = (d * d).sum(1) * rc2
    return (*(np.ascontiguousarray(c) for c in (a[:, 0], a[:, 1], a[:, 2], d[:, 0], d[:, 1], d[:, 2])),
            np.ascontiguousarray(gamma, dtype=float).ravel(), np.ascontiguousarray(rr))


def segment_velocity(targets: np.ndarray, a: np.ndarray, b: np.ndarray, gamma: np.ndarray,
                     rc2: np.ndarray | float = 0.0) -> np.ndarray:
    """Velocity (n, 3) at targets (n, 3) induced by segments a -> b (m, 3) with circulations (m,) [m/s]."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    out = np.zeros((targets.shape[0], 3))
    if np.size(gamma) == 0 or targets.shape[0] == 0:
        return out
    induced_velocity(targets, *pack(a, b, gamma, rc2), out)
    return out

