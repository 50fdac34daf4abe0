"""Issue 20's targets with the per-step surrogate in the loop (`hawksim fly --aero surrogate --control lqr`,
docs/control.md "The per-step surrogate in the loop"): the gain schedule of the shipped surrogate orbits and control
derivatives (hawksim/insects/hawkmoth/data/orbit_table_surrogate.json, control_models_surrogate.json), with

* the open- and closed-loop multipliers at every schedule speed, without and with a one-beat sensing delay;
* 100 controlled wingbeats from each orbit, and from a perturbed start (v, w +0.05 m/s, phi, theta +1 deg);
* the ascent profile 0:2, 1:25, 2:25 (60 beats; the surrogate's speed reference moves 0.05 m/s per beat,
  hawksim.backends.builtin.SURROGATE_SPEED_RATE) and its overshoot;
* a 0.5 m/s lateral gust (world +y) over beats 5-6, 30 beats, at every speed: beats until recovered; and the same
  for lateral gusts of 0.05-0.4 m/s (the largest the loop recovers from within 10 beats);
* the one-beat sensing delay: the perturbed start at every speed and a 0.2 m/s lateral gust at 1 m/s, 100 beats
  (delay-aware gains, and gains without the delay), and the 0.5 m/s gust at 1 m/s;
* an experiment: the same design with theta0 kept in it (the perturbed start and the gust at every speed);
* an experiment: orbits with a margin below the Table 2 bounds the shipped orbits sit on (phi_a 58 instead of 60,
  theta0 23 instead of 25 deg; f and phi0 re-solved), linearized, and the lateral gusts flown from them (hover and
  2 m/s; not shipped);
* the open-loop flight at 1 m/s (where it departs);
* the cost of control: mean P+ of each flight against the orbit's, and the commands' largest excursions.

Writes results/control/control_surrogate.json. ``NUMBA_NUM_THREADS=1 python scripts/studies/control_surrogate.py``
(a few minutes on one core; the flights are deterministic, no seed). ``--rate half-stroke``: the same targets with
the kinematics updated per half-stroke (hawksim.control.halfstroke; the two experiments left out), written to
results/control/control_surrogate_half_stroke.json.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from hawksim.control.closed_loop import Gust, body_length, fly_closed_loop
from hawksim.control.schedule import Schedule, surrogate_schedule_speeds
from hawksim.jsonout import host_info

OUT = Path(__file__).resolve().parents[2] / "results" / "control"
L = body_length()
BOUNDS = dict(speed_error=0.02, pitch_error_deg=2.0, roll_deg=2.0, horizontal_drift_m=L)
"""Issue 20's bounds: beat-mean vertical speed within 0.02 m/s of the command, pitch (against the orbit's mean) and
roll within 2 deg, horizontal drift below one body length."""
GUST = Gust(np.array([0.0, 0.5, 0.0]), 5, 2)
GUST_SWEEP = (0.05, 0.1, 0.2, 0.3, 0.4)
"""Smaller lateral gusts [m/s] (world +y, beats 5-6) flown to find the largest the loop recovers from."""
AERO = "surrogate"
PROFILE = [(0.0, 2), (1.0, 25), (2.0, 25)]
"""The ascent profile [(speed m/s, beats)], then 2 m/s held (60 beats in all)."""


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def stats(cl, skip=0):
    b = cl.beats[skip:]
    return {k: float(max(abs(x[k]) for x in b)) for k in BOUNDS} | {
        "mean_P_plus": float(np.mean([x["P_plus"] for x in b])), "saturated_beats": sum(x["saturated"] for x in b)}


def within(b):
    return all(abs(b[k]) <= v for k, v in BOUNDS.items())


def settled_at(cl):
    """First beat from which every later beat is within the bounds (None: never)."""
    ok = [within(b) for b in cl.beats]
    return next((cl.beats[k]["beat"] for k in range(len(ok)) if all(ok[k:])), None)


def recovered_after(cl, end_beat):
    """Wingbeats after the gust's last beat until every later beat is within the bounds (None: never)."""
    k = settled_at(cl)
    return None if k is None else max(0, k - end_beat)


def command_excursion(cl, kin):
    """Largest |command - orbit| over the flight per channel (f in Hz, angles in deg)."""
    e = kin.to_edge()
    ref = {"f_hz": e["f"], "phi0_deg": e["phi0"], "alpha0_deg": e["alpha0"], "theta0_deg": e["theta0"],
           "dphi_a_deg": 0.0, "dphi0_deg": 0.0, "dalpha0_deg": 0.0}
    return {k: float(max(abs(b["commands"][k] - r) for b in cl.beats)) for k, r in ref.items()}


