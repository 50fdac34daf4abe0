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
  through the regularised (Scully-core) segment formula of :mod:`aero.biot_savart` (the lattice kernel's
  arithmetic: 1/sqrt by :func:`aero.biot_savart.rsqrt`, K = r0 . (r1/|r1| - r2/|r2|), one division).
* **Opening criterion (the error control).** A cluster acts through its moments on a leaf of targets only if,
  for every target x of the leaf, ``(rho + r_c,max) < theta |x - c|``: rho the cluster's radius, r_c,max the
  largest core radius among its segments (the far field ignores the cores, whose effect on a segment's velocity
  at distance h from its line is a factor h^2 / (h^2 + r_c^2)), theta the one parameter (:class:`TreeParams`).
  theta -> 0 opens every cluster: the direct sum (to rounding). The error of the expansion falls as theta^3;
  measured bounds are in tests/aero/test_treecode.py and docs/performance.md ("Treecode").
* **Trees.** Sources (by segment midpoint) and targets are split into binary trees by median bisection along the
  longest side of each node's bounding box (deterministic: stable sorts), rebuilt every call (the wake moves every
  step). Targets are evaluated a leaf at a time: one traversal of the source tree per target leaf, its interaction
  decisions shared by the leaf's targets, whose loops then vectorise.

Determinism: a target's sum is computed by one task in a fixed order (the traversal of its leaf), so results are
bit-identical for any thread count and chunking (:func:`aero.scheduling.run_chunked` over target leaves).

Units SI: positions [m], circulations [m^2/s], squared cores [m^2], velocities [m/s]; any one Cartesian frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from aero.biot_savart import FOUR_PI, RSQRT_MIN, TINY, claim, rsqrt
from aero.scheduling import run_chunked

N_MOMENTS = 30
"""Per cluster: M0 (3), M1 (3 x 3, row-major q, k), M2 (3 x 6: q, then kl in xx, yy, zz, xy, xz, yz)."""

STACK = 512
"""Depth of the traversal stack (a binary tree of 1e9 leaves needs < 64)."""


@dataclass(frozen=True)
class TreeParams:
    """Error control and granularity of the treecode.

    theta: opening angle, (cluster radius + its largest core radius) / distance below which a cluster acts by its
    moments on every target of a target leaf (0: direct sum); source_leaf, target_leaf: most segments / targets per
    leaf (granularity only: the result's accuracy is set by theta; tuned for speed, docs/performance.md).
    """

    theta: float = 0.4
    source_leaf: int = 32
    target_leaf: int = 32

    def __post_init__(self):
        if not (np.isfinite(self.theta) and 0.0 <= self.theta < 1.0):
            raise ValueError(f"TreeParams.theta must lie in [0, 1), got {self.theta!r}")
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
def _source_nodes(start, end, ax, ay, az, dx, dy, dz, g, rc2):
    """Per node (segments in tree order): centre (nodes, 3) [m], radius covering every segment end point [m],
    largest core radius [m], moments (nodes, N_MOMENTS) about the centre."""
    nn = start.shape[0]
    centre = np.empty((nn, 3))
    rho = np.empty(nn)
    rc = np.empty(nn)
    mom = np.zeros((nn, N_MOMENTS))
    for k in range(nn):
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        r2max = 0.0
        for j in range(start[k], end[k]):
            a = (ax[j], ay[j], az[j])
            b = (ax[j] + dx[j], ay[j] + dy[j], az[j] + dz[j])
            for q in range(3):
                lo[q] = min(lo[q], a[q], b[q])
                hi[q] = max(hi[q], a[q], b[q])
            r2max = max(r2max, rc2[j])
        c = 0.5 * (lo + hi)
        centre[k] = c
        rad2 = 0.0
        for j in range(start[k], end[k]):
            ex = ax[j] - c[0]
            ey = ay[j] - c[1]
            ez = az[j] - c[2]
            rad2 = max(rad2, ex * ex + ey * ey + ez * ez)
            ex += dx[j]
            ey += dy[j]
            ez += dz[j]
            rad2 = max(rad2, ex * ex + ey * ey + ez * ez)
            d = (dx[j], dy[j], dz[j])
            s = (ax[j] + 0.5 * dx[j] - c[0], ay[j] + 0.5 * dy[j] - c[1], az[j] + 0.5 * dz[j] - c[2])
            for q in range(3):
                al = g[j] * d[q]
                mom[k, q] += al
                for kk in range(3):
                    mom[k, 3 + 3 * q + kk] += al * s[kk]
                b0 = 12 + 6 * q
                mom[k, b0 + 0] += al * (s[0] * s[0] + d[0] * d[0] / 12.0)
                mom[k, b0 + 1] += al * (s[1] * s[1] + d[1] * d[1] / 12.0)
                mom[k, b0 + 2] += al * (s[2] * s[2] + d[2] * d[2] / 12.0)
                mom[k, b0 + 3] += al * (s[0] * s[1] + d[0] * d[1] / 12.0)
                mom[k, b0 + 4] += al * (s[0] * s[2] + d[0] * d[2] / 12.0)
                mom[k, b0 + 5] += al * (s[1] * s[2] + d[1] * d[2] / 12.0)
        rho[k] = np.sqrt(rad2)
        rc[k] = np.sqrt(r2max)
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
def _far(t0, t1, x, y, z, cx, cy, cz, m, ux, uy, uz):
    """Add 4 pi x the far field of one cluster (centre cx, cy, cz; moments m (N_MOMENTS,)) to ux, uy, uz at the
    targets t0..t1 (leaf-local index j - t0)."""
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
    for j in range(t0, t1):
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
        k = j - t0
        ux[k] += by * rz - bz * ry - i3 * axm1x - 3.0 * i5 * axux
        uy[k] += bz * rx - bx * rz - i3 * axm1y - 3.0 * i5 * axuy
        uz[k] += bx * ry - by * rx - i3 * axm1z - 3.0 * i5 * axuz


