"""What `hawksim fly` reports: the compact JSON object, the per-beat table, the summary a person reads, ``--out``.

The JSON object (docs/output.md lists every key) holds the CLI contract's scalars, one ``beats`` row per wingbeat
(the contract's beat means, plus for a controlled flight its command, tracking errors and kinematic commands), the
worst beat-mean errors, what the flight started from, the largest Floquet multiplier where it is known, and where
the files went. What a person does not read at a terminal (the controller's gains, the closed-loop multipliers of
its augmented states, each beat's end state and half-stroke commands) is left out unless ``--json-full`` asks for
it; ``--out FILE`` saves everything, per step and per beat (:mod:`hawksim.flight.export`).
"""

from __future__ import annotations

import sys
import time

BEAT_KEYS = ("beat", "mean_vertical_speed", "horizontal_speed", "pitch_deg", "roll_deg", "yaw_deg", "P_plus")
"""The per-beat keys of every flight (the contract's five, the beat's number and its P+)."""
CONTROL_BEAT_KEYS = ("speed_command", "speed_reference", "speed_error", "pitch_error_deg", "horizontal_drift_m",
                     "air_velocity", "saturated", "commands")
"""The per-beat keys a controlled flight adds to the compact table (``--json-full`` and ``--out`` also keep
``state``, ``horizontal_offset_m`` and, per half-stroke, ``commands_half_stroke``)."""
SCHEDULE_KEYS = ("speed", "aero", "rate", "orbit_f_hz", "orbit_residual", "open_loop_max_multiplier",
                 "closed_loop_spectral_radius_long", "closed_loop_spectral_radius_lat", "inputs_long", "inputs_lat")
"""The keys of a gain-schedule point in the compact JSON (``--json-full`` adds the gains and every closed-loop
multiplier)."""


TIMING_LABELS = {"controller_start_up_s": "controller start-up", "flight_s": "flight", "recording_s": "recording",
                 "out_file_s": "data file", "rest_s": "set-up"}


def beat_table(result, control_beats: list[dict] | None) -> list[dict]:
    """The full per-beat table (:meth:`hawksim.flight.result.FlightResult.beat_table`) merged with the controlled
    flight's per-beat record ``control_beats`` (:attr:`FlightResult.beat_log`)."""
    return result.beat_table(control_beats)


def compact_beats(rows: list[dict]) -> list[dict]:
    """The rows of :func:`beat_table` with the keys of :data:`BEAT_KEYS` and :data:`CONTROL_BEAT_KEYS` only, less
    ``speed_reference`` where it equals ``speed_command`` in every beat (no rate-limited profile) and
    ``air_velocity`` where it is zero in every beat (no gust)."""
    keep = list(BEAT_KEYS + CONTROL_BEAT_KEYS)
    if all(r.get("speed_reference") == r.get("speed_command") for r in rows):
        keep.remove("speed_reference")
    if all(not any(r.get("air_velocity") or ()) for r in rows):
        keep.remove("air_velocity")
    return [{k: r[k] for k in keep if k in r} for r in rows]


def worst_errors(rows: list[dict], speed_target: float) -> dict:
    """Largest |beat mean| over the beats of: the vertical speed's error (against each beat's command where the
    flight is controlled, else the target), the horizontal speed, the pitch error (against the orbit's mean pitch
    under control, else against the first beat's), and roll and yaw (yaw against the first beat's). Units: m/s and
    deg. None without beats."""
    if not rows:
        return None
    p0, y0 = rows[0]["pitch_deg"], rows[0]["yaw_deg"]

    def most(f):
        return max(abs(f(r)) for r in rows)

    return {"speed_error": most(lambda r: r.get("speed_error", r["mean_vertical_speed"] - speed_target)),
            "horizontal_speed": most(lambda r: r["horizontal_speed"]),
            "pitch_error_deg": most(lambda r: r.get("pitch_error_deg", r["pitch_deg"] - p0)),
            "roll_deg": most(lambda r: r["roll_deg"]), "yaw_deg": most(lambda r: r["yaw_deg"] - y0),
            "horizontal_drift_m": None if "horizontal_drift_m" not in rows[0] else most(
                lambda r: r["horizontal_drift_m"])}


