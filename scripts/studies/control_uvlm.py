"""UVLM in the loop (issue 20): the UVLM gain schedule over 1-2 m/s (the shipped UVLM orbits and their shipped
one-beat control derivatives, insects/hawkmoth/data/control_models_uvlm.json), 20 controlled wingbeats from each orbit
(1, 1.5, 2 m/s), the same 20 open loop, and the profile 1 -> 1.5 -> 2 m/s under control. Writes
results/control/control_uvlm.json. ``python scripts/studies/control_uvlm.py`` (~2 min on a quiet machine:
the UVLM flies ~4 wingbeats per wall second)."""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

from hawksim.control.closed_loop import body_length, fly_closed_loop
from hawksim.control.schedule import UVLM_SCHEDULE_SPEEDS, Schedule

OUT = Path(__file__).resolve().parents[2] / "results" / "control"
KEYS = ("speed_error", "pitch_error_deg", "roll_deg", "horizontal_drift_m")


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def flight(speed, sch, control="lqr", profile=None, beats=20):
    try:
        cl = fly_closed_loop(speed, beats, schedule=sch, aero="uvlm", control=control, profile=profile,
                             progress=lambda k, n: log(f"{control} {speed:g} m/s beat {k}/{n}"))
    except FloatingPointError as exc:
        return {"diverged": str(exc)}
    b = cl.beats
    return {"wall_s": cl.wall_time_s, "beats": [
        {k: x[k] for k in ("beat", "speed_command", "speed_reference", "mean_vertical_speed", "speed_error",
                           "pitch_error_deg", "roll_deg", "yaw_deg", "horizontal_drift_m", "P_plus", "commands")}
        for x in b],
        "max_abs": {k: float(max(abs(x[k]) for x in b)) for k in KEYS},
        "mean_P_plus_from_beat_5": float(sum(x["P_plus"] for x in b[4:]) / max(1, len(b[4:]))),
        "body_length_m": body_length()}


def main():
    t0 = time.time()
    res = {"host": platform.node(), "date": time.strftime("%Y-%m-%d %H:%M")}
    sch = Schedule(UVLM_SCHEDULE_SPEEDS[0], UVLM_SCHEDULE_SPEEDS[-1], aero="uvlm", log=log)
    res["schedule"] = [{**p.to_json(), "orbit_P_plus": p.orbit.P_plus, "orbit_floor": p.orbit.floor,
                        "coupling": p.model.coupling,
                        "open_loop_multipliers_long": [abs(complex(z)) for z in p.long.open_loop],
                        "open_loop_multipliers_lat": [abs(complex(z)) for z in p.lat.open_loop],
                        "closed_long": [abs(complex(z)) for z in p.long.multipliers if abs(z) > 1e-12],
                        "closed_lat": [abs(complex(z)) for z in p.lat.multipliers if abs(z) > 1e-12]}
                       for p in sch.points]
    log(json.dumps([{k: s[k] for k in ("speed", "closed_long", "closed_lat")} for s in res["schedule"]]))
    OUT.mkdir(parents=True, exist_ok=True)
    runs = [(f"lqr_{v:g}", v, "lqr", None) for v in UVLM_SCHEDULE_SPEEDS]
    runs += [("profile_1_1.5_2", 1.0, "lqr", [(1.0, 3), (1.5, 5), (2.0, 12)])]
    runs += [(f"none_{v:g}", v, "none", None) for v in UVLM_SCHEDULE_SPEEDS]
    for key, v, control, profile in runs:  # the controlled flights first; the file is rewritten after each
        res[key] = r = flight(v, sch, control, profile)
        log(f"{key}: {json.dumps(r.get('max_abs', r))}")
        res["wall_s"] = time.time() - t0
        (OUT / "control_uvlm.json").write_text(json.dumps(res, indent=1, default=float))


if __name__ == "__main__":
    main()
