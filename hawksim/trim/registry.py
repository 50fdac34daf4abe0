"""The one registry of the shipped operating points: every shipped table of the default insect's folder (trims,
orbits, control models) is read once per process (:func:`shipped_table`), and points are looked up by
:func:`point_key`: (insect digest, backend, speed, MJCF digest). The shipped tables are the default insect's on its
generated MJCF, so another insect or another model finds none; the same key names the process caches of the points and
linear models made here (:mod:`hawksim.control.schedule`, :mod:`hawksim.control.constrained`), so that two insects (or
two MJCF models) in one process never share an orbit or a gain. Finding a point (shipped or solved):
:func:`hawksim.flight.points.find_operating_point`.
"""

from __future__ import annotations

import hashlib
import json
from functools import lru_cache

import numpy as np

from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.trim.point import OperatingPoint

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
    spec = (default_insect() if insect is None else insect).to_dict()
    return hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()


@lru_cache(maxsize=8)
def _default_model_digest(insect_hex: str) -> str:
    from hawksim.insect.model import load_model

    return model_digest(load_model(morph=default_insect().morphology))


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
    """The default insect's shipped table ``<its folder>/data/<name>`` (as its manifest lists it:
    :func:`hawksim.insect.tables.table_status`), parsed once per process; None if it ships none or the manifest
    says it was computed on another MJCF. Read-only by contract: callers build their values from it and never change
    it."""
    from hawksim.insect.tables import table_status

    for kind in ("trim", "orbit", "control_model", "forward_trim"):
        path, _ = table_status(default_insect(), kind, name=name)
        if path is not None:
            return json.loads(path.read_text())
    return None


@lru_cache(maxsize=None)
def _shipped_points(table_name: str) -> dict:
    """{point_key: OperatingPoint} of the shipped orbit table ``table_name`` (each row parsed once)."""
    out = {}
    for row in shipped_table(table_name)["rows"]:
        p = OperatingPoint.from_json(row)
        out[point_key(p.speed, p.aero)] = p
    return out


def shipped_point(speed: float, aero: str, *, insect: Insect | None = None, model=None) -> OperatingPoint | None:
    """The shipped free-body operating point (periodic orbit) of ``aero`` at exactly ``speed`` [m/s] for ``insect``
    on ``model`` (None: the insect's generated MJCF), None if the registry holds none for that key (the shipped
    tables are the default insect's on its generated MJCF; the surrogate's hold for the shipped network only)."""
    from hawksim.backends.registry import descriptor

    desc = descriptor(aero)
    table = shipped_table(desc.orbit_table) if desc.orbit_table else None
    if table is None or not desc.tables_hold(table):  # checked at each call: the surrogate's network may change
        return None
    pts = _shipped_points(desc.orbit_table)
    want = point_key(speed, aero, insect, model)
    for key, p in pts.items():  # speeds as tabulated: the old lookup's 1e-9 tolerance
        if key[0] == want[0] and key[3] == want[3] and abs(key[2] - want[2]) < 1e-9:
            return p
    return None
