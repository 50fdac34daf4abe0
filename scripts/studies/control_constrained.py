"""The constrained LQR (hawksim.control.constrained) against the per-beat LQR with the per-step surrogate in the
loop, on issue 20's targets, and the UVLM's own controlled response to the same gusts (docs/control.md,
"Gusts: the surrogate, its envelope and the UVLM").

Controllers (per beat, the shipped surrogate orbits and control derivatives):

* ``lqr``: the per-beat LQR of hawksim.control.schedule (theta0 left out, each wing clipped at Table 2);
* ``constrained``: the constrained LQR planning within Table 2 (theta0 held at its bound);
* ``constrained_env``: the same within the network's training envelope (each parameter within +-ENVELOPE x Table 2's
  width of the reference; hawksim.surrogate.flights.KIN_SPREAD is 0.025).

Per speed (0, 0.5, 1, 1.5, 2 m/s): 100 beats from the orbit; 100 beats from the perturbed start (v, w +0.05 m/s, bank
and pitch +1 deg), first beat from which every later beat is within the bounds; lateral gusts (world +y) of
0.1-0.5 m/s over beats 5-6, 30 beats, beats after the gust until recovered; the perturbed start with a one-beat sensing
delay (delay-aware design). With ``--uvlm``: the UVLM in the loop under its own LQR (1, 1.5, 2 m/s, 20 beats) with
the 0.5 m/s gust, and the open-loop response of the three backends to it at 1 m/s.

    NUMBA_NUM_THREADS=1 python scripts/studies/control_constrained.py [--uvlm] [--out FILE.json]

Deterministic (no seed).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from hawksim.control.closed_loop import Gust, body_length, fly_closed_loop
from hawksim.control.constrained import ConstrainedSchedule
from hawksim.control.schedule import Schedule, surrogate_schedule_speeds
from hawksim.jsonout import host_info

OUT = Path(__file__).resolve().parents[2] / "results" / "control" / "control_constrained.json"
L = body_length()
BOUNDS = dict(speed_error=0.02, pitch_error_deg=2.0, roll_deg=2.0, horizontal_drift_m=L)
"""Issue 20's bounds (as scripts/studies/control_surrogate.py)."""
GUSTS = (0.1, 0.2, 0.3, 0.4, 0.5)
GUST_START, GUST_BEATS = 5, 2
PERTURBATION = np.array([0, 0.05, 0.05, 0, 0, 0, np.deg2rad(1.0), np.deg2rad(1.0), 0])
"""v, w +0.05 m/s, bank and pitch +1 deg (STATE_NAMES order), as the surrogate study's perturbed start."""
ENVELOPE = 0.05
"""Twice the network's training spread (hawksim.surrogate.flights.KIN_SPREAD = 0.025 of Table 2's width)."""
CONTROLLERS = ("lqr", "constrained", "constrained_env")


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def within(b):
    return all(abs(b[k]) <= v for k, v in BOUNDS.items())


def settled_at(beats):
    ok = [within(b) for b in beats]
    return next((beats[k]["beat"] for k in range(len(ok)) if all(ok[k:])), None)


def peaks(beats):
    return {k: float(max(abs(b[k]) for b in beats)) for k in BOUNDS} | {
        "mean_P_plus": float(np.mean([b["P_plus"] for b in beats]))}


def schedule(name, v, delay=0):
    if name == "lqr":
        return Schedule(v, v, aero="surrogate", speeds=(v,), delay=delay)
    env = ENVELOPE if name == "constrained_env" else None
    return ConstrainedSchedule(v, v, aero="surrogate", speeds=(v,), delay=delay, envelope=env)


def flight(v, beats, sch, aero="surrogate", **kw):
    try:
        return fly_closed_loop(v, beats, aero=aero, schedule=sch, **kw).beats
    except FloatingPointError as exc:
        return str(exc)


def summary(beats, gust_end=None):
    if isinstance(beats, str):
        return {"diverged": beats}
    k = settled_at(beats)
    out = {"within_bounds_from_beat": k, "peak": peaks(beats)}
    if gust_end is not None:
        out["recovered_beats_after_gust"] = None if k is None else max(0, k - gust_end)
    return out


