"""Vortex-ring lattices as unique straight edges, and the velocity they induce.

A lattice of vortex rings on a corner grid G (r+1, s+1, 3) [m] with ring circulations g (r, s) [m^2/s] (each
ring's loop (i,j) -> (i,j+1) -> (i+1,j+1) -> (i+1,j)) is the set of its shared edges with net circulations:
spanwise edges (i, j)->(i, j+1), i = 0..r, carry g[i,j] - g[i-1,j]; chordwise edges (i, j)->(i+1, j),
j = 0..s, carry g[i,j-1] - g[i,j] (circulation outside the lattice is zero). This halves the Biot-Savart work
of a ring-by-ring evaluation, and the corners the edges share let the kernel compute each target's distances
once per corner, not twice per edge (:func:`aero.lattice_lanes.lattice_induced_velocity`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from aero.lattice_lanes import lattice_induced_velocity


@dataclass(frozen=True)
class Segments:
    """Straight vortex segments a -> b (m, 3) [m], circulation (m,) [m^2/s], squared core radius (m,) [m^2]."""

    a: np.ndarray
    b: np.ndarray
    gamma: np.ndarray
    rc2: np.ndarray


@dataclass(frozen=True)
class Lattice:
    """A ring lattice's unique edges.

    G (r+1, s+1, 3): corner grid [m]; spanwise edges (i, j)->(i, j+1): span_gamma (r+1, s) [m^2/s] and squared
    core radii span_rc2 (r+1, s) [m^2]; chordwise edges (i, j)->(i+1, j): chord_gamma (r, s+1), chord_rc2
    (r, s+1).
    """

    G: np.ndarray
    span_gamma: np.ndarray
    span_rc2: np.ndarray
    chord_gamma: np.ndarray
    chord_rc2: np.ndarray

    def segments(self, skip_last_row: bool = False) -> Segments:
        """The edges as segments: spanwise edges row by row, then chordwise. skip_last_row leaves out the
        spanwise edges of the last corner row (a wing's trailing-edge segment, which carries no force under the
        Kutta condition)."""
        G = self.G
        rows = G.shape[0] - 1 if skip_last_row else G.shape[0]
        a = np.concatenate([G[:rows, :-1].reshape(-1, 3), G[:-1, :].reshape(-1, 3)])
        b = np.concatenate([G[:rows, 1:].reshape(-1, 3), G[1:, :].reshape(-1, 3)])
        gam = np.concatenate([self.span_gamma[:rows].ravel(), self.chord_gamma.ravel()])
        rc2 = np.concatenate([self.span_rc2[:rows].ravel(), self.chord_rc2.ravel()])
        return Segments(a, b, gam, rc2)


def edge_circulations(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Net circulations of the spanwise (r+1, s) and chordwise (r, s+1) edges of rings g (r, s)."""
    r, s = g.shape
    gp = np.zeros((r + 2, s + 2))
    gp[1:-1, 1:-1] = g
    return gp[1:, 1:-1] - gp[:-1, 1:-1], gp[1:-1, :-1] - gp[1:-1, 1:]


def ring_lattice(G: np.ndarray, g: np.ndarray, span_rc2, chord_rc2) -> Lattice:
    """The lattice of rings g (r, s) on corners G (r+1, s+1, 3); span_rc2 and chord_rc2: squared cores of the
    spanwise and chordwise edges (scalars or arrays that broadcast to (r+1, s) and (r, s+1)) [m^2]."""
    r, s = g.shape
    span, chord = edge_circulations(g)
    return Lattice(G, span, np.broadcast_to(np.asarray(span_rc2, float), (r + 1, s)),
                   chord, np.broadcast_to(np.asarray(chord_rc2, float), (r, s + 1)))


@njit(cache=True)
def _fill(G, span_gamma, span_rc2, chord_gamma, chord_rc2, off, vx, vy, vz, sg, sr, cg, cr):
    """Write one lattice into the kernel arrays from corner ``off`` on: its corners G (r+1, s+1, 3) row-major
    into vx, vy, vz, and per corner the edges that start there, padded with zero-circulation edges (gamma 0,
    rr 1) where there is none: spanwise (to the next corner in the row) sg, sr = |r0|^2 r_c^2, chordwise (to the
    same corner of the next row) cg, cr. Same arithmetic as numpy's ((b - a) ** 2).sum(-1) * rc2 (no fastmath,
    so bit for bit)."""
    r1, s1 = G.shape[0], G.shape[1]
    for i in range(r1):
        for j in range(s1):
            c = off + i * s1 + j
            vx[c] = G[i, j, 0]
            vy[c] = G[i, j, 1]
            vz[c] = G[i, j, 2]
            if j < s1 - 1:
                dx = G[i, j + 1, 0] - G[i, j, 0]
                dy = G[i, j + 1, 1] - G[i, j, 1]
                dz = G[i, j + 1, 2] - G[i, j, 2]
                sg[c] = span_gamma[i, j]
                sr[c] = (dx * dx + dy * dy + dz * dz) * span_rc2[i, j]
            else:
                sg[c] = 0.0
                sr[c] = 1.0
            if i < r1 - 1:
                dx = G[i + 1, j, 0] - G[i, j, 0]
                dy = G[i + 1, j, 1] - G[i, j, 1]
                dz = G[i + 1, j, 2] - G[i, j, 2]
                cg[c] = chord_gamma[i, j]
                cr[c] = (dx * dx + dy * dy + dz * dz) * chord_rc2[i, j]
            else:
                cg[c] = 0.0
                cr[c] = 1.0


def stacked_lattices(lattices) -> dict[int, np.ndarray]:
    """The kernel arrays of the lattices, stacked per row length: {stride: (7, nc) array of vx, vy, vz, sg, sr, cg,
    cr} (:func:`_fill`; lattices with no edge are left out)."""
    groups: dict[int, list[Lattice]] = {}
    for lat in lattices:
        if lat.span_gamma.size + lat.chord_gamma.size:
            groups.setdefault(lat.G.shape[1], []).append(lat)
    out = {}
    for stride, lats in groups.items():
        arrays = np.empty((7, stride * sum(lat.G.shape[0] for lat in lats)))
        off = 0
        for lat in lats:
            # contiguous copies of the broadcast core arrays: one compiled specialisation of _fill, not two
            _fill(*(np.ascontiguousarray(a) for a in (lat.G, lat.span_gamma, lat.span_rc2, lat.chord_gamma,
                                                      lat.chord_rc2)), off, *arrays)
            off += lat.G.shape[0] * stride
        out[stride] = arrays
    return out


def lattice_velocity(targets: np.ndarray, lattices, precision: str = "float64") -> np.ndarray:
    """Velocity (n, 3) [m/s] at targets (n, 3) [m] induced by the edges of all lattices (Scully cores, the
    formula of :mod:`aero.biot_savart`). Lattices with the same number of corners per row share one kernel
    call. precision: the pair evaluations' (:data:`aero.biot_savart.PRECISIONS`)."""
    targets = np.ascontiguousarray(targets, dtype=float).reshape(-1, 3)
    out = np.zeros((targets.shape[0], 3))
    for stride, arrays in stacked_lattices(lattices).items():
        vx, vy, vz, sg, sr, cg, cr = arrays
        lattice_induced_velocity(targets, vx, vy, vz, stride, sg, sr, cg, cr, out, precision=precision)
    return out
