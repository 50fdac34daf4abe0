"""Barnes-Hut treecode for the velocity induced by many regularised vortex segments (the free wake on itself).

The direct sum over N targets and M segments costs N M pair evaluations; for a free wake convected by itself
(N ~ M/2 corners, M edges) that is O(M^2) per step. This module evaluates the same sum in ~O(N log M):

* **Sources.** Each straight segment a -> b of circulation Gamma is a line of vortex-particle density
  Gamma (b - a) ds, s in [0, 1]. A cluster of segments is summarised about its centre c by the exact moments of
  those lines (units m^2/s times m^k):

      M0_q      = sum Gamma d_q                                      (d = b - a, m the midpoint, s = m - c)
      M1_qk     = sum Gamma d_q s_k
      M2_qkl    = sum Gamma d_q (s_k s_l + d_k d_l / 12)

  and the far field of the cluster at x (R = x - c) is the Taylor expansion of the singular Biot-Savart kernel
  v = 1/(4 pi) sum alpha x (x - y)/|x - y|^3 to second order (monopole, dipole, quadrupole), i.e. it neglects
  terms of relative size (rho / |R|)^3, rho the cluster's radius about c (covering every segment end point).
* **Near field.** Clusters that do not pass the opening criterion are opened; at a leaf the segments act exactly,
  in the lattice kernel's arithmetic (:func:`aero.biot_savart.edge_sum`: the Scully-core formula with
  K = r0 . (r1/|r1| - r2/|r2|), one 1/sqrt (:func:`aero.biot_savart.rsqrt`) per corner and target, one
  division per edge).
* **Opening criterion (the error control).** A cluster acts through its moments on a leaf of targets only if,
  for every target x of the leaf, ``(rho + kappa r_c,max) < theta |x - c|``: rho the cluster's radius, r_c,max the
  largest core radius among its segments (the far field ignores the cores, whose effect on a segment's velocity
  at distance h from its line is a factor h^2 / (h^2 + r_c^2)), kappa = ``core_factor`` (1), theta the error
  parameter (:class:`TreeParams`). theta = 0 opens every cluster: the direct sum (to rounding). The expansion's
  error falls as theta^3 or faster; measured bounds: tests/aero/test_treecode.py, docs/performance.md
  ("Treecode for the free wake"), where theta = 0.2 keeps the UVLM's cycle averages within 1e-4.
* **Trees.** The sources are the edges of ring lattices (wing or wake, stacked as
  :func:`aero.lattice.stacked_lattices` writes them): a binary tree of corner blocks (rows x columns, halved at
  the middle index along the side that is longer in space; a block owns the edges that start at its corners), so
  that a leaf's edges share their corners as in the lattice kernel. Free segments (:func:`tree_velocity`) are
  first put in spatial order and treated as a lattice of one edge per row. Targets are split into a binary tree by
  median bisection along the longest side of each node's bounding box (stable sorts). Both trees are rebuilt every
  call (the wake moves every step). Targets are evaluated a leaf at a time: one traversal of the source tree per
  target leaf, its decisions shared by the leaf's targets, whose loops then vectorise. ``plan=True``
  (:func:`lattice_tree_velocity`) counts that traversal's work first and declines (None) where the direct sum is
  the cheaper.

Determinism: a target's sum is computed by one task in a fixed order (the traversal of its leaf), so results are
bit-identical for any thread count and chunking (:func:`aero.scheduling.run_chunked` over target leaves).

Units SI: positions [m], circulations [m^2/s], squared cores [m^2], velocities [m/s]; any one Cartesian frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from aero.biot_savart import FOUR_PI, RSQRT_MIN, edge_sum, aligned_scratch, claim, corner_vectors, rsqrt
from aero.lattice import stacked_lattices
from aero.scheduling import run_chunked

N_MOMENTS = 30
"""Per cluster: M0 (3), M1 (3 x 3, row-major q, k), M2 (3 x 6: q, then kl in xx, yy, zz, xy, xz, yz)."""

STACK = 512
"""Depth of the traversal stack (a binary tree of 1e9 leaves needs < 64)."""


@dataclass(frozen=True)
class TreeParams:
    """Error control and granularity of the treecode.

    theta: opening angle: a cluster acts by its moments on a target leaf only if (its radius + core_factor x its
    largest core radius) < theta x the distance from its centre to every target of the leaf (0: the direct sum);
    core_factor: weight of the cores in that criterion (the far field ignores them; 1 keeps their error below the
    expansion's on the UVLM's wakes, docs/performance.md); source_leaf: most lattice corners per source leaf (a
    block of rows x columns of a lattice), target_leaf: most targets per target leaf (granularity: speed, and the
    error only through the leaves' sizes in the criterion; tuned on 10-beat wakes, docs/performance.md).
    """

    theta: float = 0.2
    core_factor: float = 1.0
    source_leaf: int = 128
    target_leaf: int = 32

    def __post_init__(self):
        if not (np.isfinite(self.theta) and 0.0 <= self.theta < 1.0):
            raise ValueError(f"TreeParams.theta must lie in [0, 1), got {self.theta!r}")
        if not (np.isfinite(self.core_factor) and self.core_factor >= 0.0):
            raise ValueError(f"TreeParams.core_factor must be finite and >= 0, got {self.core_factor!r}")
        for name in ("source_leaf", "target_leaf"):
            v = getattr(self, name)
            if int(v) != v or v < 1:
                raise ValueError(f"TreeParams.{name} must be a positive integer, got {v!r}")


@njit(cache=True)
def _split(x, y, z, leaf):
    """Binary tree over points (n,) each of x, y, z: median bisection along the longest side of each node's
    bounding box until a node holds at most ``leaf`` points. Returns (perm (n,): the points in tree order,
    start, end (nodes,): each node's range in perm, left, right (nodes,): children, -1 at leaves); node 0 is the
    root, nodes in breadth-first order."""
    n = x.shape[0]
    perm = np.arange(n)
    maxn = 4 * (n // max(leaf, 1)) + 8
    start = np.empty(maxn, np.int64)
    end = np.empty(maxn, np.int64)
    left = np.full(maxn, -1, np.int64)
    right = np.full(maxn, -1, np.int64)
    start[0] = 0
    end[0] = n
    nn = 1
    i = 0
    while i < nn:
        s, e = start[i], end[i]
        if e - s > leaf:
            lo = np.full(3, np.inf)
            hi = np.full(3, -np.inf)
            for j in range(s, e):
                p = perm[j]
                lo[0] = min(lo[0], x[p])
                hi[0] = max(hi[0], x[p])
                lo[1] = min(lo[1], y[p])
                hi[1] = max(hi[1], y[p])
                lo[2] = min(lo[2], z[p])
                hi[2] = max(hi[2], z[p])
            ext = hi - lo
            axis = 0
            if ext[1] > ext[axis]:
                axis = 1
            if ext[2] > ext[axis]:
                axis = 2
            coord = x if axis == 0 else (y if axis == 1 else z)
            sub = perm[s:e].copy()
            key = np.empty(e - s)
            for j in range(e - s):
                key[j] = coord[sub[j]]
            order = np.argsort(key, kind="mergesort")
            for j in range(e - s):
                perm[s + j] = sub[order[j]]
            mid = s + (e - s) // 2
            left[i], right[i] = nn, nn + 1
            start[nn], end[nn] = s, mid
            start[nn + 1], end[nn + 1] = mid, e
            nn += 2
        i += 1
    return perm, start[:nn], end[:nn], left[:nn], right[:nn]


@njit(cache=True)
def _block_tree(vx, vy, vz, stride, leaf):
    """Binary tree of corner blocks over a stacked lattice (corners row-major, ``stride`` per row, as
    :func:`aero.lattice._fill` writes them): node k holds corner rows [r0, r1) x columns [c0, c1) and owns the
    edges that start at its corners. A node of more than ``leaf`` corners is halved along the side (rows or
    columns) that is longer in space, at the middle index; columns only while more than 2 wide. Returns
    (r0, r1, c0, c1, left, right), node 0 the root, breadth-first; left = right = -1 at leaves."""
    nrows = vx.shape[0] // stride
    maxn = 4 * (nrows * stride // max(leaf, 1)) + 8
    r0 = np.empty(maxn, np.int64)
    r1 = np.empty(maxn, np.int64)
    c0 = np.empty(maxn, np.int64)
    c1 = np.empty(maxn, np.int64)
    left = np.full(maxn, -1, np.int64)
    right = np.full(maxn, -1, np.int64)
    r0[0], r1[0], c0[0], c1[0] = 0, nrows, 0, stride
    nn = 1
    i = 0
    while i < nn:
        nr, nc = r1[i] - r0[i], c1[i] - c0[i]
        if nr * nc > leaf and (nr > 1 or nc > 2):
            rm = (r0[i] + r1[i]) // 2
            cm = (c0[i] + c1[i]) // 2
            a = (r0[i]) * stride + cm
            b = (r1[i] - 1) * stride + cm
            lr = (vx[a] - vx[b]) ** 2 + (vy[a] - vy[b]) ** 2 + (vz[a] - vz[b]) ** 2
            a = rm * stride + c0[i]
            b = rm * stride + c1[i] - 1
            lc = (vx[a] - vx[b]) ** 2 + (vy[a] - vy[b]) ** 2 + (vz[a] - vz[b]) ** 2
            split_rows = nr > 1 and (nc <= 2 or lr >= lc)
            left[i], right[i] = nn, nn + 1
            for k in (nn, nn + 1):
                r0[k], r1[k], c0[k], c1[k] = r0[i], r1[i], c0[i], c1[i]
            if split_rows:
                r1[nn] = rm
                r0[nn + 1] = rm
            else:
                c1[nn] = cm
                c0[nn + 1] = cm
            nn += 2
        i += 1
    return r0[:nn], r1[:nn], c0[:nn], c1[:nn], left[:nn], right[:nn]


@njit(cache=True)
def _block_nodes(r0, r1, c0, c1, vx, vy, vz, stride, sg, sr, cg, cr):
    """Per node of :func:`_block_tree`, from the edges it owns (span edge c -> c + 1 with circulation sg[c] and
    rr = |r0|^2 r_c^2 sr[c], chord edge c -> c + stride with cg[c], cr[c]; zero-circulation edges left out):
    centre (nodes, 3) [m] (of the bounding box of the edges' end points), radius about it covering every end
    point [m], largest core radius [m] and moments (nodes, N_MOMENTS) about the centre."""
    nn = r0.shape[0]
    nrows = vx.shape[0] // stride
    centre = np.zeros((nn, 3))
    rho = np.zeros(nn)
    rc = np.zeros(nn)
    mom = np.zeros((nn, N_MOMENTS))
    for k in range(nn):
        for sweep in range(2):  # 0: bounding box and cores; 1: radius and moments about the centre
            lo = np.full(3, np.inf)
            hi = np.full(3, -np.inf)
            r2max = 0.0
            rad2 = 0.0
            cxk, cyk, czk = centre[k, 0], centre[k, 1], centre[k, 2]
            for i in range(r0[k], r1[k]):
                for j in range(c0[k], c1[k]):
                    c = i * stride + j
                    for e in range(2):
                        if e == 0:
                            if j >= stride - 1:
                                continue
                            t, gam, rr = c + 1, sg[c], sr[c]
                        else:
                            if i >= nrows - 1:
                                continue
                            t, gam, rr = c + stride, cg[c], cr[c]
                        if gam == 0.0:
                            continue
                        ax, ay, az = vx[c], vy[c], vz[c]
                        dx, dy, dz = vx[t] - ax, vy[t] - ay, vz[t] - az
                        d2 = dx * dx + dy * dy + dz * dz
                        if sweep == 0:
                            lo[0] = min(lo[0], ax, ax + dx)
                            hi[0] = max(hi[0], ax, ax + dx)
                            lo[1] = min(lo[1], ay, ay + dy)
                            hi[1] = max(hi[1], ay, ay + dy)
                            lo[2] = min(lo[2], az, az + dz)
                            hi[2] = max(hi[2], az, az + dz)
                            if d2 > 0.0:
                                r2max = max(r2max, rr / d2)
                            continue
                        ex, ey, ez = ax - cxk, ay - cyk, az - czk
                        rad2 = max(rad2, ex * ex + ey * ey + ez * ez)
                        ex, ey, ez = ex + dx, ey + dy, ez + dz
                        rad2 = max(rad2, ex * ex + ey * ey + ez * ez)
                        d = (dx, dy, dz)
                        sv = (ax + 0.5 * dx - cxk, ay + 0.5 * dy - cyk, az + 0.5 * dz - czk)
                        for q in range(3):
                            al = gam * d[q]
                            mom[k, q] += al
                            for kk in range(3):
                                mom[k, 3 + 3 * q + kk] += al * sv[kk]
                            b0 = 12 + 6 * q
                            mom[k, b0 + 0] += al * (sv[0] * sv[0] + d[0] * d[0] / 12.0)
                            mom[k, b0 + 1] += al * (sv[1] * sv[1] + d[1] * d[1] / 12.0)
                            mom[k, b0 + 2] += al * (sv[2] * sv[2] + d[2] * d[2] / 12.0)
                            mom[k, b0 + 3] += al * (sv[0] * sv[1] + d[0] * d[1] / 12.0)
                            mom[k, b0 + 4] += al * (sv[0] * sv[2] + d[0] * d[2] / 12.0)
                            mom[k, b0 + 5] += al * (sv[1] * sv[2] + d[1] * d[2] / 12.0)
            if sweep == 0:
                if lo[0] > hi[0]:  # no edge with circulation: a node that acts as nothing (rc < 0 marks it)
                    rc[k] = -1.0
                    break
                for q in range(3):
                    centre[k, q] = 0.5 * (lo[q] + hi[q])
                rc[k] = np.sqrt(r2max)
            else:
                rho[k] = np.sqrt(rad2)
    return centre, rho, rc, mom


@njit(cache=True)
def _target_leaves(start, end, left, x, y, z):
    """The target tree's leaves: ranges (leaves,) in tree order, centres (leaves, 3) and radii (leaves,) [m]."""
    leaves = np.nonzero(left < 0)[0]
    nl = leaves.shape[0]
    ls = np.empty(nl, np.int64)
    le = np.empty(nl, np.int64)
    centre = np.empty((nl, 3))
    rad = np.empty(nl)
    for i in range(nl):
        k = leaves[i]
        ls[i], le[i] = start[k], end[k]
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        for j in range(start[k], end[k]):
            lo[0] = min(lo[0], x[j])
            hi[0] = max(hi[0], x[j])
            lo[1] = min(lo[1], y[j])
            hi[1] = max(hi[1], y[j])
            lo[2] = min(lo[2], z[j])
            hi[2] = max(hi[2], z[j])
        c = 0.5 * (lo + hi)
        centre[i] = c
        r2 = 0.0
        for j in range(start[k], end[k]):
            ex, ey, ez = x[j] - c[0], y[j] - c[1], z[j] - c[2]
            r2 = max(r2, ex * ex + ey * ey + ez * ez)
        rad[i] = np.sqrt(r2)
    return ls, le, centre, rad


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def _far(nt, x, y, z, cx, cy, cz, m, ux, uy, uz):
    """Add 4 pi x the far field of one cluster (centre cx, cy, cz; moments m (N_MOMENTS,)) to ux, uy, uz at the
    targets j < nt (sliced to the leaf)."""
    m0x, m0y, m0z = m[0], m[1], m[2]
    a00, a01, a02, a10, a11, a12, a20, a21, a22 = m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]
    # M2[q] as a symmetric 3 x 3 (xx, yy, zz, xy, xz, yz)
    p0xx, p0yy, p0zz, p0xy, p0xz, p0yz = m[12], m[13], m[14], m[15], m[16], m[17]
    p1xx, p1yy, p1zz, p1xy, p1xz, p1yz = m[18], m[19], m[20], m[21], m[22], m[23]
    p2xx, p2yy, p2zz, p2xy, p2xz, p2yz = m[24], m[25], m[26], m[27], m[28], m[29]
    # constant parts: axial vector of M1, trace t_q of M2[q]
    axm1x = a12 - a21
    axm1y = a20 - a02
    axm1z = a01 - a10
    tx = p0xx + p0yy + p0zz
    ty = p1xx + p1yy + p1zz
    tz = p2xx + p2yy + p2zz
    for j in range(nt):
        rx = x[j] - cx
        ry = y[j] - cy
        rz = z[j] - cz
        r2 = rx * rx + ry * ry + rz * rz
        inv = rsqrt(max(r2, RSQRT_MIN))
        i2 = inv * inv
        i3 = inv * i2
        i5 = i3 * i2
        i7 = i5 * i2
        # w_q = M1_qk R_k
        wx = a00 * rx + a01 * ry + a02 * rz
        wy = a10 * rx + a11 * ry + a12 * rz
        wz = a20 * rx + a21 * ry + a22 * rz
        # u_qi = M2_qil R_l (rows q)
        u0x = p0xx * rx + p0xy * ry + p0xz * rz
        u0y = p0xy * rx + p0yy * ry + p0yz * rz
        u0z = p0xz * rx + p0yz * ry + p0zz * rz
        u1x = p1xx * rx + p1xy * ry + p1xz * rz
        u1y = p1xy * rx + p1yy * ry + p1yz * rz
        u1z = p1xz * rx + p1yz * ry + p1zz * rz
        u2x = p2xx * rx + p2xy * ry + p2xz * rz
        u2y = p2xy * rx + p2yy * ry + p2yz * rz
        u2z = p2xz * rx + p2yz * ry + p2zz * rz
        # s_q = u_qi R_i; axial vector of u
        sx = u0x * rx + u0y * ry + u0z * rz
        sy = u1x * rx + u1y * ry + u1z * rz
        sz = u2x * rx + u2y * ry + u2z * rz
        axux = u1z - u2y
        axuy = u2x - u0z
        axuz = u0y - u1x
        # vector a x R with a = i3 M0 + 3 i5 w - 1.5 i5 t + 7.5 i7 s; constant part -(i3 ax(M1) + 3 i5 ax(u))
        bx = i3 * m0x + i5 * (3.0 * wx - 1.5 * tx) + 7.5 * i7 * sx
        by = i3 * m0y + i5 * (3.0 * wy - 1.5 * ty) + 7.5 * i7 * sy
        bz = i3 * m0z + i5 * (3.0 * wz - 1.5 * tz) + 7.5 * i7 * sz
        ux[j] += by * rz - bz * ry - i3 * axm1x - 3.0 * i5 * axux
        uy[j] += bz * rx - bx * rz - i3 * axm1y - 3.0 * i5 * axuy
        uz[j] += bx * ry - by * rx - i3 * axm1z - 3.0 * i5 * axuz


@njit(nogil=True, fastmath=True, error_model="numpy", cache=True)
def _tree_chunks(x, y, z, ls, le, lc, lr, b_r0, b_r1, b_c0, b_c1, b_left, b_right, b_c, b_rho, b_rc, b_mom,
                 vx, vy, vz, stride, sg, sr, cg, cr, theta, kappa, out, counter, nchunk):
    """One task of :func:`lattice_tree_velocity`: chunks q = claim(counter) < nchunk of the target leaves
    (targets x, y, z in target-tree order; leaf L holds targets ls[L]..le[L], centre lc[L], radius lr[L]);
    out (n, 3) in target-tree order, overwritten. Leaves of the source tree act by the lattice kernel's
    arithmetic (:func:`aero.biot_savart.edge_sum` on the block's corners, each corner's 1/sqrt once per
    target; the block's corners and owned edges are first copied into contiguous local arrays, with
    zero-circulation padding where an edge is not the block's, so that its edges are two vectorised loops)."""
    nl = ls.shape[0]
    nrows = vx.shape[0] // stride
    stack = np.empty(STACK, np.int64)
    width = 1
    for i in range(nl):
        width = max(width, le[i] - ls[i])
    size = 1
    for k in range(b_r0.shape[0]):
        if b_left[k] < 0:
            size = max(size, (b_r1[k] - b_r0[k] + 1) * (b_c1[k] - b_c0[k] + 1))
    ux = np.empty(width)
    uy = np.empty(width)
    uz = np.empty(width)
    rx, ry, rz, ex, ey, ez = aligned_scratch(size + 1)
    bx = np.empty(size)
    by = np.empty(size)
    bz = np.empty(size)
    lsg = np.empty(size)
    lsr = np.empty(size)
    lcg = np.empty(size)
    lcr = np.empty(size)
    scale = 1.0 / FOUR_PI
    q = claim(counter)
    while q < nchunk:
        for L in range(q * nl // nchunk, (q + 1) * nl // nchunk):
            t0, t1 = ls[L], le[L]
            nt = t1 - t0
            xs, ys, zs = x[t0:t1], y[t0:t1], z[t0:t1]
            for j in range(nt):
                ux[j] = 0.0
                uy[j] = 0.0
                uz[j] = 0.0
            stack[0] = 0
            sp = 1
            while sp > 0:
                sp -= 1
                k = stack[sp]
                if b_rc[k] < 0.0:
                    continue  # a node without circulation
                dx = lc[L, 0] - b_c[k, 0]
                dy = lc[L, 1] - b_c[k, 1]
                dz = lc[L, 2] - b_c[k, 2]
                dist = np.sqrt(dx * dx + dy * dy + dz * dz)
                if b_rho[k] + kappa * b_rc[k] < theta * (dist - lr[L]):
                    _far(nt, xs, ys, zs, b_c[k, 0], b_c[k, 1], b_c[k, 2], b_mom[k], ux, uy, uz)
                elif b_left[k] < 0:  # the block's corners and owned edges into contiguous local arrays
                    r0, r1, c0, c1 = b_r0[k], b_r1[k], b_c0[k], b_c1[k]
                    w = min(c1, stride - 1) - c0 + 1
                    h = min(r1, nrows - 1) - r0 + 1
                    nspan = min(c1, stride - 1) - c0
                    for li in range(h):
                        own = li < r1 - r0
                        chord = own and r0 + li < nrows - 1
                        for kk in range(w):
                            gi = (r0 + li) * stride + c0 + kk
                            lo = li * w + kk
                            bx[lo], by[lo], bz[lo] = vx[gi], vy[gi], vz[gi]
                            if own and kk < nspan:
                                lsg[lo], lsr[lo] = sg[gi], sr[gi]
                            else:
                                lsg[lo], lsr[lo] = 0.0, 1.0
                            if chord and kk < c1 - c0:
                                lcg[lo], lcr[lo] = cg[gi], cr[gi]
                            else:
                                lcg[lo], lcr[lo] = 0.0, 1.0
                    nloc = h * w
                    for j in range(nt):
                        corner_vectors(xs[j], ys[j], zs[j], bx, by, bz, nloc, rx, ry, rz, ex, ey, ez)
                        sx, sy, sz = edge_sum(nloc - 1, rx, ry, rz, ex, ey, ez, rx[1:], ry[1:], rz[1:], ex[1:],
                                               ey[1:], ez[1:], lsg, lsr, 0.0, 0.0, 0.0)
                        if h > 1:
                            sx, sy, sz = edge_sum(nloc - w, rx, ry, rz, ex, ey, ez, rx[w:], ry[w:], rz[w:],
                                                   ex[w:], ey[w:], ez[w:], lcg, lcr, sx, sy, sz)
                        ux[j] += sx
                        uy[j] += sy
                        uz[j] += sz
                else:
                    stack[sp] = b_right[k]
                    stack[sp + 1] = b_left[k]
                    sp += 2
            for j in range(nt):
                out[t0 + j, 0] = ux[j] * scale
                out[t0 + j, 1] = uy[j] * scale
                out[t0 + j, 2] = uz[j] * scale
        q = claim(counter)


NEAR_COST = 1.6
"""Cost of one near-field edge-target pair of the treecode (a block's edges, padding included) in direct-sum pairs
(the lattice kernel's). Tuned: first measured 0.22 s against 0.13 s for the same 10-beat wake with theta = 0 (one
thread, the corner-block kernel); re-fitted with the targets-in-lanes kernel by ``scripts/studies/tree_cost.py``
(1.55 at 256 bits, 1.64 at 512 on an AVX-512 Xeon: results/tree_cost_*.json). It moves where
``wake_summation="auto"`` switches to the tree: with it the plan chose the faster sum in all 13 crossover cases at
both widths."""

FAR_COST = 3.0
"""Cost of one cluster-target far-field evaluation (:func:`_far`, ~80 FP operations) in direct-sum pairs (~34).
Estimated from the operation count, not fitted: at theta = 0.2 the crossover cases do too few far evaluations to
pin it (tree_cost.py's least-squares fit gave 15-19, with the same 13 decisions as 3.0)."""

TREE_MARGIN = 0.8
"""``plan``: the tree is worth it when its estimated cost is below this fraction of the direct sum's."""


@njit(cache=True)
def _plan(lc, lr, ln, b_c, b_rho, b_rc, b_left, b_right, b_r0, b_r1, b_c0, b_c1, nrows, stride, theta, kappa):
    """The traversal of :func:`_tree_chunks` without the arithmetic: (near-field edge-target pairs, far-field
    cluster-target evaluations)."""
    near = 0.0
    far = 0.0
    stack = np.empty(STACK, np.int64)
    for L in range(lc.shape[0]):
        stack[0] = 0
        sp = 1
        while sp > 0:
            sp -= 1
            k = stack[sp]
            if b_rc[k] < 0.0:
                continue
            dx = lc[L, 0] - b_c[k, 0]
            dy = lc[L, 1] - b_c[k, 1]
            dz = lc[L, 2] - b_c[k, 2]
            dist = np.sqrt(dx * dx + dy * dy + dz * dz)
            if b_rho[k] + kappa * b_rc[k] < theta * (dist - lr[L]):
                far += ln[L]
            elif b_left[k] < 0:
                w = min(b_c1[k], stride - 1) - b_c0[k] + 1
                h = min(b_r1[k], nrows - 1) - b_r0[k] + 1
                near += ln[L] * 2.0 * h * w
            else:
                stack[sp] = b_right[k]
                stack[sp + 1] = b_left[k]
                sp += 2
    return near, far


def _trees(targets, vx, vy, vz, stride, sg, sr, cg, cr, params: TreeParams):
    """Both trees of :func:`lattice_tree_velocity`: (source blocks, their nodes, the targets in tree order, the
    target leaves, the targets' permutation)."""
    blocks = _block_tree(vx, vy, vz, stride, params.source_leaf)
    nodes = _block_nodes(*blocks[:4], vx, vy, vz, stride, sg, sr, cg, cr)
    tperm, t_start, t_end, t_left, _ = _split(*(np.ascontiguousarray(targets[:, i]) for i in range(3)),
                                              params.target_leaf)
    xyz = tuple(np.ascontiguousarray(targets[tperm, i]) for i in range(3))
    return blocks, nodes, xyz, _target_leaves(t_start, t_end, t_left, *xyz), tperm


def _counts(trees, nrows: int, stride: int, params: TreeParams) -> tuple[float, float]:
    """(near-field edge-target pairs, far-field cluster-target evaluations) of the traversal on ``trees``."""
    (b_r0, b_r1, b_c0, b_c1, b_left, b_right), (b_c, b_rho, b_rc, _), _, (ls, le, lc, lr), _ = trees
    return _plan(lc, lr, le - ls, b_c, b_rho, b_rc, b_left, b_right, b_r0, b_r1, b_c0, b_c1, nrows, stride,
                 float(params.theta), float(params.core_factor))


def tree_work(targets, vx, vy, vz, stride, sg, sr, cg, cr, params: TreeParams = TreeParams()) -> tuple[float, float]:
    """The work :func:`lattice_tree_velocity` would do on these arguments, counted without evaluating anything:
    (near-field edge-target pairs, padding included; far-field cluster-target evaluations). ``plan`` weighs them
    by :data:`NEAR_COST` and :data:`FAR_COST` against the direct sum's 2 x targets x corners pairs."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    if targets.shape[0] == 0 or vx.shape[0] < 2:
        return 0.0, 0.0
    return _counts(_trees(targets, vx, vy, vz, stride, sg, sr, cg, cr, params), vx.shape[0] // stride, stride,
                   params)


def lattice_tree_velocity(targets, vx, vy, vz, stride, sg, sr, cg, cr, params: TreeParams = TreeParams(),
                          threads: int | None = None, plan: bool = False) -> np.ndarray | None:
    """Velocity (n, 3) [m/s] at targets (n, 3) [m] induced by the edges of a stacked lattice (the arrays of
    :func:`aero.lattice_lanes.lattice_induced_velocity`: corners vx, vy, vz (nc,) row-major with ``stride`` per
    row, span / chord edge circulations sg, cg and rr = |r0|^2 r_c^2 sr, cr per corner, zero-circulation padding
    where an edge does not exist), by the treecode with ``params``. threads: default numba's thread count; the
    result is the same, bit for bit, for any. plan: first estimate the tree's cost from its interaction counts
    (:data:`NEAR_COST`, :data:`FAR_COST`) and return None, having evaluated nothing, when it is not below
    :data:`TREE_MARGIN` x the direct sum's (n x 2 nc pairs)."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    n = targets.shape[0]
    out = np.zeros((n, 3))
    if n == 0 or vx.shape[0] < 2:
        return out
    trees = _trees(targets, vx, vy, vz, stride, sg, sr, cg, cr, params)
    if plan:
        near, far = _counts(trees, vx.shape[0] // stride, stride, params)
        if NEAR_COST * near + FAR_COST * far >= TREE_MARGIN * 2.0 * n * vx.shape[0]:
            return None
    (b_r0, b_r1, b_c0, b_c1, b_left, b_right), (b_c, b_rho, b_rc, b_mom), (x, y, z), (ls, le, lc, lr), tperm = trees
    res = np.empty((n, 3))
    run_chunked(_tree_chunks, (x, y, z, ls, le, lc, lr, b_r0, b_r1, b_c0, b_c1, b_left, b_right, b_c, b_rho, b_rc,
                               b_mom, vx, vy, vz, stride, sg, sr, cg, cr, float(params.theta),
                               float(params.core_factor), res),
                ls.shape[0], float(n) * 64.0 * np.log2(max(vx.shape[0], 2)), threads)
    out[tperm] = res
    return out


def lattice_tree(targets: np.ndarray, lattices, params: TreeParams = TreeParams(), threads: int | None = None,
                 plan: bool = False) -> np.ndarray | None:
    """:func:`aero.lattice.lattice_velocity` by the treecode: velocity (n, 3) [m/s] at targets (n, 3) [m]
    induced by the edges of the ring lattices (:class:`aero.lattice.Lattice`, wing or wake, Scully cores);
    lattices with the same number of corners per row share one tree. plan: None where the tree would not be
    the faster (:func:`lattice_tree_velocity`) for any group of lattices."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    out = np.zeros((targets.shape[0], 3))
    for stride, arrays in stacked_lattices(lattices).items():
        v = lattice_tree_velocity(targets, *arrays[:3], stride, *arrays[3:], params=params, threads=threads,
                                  plan=plan)
        if v is None:
            return None
        out += v
    return out


def tree_velocity(targets: np.ndarray, a: np.ndarray, b: np.ndarray, gamma: np.ndarray, rc2,
                  params: TreeParams = TreeParams(), threads: int | None = None) -> np.ndarray:
    """Velocity (n, 3) [m/s] at targets (n, 3) [m] induced by free segments a -> b (m, 3) [m] of circulation
    gamma (m,) [m^2/s] and squared core radius rc2 (m,) or scalar [m^2], by the treecode: the direct sum of
    :func:`aero.biot_savart.segment_velocity` to within what theta allows (theta = 0: the direct sum to
    rounding). The segments, put in spatial order (median bisection of their midpoints), are a lattice of one
    edge per row (2 corners a row), whose row blocks are then spatial clusters."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    a = np.asarray(a, dtype=float).reshape(-1, 3)
    b = np.asarray(b, dtype=float).reshape(-1, 3)
    gamma = np.asarray(gamma, dtype=float).ravel()
    rc2 = np.broadcast_to(np.asarray(rc2, dtype=float), gamma.shape)
    m = gamma.size
    if m == 0 or targets.shape[0] == 0:
        return np.zeros((targets.shape[0], 3))
    mid = 0.5 * (a + b)
    perm = _split(*(np.ascontiguousarray(mid[:, i]) for i in range(3)), 1)[0]
    v = np.empty((2 * m, 3))
    v[0::2], v[1::2] = a[perm], b[perm]
    d = b[perm] - a[perm]
    sg = np.zeros(2 * m)
    sr = np.ones(2 * m)
    sg[0::2] = gamma[perm]
    sr[0::2] = (d * d).sum(1) * rc2[perm]
    vx, vy, vz = (np.ascontiguousarray(v[:, i]) for i in range(3))
    return lattice_tree_velocity(targets, vx, vy, vz, 2, sg, sr, np.zeros(2 * m), np.ones(2 * m), params,
                                 threads)
