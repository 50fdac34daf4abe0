"""Find an operating point (python-control's ``find_operating_point``).

:func:`find_operating_point` returns an :class:`hawksim.trim.point.OperatingPoint` with the body free (the periodic
orbit of the free body, :func:`hawksim.flight.orbit.periodic_orbit`; a shipped one where the registry
:mod:`hawksim.trim.registry` holds it for the insect, backend, speed and MuJoCo model) or held (the held-body trim:
given kinematics, or the shipped trim table's row, :func:`hawksim.trim.tables.shipped_trim`).
"""

from __future__ import annotations

from hawksim.condition import check_forward_speed
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import Kinematics
from hawksim.trim.point import BODIES, OperatingPoint
from hawksim.trim.registry import (insect_digest, model_digest, point_key, shipped_point,  # noqa: F401 (re-exported)
                                   shipped_table)


def find_operating_point(speed: float, *, aero: str = "quasi-steady", body: str = "free",
                         insect: Insect | None = None, kinematics: Kinematics | None = None, model=None,
                         shipped: bool = True, log=None, forward_speed: float = 0.0, **solve) -> OperatingPoint:
    """The operating point of ``insect`` (default :func:`hawksim.insect.folder.default_insect`) at ascent
    ``speed`` [m/s] (and ``forward_speed`` [m/s], :mod:`hawksim.condition`) on the aerodynamic model ``aero``.

    Forward flight (forward_speed > 0) starts from given ``kinematics`` or, without them, from the default insect's
    shipped forward trims in level flight (:func:`hawksim.trim.tables.forward_start`: 0-4 m/s, ValueError naming
    ``forward_speed`` elsewhere): the held-body point at them, or the free body's periodic orbit solved from them
    (:func:`hawksim.flight.orbit.periodic_orbit` with ``forward_speed``; quasi-steady and UVLM backends only,
    :func:`hawksim.condition.check_forward_backend`; docs/forward_flight.md).

    ``body="free"``: the periodic orbit of the free body: the shipped one where the registry holds it
    (``shipped``, no ``kinematics``: :func:`shipped_point`), else solved by Newton shooting
    (:func:`hawksim.flight.orbit.periodic_orbit`, from ``kinematics`` if given; ``solve``: its other keywords:
    ``tol``, ``max_iter``, ``warm_beats``, ``x0``, ``fd_step``). ``body="held"``: the held-body trim: ``kinematics``
    if given (source "given"), else the shipped trim table's (the default insect's only; ValueError for another:
    find its free-body point, or balance a trim with :mod:`hawksim.trim`). SI (kinematics in radians and Hz)."""
    if body not in BODIES:
        raise ValueError(f"body must be one of {BODIES}, got {body!r}")
    ins = default_insect() if insect is None else insect
    forward_speed = check_forward_speed(forward_speed)
    if forward_speed > 0 and kinematics is None:  # the shipped forward trims (ValueError outside them)
        from hawksim.trim.tables import forward_start

        kinematics = forward_start(forward_speed, speed, insect)
    if body == "held":
        if solve:
            raise ValueError(f"body='held' takes no orbit-solve keywords (got {', '.join(sorted(solve))})")
        if kinematics is not None:
            return OperatingPoint(float(speed), kinematics, aero=aero, source="given", body="held", insect=ins,
                                  forward_speed=forward_speed)
        if ins != default_insect():
            raise ValueError(f"insect {ins.name!r}: no shipped held-body trim (the tables are the default insect's); "
                             "give kinematics, or find its free-body point (body='free')")
        from hawksim.trim.tables import shipped_trim

        return shipped_trim(speed, aero)
    if shipped and kinematics is None and not solve:
        p = shipped_point(speed, aero, insect=insect, model=model)
        if p is not None:
            return p
    from hawksim.flight.orbit import periodic_orbit

    return periodic_orbit(speed, aero, kinematics=kinematics, model=model, insect=insect, log=log,
                          **({"forward_speed": forward_speed} if forward_speed else {}), **solve)
