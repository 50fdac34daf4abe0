"""Vortex lattices as unique straight segments, and the free wake of one wing.

A lattice of vortex rings on a corner grid G (r+1, s+1, 3) with ring circulations g (r, s) (each ring's loop
(i,j) -> (i,j+1) -> (i+1,j+1) -> (i+1,j)) is the set of its shared edges with net circulations:
spanwise edges (i, j)->(i, j+1), i = 0..r, carry g[i,j] - g[i-1,j]; chordwise edges (i, j)->(i+1, j),
j = 0..s, carry g[i,j-1] - g[i,j] (circulation outside the lattice is zero). This halves the Biot-Savart work
of a ring-by-ring evaluation.

Vortex cores (Ramasamy & Leishman 2007, J. Am. Helicopter Soc. 52:214): r_c^2 = r0^2 + 4 a_L delta nu t with
a_L = 1.25643 (Lamb-Oseen), delta = 1 + a' |Gamma| / nu the turbulent-viscosity factor, t the age of the
segment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

A_LAMB = 1.25643
"""Lamb-Oseen constant a_L (Ramasamy & Leishman 2007)."""


@dataclass(frozen=True)
class Segments:
    """Straight vortex segments a -> b (m, 3) [m], circulation (m,) [m^2/s], squared core radius (m,) [m^2]."""

    a: np.ndarray
    b: np.ndarray
    gamma: np.ndarray
    rc2: np.ndarray

    @staticmethod
    def concat(parts) -> Segments:
        parts = [p for p in parts if p.gamma.size]
        if not parts:
            z = np.zeros((0, 3))
            return Segments(z, z, np.zeros(0), np.zeros(0))
        return Segments(*(np.concatenate([getattr(p, f) for p in parts]) for f in ("a", "b", "gamma", "rc2")))


def lattice_segments(G: np.ndarray, g: np.ndarray, rc2_span: np.ndarray, rc2_chord: np.ndarray,
                     skip_last_row: bool = False) -> Segments:
    """Unique edges of a ring lattice.

    Args:
        G (r+1, s+1, 3): corner grid; g (r, s): ring circulations.
        rc2_span (r+1, s) and rc2_chord (r, s+1): squared core radii of the spanwise and chordwise edges.
        skip_last_row: leave out the spanwise edges of the last corner row (a wing's trailing-edge segment,
            which carries no force under the Kutta condition).
    """
    r, s = g.shape
    gp = np.zeros((r + 2, s + 2))
    gp[1:-1, 1:-1] = g
    span_gamma = gp[1:, 1:-1] - gp[:-1, 1:-1]  # (r+1, s): g[i] - g[i-1]
    chord_gamma = gp[1:-1, :-1] - gp[1:-1, 1:]  # (r, s+1): g[:, j-1] - g[:, j]
    rows = r if skip_last_row else r + 1
    a = np.concatenate([G[:rows, :-1].reshape(-1, 3), G[:-1, :].reshape(-1, 3)])
    b = np.concatenate([G[:rows, 1:].reshape(-1, 3), G[1:, :].reshape(-1, 3)])
    gam = np.concatenate([span_gamma[:rows].ravel(), chord_gamma.ravel()])
    rc2 = np.concatenate([np.broadcast_to(rc2_span, (r + 1, s))[:rows].ravel(),
                          np.broadcast_to(rc2_chord, (r, s + 1)).ravel()])
    return Segments(a, b, gam, rc2)


class Wake:
    """The free wake of one wing, in world coordinates.

    vertices (rows+1, ns+1, 3): corner grid, row 0 attached to the wing's trailing edge (newest row first);
    gamma (rows, ns): ring circulations; age (rows+1,): time since each corner row left the trailing edge [s].
    """

    def __init__(self, n_span: int):
        self.vertices = np.zeros((0, n_span + 1, 3))
        self.gamma = np.zeros((0, n_span))
        self.age = np.zeros(0)

    @property
    def rows(self) -> int:
        return self.gamma.shape[0]

    def attach(self, trailing_edge: np.ndarray) -> None:
        """Move the newest corner row onto the trailing edge (ns+1, 3) at its current position."""
        if self.vertices.shape[0]:
            self.vertices[0] = trailing_edge

    def shed(self, trailing_edge: np.ndarray, gamma_te: np.ndarray) -> None:
        """Add a ring row of circulation gamma_te (ns,) between the trailing edge and the previous newest row."""
        if self.vertices.shape[0] == 0:
            self.vertices = np.stack([trailing_edge, trailing_edge]).copy()
            self.age = np.zeros(2)
        else:
            self.vertices = np.concatenate([trailing_edge[None], self.vertices])
            self.age = np.concatenate([[0.0], self.age])
        self.gamma = np.concatenate([gamma_te[None], self.gamma])

    def truncate(self, rows: int) -> None:
        """Keep only the ``rows`` newest ring rows (the oldest are dropped)."""
        if self.rows > rows:
            self.vertices = self.vertices[:rows + 1]
            self.gamma = self.gamma[:rows]
            self.age = self.age[:rows + 1]

    def segments(self, r0: float, nu: float, a_prime: float, core_growth: bool, r_attached: float | None = None
                 ) -> Segments:
        """The wake's unique edges with grown cores. r0: initial core [m]; r_attached: core of the spanwise
        edges on the trailing edge (row 0), equal to the bound core so that they cancel the bound trailing-edge
        segment exactly when the circulation does not change (default r0)."""
        if self.rows == 0:
            return Segments.concat([])
        ns = self.gamma.shape[1]
        if core_growth:
            age_span = np.broadcast_to(self.age[:, None], (self.rows + 1, ns))
            age_chord = np.broadcast_to(0.5 * (self.age[1:] + self.age[:-1])[:, None], (self.rows, ns + 1))
        else:
            age_span = np.zeros((self.rows + 1, ns))
            age_chord = np.zeros((self.rows, ns + 1))
        seg = lattice_segments(self.vertices, self.gamma, age_span, age_chord)
        if core_growth:
            delta = 1.0 + a_prime * np.abs(seg.gamma) / nu
            rc2 = r0 * r0 + 4.0 * A_LAMB * delta * nu * seg.rc2  # rc2 held the ages
        else:
            rc2 = np.full_like(seg.gamma, r0 * r0)
        if r_attached is not None:
            rc2[:ns] = r_attached * r_attached  # spanwise edges of corner row 0 come first
        return Segments(seg.a, seg.b, seg.gamma, rc2)
