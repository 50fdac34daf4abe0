"""The free wake of one wing: a ring lattice in world coordinates whose vortex cores grow with age; and the opt-in
view of it the wing may take near the trailing edge (:func:`lump_near_wake`).

Vortex cores (Ramasamy & Leishman 2007, J. Am. Helicopter Soc. 52:214): r_c^2 = r0^2 + 4 a_L delta nu t with
a_L = 1.25643 (Lamb-Oseen), delta = 1 + a' |Gamma| / nu the turbulent-viscosity factor, t the age of the
segment.
"""

from __future__ import annotations

import numpy as np

from aero.lattice import Lattice, edge_circulations

A_LAMB = 1.25643
"""Lamb-Oseen constant a_L (Ramasamy & Leishman 2007)."""


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

    def lattice(self, r0: float, nu: float, a_prime: float, core_growth: bool, r_attached: float | None = None
                ) -> Lattice | None:
        """The wake's edges with grown cores (None before the first shed). r0: initial core [m]; r_attached: core
        of the spanwise edges on the trailing edge (row 0), equal to the bound core so that they cancel the
        bound trailing-edge segment exactly when the circulation does not change (default r0)."""
        if self.rows == 0:
            return None
        span, chord = edge_circulations(self.gamma)

        def core2(gamma, age):
            if not core_growth:
                return np.full(gamma.shape, r0 * r0)
            return r0 * r0 + 4.0 * A_LAMB * nu * (1.0 + a_prime * np.abs(gamma) / nu) * age[:, None]

        span_rc2 = core2(span, self.age)
        chord_rc2 = core2(chord, 0.5 * (self.age[1:] + self.age[:-1]))
        if r_attached is not None:
            span_rc2[0] = r_attached * r_attached
        return Lattice(self.vertices, span, span_rc2, chord, chord_rc2)


def lump_near_wake(lat: Lattice, lengths: np.ndarray, r_attached2: float, zones: int) -> Lattice:
    """The wake lattice as the wing sees it with ``UVLMConfig.near_wake_zones`` = zones >= 1 (opt-in, a study).

    Each corner's distance d from the attached row (the newest wake vortex) is cut into zones of one chordwise
    panel, ``lengths`` (ns+1,) [m] at each spanwise station; the corners in zone z < zones move onto the zone's
    newest corner (zone 0: the attached row itself), so that the rows shed finer than the bound panels act as the
    lattice lumps each panel's vorticity, as they do when the wake moves one panel per step. The corners moved into
    zone 0 take the attached row's core (r_attached2 [m^2]). Returns a new Lattice; the wake itself is unchanged.
    """
    G = lat.G.copy()
    d = np.linalg.norm(G[1:] - G[0], axis=-1)  # (rows, ns+1)
    zone = np.floor(d / lengths).astype(int)
    span_rc2 = np.array(lat.span_rc2, copy=True)
    cols = np.arange(G.shape[1])
    for z in range(zones):
        inz = zone == z
        if not inz.any():
            continue
        anchor = G[0] if z == 0 else G[1:][np.argmax(inz, axis=0), cols]  # newest corner of the zone
        G[1:][inz] = np.broadcast_to(anchor, G[1:].shape)[inz]
        if z == 0:
            span_rc2[1:][inz[:, :-1] & inz[:, 1:]] = r_attached2
    return Lattice(G, lat.span_gamma, span_rc2, lat.chord_gamma, lat.chord_rc2)
