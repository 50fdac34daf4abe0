"""Extended-UVLM backend (:mod:`aero.uvlm`) for the hawkmoth's two wings.

The wing lattices are the morphology's beta-distributed planform (:mod:`hawksim.insect.morphology`) with
``n_chord`` x ``n_span`` vortex rings per wing, uniform spanwise stations (see :func:`hawkmoth_meshes`).
Every call places the lattices at the wing poses of the flight state (world frame), solves, returns the loads
and sheds/convects the wake, which lives in world coordinates. With ``symmetric=True`` only the left wing is
solved and the right one is its mirror image across the body's sagittal plane (exact for left/right symmetric
motion, half the cost).

Disturbances (paper Eq. 15) enter as a rigid air-velocity field (``aero.uvlm.FreeStream``) given at
construction: the air moves with v0 + omega x (x - ref) in the world frame, plus the flight state's uniform
``air_v`` (the ascent stream of a held-body run).
"""

from __future__ import annotations

import numpy as np

from aero.mesh import mirror_mesh, planform_area, wing_mesh
from aero.uvlm import UVLM, FreeStream, UVLMConfig
from hawksim.backends.base import FlightState, WingLoads
from hawksim.backends.resolution import DEFAULT
from hawksim.insect.folder import default_insect
from hawksim.insect.morphology import RHO_AIR, Morphology


def hawkmoth_meshes(morph: Morphology | None = None, n_chord: int = DEFAULT.n_chord, n_span: int = DEFAULT.n_span):
    """(left, right) vortex-lattice meshes in their wing frames [m].

    Uniform spanwise stations; the beta distribution's zero chord at the root and tip is replaced by the
    chord a quarter panel inboard of the tip / outboard of the root (zero-chord end rings make sliver
    triangles whose near-field blows up the free wake), and all chords are then scaled so that the mesh
    area equals the wing area S exactly. ``morph``: the insect's (None: the default insect's).
    """
    morph = default_insect().morphology if morph is None else morph
    pl = morph.planform
    span = np.linspace(0.0, morph.R, n_span + 1)
    dr = span[1]
    r_eval = span.copy()
    r_eval[0], r_eval[-1] = 0.25 * dr, morph.R - 0.25 * dr
    le, te = pl.leading_edge(r_eval), pl.trailing_edge(r_eval)
    mesh = wing_mesh(span, le, te, n_chord)
    scale = morph.wing_area / planform_area(mesh)
    left = wing_mesh(span, le * scale, te * scale, n_chord)
    return left, mirror_mesh(left)


def _reflect(v: np.ndarray, n: np.ndarray, pseudo: bool = False) -> np.ndarray:
    """Reflection of vectors v (..., 3) across the plane with unit normal n; pseudovectors change sign."""
    r = v - 2 * (v @ n)[..., None] * n
    return -r if pseudo else r


class UVLMBackend:
    """Extended UVLM loads for :class:`hawksim.backends.base.AeroBackend`.

    Args:
        n_chord, n_span: vortex rings per wing (default: :data:`hawksim.backends.resolution.DEFAULT`'s).
        symmetric: solve the left wing only and mirror it (requires left/right symmetric motion).
        freestream: air-velocity field (world) for disturbance runs; default still air.
        config: solver switches (leading-edge suction, core growth, free wake); air density from morphology.
        keep_panels: put panel vertices, pressure and the wake in ``WingLoads.extras`` (for recordings).
        max_wake_rows: truncate the wake to this many newest rows (long free flights; None: keep all).
        wake_summation: how the wake-on-wake velocities are summed (``aero.uvlm.UVLMConfig.wake_summation``:
            "direct", "tree" or "auto"); with ``config`` given, its own.
        wake_precision: the pair evaluations of those velocities (``aero.uvlm.UVLMConfig.wake_precision``:
            "float64" or the opt-in "mixed"); with ``config`` given, its own.
    """

    name = "uvlm"

    def __init__(self, morph: Morphology | None = None, n_chord: int = DEFAULT.n_chord,
                 n_span: int = DEFAULT.n_span, *,
                 symmetric: bool = True, freestream: FreeStream | None = None,
                 config: UVLMConfig | None = None, keep_panels: bool = False, max_wake_rows: int | None = None,
                 wake_summation: str = "direct", wake_precision: str = "float64"):
        self.meshes = hawkmoth_meshes(morph, n_chord, n_span)
        self.symmetric = symmetric
        self.freestream = freestream if freestream is not None else FreeStream()
        self.config = config if config is not None else UVLMConfig(rho=RHO_AIR, max_wake_rows=max_wake_rows,
                                                                    wake_summation=wake_summation,
                                                                    wake_precision=wake_precision)
        self.keep_panels = keep_panels
        self.solver: UVLM | None = None

    def reset(self, state: FlightState) -> None:
        meshes = self.meshes[:1] if self.symmetric else self.meshes
        self.solver = UVLM(list(meshes), self.config)

    def loads(self, state: FlightState) -> WingLoads:
        if self.solver is None:
            self.reset(state)
        k = 1 if self.symmetric else 2
        plane = (state.body_pos, state.body_R[:, 1]) if self.symmetric else None
        fs = self.freestream
        if np.any(state.air_v):
            fs = FreeStream(v0=np.asarray(fs.v0) + state.air_v, omega=fs.omega, ref=fs.ref)
        res = self.solver.step(state.dt, state.wing_R[:k], state.wing_origin[:k], state.wing_v[:k],
                               state.wing_omega[:k], freestream=fs, mirror_plane=plane)
        force = res.force
        moment = res.moment_per_wing(state.wing_origin[:k])
        power = res.power(state.body_v, state.body_omega, state.body_pos)
        if self.symmetric:
            n = state.body_R[:, 1]
            force = np.concatenate([force, _reflect(force, n)])
            moment = np.concatenate([moment, _reflect(moment, n, pseudo=True)])
            power *= 2.0
        extras = {}
        if self.keep_panels:
            panels, pressure, wake = self._panel_vertices(state, k), res.pressure, self.solver.wake
            if self.symmetric:  # the right wing is the left one's mirror image
                p0, n = state.body_pos, state.body_R[:, 1]

                def refl(x):
                    return x - 2.0 * ((x - p0) @ n)[..., None] * n

                panels = np.concatenate([panels, refl(panels)])
                pressure = np.concatenate([pressure, pressure])
                wake = wake + [(refl(v), g) for v, g in wake]
            extras = {"pressure": pressure, "panels": panels, "wake": wake}
        return WingLoads(force=force, moment=moment, power=float(power), extras=extras)

    def _panel_vertices(self, state: FlightState, k: int) -> np.ndarray:
        """Ring-corner grids of the solved wings in world coordinates, (k, nc+1, ns+1, 3)."""
        return np.stack([
            state.wing_origin[i] + self.meshes[i].vertices @ state.wing_R[i].T for i in range(k)
        ])