def fly(*a, **kw):
    try:
        return fly_closed_loop(*a, aero=AERO, **kw)
    except FloatingPointError as exc:
        return str(exc)


def margin_experiment(speeds=(0.0, 2.0), phi_a_deg=58.0, theta0_deg=23.0, gusts=(0.1, 0.3, 0.5)):
    """Orbits with a margin below the bounds (module docstring), their LQR, and lateral gusts over beats 5-6."""
    from hawksim.control import schedule as S
    from hawksim.control.derivatives import linearize
    from hawksim.flight.orbit import periodic_orbit, shipped_orbit
    from hawksim.insect.kinematics import Kinematics

    out = {"phi_a_deg": phi_a_deg, "theta0_deg": theta0_deg}
    for v in speeds:
        o0 = shipped_orbit(v, AERO)
        e = {**o0.kinematics.to_edge(), "phi_a": phi_a_deg, "theta0": theta0_deg}
        o = periodic_orbit(v, AERO, kinematics=Kinematics.from_edge(e), x0=o0.launch_state.as_array())
        with S.operating_point_override(v, AERO, o, linearize(o)):  # this orbit for the experiment only
            sch = S.Schedule(v, v, aero=AERO, speeds=(v,))
            p = sch.points[0]
            row = {"orbit_f_hz": o.kinematics.f, "orbit_residual": o.residual, "orbit_P_plus": o.P_plus,
                   "shipped_orbit_P_plus": o0.P_plus, "long_inputs": list(p.long.inputs),
                   "closed_loop_spectral_radius": max(p.long.spectral_radius, p.lat.spectral_radius)}
            for g in gusts:
                cl = fly(v, 30, schedule=sch, gusts=[Gust(np.array([0.0, g, 0.0]), GUST.start, GUST.beats)])
                row[f"gust_{g:g}"] = {"diverged": cl} if isinstance(cl, str) else {
                    "recovered_beats_after_gust": recovered_after(cl, GUST.start + GUST.beats - 1), "peak": stats(cl)}
        out[f"{v:g}"] = row
        log(f"margin {v:g}: {json.dumps(row, default=float)[:500]}")
    return out


def theta0_experiment(speeds):
    """The same design with theta0 kept (hawksim.control.schedule.ONE_SIDED_DROPPED emptied): the perturbed start
    and the 0.5 m/s gust at every speed."""
    from hawksim.control import schedule as S

    saved = S.ONE_SIDED_DROPPED
    S.ONE_SIDED_DROPPED = ()
    try:
        sch = S.Schedule(speeds[0], speeds[-1], aero=AERO)
        out = {"long_inputs": [list(p.long.inputs) for p in sch.points],
               "closed_loop_spectral_radius": [max(p.long.spectral_radius, p.lat.spectral_radius) for p in sch.points]}
        pert = np.zeros(9)
        pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)
        for v in speeds:
            cp = fly(v, 100, schedule=sch, perturbation=pert)
            cg = fly(v, 30, schedule=sch, gusts=[GUST])
            out[f"{v:g}"] = {
                "perturbed_start": {"diverged": cp} if isinstance(cp, str) else {**stats(cp), "settled_at_beat":
                                                                                  settled_at(cp)},
                "gust_recovered_beats_after": None if isinstance(cg, str) else recovered_after(cg, 6)}
    finally:
        S.ONE_SIDED_DROPPED = saved
    log(f"theta0 kept: {json.dumps(out, default=float)[:500]}")
    return out


FIGURE_PROFILE = [(0.0, 2), (1.0, 25), (2.0, 48)]
FIGURE_GUST = Gust(np.array([0.0, 0.5, 0.0]), 58, 2)
"""The figure's flight (results/control/controlled_flight_surrogate.png, with ``--rate half-stroke``, the
surrogate's default): the ascent profile, then issue 20's 0.5 m/s lateral gust at 2 m/s over beats 58-59, 75 beats."""


def figure(rate):
    from hawksim.control.figure import controlled_flight_figure

    cl = fly_closed_loop(0.0, 75, profile=FIGURE_PROFILE, gusts=[FIGURE_GUST], aero=AERO, rate=rate, record=True)
    b = cl.beats
    out = {"overshoot_m_s": float(max(x["mean_vertical_speed"] - x["speed_command"] for x in b)),
           "max_pitch_error_deg": float(max(abs(x["pitch_error_deg"]) for x in b)),
           "max_roll_deg": float(max(abs(x["roll_deg"]) for x in b)),
           "recovered_beats_after_gust": recovered_after(cl, FIGURE_GUST.start + FIGURE_GUST.beats - 1)}
    controlled_flight_figure(cl, OUT / "controlled_flight_surrogate.png",
                             title=f"LQR per {rate}, per-step surrogate: profile 0:2,1:25,2:48 m/s:beats, gust "
                                   "0,0.5,0 m/s @ beats 58-59 (shaded)",
                             caption=f"hawksim fly --aero surrogate --speed 0 --cycles 75 --ascent-profile "
                                     f"0:2,1:25,2:48 --gust 0,0.5,0@58:2 --control-rate {rate} "
                                     "(scripts/studies/control_surrogate.py --rate half-stroke). The speed reference "
                                     "moves 0.05 m/s per beat (SURROGATE_SPEED_RATE).")
    return out


