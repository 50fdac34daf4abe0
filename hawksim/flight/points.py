"""Operating points: find one (python-control's ``find_operating_point``), and the one registry of the shipped ones.

:func:`find_operating_point` returns an :class:`hawksim.trim.point.OperatingPoint` with the body free (the periodic
orbit of the free body, :func:`hawksim.flight.orbit.periodic_orbit`; a shipped one where the insect, backend, speed
and MuJoCo model are those it was solved for) or held (the held-body trim: given kinematics, or the shipped trim
table's row, :func:`hawksim.trim.tables.shipped_trim`).

The registry. Every shipped table of ``hawksim/data`` (orbits, control models) is read once per process
(:func:`shipped_table`) and its rows are looked up by :func:`point_key`: (insect digest, backend, speed, MJCF
digest). The shipped tables are the default insect's on its generated MJCF, so another insect or another model finds
none; the same key names the process caches of the points and linear models solved here
(:mod:`hawksim.control.schedule`, :mod:`hawksim.control.constrained`), so that two insects (or two MJCF models) in
one process never share an orbit or a gain.
"""

from __future__ import annotations

import hashlib
import json
from functools import lru_cache

import numpy as np

from hawksim.insect.insect import DEFAULT_INSECT, Insect
from hawksim.insect.kinematics import Kinematics
from hawksim.trim.point import BODIES, OperatingPoint

_MODEL_FIELDS = ("body_mass", "body_inertia", "body_pos", "body_quat", "body_ipos", "body_iquat", "jnt_axis",
                 "jnt_pos", "jnt_type", "dof_damping", "dof_armature")
"""The MjModel arrays a flight's mechanics depend on, hashed into :func:`model_digest` (with the time step and
gravity)."""


def model_digest(model) -> str:
    """SHA-256 over the mechanics of a MuJoCo model (:data:`_MODEL_FIELDS`, time step, gravity)."""
    h = hashlib.sha256()
    for name in _MODEL_FIELDS:
        h.update(np.ascontiguousarray(getattr(model, name)).tobytes())
    h.update(np.array([model.opt.timestep, *model.opt.gravity]).tobytes())
    return h.hexdigest()


def insect_digest(insect: Insect | None) -> str:
    """SHA-256 of an insect's spec (:meth:`hawksim.insect.insect.Insect.to_dict`: morphology, P0 and bounds, sorted
    JSON); None means the default insect."""
    spec = (DEFAULT_INSECT if insect is None else insect).to_dict()
    return hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()


@lru_cache(maxsize=8)
def _default_model_digest(insect_hex: str) -> str:
    from hawksim.insect.model import load_model

    return model_digest(load_model(morph=DEFAULT_INSECT.morphology))


def point_key(speed: float, aero: str, insect: Insect | None = None, model=None, *extra) -> tuple:
    """The key of an operating point (and of what is made about it): (insect digest, backend, speed [m/s], MJCF
    digest, then ``extra``). ``model`` None: the insect's generated MJCF (the same digest as passing it)."""
    ins = insect_digest(insect)
    if model is None:
        md = _default_model_digest(ins) if ins == insect_digest(None) else "generated:" + ins
    else:
        md = model_digest(model)
    return (ins, aero, float(speed), md, *extra)


@lru_cache(maxsize=None)
def shipped_table(name: str) -> dict | None:
    """The shipped table ``hawksim/data/<name>`` parsed once per process (None if absent). Read-only by contract:
    callers build their values from it and never change it."""
    from importlib import resources

    path = resources.files("hawksim") / "data" / name
    return json.loads(path.read_text()) if path.is_file() else None


def _shipped_key(speed: float, aero: str) -> tuple:
    return point_key(speed, aero)


@lru_cache(maxsize=None)
def _shipped_points(aero: str) -> dict:
    """{point_key: OperatingPoint} of ``aero``'s shipped orbit table (its descriptor's ``orbit_table``), empty if
    it has none or the table does not hold for the backend as built now."""
    from hawksim.backends.registry import descriptor

    desc = descriptor(aero)
    table = shipped_table(desc.orbit_table) if desc.orbit_table else None
    if table is None or not desc.tables_hold(table):
        return {}
    out = {}
    for row in table["rows"]:
        p = OperatingPoint.from_json(row)
        out[_shipped_key(p.speed, aero)] = p
    return out


def shipped_point(speed: float, aero: str, *, insect: Insect | None = None, model=None) -> OperatingPoint | None:
    """The shipped free-body operating point (periodic orbit) of ``aero`` at exactly ``speed`` [m/s] for ``insect``
    on ``model`` (None: the insect's generated MJCF), None if the registry holds none for that key (the shipped
    tables are the default insect's on its generated MJCF; the surrogate's hold for the shipped network only)."""
    pts = _shipped_points(aero)
    if not pts:
        return None
    want = point_key(speed, aero, insect, model)
    for key, p in pts.items():  # speeds as tabulated: the old lookup's 1e-9 tolerance
        if key[0] == want[0] and key[3] == want[3] and abs(key[2] - want[2]) < 1e-9:
            return p
    return None


def find_operating_point(speed: float, *, aero: str = "quasi-steady", body: str = "free",
                         insect: Insect | None = None, kinematics: Kinematics | None = None, model=None,
                         shipped: bool = True, log=None, **solve) -> OperatingPoint:
    """The operating point of ``insect`` (default :data:`hawksim.insect.insect.DEFAULT_INSECT`) at ascent
    ``speed`` [m/s] on the aerodynamic model ``aero``.

    ``body="free"``: the periodic orbit of the free body: the shipped one where the registry holds it
    (``shipped``, no ``kinematics``: :func:`shipped_point`), else solved by Newton shooting
    (:func:`hawksim.flight.orbit.periodic_orbit`, from ``kinematics`` if given; ``solve``: its other keywords:
    ``tol``, ``max_iter``, ``warm_beats``, ``x0``, ``fd_step``). ``body="held"``: the held-body trim: ``kinematics``
    if given (source "given"), else the shipped trim table's (the default insect's only; ValueError for another:
    find its free-body point, or balance a trim with :mod:`hawksim.trim`). SI (kinematics in radians and Hz)."""
    if body not in BODIES:
        raise ValueError(f"body must be one of {BODIES}, got {body!r}")
    ins = DEFAULT_INSECT if insect is None else insect
    if body == "held":
        if solve:
            raise ValueError(f"body='held' takes no orbit-solve keywords (got {', '.join(sorted(solve))})")
        if kinematics is not None:
            return OperatingPoint(float(speed), kinematics, aero=aero, source="given", body="held", insect=ins)
        if ins != DEFAULT_INSECT:
            raise ValueError(f"insect {ins.name!r}: no shipped held-body trim (the tables are the default insect's); "
                             "give kinematics, or find its free-body point (body='free')")
        from hawksim.trim.tables import shipped_trim

        return shipped_trim(speed, aero)
    if shipped and kinematics is None and not solve:
        p = shipped_point(speed, aero, insect=insect, model=model)
        if p is not None:
            return p
    from hawksim.flight.orbit import periodic_orbit

    return periodic_orbit(speed, aero, kinematics=kinematics, model=model, insect=insect, log=log, **solve)
