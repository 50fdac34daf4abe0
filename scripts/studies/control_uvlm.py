"""UVLM in the loop (issue 20): the UVLM orbit at 1 m/s, its control derivatives (wake held at the orbit's),
the LQR, 20 controlled wingbeats, and the same 20 open loop. Writes results/control/control_uvlm.json.
``python scripts/studies/control_uvlm.py`` (~6-8 min on one core)."""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path


from hawksim.control.closed_loop import body_length, fly_closed_loop
from hawksim.control.schedule import Schedule

OUT = Path(__file__).resolve().parents[2] / "results" / "control"


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def main():
    t0 = time.time()
    res = {"host": platform.node(), "date": time.strftime("%Y-%m-%d %H:%M")}
    sch = Schedule(1.0, 1.0, aero="uvlm", speeds=(1.0,), log=log)
    p = sch.points[0]
    res["orbit"] = {"residual": p.orbit.residual, "f_hz": p.orbit.kinematics.f, "wall_s": p.orbit.wall_time_s,
                    "P_plus": p.orbit.P_plus, "floor": p.orbit.floor}
    res["linearize_wall_s"] = p.model.wall_time_s
    res["coupling"] = p.model.coupling
    res["open_loop_multipliers_long"] = [abs(complex(z)) for z in p.long.open_loop]
    res["open_loop_multipliers_lat"] = [abs(complex(z)) for z in p.lat.open_loop]
    res["closed_long"] = [abs(complex(z)) for z in p.long.multipliers if abs(z) > 1e-12]
    res["closed_lat"] = [abs(complex(z)) for z in p.lat.multipliers if abs(z) > 1e-12]
    log(json.dumps(res))
    for control in ("lqr", "none"):
        try:
            cl = fly_closed_loop(1.0, 20, schedule=sch, aero="uvlm", control=control,
                                 progress=lambda k, n, c=control: log(f"{c} beat {k}/{n}"))
            b = cl.beats
            res[control] = {"wall_s": cl.wall_time_s, "beats": [
                {k: x[k] for k in ("beat", "mean_vertical_speed", "speed_error", "pitch_error_deg", "roll_deg",
                                   "horizontal_drift_m", "P_plus", "commands")} for x in b],
                "max_abs": {k: float(max(abs(x[k]) for x in b)) for k in
                            ("speed_error", "pitch_error_deg", "roll_deg", "horizontal_drift_m")},
                "body_length_m": body_length()}
        except FloatingPointError as exc:
            res[control] = {"diverged": str(exc)}
        log(json.dumps(res[control].get("max_abs", res[control])))
    res["wall_s"] = time.time() - t0
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "control_uvlm.json").write_text(json.dumps(res, indent=1, default=float))


if __name__ == "__main__":
    main()
