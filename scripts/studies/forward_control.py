"""The LQR in forward flight on the forward-flight schedule (issue 51, item 5; docs/forward_flight.md, "Control").

Quasi-steady, level flight, the schedule of :class:`hawksim.control.schedule.Schedule` with ``axis="forward"`` (its
orbits at :data:`hawksim.control.schedule.FORWARD_SCHEDULE_SPEEDS`). Measured here:

- ``holds``: from every schedule orbit pitched and banked by 2 deg and 0.1 m/s fast, 100 beats per beat (and per
  half-stroke at ``--half-stroke-speeds``): departed or not, the last beat's errors, the largest pitch error;
- ``gusts``: at 3 m/s, a 0.5 m/s gust over one beat (beat 5) from the side, head-on and from behind, 40 beats;
- ``profiles``: hover -> U_max -> hover for each U_max of ``--profile-tops`` at each rate of ``--speed-rates`` [m/s
  per beat] (:data:`hawksim.control.controller.FORWARD_SPEED_RATE` and the vertical schedule's
  :data:`hawksim.control.controller.SPEED_RATE`), with where it departed and the commands then.

    python -m scripts.studies.forward_control --out results/forward_flight/control.json
    python -m scripts.studies.forward_control --from results/forward_flight/control.json --markdown
    python -m scripts.studies.forward_control --plot docs/images/forward_profile.png
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from hawksim import __version__
from hawksim.atomic import write_text
from hawksim.control.controller import FORWARD_SPEED_RATE, LQR, SPEED_RATE
from hawksim.control.schedule import Schedule
from hawksim.flight.loop import Gust, fly

GUSTS = {"side": (0.0, 0.5, 0.0), "head-on": (-0.5, 0.0, 0.0), "from behind": (0.5, 0.0, 0.0)}
"""The 3 m/s gusts [m/s] (world: x forward, y left, z up), over beat 5 only."""


def _summary(r, ref_speed: float | None = None) -> dict:
    b = r.beat_log
    last = b[-1]
    out = {"departed_at_beat": r.departed_at_beat(), "beats": len(b),
           "largest_pitch_error_deg": max(abs(x["pitch_error_deg"]) for x in b),
           "largest_roll_deg": max(abs(x["roll_deg"]) for x in b),
           "saturated_beats": int(sum(x["saturated"] for x in b)),
           "last": {k: last[k] for k in ("mean_forward_speed", "mean_vertical_speed", "pitch_error_deg", "roll_deg",
                                         "horizontal_offset_m")}}
    if ref_speed is not None:
        out["last"]["forward_speed_error"] = last["mean_forward_speed"] - ref_speed
    return out


def holds(sch: Schedule, beats: int) -> list[dict]:
    rows = []
    for U in sch.speeds:
        ctl = LQR(sch, float(U))
        r = fly(ctl.point, cycles=beats, controller=ctl, perturb={"theta": 2, "phi": 2, "u": 0.1})
        p = next(p for p in sch.points if p.forward_speed == U)
        rows.append({"forward_speed": float(U), "rate": sch.rate, "orbit_residual": p.orbit.residual,
                     "orbit_P_plus": p.orbit.P_plus, "orbit_kinematics": p.orbit.kinematics.to_edge(),
                     "closed_loop_spectral_radius": [p.long.spectral_radius, p.lat.spectral_radius],
                     **_summary(r, float(U))})
        print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    return rows


def _departed(r: dict) -> str:
    return f"beat {r['departed_at_beat']}" if r["departed_at_beat"] else "no"


def markdown(d: dict) -> str:
    """The docs' tables: the holds, the gusts, the profiles."""
    lines = ["| U [m/s] | rate | orbit P+ | closed-loop spectral radius (lon, lat) | departed | largest pitch error "
             "[deg] | last beat: forward speed error [m/s], pitch error, roll [deg] | beats saturated |",
             "|---|---|---|---|---|---|---|---|"]
    for r in d["holds"]:
        last = r["last"]
        lines.append(f"| {r['forward_speed']:g} | {r['rate']} | {r['orbit_P_plus']:.3f} | "
                     f"{r['closed_loop_spectral_radius'][0]:.3f}, {r['closed_loop_spectral_radius'][1]:.3f} | "
                     f"{_departed(r)} | "
                     f"{r['largest_pitch_error_deg']:.2f} | {last['forward_speed_error']:+.1e}, "
                     f"{last['pitch_error_deg']:+.3f}, {last['roll_deg']:+.3f} | {r['saturated_beats']} |")
    lines += ["", "| gust at 3 m/s (0.5 m/s, beat 5) | departed | largest pitch error [deg] | largest roll [deg] | "
              "beat 40: forward speed error [m/s], pitch error, roll [deg], sideways offset [mm] |",
              "|---|---|---|---|---|"]
    for g in d["gusts"]:
        last = g["last"]
        lines.append(f"| {g['from']} | {_departed(g)} | "
                     f"{g['largest_pitch_error_deg']:.2f} | {g['largest_roll_deg']:.2f} | "
                     f"{last['forward_speed_error']:+.1e}, {last['pitch_error_deg']:+.3f}, {last['roll_deg']:+.3f}, "
                     f"{1e3 * last['horizontal_offset_m'][1]:+.1f} |")
    lines += ["", "| profile | speed rate [m/s per beat] | departed | largest pitch error [deg] | largest roll [deg] | "
              "beats saturated | last beat: forward speed [m/s] |", "|---|---|---|---|---|---|---|"]
    for p in d["profiles"]:
        dep = "no" if p["departed_at_beat"] is None else (
            f"beat {p['departed_at_beat']} (reference {p['at_departure']['speed_reference']:.2f} m/s, flying "
            f"{p['at_departure']['mean_forward_speed']:.2f})")
        lines.append(f"| 0 -> {p['top']:g} -> 0 m/s | {p['speed_rate']:g} | {dep} | {p['largest_pitch_error_deg']:.2f}"
                     f" | {p['largest_roll_deg']:.2f} | {p['saturated_beats']} of {p['beats']} | "
                     f"{p['last']['mean_forward_speed']:.4f} |")
    return "\n".join(lines)