def floquet_of(out: dict) -> dict:
    """The largest Floquet multiplier per wingbeat where this run knows it: a controlled flight's, from its
    controller's one-beat (or half-stroke) model at the schedule point of the start speed (open loop, and the closed
    loop's spectral radius); an open-loop flight computes none (``hawksim stability --floquet`` does)."""
    pts = (out.get("control") or {}).get("schedule") or []
    if not pts:
        from hawksim.backends.registry import find

        desc = find(out["aero"])
        if desc is not None and not desc.orbits:
            return {"open_loop_max": None, "closed_loop_max": None,
                    "source": f"none: {out['aero']} has no periodic orbit ({desc.orbits.why_not})"}
        return {"open_loop_max": None, "closed_loop_max": None,
                "source": f"not computed for an open-loop flight: hawksim stability --floquet --aero {out['aero']} "
                          f"--speed {out['speed_target']:g}"}
    p = min(pts, key=lambda q: abs(q["speed"] - out["speed_target"]))
    return {"open_loop_max": p["open_loop_max_multiplier"],
            "closed_loop_max": max(p["closed_loop_spectral_radius_long"], p["closed_loop_spectral_radius_lat"]),
            "source": f"the controller's linear model at {p['speed']:g} m/s ({p['aero']}, per {p['rate']})"}


def compact_control(ctl: dict) -> dict:
    """The controller's object without the per-beat record (merged into ``beats``) and each schedule point with
    :data:`SCHEDULE_KEYS` only."""
    out = {k: v for k, v in ctl.items() if k not in ("beats", "schedule", "constrained")}
    out["schedule"] = [{k: p[k] for k in SCHEDULE_KEYS if k in p} for p in ctl.get("schedule", [])]
    return out


def report(args, out: dict, result, cl, times: dict) -> dict:
    """`hawksim fly`'s output object from the flight's summary ``out`` (:meth:`FlightResult.summary`, or
    :func:`hawksim.control.command.command_summary` for a controlled flight ``cl``): the per-beat table merged, the
    controller's object compacted (unless ``--json-full``), the worst errors, the Floquet multiplier, ``--out`` written
    (all or nothing), and ``wall_time_s`` from the command's start to now, recording and file included. Sets
    ``args.human`` to :func:`render` for the output without ``--json``."""
    full = bool(getattr(args, "json_full", False))
    rows = beat_table(result, cl.beats if cl is not None else None)
    out["beats"] = compact_beats(rows)  # (--json-full: the controller's own record under control.beats)
    if "control" in out and not full:
        out["control"] = compact_control(out["control"])
    out["worst_beat_errors"] = worst_errors(rows, out["speed_target"])
    out["floquet"] = floquet_of(out)
    out["flight_wall_time_s"] = result.wall_time_s
    out["out"] = None
    if getattr(args, "out", None):
        t = time.perf_counter()
        out["out"] = str(_save(args, out, result, rows))
        times["out_file_s"] = time.perf_counter() - t
    out["timings_s"] = times
    t0 = getattr(args, "t0", None)
    out["wall_time_s"] = time.perf_counter() - t0 if t0 is not None else sum(times.values())
    args.human = render
    return out


def _save(args, out: dict, result, rows: list[dict]):
    from hawksim.cli.progress import stage_for
    from hawksim.flight.export import save_flight

    with stage_for(args, f"fly: writing {args.out}"):
        return save_flight(args.out, result, rows, command=["hawksim", *sys.argv[1:]] if sys.argv else None,
                           summary=out)


def _g(x, digits: int = 3) -> str:
    """A float for a person: fixed where that reads well, else scientific."""
    if x is None:
        return "-"
    if x == 0 or 1e-3 <= abs(x) < 1e5:
        return f"{x:.{digits}g}" if abs(x) >= 1 else f"{x:.{digits}f}".rstrip("0").rstrip(".")
    return f"{x:.{max(digits - 1, 1)}e}"