@njit(fastmath=True, error_model="numpy", inline="always", cache=True)
def _near(t0, t1, x, y, z, s0, s1, ax, ay, az, dx, dy, dz, g, rr, ux, uy, uz):
    """Add 4 pi x the exact velocity of segments s0..s1 (regularised, :mod:`aero.biot_savart`'s formula) to
    ux, uy, uz at the targets t0..t1."""
    for j in range(t0, t1):
        px, py, pz = x[j], y[j], z[j]
        sx = 0.0
        sy = 0.0
        sz = 0.0
        for k in range(s0, s1):
            r1x = px - ax[k]
            r1y = py - ay[k]
            r1z = pz - az[k]
            r2x = r1x - dx[k]
            r2y = r1y - dy[k]
            r2z = r1z - dz[k]
            i1 = rsqrt(max(r1x * r1x + r1y * r1y + r1z * r1z, RSQRT_MIN))
            i2 = rsqrt(max(r2x * r2x + r2y * r2y + r2z * r2z, RSQRT_MIN))
            cx = r1y * r2z - r1z * r2y
            cy = r1z * r2x - r1x * r2z
            cz = r1x * r2y - r1y * r2x
            K = dx[k] * (r1x * i1 - r2x * i2) + dy[k] * (r1y * i1 - r2y * i2) + dz[k] * (r1z * i1 - r2z * i2)
            f = g[k] * K / (cx * cx + cy * cy + cz * cz + rr[k] + TINY)
            sx += f * cx
            sy += f * cy
            sz += f * cz
        ux[j - t0] += sx
        uy[j - t0] += sy
        uz[j - t0] += sz


