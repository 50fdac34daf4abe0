"""`hawksim reproduce --only validation_uvlm`, one process per speed (the UVLM's three speeds in parallel on a
shared machine), then combined into results/free_flight/validation.json by the same writer.

    python scripts/studies/validation_by_speed.py --speed 1 --part /tmp/v1.json      # one per speed, in parallel
    python scripts/studies/validation_by_speed.py --combine /tmp/v0.json /tmp/v1.json /tmp/v2.json
"""

from __future__ import annotations

import argparse
import datetime
import json
import platform
import time
from pathlib import Path

import numpy as np

from hawksim.stability import validation as V


def _jsonable(x):
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, (np.floating, np.integer, np.bool_)):
        return x.item()
    if isinstance(x, complex):
        return [x.real, x.imag]
    return x


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--speed", type=float)
    p.add_argument("--aero", default="uvlm")
    p.add_argument("--part", type=Path)
    p.add_argument("--combine", type=Path, nargs="+")
    p.add_argument("--out", type=Path, default=Path("results/free_flight"))
    a = p.parse_args()
    if a.combine:
        parts = [json.loads(f.read_text()) for f in a.combine]
        meta = {a.aero: {"command": "python scripts/studies/validation_by_speed.py (one process per speed, the "
                         "functions of hawksim reproduce --only validation_uvlm)",
                         "date": datetime.datetime.now().isoformat(timespec="seconds"), "host": platform.node(),
                         "wall_time_s": max(r["_part_wall_s"] for r in parts),
                         "constants": {"BEATS": V.BEATS, "UVLM_BEATS": V.UVLM_BEATS, "DRIFT_MAX": V.DRIFT_MAX,
                                       "DEV_MAX": V.DEV_MAX, "EPS_MAX": V.EPS_MAX, "LAT_EPS": V.LAT_EPS,
                                       "LAT_DEV_MAX": V.LAT_DEV_MAX, "UVLM_EPS": V.UVLM_EPS,
                                       "NOISE_REL": V.NOISE_REL}}}
        for r in parts:
            r.pop("_part_wall_s")
        print(json.dumps(V.write(parts, a.out, meta)))
        return
    t0 = time.perf_counter()
    r = V.run_speed(a.speed, a.aero, log=print)
    r["_part_wall_s"] = time.perf_counter() - t0
    a.part.write_text(json.dumps(_jsonable(r)))


if __name__ == "__main__":
    main()
