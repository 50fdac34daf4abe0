"""Linearize: the one entry point from an operating point to its :class:`hawksim.stability.linear_model.LinearModel`
(python-control's find_operating_point -> linearize -> state space -> lqr shape).

:func:`linearize` takes an :class:`hawksim.trim.point.OperatingPoint` and the map to linearize
(:data:`hawksim.stability.linear_model.MAPS`); each map's differencing is its module's (the central differences of
:func:`hawksim.control.derivatives.central_jacobians` and :func:`~hawksim.control.derivatives.record_jacobians` for
the controlled maps, the launches of :func:`hawksim.stability.floquet.monodromy` for the free body's monodromy, held
runs for the averaged model), so the numbers are exactly theirs. ``record``: for a history network's orbit, the map
on the augmented state (body and the network's record of calls) instead of the record held at the orbit's.
"""

from __future__ import annotations

import numpy as np

from hawksim.stability.linear_model import MAPS, LinearModel
from hawksim.trim.point import OperatingPoint

AVERAGED_STATES = ("u", "w", "q", "theta", "v", "p", "r", "phi")
"""The averaged model's states: A_long's (u, w, q, theta) then A_lat's (v, p, r, phi) (stability axes,
nondimensional: :func:`hawksim.stability.system.a_long`, ``a_lat``)."""


def averaged_model(point: OperatingPoint, *, steps_per_cycle: int = 200) -> LinearModel:
    """The quasi-steady backend's cycle-averaged model at ``point``'s kinematics and speed
    (:func:`hawksim.stability.floquet.quasi_steady_system`), as a continuous-time :class:`LinearModel` in t+ = t / T:
    A (8, 8) the block diagonal of A_long and A_lat (:data:`AVERAGED_STATES`), the derivatives and Eq. 8's scalars
    kept."""
    import time

    from hawksim.stability.floquet import quasi_steady_system

    t0 = time.perf_counter()
    s = quasi_steady_system(point.kinematics, point.speed, steps_per_cycle=steps_per_cycle, insect=point.insect,
                            forward_speed=point.forward_speed)
    A = np.zeros((8, 8))
    A[:4, :4], A[4:, 4:] = s.A_long, s.A_lat
    return LinearModel(point=point, map="averaged", states=AVERAGED_STATES, inputs=(), A=A, dt=None,
                       wall_time_s=time.perf_counter() - t0, derivatives=s.derivatives,
                       nondimensional=s.nondimensional, scalars=s.scalars)


def linearize(point: OperatingPoint, *, map: str = "beat", record: bool = False, delta: float | None = None,
              model=None, clip: bool | None = None, A: np.ndarray | None = None, lateral: bool = True,
              steps_per_cycle: int = 200) -> LinearModel:
    """The :class:`LinearModel` of ``map`` about ``point`` (normalized states and inputs: velocities / U, rates x T,
    angles in radians, positions / (U T); f relative).

    Maps: "beat" (the controlled one-beat map, :func:`hawksim.control.derivatives.linearize`), "half-stroke"
    (:func:`hawksim.control.halfstroke.linearize_half_stroke`), "wings" (per-wing channels,
    :func:`hawksim.control.constrained.linearize_wings`; ``A``: its state block if known), "monodromy" (the free
    body's one-beat map, :func:`hawksim.stability.floquet.monodromy`; ``lateral`` False: the longitudinal columns
    only), "history" (the same on a history network's augmented state,
    :func:`hawksim.stability.history_floquet.history_monodromy`), "averaged" (the quasi-steady cycle-averaged model,
    continuous time: :func:`averaged_model`). ``record``: the "beat" map on a history network's augmented state, and
    "monodromy" -> "history" for an orbit with a record. ``delta``: the central-difference step (default the
    backend's); ``model``: the MuJoCo model (default the insect's generated MJCF); ``clip``: the "beat" map saturated
    at Table 2 (default the backend's choice). ValueError for a map the point cannot give (a held-body point has no
    one-beat map; the held body's is "averaged")."""
    if map not in MAPS:
        raise ValueError(f"map must be one of {', '.join(MAPS)}, got {map!r}")
    if map == "averaged":
        return averaged_model(point, steps_per_cycle=steps_per_cycle)
    if not point.free:
        raise ValueError(f"map={map!r} linearizes the free body's one-beat map about a periodic orbit; this point is a "
                         "held-body trim (find_operating_point(..., body='free'), or map='averaged')")
    if map == "beat":
        from hawksim.control.derivatives import linearize as beat

        return beat(point, delta=delta, model=model, clip=clip, records=record)
    if map == "half-stroke":
        from hawksim.control.halfstroke import linearize_half_stroke

        return linearize_half_stroke(point, delta=delta, model=model)
    if map == "wings":
        from hawksim.control.constrained import linearize_wings

        return linearize_wings(point, A=A, delta=delta, model=model)
    if map == "history" or (record and point.record is not None):
        from hawksim.stability.history_floquet import history_monodromy

        kw = {} if delta is None else {"delta": delta}
        return history_monodromy(point, model=model, **kw).linear
    from hawksim.stability.floquet import monodromy

    return monodromy(point, delta=delta, model=model, lateral=lateral).linear
