"""The trim kinematics used by default at each ascent speed.

Each aerodynamic model has its own trim, since each balances the insect differently: ``trim_table.json``
(balanced on the UVLM; also used by the surrogate and by vacuum runs) and ``trim_table_quasi_steady.json``
(balanced on the quasi-steady model), both in ``hawksim/data`` and produced by
``scripts/studies/uvlm_trim_table.py`` (the command is recorded in each file). Without a shipped table: the paper's
Table 3 (Nguyen et al. 2020). Between tabulated speeds the parameters are interpolated linearly.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from hawksim.backends.averages import OUTPUTS, CycleAverages
from hawksim.insect.kinematics import PARAM_NAMES, TABLE3_DEG, TABLE3_SPEEDS, Kinematics
from hawksim.trim.point import Trim


def _trim_model(aero: str) -> str:
    """The backend whose shipped trim table ``aero`` flies: its own (its descriptor's ``trim_table``), else the
    UVLM's (vacuum, an unregistered name, a backend that ships none)."""
    from hawksim.backends.registry import find

    desc = find(aero)
    return aero if desc is not None and desc.trim_table else "uvlm"


@lru_cache(maxsize=4)
def _table(aero: str = "uvlm") -> tuple[str, tuple[float, ...], dict[str, tuple[float, ...]]]:
    from hawksim.backends.registry import descriptor
    from hawksim.trim.registry import shipped_table

    name = descriptor(_trim_model(aero)).trim_table
    data = shipped_table(name)  # read once per process (the registry's)
    if data is not None:
        rows = sorted(data["rows"], key=lambda r: r["speed"])
        speeds = tuple(float(r["speed"]) for r in rows)
        return "hawksim trim table (" + data.get("source", name) + ")", speeds, {
            k: tuple(float(r["kinematics"][k]) for r in rows) for k in PARAM_NAMES}
    return "Nguyen et al. (2020) Table 3", TABLE3_SPEEDS, TABLE3_DEG


def trim_source(aero: str = "uvlm") -> str:
    """Where the default trim for the aerodynamic model ``aero`` comes from."""
    return _table(aero)[0]


def shipped_trim(speed: float, aero: str = "uvlm") -> Trim:
    """The default trim at ascent speed [m/s] for the aerodynamic model ``aero`` (ValueError outside the table's
    speed range); between tabulated speeds the parameters are interpolated linearly (averages not recorded)."""
    source, speeds, table = _table(aero)
    if not (speeds[0] <= speed <= speeds[-1]):
        raise ValueError(f"speed {speed:g} m/s is outside the trim table's range [{speeds[0]:g}, {speeds[-1]:g}] m/s")
    kin = Kinematics.from_edge({k: float(np.interp(speed, speeds, v)) for k, v in table.items()})
    return Trim(float(speed), kin, model=_trim_model(aero), source=source)


def trim_kinematics(speed: float, aero: str = "uvlm") -> Kinematics:
    """The kinematics of :func:`shipped_trim` at ``speed`` [m/s] on ``aero``, SI (angles in radians, f in Hz)."""
    return shipped_trim(speed, aero).kinematics


FORWARD_TRIM_TABLE = "forward_trim_table_quasi_steady.json"
"""The default hawkmoth's shipped minimum-power trims in level forward flight (quasi-steady, U = 0-5 m/s:
``python -m scripts.studies.forward_trims --from results/forward_flight/qs_trims.json --ship ...``, its rows'
searches recorded in the file; docs/forward_flight.md)."""


def forward_trim(forward_speed: float, aero: str = "quasi-steady") -> Trim:
    """The shipped minimum-power trim in level flight at ``forward_speed`` [m/s] (a row of
    :data:`FORWARD_TRIM_TABLE`, exactly that speed: no interpolation), held-body averages in ``averages``.
    ValueError naming ``forward_speed`` where the table has no balanced trim there (5 m/s: none balanced within
    Table 2's bounds) or ``aero`` where it is not the quasi-steady model (the only forward table shipped)."""
    from hawksim.trim.registry import shipped_table

    if aero != "quasi-steady":
        raise ValueError(f"aero {aero!r}: the shipped forward-flight trims are the quasi-steady model's "
                         "(hawksim trim --forward-speed U searches others)")
    data = shipped_table(FORWARD_TRIM_TABLE)
    rows = {} if data is None else {float(r["forward_speed"]): r for r in data["rows"] if r["converged"]}
    row = rows.get(float(forward_speed))
    if row is None:
        raise ValueError(f"forward_speed {forward_speed:g} m/s: no shipped balanced forward-flight trim there (they "
                         f"are at {', '.join(f'{u:g}' for u in sorted(rows)) or 'no speed'} m/s)")
    return Trim(float(row["speed"]), Kinematics.from_edge(row["kinematics"]), model=aero,
                source=f"hawksim forward trim table ({data['source']})",
                averages=CycleAverages(**{k: float(row[k]) for k in (*OUTPUTS, "power_W")}),
                tolerance=float(row["tolerance"]), search_seed=row["seed"], converged=True,
                forward_speed=float(forward_speed))


def forward_trim_speeds() -> tuple[float, ...]:
    """Forward speeds [m/s] of the shipped balanced forward-flight trims (:func:`forward_trim`)."""
    from hawksim.trim.registry import shipped_table

    data = shipped_table(FORWARD_TRIM_TABLE)
    return tuple(sorted(float(r["forward_speed"]) for r in (data or {"rows": []})["rows"] if r["converged"]))


def forward_trim_kinematics(forward_speed: float) -> Kinematics:
    """The quasi-steady forward-flight kinematics at ``forward_speed`` [m/s]: the shipped trim's there
    (:func:`forward_trim`), between two shipped speeds the parameters interpolated linearly (as
    :func:`shipped_trim` does in vertical flight; not a balanced trim: a periodic-orbit solve balances it through f
    and phi0). ValueError naming ``forward_speed`` outside the shipped balanced range (0-4 m/s)."""
    speeds = forward_trim_speeds()
    u = float(forward_speed)
    if not speeds or not (speeds[0] <= u <= speeds[-1]):
        raise ValueError(f"forward_speed {forward_speed:g} m/s is outside the shipped forward trims' range "
                         f"[{speeds[0]:g}, {speeds[-1]:g}] m/s (none balanced within Table 2 above it); give "
                         "kinematics (hawksim.trim.model_search.trim_on_model)" if speeds
                         else "no shipped forward trims")
    if u in speeds:
        return forward_trim(u).kinematics
    i = int(np.searchsorted(speeds, u)) - 1
    a, b = forward_trim(speeds[i]).kinematics.as_array(), forward_trim(speeds[i + 1]).kinematics.as_array()
    w = (u - speeds[i]) / (speeds[i + 1] - speeds[i])
    return Kinematics.from_array((1 - w) * a + w * b)


def forward_start(forward_speed: float, speed: float = 0.0, insect=None) -> Kinematics:
    """The kinematics a forward-flight operating point starts from when none are given: the default insect's shipped
    trims in level flight (:func:`forward_trim_kinematics`, 0-4 m/s). ValueError naming ``forward_speed`` elsewhere
    (a climb, ``speed`` != 0; above 4 m/s, where none balanced within Table 2; another insect)."""
    from hawksim.insect.folder import default_insect

    if insect is not None and insect != default_insect():
        raise ValueError(f"forward_speed {forward_speed:g} m/s: no shipped forward trim for insect {insect.name!r} "
                         "(they are the default hawkmoth's); give kinematics (hawksim.trim.model_search.trim_on_model)")
    if speed != 0:
        raise ValueError(f"forward_speed {forward_speed:g} m/s at {speed:g} m/s vertical: the shipped forward trims "
                         "are level flight; give kinematics (hawksim.trim.model_search.trim_on_model)")
    return forward_trim_kinematics(forward_speed)  # (ValueError naming forward_speed outside their range)