def fly_profile(sch: Schedule, top: float, rate: float):
    """Hover -> ``top`` [m/s] -> hover with the speed reference at ``rate`` [m/s per beat]: ``top / rate`` + 20 beats
    commanded at ``top``, then 40 more than the ramp down at 0 (the flight's FlightResult)."""
    n = int(round(top / rate))
    ctl = LQR(sch, 0.0, profile=[(top, n + 20), (0.0, n + 40)], speed_rate=rate)
    return fly(ctl.point, cycles=2 * n + 60, controller=ctl)


def plot_profile(sch: Schedule, path: Path, top: float = 4.0, rate: float = FORWARD_SPEED_RATE) -> dict:
    """Fly :func:`fly_profile` and draw the forward speed against its reference and command, the pitch error and the
    commands per beat; returns the flight's summary."""
    from hawksim import plotting

    r = fly_profile(sch, top, rate)
    b = r.beat_log
    k = [x["beat"] for x in b]
    with plotting.style():
        plt = plotting.pyplot()
        fig, ax = plt.subplots(1, 3, figsize=(plotting.WIDE, 3.0))
        ax[0].plot(k, [x["speed_command"] for x in b], ":", color="grey", label="command")
        ax[0].plot(k, [x["speed_reference"] for x in b], "--", color="C0", label="reference (0.05 m/s per beat)")
        ax[0].plot(k, [x["mean_forward_speed"] for x in b], "-", color="k", label="flown (beat mean)")
        ax[0].set(xlabel="wingbeat", ylabel="forward speed U [m/s]", title="forward speed")
        ax[0].legend(loc="lower center")
        ax[1].plot(k, [x["pitch_error_deg"] for x in b], "-", color="k", label="pitch error")
        ax[1].plot(k, [x["mean_vertical_speed"] * 100 for x in b], "-", color="C1", label="vertical speed [cm/s]")
        ax[1].set(xlabel="wingbeat", ylabel="deg; cm/s", title="pitch error, vertical speed")
        ax[1].legend(loc="upper right")
        for key, label in (("phi0_deg", "phi0"), ("alpha0_deg", "alpha0"), ("theta0_deg", "theta0")):
            ax[2].plot(k, [x["commands"][key] for x in b], label=label)
        ax[2].axhline(-25.0, ls=":", color="grey", label="Table 2 bound")
        f = ax[2].twinx()
        f.plot(k, [x["commands"]["f_hz"] for x in b], color="k", lw=0.8, label="f [Hz] (right)")
        f.set(ylabel="f [Hz]")
        ax[2].set(xlabel="wingbeat", ylabel="deg", title="commands")
        ax[2].legend(loc="lower left")
        f.legend(loc="upper right")
        plotting.panel_letters(ax)
        plotting.save(fig, path, title="The LQR on the forward-flight schedule: hover to 4 m/s and back",
                      caption="Quasi-steady, level flight; schedule orbits every 0.5 m/s from the shipped forward "
                              "trims; python -m scripts.studies.forward_control --plot " + str(path))
    return _summary(r, 0.0)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--beats", type=int, default=100)
    ap.add_argument("--half-stroke-speeds", type=float, nargs="*", default=[1.0, 2.0, 3.0])
    ap.add_argument("--speed-rates", type=float, nargs="*", default=[FORWARD_SPEED_RATE, SPEED_RATE],
                    help="the profiles' speed-reference rates [m/s per beat]")
    ap.add_argument("--profile-tops", type=float, nargs="*", default=[4.0])
    ap.add_argument("--out", type=Path, help="write the JSON here")
    ap.add_argument("--from", dest="source", type=Path, help="read the JSON instead of computing")
    ap.add_argument("--markdown", action="store_true", help="print the docs' tables")
    ap.add_argument("--plot", type=Path, help="instead: fly the hover -> 4 m/s -> hover profile and draw it here")
    a = ap.parse_args()
    if a.plot is not None:
        print(json.dumps(plot_profile(Schedule(0.0, 4.0, axis="forward"), a.plot)))
        return
    if a.source is not None:
        d = json.loads(a.source.read_text())
        print(markdown(d) if a.markdown else json.dumps(d))
        return
    if a.out is None:
        ap.error("--out or --from is required")
    t0 = time.time()
    sch = Schedule(0.0, 4.0, axis="forward")
    out = {"command": " ".join(["python -m scripts.studies.forward_control", *sys.argv[1:]]),
           "hawksim_version": __version__, "created": time.strftime("%Y-%m-%d"), "seed": None,
           "seed_note": "deterministic: no random process", "schedule_speeds": [float(v) for v in sch.speeds]}
    out["holds"] = holds(sch, a.beats)
    for U in a.half_stroke_speeds:
        out["holds"] += holds(Schedule(U, U, axis="forward", rate="half-stroke"), a.beats)
    out["gusts"] = []
    for name, g in GUSTS.items():
        ctl = LQR(sch, 3.0)
        r = fly(ctl.point, cycles=40, controller=ctl, gusts=[Gust(np.array(g), 5, 1)])
        out["gusts"].append({"from": name, "air_velocity": list(g), "forward_speed": 3.0, **_summary(r, 3.0)})
        print(json.dumps(out["gusts"][-1]), file=sys.stderr, flush=True)
    out["profiles"] = []
    for top, rate in [(t, r) for t in a.profile_tops for r in a.speed_rates]:
        r = fly_profile(sch, top, rate)
        s = _summary(r, 0.0)
        k = s["departed_at_beat"]
        if k is not None:
            b = r.beat_log[k - 1]
            first_sat = next((x for x in r.beat_log if x["saturated"]), None)
            s["at_departure"] = {"speed_reference": b["speed_reference"], "mean_forward_speed": b["mean_forward_speed"],
                                 "pitch_error_deg": b["pitch_error_deg"], "commands": b["commands"]}
            s["first_saturated"] = None if first_sat is None else {
                "beat": first_sat["beat"], "speed_reference": first_sat["speed_reference"],
                "commands": first_sat["commands"]}
        else:
            s["largest_forward_speed_error"] = max(abs(x["speed_error"]) for x in r.beat_log)
        out["profiles"].append({"top": top, "speed_rate": rate, **s})
        print(json.dumps(out["profiles"][-1]), file=sys.stderr, flush=True)
    out["wall_time_s"] = time.time() - t0
    write_text(a.out, json.dumps(out, indent=1) + "\n")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
