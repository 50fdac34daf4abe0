"""Per-beat against per-half-stroke control updates (issue 20: "once per wingbeat (or per half-stroke: try both,
say which is better)"), quasi-steady, on issue 20's targets: closed-loop multipliers, 100 beats at 0-2 m/s from
the orbit and from a perturbed start, the 0 -> 1 -> 2 m/s profile, the 0.5 m/s lateral gust over 2 beats, the
one-beat sensing delay, the cost of control (P+) and how hard the commands work; the half-stroke design both with
:data:`hawksim.control.schedule.HALF_STROKE_COMMAND_WEIGHT` (shipped) and with the per-beat design's weights. Writes
results/control/control_rate_study.json and prints the table of docs/control.md ("Per beat or per half-stroke").
``python scripts/studies/control_rate_study.py`` (~6-9 min on one core)."""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from hawksim.control.closed_loop import Gust, body_length, fly_closed_loop
from hawksim.control.schedule import HALF_STROKE_COMMAND_WEIGHT, SCHEDULE_SPEEDS, Schedule

OUT = Path(__file__).resolve().parents[2] / "results" / "control"
L = body_length()
BOUNDS = dict(speed_error=0.02, pitch_error_deg=2.0, roll_deg=2.0, horizontal_drift_m=L)
GUST = Gust(np.array([0.0, 0.5, 0.0]), 5, 2)
DESIGNS = {"beat": ("beat", None), "half-stroke": ("half-stroke", HALF_STROKE_COMMAND_WEIGHT),
           "half-stroke, equal weights": ("half-stroke", 1.0)}
"""The designs compared: name -> (update rate, command weight of the half-stroke LQR)."""
CMD = ("f_hz", "phi0_deg", "alpha0_deg", "theta0_deg", "dphi_a_deg", "dphi0_deg", "dalpha0_deg")


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def stats(cl, skip=0):
    b = cl.beats[skip:]
    return {k: float(max(abs(x[k]) for x in b)) for k in BOUNDS} | {
        "mean_P_plus": float(np.mean([x["P_plus"] for x in b]))}


def within(b):
    return all(abs(b[k]) <= v for k, v in BOUNDS.items())


def recovered_after(cl, end_beat):
    """Wingbeats after the gust's last beat until every later beat is within the bounds (None: never)."""
    ok = [within(b) for b in cl.beats]
    for k in range(len(ok)):
        if all(ok[k:]):
            return max(0, cl.beats[k]["beat"] - end_beat)
    return None


def activity(cl, orbit_kin):
    """Largest |command - orbit| over the flight, per channel (f in Hz, angles in deg), every update."""
    ref = {"f_hz": orbit_kin.f, "phi0_deg": np.rad2deg(orbit_kin.phi0), "alpha0_deg": np.rad2deg(orbit_kin.alpha0),
           "theta0_deg": np.rad2deg(orbit_kin.theta0)}
    cmds = [b[key] for b in cl.beats for key in ("commands", "commands_half_stroke") if key in b]
    return {c: float(max(abs(x[c] - ref.get(c, 0.0)) for x in cmds)) for c in CMD}


def mu(g):
    return [float(abs(complex(z))) for z in g.multipliers if abs(z) > 1e-12]


