"""Steady horseshoe vortex-lattice method for a flat wing (reference solution for the UVLM's steady limit).

Classical planar VLM (Katz & Plotkin 2001, Sec. 12.3; Bertin & Cummings): one horseshoe vortex per panel,
bound segment on the panel's quarter-chord line, trailing legs parallel to the wing-frame -x axis
(semi-infinite, truncated at ``TRAIL_LENGTH`` spans), collocation at the 3/4-chord point; lift by
Kutta-Joukowski on the bound segments. Independent of :mod:`aero.uvlm` except for the Biot-Savart law.
"""

from __future__ import annotations

import numpy as np

from aero.biot_savart import segment_velocity
from aero.mesh import WingMesh

TRAIL_LENGTH = 1e4
"""Length of the trailing legs in spans (stands in for infinity: relative error ~1/TRAIL_LENGTH)."""


def steady_lift_coefficient(mesh: WingMesh, alpha: float) -> float:
    """C_L of the flat wing (wing frame, air from +x) at angle of attack alpha [rad], small-disturbance BC:
    normal velocity -U sin(alpha) cancelled at the 3/4-chord points; C_L = sum rho U Gamma dy / (q S)."""
    v = mesh.vertices
    qc = v[:-1] + 0.25 * (v[1:] - v[:-1])            # quarter-chord lines (nc, ns+1, 3)
    tq = v[:-1] + 0.75 * (v[1:] - v[:-1])
    col = 0.5 * (tq[:, :-1] + tq[:, 1:]).reshape(-1, 3)
    span = np.ptp(v[..., 1])
    far = np.array([-TRAIL_LENGTH * span, 0.0, 0.0])
    a_b, b_b = qc[:, 1:].reshape(-1, 3), qc[:, :-1].reshape(-1, 3)       # bound: tip-side -> root-side (-y)
    # horseshoe: from far downstream to the tip-side end, bound, root-side end to far downstream
    a = np.concatenate([a_b + far, a_b, b_b])
    b = np.concatenate([a_b, b_b, b_b + far])
    n = a_b.shape[0]
    # normal velocity at every collocation point induced by each horseshoe with unit circulation
    w = np.empty((col.shape[0], n))
    for k in range(n):
        legs = [k, n + k, 2 * n + k]
        w[:, k] = segment_velocity(col, a[legs], b[legs], np.ones(3))[:, 2]
    gam = np.linalg.solve(w, -np.full(n, np.sin(alpha)))               # U = 1
    dy = np.abs(a_b[:, 1] - b_b[:, 1])
    return float(2.0 * (gam * dy).sum() / mesh.panel_areas.sum())