@njit(nogil=True, fastmath=True, error_model="numpy", cache=True)
def _tree_chunks(x, y, z, ls, le, lc, lr, s_start, s_end, s_left, s_right, s_c, s_rho, s_rc, s_mom,
                 ax, ay, az, dx, dy, dz, g, rr, theta, out, counter, nchunk):
    """One task of :func:`tree_velocity`: chunks q = claim(counter) < nchunk of the target leaves; out (n, 3) in
    target tree order, overwritten."""
    nl = ls.shape[0]
    stack = np.empty(STACK, np.int64)
    width = 0
    for i in range(nl):
        width = max(width, le[i] - ls[i])
    ux = np.empty(width)
    uy = np.empty(width)
    uz = np.empty(width)
    scale = 1.0 / FOUR_PI
    q = claim(counter)
    while q < nchunk:
        for L in range(q * nl // nchunk, (q + 1) * nl // nchunk):
            t0, t1 = ls[L], le[L]
            for j in range(t1 - t0):
                ux[j] = 0.0
                uy[j] = 0.0
                uz[j] = 0.0
            stack[0] = 0
            sp = 1
            while sp > 0:
                sp -= 1
                k = stack[sp]
                ex = lc[L, 0] - s_c[k, 0]
                ey = lc[L, 1] - s_c[k, 1]
                ez = lc[L, 2] - s_c[k, 2]
                dist = np.sqrt(ex * ex + ey * ey + ez * ez)
                if s_rho[k] + s_rc[k] < theta * (dist - lr[L]):
                    _far(t0, t1, x, y, z, s_c[k, 0], s_c[k, 1], s_c[k, 2], s_mom[k], ux, uy, uz)
                elif s_left[k] < 0:
                    _near(t0, t1, x, y, z, s_start[k], s_end[k], ax, ay, az, dx, dy, dz, g, rr, ux, uy, uz)
                else:
                    stack[sp] = s_right[k]
                    stack[sp + 1] = s_left[k]
                    sp += 2
            for j in range(t1 - t0):
                out[t0 + j, 0] = ux[j] * scale
                out[t0 + j, 1] = uy[j] * scale
                out[t0 + j, 2] = uz[j] * scale
        q = claim(counter)


def tree_velocity(targets: np.ndarray, a: np.ndarray, b: np.ndarray, gamma: np.ndarray, rc2,
                  params: TreeParams = TreeParams(), threads: int | None = None) -> np.ndarray:
    """Velocity (n, 3) [m/s] at targets (n, 3) [m] induced by the segments a -> b (m, 3) [m] of circulation gamma
    (m,) [m^2/s] and squared core radius rc2 (m,) or scalar [m^2], by the treecode (module docstring): the
    direct sum of :func:`aero.biot_savart.segment_velocity` to within the error theta allows (params.theta = 0:
    the direct sum to rounding). Segments with zero circulation are left out. threads: default numba's thread
    count; the result is the same, bit for bit, for any."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    a = np.asarray(a, dtype=float).reshape(-1, 3)
    d = np.asarray(b, dtype=float).reshape(-1, 3) - a
    gamma = np.asarray(gamma, dtype=float).ravel()
    rc2 = np.broadcast_to(np.asarray(rc2, dtype=float), gamma.shape)
    n = targets.shape[0]
    out = np.zeros((n, 3))
    keep = gamma != 0.0
    if n == 0 or not keep.any():
        return out
    a, d, gamma, rc2 = a[keep], d[keep], gamma[keep], rc2[keep]
    mid = a + 0.5 * d
    perm, s_start, s_end, s_left, s_right = _split(*(np.ascontiguousarray(mid[:, i]) for i in range(3)),
                                                   params.source_leaf)
    ax, ay, az, dx, dy, dz = (np.ascontiguousarray(v[perm]) for v in (a[:, 0], a[:, 1], a[:, 2], d[:, 0], d[:, 1],
                                                                        d[:, 2]))
    g = np.ascontiguousarray(gamma[perm])
    c2 = np.ascontiguousarray(rc2[perm])
    rr = (dx * dx + dy * dy + dz * dz) * c2
    s_c, s_rho, s_rc, s_mom = _source_nodes(s_start, s_end, ax, ay, az, dx, dy, dz, g, c2)
    tperm, t_start, t_end, t_left, _ = _split(*(np.ascontiguousarray(targets[:, i]) for i in range(3)),
                                              params.target_leaf)
    x, y, z = (np.ascontiguousarray(targets[tperm, i]) for i in range(3))
    ls, le, lc, lr = _target_leaves(t_start, t_end, t_left, x, y, z)
    res = np.empty((n, 3))
    run_chunked(_tree_chunks, (x, y, z, ls, le, lc, lr, s_start, s_end, s_left, s_right, s_c, s_rho, s_rc, s_mom,
                               ax, ay, az, dx, dy, dz, g, rr, float(params.theta), res),
                ls.shape[0], float(n) * 64.0 * np.log2(max(gamma.size, 2)), threads)
    out[tperm] = res
    return out