def study(rate: str, command_weight) -> dict:
    t0 = time.time()
    sch = {d: Schedule(0, 2, delay=d, rate=rate, command_weight=command_weight) for d in (0, 1)}
    res = {"schedule": {d: [{"speed": p.speed, "orbit_P_plus": p.orbit.P_plus,
                             "open_loop_max_multiplier_long": float(np.abs(p.long.open_loop).max()),
                             "closed_long": mu(p.long), "closed_lat": mu(p.lat)} for p in sch[d].points]
                        for d in (0, 1)}}
    res["linearize_wall_s"] = [p.half.wall_time_s if p.half is not None else p.model.wall_time_s
                               for p in sch[0].points]
    hold, gust = {}, {}
    pert = np.zeros(9)
    pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)  # v, w [m/s], phi, theta [rad]
    for i, v in enumerate(SCHEDULE_SPEEDS):
        kin = sch[0].points[i].orbit.kinematics
        cl = fly_closed_loop(v, 100, schedule=sch[0])
        cp = fly_closed_loop(v, 100, schedule=sch[0], perturbation=pert)
        ok = [within(b) for b in cp.beats]
        settle = next((k for k in range(len(ok)) if all(ok[k:])), None)
        hold[v] = {"from_orbit": stats(cl), "orbit_P_plus": sch[0].points[i].orbit.P_plus, "wall_s": cl.wall_time_s,
                   "perturbed_start": stats(cp), "perturbed_after_10": stats(cp, 10),
                   "perturbed_settled_at_beat": None if settle is None else cp.beats[settle]["beat"],
                   "perturbed_activity": activity(cp, kin)}
        cg = fly_closed_loop(v, 30, gusts=[GUST], schedule=sch[0])
        gust[v] = {"recovered_beats_after_gust": recovered_after(cg, GUST.start + GUST.beats - 1),
                   "peak": stats(cg), "activity": activity(cg, kin)}
        log(f"{rate} {command_weight} V={v:g}: hold {hold[v]['perturbed_start']} gust {gust[v]}")
    res["hold_100_beats"], res["gust_0.5_lateral_2_beats"] = hold, gust
    prof = fly_closed_loop(0, 40, profile=[(0, 2), (1, 10), (2, 10)], schedule=sch[0])
    res["profile_0_1_2"] = {"overshoot_m_s": float(max(b["mean_vertical_speed"] - b["speed_command"]
                                                       for b in prof.beats)),
                            "saturated_beats": int(sum(b["saturated"] for b in prof.beats)),
                            "activity": activity(prof, sch[0].points[0].orbit.kinematics),
                            "stats": stats(prof), "final_10": stats(prof, 30),
                            "settled_within_0.02_at_beat": next(
                                (b["beat"] for b in prof.beats if b["beat"] > 12 and all(
                                    abs(x["speed_error"]) <= 0.02 for x in prof.beats[b["beat"] - 1:])), None)}
    dl = {}
    for name, s in (("delay-aware design", sch[1]), ("design without delay", sch[0])):
        try:
            cl = fly_closed_loop(1.0, 100, delay=1, schedule=s, gusts=[GUST])
            dl[name] = {"stats": stats(cl), "after_20": stats(cl, 20),
                        "recovered_beats_after_gust": recovered_after(cl, GUST.start + GUST.beats - 1)}
        except FloatingPointError as exc:
            dl[name] = {"diverged": str(exc)}
    res["delay_1_beat_1ms_gust"] = dl
    res["wall_s"] = time.time() - t0
    return res


def table(res):
    """The markdown rows of docs/control.md's comparison."""
    lines = []
    for v in SCHEDULE_SPEEDS:
        cells = []
        for name in DESIGNS:
            r = res[name]
            s = next(p for p in r["schedule"]["0"] if p["speed"] == v)
            h, g = r["hold_100_beats"][str(v)], r["gust_0.5_lateral_2_beats"][str(v)]
            o, p = h["from_orbit"], h["perturbed_start"]
            gp = g["peak"]
            cells.append(f"{max(s['closed_long']):.3f} / {max(s['closed_lat']):.3f} | "
                         f"{o['speed_error']:.1e} / {o['pitch_error_deg']:.4f} / {o['roll_deg']:.0e} / "
                         f"{o['horizontal_drift_m'] * 1e3:.3f} | "
                         f"{p['speed_error']:.3f} / {p['pitch_error_deg']:.2f} / {p['roll_deg']:.2f} / "
                         f"{p['horizontal_drift_m'] * 1e3:.1f}, {h['perturbed_settled_at_beat']} | "
                         f"{g['recovered_beats_after_gust']}: {gp['speed_error']:.3f} / {gp['pitch_error_deg']:.2f} / "
                         f"{gp['roll_deg']:.2f} / {gp['horizontal_drift_m'] * 1e3:.1f} | "
                         f"{h['orbit_P_plus']:.4f} / {o['mean_P_plus']:.4f} / {p['mean_P_plus']:.4f} / "
                         f"{gp['mean_P_plus']:.4f}")
        for name, c in zip(DESIGNS, cells):
            lines.append(f"| {v:g} | {name} | {c} |")
    return "\n".join(lines)


def main():
    t0 = time.time()
    res = {"host": platform.node(), "date": time.strftime("%Y-%m-%d %H:%M"), "body_length_m": L, "bounds": BOUNDS}
    for name, (rate, cw) in DESIGNS.items():
        res[name] = study(rate, cw)
    res["wall_s"] = time.time() - t0
    OUT.mkdir(parents=True, exist_ok=True)
    text = json.dumps(res, indent=1, default=float)
    (OUT / "control_rate_study.json").write_text(text)
    res = json.loads(text)  # speeds as the JSON's string keys
    print(table(res))
    for name in DESIGNS:
        r = res[name]
        print(name, json.dumps({k: r[k] for k in ("profile_0_1_2", "delay_1_beat_1ms_gust", "wall_s")}))
        print(name, "schedule d=1", json.dumps(r["schedule"]["1"]))
        print(name, "activity (perturbed, gust) at 1 m/s",
              json.dumps(r["hold_100_beats"]["1.0"]["perturbed_activity"]),
              json.dumps(r["gust_0.5_lateral_2_beats"]["1.0"]["activity"]))


if __name__ == "__main__":
    main()
