"""Wing surface meshes and their vortex-ring lattices (Katz & Plotkin 2001, Sec. 12.3 and 13.12).

Frames: a wing mesh lives in its WING frame (x toward the leading edge, y along the span, z = x cross y, the
upper-surface normal). Index conventions: chordwise index i = 0 at the leading edge, spanwise j = 0 at the
root for a left wing. All lengths in metres.

A panel grid P (nc+1, ns+1, 3) of the mean surface defines the vortex rings: ring corners lie a quarter panel
behind the panel corners (the leading segment of each ring on the panel's quarter chord; the trailing-edge
row extends a quarter panel past the trailing edge), and the collocation points are the ring centres
(the panels' three-quarter-chord points).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

MIN_PANEL_AREA_FRACTION = 1e-8
"""A ring smaller than this fraction of the mean ring area makes the mesh degenerate."""


@dataclass(frozen=True)
class WingMesh:
    """Panel corners (nc+1, ns+1, 3) in the wing frame [m]. Build with :func:`wing_mesh`."""

    vertices: np.ndarray

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 3 or v.shape[2] != 3 or v.shape[0] < 2 or v.shape[1] < 2:
            raise ValueError(f"mesh vertices must have shape (nc+1, ns+1, 3) with nc, ns >= 1, got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError("mesh vertices must be finite")
        object.__setattr__(self, "vertices", v)
        a = self.ring_areas
        if not np.all(a > MIN_PANEL_AREA_FRACTION * a.mean()):
            raise ValueError(f"degenerate mesh: {int((a <= MIN_PANEL_AREA_FRACTION * a.mean()).sum())} ring(s) "
                             "with (near) zero area")

    @property
    def shape(self) -> tuple[int, int]:
        """(nc, ns): rings chordwise and spanwise."""
        return self.vertices.shape[0] - 1, self.vertices.shape[1] - 1

    @cached_property
    def rings(self) -> np.ndarray:
        """Vortex-ring corner grid (nc+1, ns+1, 3), a quarter panel behind the panel corners."""
        P = self.vertices
        R = np.empty_like(P)
        R[:-1] = P[:-1] + 0.25 * (P[1:] - P[:-1])
        R[-1] = P[-1] + 0.25 * (P[-1] - P[-2])
        return R

    @cached_property
    def collocation(self) -> np.ndarray:
        """Ring centres (nc, ns, 3)."""
        R = self.rings
        return 0.25 * (R[:-1, :-1] + R[1:, :-1] + R[:-1, 1:] + R[1:, 1:])

    @cached_property
    def normals(self) -> np.ndarray:
        """Unit ring normals (nc, ns, 3), by the cross product of the diagonals, on the wing's +z side."""
        R = self.rings
        n = np.cross(R[:-1, 1:] - R[1:, :-1], R[1:, 1:] - R[:-1, :-1])
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    @cached_property
    def ring_areas(self) -> np.ndarray:
        """Ring areas (nc, ns) [m^2]."""
        R = self.rings
        n = np.cross(R[:-1, 1:] - R[1:, :-1], R[1:, 1:] - R[:-1, :-1])
        return 0.5 * np.linalg.norm(n, axis=-1)

    @cached_property
    def panel_areas(self) -> np.ndarray:
        """Panel areas (nc, ns) [m^2] of the surface grid."""
        P = self.vertices
        n = np.cross(P[:-1, 1:] - P[1:, :-1], P[1:, 1:] - P[:-1, :-1])
        return 0.5 * np.linalg.norm(n, axis=-1)

    @property
    def mean_chordwise_length(self) -> float:
        """Mean chordwise panel length [m] (area-weighted)."""
        P = self.vertices
        dc = np.linalg.norm(P[1:] - P[:-1], axis=-1)  # (nc, ns+1)
        dc = 0.5 * (dc[:, 1:] + dc[:, :-1])
        return float((dc * self.panel_areas).sum() / self.panel_areas.sum())


def wing_mesh(span: np.ndarray, x_le: np.ndarray, x_te: np.ndarray, n_chord: int) -> WingMesh:
    """A flat wing mesh in the wing frame.

    Args:
        span (ns+1,): spanwise stations y >= 0 [m], increasing.
        x_le, x_te (ns+1,): leading- and trailing-edge x at the stations [m] (x_le >= x_te). A zero chord at
            the root or tip gives triangular end rings.
        n_chord: chordwise rings (uniform spacing).
    """
    span, x_le, x_te = (np.asarray(a, dtype=float) for a in (span, x_le, x_te))
    if n_chord < 1 or span.ndim != 1 or span.size < 2:
        raise ValueError(f"need n_chord >= 1 and >= 2 spanwise stations, got n_chord={n_chord}, {span.size} stations")
    if not (span.shape == x_le.shape == x_te.shape):
        raise ValueError("span, x_le and x_te must have the same shape")
    if not np.all(np.diff(span) > 0):
        raise ValueError("spanwise stations must be strictly increasing")
    if np.any(x_le < x_te):
        raise ValueError("leading edge behind the trailing edge (x_le < x_te) at some station")
    s = np.linspace(0.0, 1.0, n_chord + 1)[:, None]
    x = x_le[None, :] + s * (x_te - x_le)[None, :]
    y = np.broadcast_to(span[None, :], x.shape)
    return WingMesh(np.stack([x, y, np.zeros_like(x)], axis=-1))


def mirror_mesh(mesh: WingMesh) -> WingMesh:
    """The mirror image (y -> -y) for the right wing; spanwise order reversed so normals stay on +z."""
    v = mesh.vertices * np.array([1.0, -1.0, 1.0])
    return WingMesh(np.ascontiguousarray(v[:, ::-1]))


def planform_area(mesh: WingMesh) -> float:
    """Area of the mesh's planform [m^2]."""
    return float(mesh.panel_areas.sum())
