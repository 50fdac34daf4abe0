"""Biot-Savart kernels for straight vortex segments with a regularised core (numba, float64).

Velocity induced at a point p by a straight segment from a to b of circulation Gamma (Katz & Plotkin 2001,
Eq. 10.115), regularised with the Scully (Vatistas n = 1) core profile, v_theta = Gamma h / (2 pi (h^2 + r_c^2))
(Scully 1975; the profile Ramasamy & Leishman 2007 pair with their core-growth law):

    v = Gamma / (4 pi) * (r1 x r2) * K / (|r1 x r2|^2 + |r0|^2 r_c^2),   K = r0 . (r1/|r1| - r2/|r2|),

with r1 = p - a, r2 = p - b, r0 = b - a. Since |r1 x r2| = h |r0| (h the distance from the segment's line),
this is the singular formula times h^2 / (h^2 + r_c^2): exact far from the core, zero on the axis. With
r_c = 0 it is the classical formula (a point on the segment's line gets zero).

Segments are passed as structure-of-arrays: start (ax, ay, az), direction r0 = b - a (dx, dy, dz), gamma,
and rr = |r0|^2 r_c^2; targets as (n, 3). The loops are parallel over targets (``prange``) and, with
``fastmath`` (float64 still; only reassociation of the sums changes, ~1e-15 relative) and IEEE division
(``error_model="numpy"``: no Python zero-division checks), vectorised over segments. Cost per evaluation: two
square roots and one division, which bound it at ~0.45 G evaluations/s per core with 256-bit vectors here.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

FOUR_PI = 4.0 * np.pi
TINY = 1e-300
"""Guards divisions by zero (a target on a segment's end point gets zero from it)."""


@njit(parallel=True, fastmath=True, error_model="numpy", cache=True)
def induced_velocity(targets, ax, ay, az, dx, dy, dz, gamma, rr, out):
    """out[i] = velocity (3,) at targets[i] induced by all segments [m/s]; out is overwritten."""
    n = targets.shape[0]
    m = ax.shape[0]
    for i in prange(n):
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


@njit(parallel=True, fastmath=False, cache=True)
def ring_influence(targets, normals, corners, rc2, out):
    """out[i, l] = normal velocity at targets[i] (along normals[i]) induced by ring l with unit circulation.

    corners (L, 4, 3): each ring's corners in loop order (the circulation runs 0 -> 1 -> 2 -> 3 -> 0).
    """
    n = targets.shape[0]
    L = corners.shape[0]
    for i in prange(n):
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