def render(out: dict) -> str:
    """The summary a person reads in seconds: what was flown, what it started from, whether it held (or where it
    departed), the worst beat-mean errors, the largest Floquet multiplier, the last beat, where the files went and
    the time taken."""
    ctl = out.get("control")
    if ctl is None:
        how = "open loop"
    else:
        how = {"lqr": "LQR control", "clqr": "constrained-LQR control", "none": "open loop"}.get(ctl["mode"],
                                                                                              ctl["mode"])
        if ctl["mode"] != "none":
            how += f" updated per {ctl['update_rate']}" + (f", {ctl['delay_beats']} beat(s) sensing delay"
                                                          if ctl.get("delay_beats") else "")
        if ctl.get("gusts"):
            how += ", " + "; ".join(f"gust {g['velocity']} m/s at beat {g['start']} for {g['beats']}"
                                    for g in ctl["gusts"])
    k = out["kinematics"]
    from hawksim.insect.folder import default_insect

    name = out.get("insect", default_insect().name)
    fwd = out.get("forward_speed")
    if ctl is not None and ctl.get("profile"):
        how += ", forward-speed profile " + ", ".join(f"{v:g} m/s for {n}" for v, n in ctl["profile"])
    lines = [f"hawksim fly: {name}, {out['aero']} aerodynamics, {out['speed_target']:g} m/s ascent"
             + (f", {fwd:g} m/s forward" if fwd else "") + f", {out['cycles']} wingbeats, {how}"]
    st = out.get("start") or {}
    lines.append(f"  start      {st.get('source', out.get('trim_source'))}")
    lines.append(f"             f {k['f']:.4g} Hz, phi0 {k['phi0']:.3g} deg, phi_a {k['phi_a']:.3g} deg, beta "
                 f"{k['beta']:.3g} deg")
    if st.get("note"):
        lines.append(f"  note       {st['note']}")
    beats = out["beats"]
    dep = out["departed_at_beat"]
    if dep is None and ctl is not None and ctl.get("axis") == "forward":
        lines.append(f"  verdict    held: all {len(beats)} beat means within 0.1 m/s of the speed references and 10 "
                     "deg of the reference pitch's change and the first beat's roll and yaw")
    elif dep is None:
        lines.append(f"  verdict    held: all {len(beats)} beat means within 0.1 m/s of the target and 10 deg of the "
                     "first beat's attitude")
    else:
        b = beats[dep - 1]
        lines.append(f"  verdict    DEPARTED at beat {dep} of {len(beats)}: mean vertical speed "
                     f"{b['mean_vertical_speed']:.3f} m/s, pitch {b['pitch_deg']:.1f} deg, roll "
                     f"{b['roll_deg']:.1f} deg")
    w = out.get("worst_beat_errors")
    if w:
        drift = (f", drift {_g(w['horizontal_drift_m'] * 1e3)} mm" if w.get("horizontal_drift_m") is not None
                 else f", horizontal speed {_g(w['horizontal_speed'])} m/s")
        lines.append(f"  errors     worst beat mean: speed {_g(w['speed_error'])} m/s, pitch {_g(w['pitch_error_deg'])}"
                     f" deg, roll {_g(w['roll_deg'])} deg, yaw {_g(w['yaw_deg'])} deg{drift}")
    last = beats[-1] if beats else None
    if last:
        lines.append(f"  last beat  vertical speed {last['mean_vertical_speed']:.6f} m/s, pitch {last['pitch_deg']:.2f}"
                     f" deg, P+ {last.get('P_plus', 0):.3f}; drift over the flight "
                     f"{_g(out['horizontal_drift'] * 1e3)} mm")
    fq = out.get("floquet") or {}
    if fq.get("open_loop_max") is not None:
        mu = fq["open_loop_max"]
        kind = "unstable" if mu > 1 else "stable"
        lines.append(f"  Floquet    largest multiplier {mu:.3g} per beat open loop ({kind}),"
                     f" {fq['closed_loop_max']:.3g} closed loop: {fq['source']}")
    else:
        lines.append(f"  Floquet    {fq.get('source', 'not computed')}")
    files = []
    if out.get("rrd"):
        files.append(f"recording {out['rrd']} (view: rerun {out['rrd']})")
    if out.get("out"):
        files.append(f"data {out['out']} (numpy .npz; docs/output.md)")
    lines.append("  files      " + ("; ".join(files) if files else
                                 "none (--rrd FILE records the flight, --out FILE saves its data)"))
    t = dict(out.get("timings_s") or {})
    t["rest_s"] = out["wall_time_s"] - sum(t.values())  # set-up: the model, the backend, a first compile
    parts = ", ".join(f"{TIMING_LABELS.get(name, name)} {v:.1f} s" for name, v in t.items() if v and v >= 0.05)
    lines.append(f"  wall time  {out['wall_time_s']:.1f} s" + (f" ({parts})" if parts else ""))
    return "\n".join(lines)
