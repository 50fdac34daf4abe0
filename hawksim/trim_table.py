"""The trim kinematics used by default at each ascent speed.

Source, in order: the project's shipped trim table ``hawksim/data/trim_table.json`` (produced by
`hawksim trim` and the UVLM polish, with the command and seed recorded in the file), else the paper's Table 3
(Nguyen et al. 2020). Between tabulated speeds the parameters are interpolated linearly.
"""

from __future__ import annotations

import json
from functools import lru_cache
from importlib import resources

import numpy as np

from hawksim.kinematics import PARAM_NAMES, TABLE3_DEG, TABLE3_SPEEDS, Kinematics

TABLE_FILE = "trim_table.json"


@lru_cache(maxsize=1)
def _table() -> tuple[str, tuple[float, ...], dict[str, tuple[float, ...]]]:
    path = resources.files("hawksim") / "data" / TABLE_FILE
    if path.is_file():
        data = json.loads(path.read_text())
        rows = sorted(data["rows"], key=lambda r: r["speed"])
        speeds = tuple(float(r["speed"]) for r in rows)
        return "hawksim trim table (" + data.get("source", TABLE_FILE) + ")", speeds, {
            k: tuple(float(r["kinematics"][k]) for r in rows) for k in PARAM_NAMES}
    return "Nguyen et al. (2020) Table 3", TABLE3_SPEEDS, TABLE3_DEG


def trim_source() -> str:
    """Where the default trim comes from."""
    return _table()[0]


def trim_kinematics(speed: float) -> Kinematics:
    """Trim kinematics at ascent speed [m/s] (ValueError outside the table's speed range)."""
    _, speeds, table = _table()
    if not (speeds[0] <= speed <= speeds[-1]):
        raise ValueError(f"speed {speed:g} m/s is outside the trim table's range [{speeds[0]:g}, {speeds[-1]:g}] m/s")
    return Kinematics.from_edge({k: float(np.interp(speed, speeds, v)) for k, v in table.items()})
