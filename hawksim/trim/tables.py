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
