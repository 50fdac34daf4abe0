"""Issue 20's targets for the quasi-steady LQR (docs/control.md): writes results/control/control_study.json and
results/control/controlled_flight.png. ``python scripts/studies/control_study.py`` (~3 min on one core)."""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from hawksim.control.closed_loop import Gust, body_length, fly_closed_loop
from hawksim.control.schedule import SCHEDULE_SPEEDS, Schedule

OUT = Path(__file__).resolve().parents[2] / "results" / "control"
L = body_length()
BOUNDS = dict(speed_error=0.02, pitch_error_deg=2.0, roll_deg=2.0, horizontal_drift_m=L)


def maxabs(beats, key):
    return float(max(abs(b[key]) for b in beats))


def stats(cl, skip=0):
    b = cl.beats[skip:]
    return {k: maxabs(b, k) for k in BOUNDS} | {"mean_P_plus": float(np.mean([x["P_plus"] for x in b]))}


def within(b):
    return all(abs(b[k]) <= v for k, v in BOUNDS.items())


def recovered_after(cl, end_beat):
    """Wingbeats after the gust's last beat until every later beat is within the bounds (None: never)."""
    ok = [within(b) for b in cl.beats]
    for k in range(len(ok)):
        if all(ok[k:]):
            return max(0, cl.beats[k]["beat"] - end_beat)
    return None


def main():
    t0 = time.time()
    res = {"host": platform.node(), "date": time.strftime("%Y-%m-%d %H:%M"), "body_length_m": L, "bounds": BOUNDS}
    sch = {d: Schedule(0, 2, delay=d) for d in (0, 1)}
    res["schedule"] = {d: [{"speed": p.speed, "orbit_P_plus": p.orbit.P_plus,
                            "open_loop_max_multiplier_long": float(np.abs(p.long.open_loop).max()),
                            "open_loop_multipliers_lat": [abs(complex(z)) for z in p.lat.open_loop],
                            "closed_long": [abs(complex(z)) for z in p.long.multipliers if abs(z) > 1e-12],
                            "closed_lat": [abs(complex(z)) for z in p.lat.multipliers if abs(z) > 1e-12],
                            "coupling": p.model.coupling} for p in sch[d].points] for d in (0, 1)}
    hold = {}
    for v in SCHEDULE_SPEEDS:
        cl = fly_closed_loop(v, 100, schedule=sch[0])
        pert = np.zeros(9)
        pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)  # v, w [m/s], phi, theta [rad]
        cp = fly_closed_loop(v, 100, schedule=sch[0], perturbation=pert)
        ok = [within(b) for b in cp.beats]
        settle = next((k for k in range(len(ok)) if all(ok[k:])), None)
        hold[v] = {"from_orbit": stats(cl), "orbit_P_plus": sch[0].points[SCHEDULE_SPEEDS.index(v)].orbit.P_plus,
                   "wall_s": cl.wall_time_s, "perturbed_start": stats(cp),
                   "perturbed_start_stats_after_10": stats(cp, 10),
                   "perturbed_settled_at_beat": None if settle is None else cp.beats[settle]["beat"]}
        print(v, hold[v], file=sys.stderr)
    res["hold_100_beats"] = hold
    prof = fly_closed_loop(0, 40, profile=[(0, 2), (1, 10), (2, 10)], schedule=sch[0])
    over = max(b["mean_vertical_speed"] - b["speed_command"] for b in prof.beats)
    res["profile_0_1_2"] = {"overshoot_m_s": float(over), "stats": stats(prof),
                            "final_10": stats(prof, 30), "speeds": [b["mean_vertical_speed"] for b in prof.beats]}
    gust = {}
    for v in SCHEDULE_SPEEDS:
        cl = fly_closed_loop(v, 30, gusts=[Gust(np.array([0.0, 0.5, 0.0]), 5, 2)], schedule=sch[0])
        gust[v] = {"recovered_beats_after_gust": recovered_after(cl, 6), "peak": stats(cl),
                   "mean_P_plus": stats(cl)["mean_P_plus"]}
    res["gust_0.5_lateral_2_beats"] = gust
    dl = {}
    for name, s in (("delay-aware design", sch[1]), ("design without delay", sch[0])):
        try:
            cl = fly_closed_loop(1.0, 100, delay=1, schedule=s, gusts=[Gust(np.array([0.0, 0.5, 0.0]), 5, 2)])
            dl[name] = {"stats": stats(cl), "after_20": stats(cl, 20),
                        "recovered_beats_after_gust": recovered_after(cl, 6)}
        except FloatingPointError as exc:
            dl[name] = {"diverged": str(exc)}
    res["delay_1_beat_1ms_gust"] = dl
    ol = fly_closed_loop(1.0, 40, control="none")
    res["open_loop_1ms"] = {
        "departed_at_beat": next((b["beat"] for b in ol.beats if abs(b["speed_error"]) > 0.1), None)}
    res["wall_s"] = time.time() - t0
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "control_study.json").write_text(json.dumps(res, indent=1, default=float))
    figure(sch[0])
    print(json.dumps({k: res[k] for k in ("profile_0_1_2", "gust_0.5_lateral_2_beats", "delay_1_beat_1ms_gust",
                                          "open_loop_1ms", "wall_s")}, default=float)[:3000])


def figure(sch):
    from hawksim.control.figure import controlled_flight_figure

    cl = fly_closed_loop(0, 40, profile=[(0, 2), (1, 10), (2, 28)], gusts=[Gust(np.array([0.0, 0.5, 0.0]), 28, 2)],
                         schedule=sch, record=True)
    controlled_flight_figure(cl, OUT / "controlled_flight.png",
                             title="LQR, quasi-steady: profile 0:2,1:10,2:28 m/s:beats, gust 0,0.5,0 m/s @ beats "
                                   "28-29 (shaded)")


if __name__ == "__main__":
    main()