def surrogate_part():
    rows = {}
    for v in surrogate_schedule_speeds():
        rows[f"{v:g}"] = row = {}
        for name in CONTROLLERS:
            t0 = time.perf_counter()
            sch = schedule(name, v)
            r = {"hold_100": summary(flight(v, 100, sch)),
                 "perturbed_100": summary(flight(v, 100, sch, perturbation=PERTURBATION))}
            for g in GUSTS:
                r[f"gust_{g:g}"] = summary(flight(v, 30, sch, gusts=[Gust(np.array([0.0, g, 0.0]), GUST_START,
                                                                          GUST_BEATS)]), GUST_START + GUST_BEATS - 1)
            sd = schedule(name, v, delay=1)
            r["delay_1_perturbed_100"] = summary(flight(v, 100, sd, perturbation=PERTURBATION, delay=1))
            r["delay_1_half_perturbed_100"] = summary(flight(v, 100, sd, perturbation=PERTURBATION / 2, delay=1))
            if hasattr(sch, "bound_active"):
                r["bound_active_commands"] = int(sch.bound_active)
            r["wall_s"] = time.perf_counter() - t0
            row[name] = r
            g = [r[f"gust_{x:g}"].get("recovered_beats_after_gust", "dep") for x in GUSTS]
            log(f"V={v:g} {name}: perturbed from {r['perturbed_100'].get('within_bounds_from_beat')}, "
                f"gusts {GUSTS} recovered after {g}, delay {r['delay_1_perturbed_100'].get('within_bounds_from_beat')}"
                f" / half {r['delay_1_half_perturbed_100'].get('within_bounds_from_beat')} ({r['wall_s']:.0f} s)")
    return rows


def uvlm_part():
    out = {"closed_loop_gust_0.5": {}, "open_loop_gust_0.5_at_1": {}}
    for v in (1.0, 1.5, 2.0):
        t0 = time.perf_counter()
        b = flight(v, 20, Schedule(v, v, aero="uvlm", speeds=(v,)), aero="uvlm",
                   gusts=[Gust(np.array([0.0, 0.5, 0.0]), GUST_START, GUST_BEATS)])
        out["closed_loop_gust_0.5"][f"{v:g}"] = s = summary(b, GUST_START + GUST_BEATS - 1)
        s["wall_s"] = time.perf_counter() - t0
        log(f"UVLM V={v:g} gust 0.5: {s.get('recovered_beats_after_gust', s.get('diverged'))}")
    for aero in ("quasi-steady", "surrogate", "uvlm"):  # open loop, gust over beats 2-3
        b = fly_closed_loop(1.0, 4, aero=aero, control="none", gusts=[Gust(np.array([0.0, 0.5, 0.0]), 2, 2)]).beats
        x1 = np.array(b[0]["state"])
        out["open_loop_gust_0.5_at_1"][aero] = [
            {"beat": c["beat"], "dv_m_s": float(np.array(c["state"])[1] - x1[1]),
             "dp_rad_s": float(np.array(c["state"])[3] - x1[3]), "dr_rad_s": float(np.array(c["state"])[5] - x1[5]),
             "dphi_deg": float(np.rad2deg(np.array(c["state"])[6] - x1[6])),
             "dpsi_deg": float(np.rad2deg(np.array(c["state"])[8] - x1[8]))} for c in b[1:]]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--uvlm", action="store_true", help="also the UVLM's controlled and open-loop gust responses")
    a = ap.parse_args()
    t0 = time.perf_counter()
    out = {"host": host_info(), "bounds": BOUNDS, "gust_beats": [GUST_START, GUST_START + GUST_BEATS - 1],
           "envelope_fraction_of_table2": ENVELOPE, "surrogate": surrogate_part()}
    if a.uvlm:
        out["uvlm"] = uvlm_part()
    out["wall_time_s"] = time.perf_counter() - t0
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(out, indent=1) + "\n")
    log(f"wrote {a.out} ({out['wall_time_s']:.0f} s)")


if __name__ == "__main__":
    main()