def main():
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rate", choices=("beat", "half-stroke"), default="beat")
    ap.add_argument("--figure-only", action="store_true", help="only the figure (--rate half-stroke's)")
    args = ap.parse_args()
    rate = args.rate
    if args.figure_only:
        log(f"figure: {figure(rate)}")
        return
    t0 = time.time()
    speeds = surrogate_schedule_speeds()
    res = {"host": host_info(), "command": "python scripts/studies/control_surrogate.py"
           + ("" if rate == "beat" else " --rate half-stroke"), "aero": AERO, "rate": rate,
           "body_length_m": L, "bounds": BOUNDS, "speeds": list(speeds)}
    sch = {d: Schedule(speeds[0], speeds[-1], delay=d, aero=AERO, log=log, rate=rate) for d in (0, 1)}
    res["schedule"] = {d: [{"speed": p.speed, "orbit_f_hz": p.orbit.kinematics.f, "orbit_P_plus": p.orbit.P_plus,
                            "open_loop_long": [abs(complex(z)) for z in p.long.open_loop],
                            "open_loop_lat": [abs(complex(z)) for z in p.lat.open_loop],
                            "closed_long": [abs(complex(z)) for z in p.long.multipliers if abs(z) > 1e-12],
                            "closed_lat": [abs(complex(z)) for z in p.lat.multipliers if abs(z) > 1e-12],
                            "closed_loop_spectral_radius": max(p.long.spectral_radius, p.lat.spectral_radius),
                            "coupling": p.model.coupling, "K_long": p.long.K.tolist(), "K_lat": p.lat.K.tolist()}
                           for p in sch[d].points] for d in (0, 1)}
    orbit_pp = {p.speed: p.orbit.P_plus for p in sch[0].points}
    hold = {}
    for v in speeds:
        cl = fly(v, 100, schedule=sch[0])
        pert = np.zeros(9)
        pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)  # v, w [m/s], phi, theta [rad]
        cp = fly(v, 100, schedule=sch[0], perturbation=pert)
        kin = next(p.orbit.kinematics for p in sch[0].points if p.speed == v)
        hold[f"{v:g}"] = {
            "orbit_P_plus": orbit_pp[v],
            "from_orbit": cl if isinstance(cl, str) else {**stats(cl), "wall_s": cl.wall_time_s,
                                                          "wall_s_per_beat": cl.wall_time_s / 100,
                                                          "command_excursion": command_excursion(cl, kin)},
            "perturbed_start": cp if isinstance(cp, str) else {
                **stats(cp), "beats_11_100": stats(cp, 10), "settled_at_beat": settled_at(cp),
                "command_excursion": command_excursion(cp, kin)}}
        log(f"hold {v:g}: {json.dumps(hold[f'{v:g}'], default=float)}")
    res["hold_100_beats"] = hold
    prof = fly(0.0, 60, profile=PROFILE, schedule=sch[0])
    if isinstance(prof, str):
        res["profile_0_1_2"] = {"diverged": prof}
    else:
        b = prof.beats
        res["profile_0_1_2"] = {
            "profile": PROFILE, "overshoot_m_s": float(max(x["mean_vertical_speed"] - x["speed_command"] for x in b)),
            "speed_rate_m_s_per_beat": prof.speed_rate,
            "max_abs_pitch_error_deg": float(max(abs(x["pitch_error_deg"]) for x in b)),
            "max_lag_behind_reference_m_s": float(max(x["speed_reference"] - x["mean_vertical_speed"] for x in b)),
            "max_f_hz": float(max(x["commands"]["f_hz"] for x in b)),
            "stats": stats(prof), "final_10": stats(prof, 50),
            "within_0.02_of_1_from_beat": next((x["beat"] for k, x in enumerate(b[:27])
                                                if all(abs(y["mean_vertical_speed"] - 1.0) <= 0.02 for y in b[k:27])),
                                               None),
            "within_0.02_of_2_from_beat": next((x["beat"] for k, x in enumerate(b)
                                                if all(abs(y["mean_vertical_speed"] - 2.0) <= 0.02 for y in b[k:])),
                                               None),
            "speeds": [x["mean_vertical_speed"] for x in b], "pitch_error_deg": [x["pitch_error_deg"] for x in b],
            "f_hz": [x["commands"]["f_hz"] for x in b], "theta0_deg": [x["commands"]["theta0_deg"] for x in b]}
    log(f"profile: {json.dumps({k: v for k, v in res['profile_0_1_2'].items() if k not in ('speeds',)})[:600]}")
    gust = {}
    for v in speeds:
        cl = fly(v, 30, gusts=[GUST], schedule=sch[0])
        gust[f"{v:g}"] = cl if isinstance(cl, str) else {
            "recovered_beats_after_gust": recovered_after(cl, GUST.start + GUST.beats - 1), "peak": stats(cl),
            "orbit_P_plus": orbit_pp[v]}
        log(f"gust {v:g}: {json.dumps(gust[f'{v:g}'], default=float)}")
    res["gust_0.5_lateral_beats_5_6"] = gust
    sweep = {}
    for v in speeds:
        sweep[f"{v:g}"] = row = {}
        for g in GUST_SWEEP:
            cl = fly(v, 30, gusts=[Gust(np.array([0.0, g, 0.0]), GUST.start, GUST.beats)], schedule=sch[0])
            row[f"{g:g}"] = {"diverged": cl} if isinstance(cl, str) else {
                "recovered_beats_after_gust": recovered_after(cl, GUST.start + GUST.beats - 1), "peak": stats(cl)}
        ok = [g for g in GUST_SWEEP if isinstance(row[f"{g:g}"].get("recovered_beats_after_gust"), int)
              and row[f"{g:g}"]["recovered_beats_after_gust"] <= 10]
        row["largest_recovered_within_10_beats_m_s"] = max(ok) if ok else None
        log(f"gust sweep {v:g}: largest recovered within 10 beats {row['largest_recovered_within_10_beats_m_s']}")
    res["gust_sweep_lateral_beats_5_6"] = sweep
    dl = {}
    pert = np.zeros(9)
    pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)
    for name, s_ in (("delay-aware design", sch[1]), ("design without delay", sch[0])):
        dl[name] = row = {}
        for v in speeds:
            cl = fly(v, 100, delay=1, schedule=s_, perturbation=pert)
            row[f"perturbed_start_{v:g}"] = {"diverged": cl} if isinstance(cl, str) else {
                "stats": stats(cl), "beats_11_100": stats(cl, 10), "settled_at_beat": settled_at(cl)}
        for v in speeds:  # half the perturbation
            cl = fly(v, 100, delay=1, schedule=s_, perturbation=pert / 2)
            row[f"perturbed_start_half_{v:g}"] = {"diverged": cl} if isinstance(cl, str) else {
                "stats": stats(cl), "beats_11_100": stats(cl, 10), "settled_at_beat": settled_at(cl)}
        for g in (0.2, 0.5):
            cl = fly(1.0, 100, delay=1, schedule=s_, gusts=[Gust(np.array([0.0, g, 0.0]), 5, 2)])
            row[f"gust_{g:g}_1"] = {"diverged": cl} if isinstance(cl, str) else {
                "stats": stats(cl), "after_20": stats(cl, 20),
                "recovered_beats_after_gust": recovered_after(cl, GUST.start + GUST.beats - 1)}
        log(f"delay {name}: {json.dumps(row, default=float)[:600]}")
    res["delay_1_beat_1ms_gust"] = dl
    if rate == "beat":
        res["margin_orbit_experiment"] = margin_experiment()
        res["theta0_in_the_design_experiment"] = theta0_experiment(speeds)
    ol = fly(1.0, 40, control="none", schedule=sch[0])
    res["open_loop_1ms"] = {"diverged": ol} if isinstance(ol, str) else {
        "departed_at_beat": next((b["beat"] for b in ol.beats if abs(b["speed_error"]) > 0.1
                                  or abs(b["pitch_error_deg"]) > 10), None),
        "speed_error": [b["speed_error"] for b in ol.beats],
        "pitch_error_deg": [b["pitch_error_deg"] for b in ol.beats]}
    res["wall_s"] = time.time() - t0
    OUT.mkdir(parents=True, exist_ok=True)
    if rate == "half-stroke":
        res["figure"] = figure(rate)
    name = "control_surrogate.json" if rate == "beat" else "control_surrogate_half_stroke.json"
    (OUT / name).write_text(json.dumps(res, indent=1, default=float) + "\n")
    log(f"wrote {OUT / name} ({res['wall_s']:.0f} s)")


if __name__ == "__main__":
    main()
