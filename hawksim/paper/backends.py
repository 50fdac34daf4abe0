"""The three aerodynamic backends compared on the same flights (issue 21, item 6): `hawksim reproduce --only backends`.

At 0, 1 and 2 m/s, for the quasi-steady model, the per-step surrogate of the UVLM and the UVLM itself:

* the periodic orbit of the free body (:func:`hawksim.flight.orbit.shipped_orbit`; the UVLM's and the surrogate's are
  the shipped tables, not recomputed): its kinematics, Newton residual, whether it converged;
* an open-loop flight from it (:func:`hawksim.flight.fly.fly` from the orbit's launch state, as
  `hawksim fly --aero NAME --control none` flies it): the
  cycle-mean L+ (world-z aerodynamic force / weight) and P+ of the orbit's beat (the first after the backend's
  warm-up beats), how many beats from there the trim holds within :data:`HOLD_SPEED` and :data:`HOLD_PITCH_DEG`
  of it, and the wall time per wingbeat of that flight (one sitting, load average and date recorded; ratios to the
  quasi-steady flight's);
* the Floquet multipliers of the orbit: quasi-steady and UVLM from the validation
  (results/free_flight/validation.json, `hawksim reproduce --only validation` / ``validation_uvlm``; the UVLM's with
  their ``resolved`` flag; its hover orbit flies the prescribed far wake, docs/free_flight.md), the surrogate's
  from the monodromy on its augmented state (body and record of calls,
  :func:`hawksim.stability.history_floquet.history_monodromy`; a memoryless network's from its shipped control
  model's monodromy, hawksim/insects/hawkmoth/data/control_models_surrogate.json);
* controlled flights under the LQR at each backend's default rate (per beat; the surrogate per half-stroke,
  :func:`hawksim.control.schedule.default_rate`; :func:`hawksim.control.closed_loop.fly_closed_loop`): quasi-steady
  and surrogate flown here (100 beats from the orbit, 100 from a perturbed start, 30 with a 0.5 m/s lateral gust over
  beats 5-6), the UVLM's 20 beats read from results/control/control_uvlm.json
  (``python scripts/studies/control_uvlm.py``; no UVLM schedule at hover).

Deterministic (no random process). Writes ``backends.json`` and ``backends.md`` (the table) into the output
directory.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np

from hawksim.atomic import write_text

SPEEDS = (0.0, 1.0, 2.0)
"""Ascent speeds [m/s] of the comparison."""

AEROS = ("quasi-steady", "surrogate", "uvlm")
"""The backends compared (the names of `hawksim fly --aero`)."""

HOLD_SPEED = 0.01
"""|beat-mean vertical speed - V| [m/s] within which an open-loop flight counts as holding its trim (the tolerance of
docs/free_flight.md's trim-hold figures)."""

HOLD_PITCH_DEG = 1.0
"""|beat-mean pitch - the orbit beat's| [deg] within which it holds."""

OPEN_LOOP_BEATS = {"quasi-steady": 30, "surrogate": 30, "uvlm": 8}
"""Open-loop beats flown from each orbit after its warm-up beats (the UVLM: 8, its trim holds 4 at 1 m/s)."""

BOUNDS = {"speed_error": 0.02, "pitch_error_deg": 2.0, "roll_deg": 2.0}
"""Issue 20's bounds on a controlled flight's beats (and horizontal drift below one body length)."""


def _results_dirs(out_dir: Path) -> list[Path]:
    """Where earlier steps' results are looked up: the output directory, then the repository's results/."""
    repo = Path(__file__).resolve().parents[2] / "results"
    return [Path(out_dir)] + ([repo] if repo.is_dir() and repo.resolve() != Path(out_dir).resolve() else [])


def _find(out_dir: Path, rel: str) -> Path | None:
    for d in _results_dirs(out_dir):
        if (d / rel).is_file():
            return d / rel
    return None


def _c(z) -> list[float]:
    z = complex(z[0], z[1]) if isinstance(z, (list, tuple)) else complex(z)
    return [float(z.real), float(z.imag)]


def floquet(aero: str, speed: float, out_dir: Path) -> dict:
    """Floquet multipliers (per beat, [re, im]) of ``aero``'s orbit at ``speed`` and where they come from."""
    if aero == "surrogate":
        from hawksim.control.schedule import shipped_control_model
        from hawksim.flight.orbit import shipped_orbit

        orb = shipped_orbit(speed, "surrogate")
        if orb is not None and orb.record is not None:  # a history network: the monodromy on the augmented state
            from hawksim.stability.history_floquet import history_monodromy

            hf = history_monodromy(orb)
            return {"source": f"hawksim.stability.history_floquet.history_monodromy (body and the record of the last "
                              f"{hf.records} calls; step {hf.delta:g}): the body modes",
                    "longitudinal": [_c(z) for z in hf.body_modes("long")],
                    "lateral": [_c(z) for z in hf.body_modes("lat")]}
        m = shipped_control_model(speed, "surrogate")
        if m is None:
            return {"source": "no shipped surrogate control model", "longitudinal": None, "lateral": None}
        from hawksim.stability.floquet import LAT, LONG

        M = m.monodromy
        out = {"source": "hawksim/insects/hawkmoth/data/control_models_surrogate.json (monodromy, step %g)" % m.delta}
        for name, ix in (("longitudinal", LONG), ("lateral", LAT)):
            w = np.linalg.eigvals(M[np.ix_(ix, ix)])
            out[name] = [_c(z) for z in w[np.argsort(-np.abs(w))]]
        return out
    p = _find(out_dir, "free_flight/validation.json")
    if p is None:
        return {"source": "results/free_flight/validation.json missing", "longitudinal": None, "lateral": None}
    out = {"source": "results/free_flight/validation.json"}
    for name in ("longitudinal", "lateral"):
        es = [e for e in json.loads(p.read_text())["entries"]
              if e["aero"] == aero and abs(e["speed"] - speed) < 1e-9 and e["system"] == name]
        es.sort(key=lambda e: -e["abs_multiplier"])
        out[name] = [{"multiplier": _c(e["multiplier"]), "resolved": bool(e["resolved"]),
                      "confirmed_by_flights": e["meets_target"]} for e in es] if es else None
    return out


def open_loop(aero: str, speed: float) -> dict:
    """The open-loop flight from the shipped orbit (module docstring)."""
    from hawksim.backends import flight_backend
    from hawksim.backends.registry import descriptor
    from hawksim.flight.fly import fly
    from hawksim.flight.orbit import periodic_orbit, shipped_orbit
    from hawksim.flight.power import P_plus
    from hawksim.insect.model import load_model
    from hawksim.insect.folder import default_insect
    from hawksim.trim.point import Trim

    orb = shipped_orbit(speed, aero)
    if orb is None and not descriptor(aero).shipped_orbits_only:  # orbits solved in this process
        orb = periodic_orbit(speed, aero)
    if orb is None:
        return {"orbit": None}
    row = {"orbit": {"kinematics": orb.kinematics.to_edge(), "residual": orb.residual, "converged": orb.converged,
                     "P_plus": orb.P_plus, "warm_beats": orb.warm_beats, "mean_pitch_deg": np.rad2deg(orb.mean_pitch)}
           | ({} if orb.far_wake is None else {"far_wake": orb.far_wake.to_json()})}
    if not orb.converged:
        row["note"] = "orbit did not converge (docs/free_flight.md: the UVLM's hover map is not smooth); not flown"
        return row
    w = orb.warm_beats
    n = w + OPEN_LOOP_BEATS[aero]
    trim = Trim(float(speed), orb.kinematics, model=aero, source="shipped periodic orbit of the free body")
    backend = flight_backend(aero, kinematics=orb.kinematics)
    orb.seed(backend)
    r = fly(trim, backend, n, model=load_model(),
            start_state=(orb.launch_state.as_array(), orb.chi_ref))  # as `hawksim fly --aero NAME --control none`
    beats = r.summary()["beats"]
    lift, _ = r.lift_drag()
    spc = r.steps_per_cycle
    L = [float(lift[k * spc:(k + 1) * spc].mean() / default_insect().weight) for k in range(n)]
    P = [P_plus(r.power_joint[k * spc:(k + 1) * spc], r.aero_every, first=k * spc) for k in range(n)]
    ref = beats[w]["pitch_deg"]
    hold = 0
    for b in beats[w:]:
        if abs(b["mean_vertical_speed"] - speed) > HOLD_SPEED or abs(b["pitch_deg"] - ref) > HOLD_PITCH_DEG:
            break
        hold += 1
    row.update({"beats_flown": n, "L_plus_orbit_beat": L[w], "P_plus_orbit_beat": P[w],
                "mean_vertical_speed": [b["mean_vertical_speed"] for b in beats],
                "pitch_deg": [b["pitch_deg"] for b in beats],
                "holds_beats": hold, "holds_all_flown": hold == n - w,
                "departed_at_beat": r.departed_at_beat(), "wall_time_s": r.wall_time_s,
                "wall_time_per_beat_s": r.wall_time_s / n})
    return row


def _worst(beats: list[dict]) -> dict:
    return {k: float(max(abs(b[k]) for b in beats)) for k in (*BOUNDS, "horizontal_drift_m")}


def controlled(aero: str, speed: float, out_dir: Path) -> dict:
    """Controlled-flight figures (module docstring)."""
    from hawksim.control.closed_loop import Gust, body_length, fly_closed_loop
    from hawksim.control.schedule import Schedule, schedule_speeds

    L = body_length()

    def within(b):
        return all(abs(b[k]) <= v for k, v in BOUNDS.items()) and b["horizontal_drift_m"] < L

    if aero == "uvlm":
        p = _find(out_dir, "control/control_uvlm.json")
        d = json.loads(p.read_text()).get(f"lqr_{speed:g}") if p is not None else None
        if d is None:
            return {"note": "no UVLM control schedule at this speed (its orbit did not converge)"
                    if speed not in schedule_speeds("uvlm") else "results/control/control_uvlm.json missing"}
        out = {"source": "results/control/control_uvlm.json (python scripts/studies/control_uvlm.py)",
               "beats": len(d["beats"]), "worst": d["max_abs"], "within_bounds": all(within(b) for b in d["beats"]),
               "mean_P_plus_from_beat_5": d["mean_P_plus_from_beat_5"]}
        g = _find(out_dir, "control/control_constrained.json")
        g = json.loads(g.read_text()).get("uvlm", {}).get("closed_loop_gust_0.5", {}).get(f"{speed:g}") if g else None
        if g is not None:  # the UVLM's own LQR in the 0.5 m/s lateral gust over beats 5-6, 20 beats
            out["gust_0.5_lateral_20"] = {**g, "source": "results/control/control_constrained.json (python "
                                                        "scripts/studies/control_constrained.py --uvlm)"}
        return out
    from hawksim.control.schedule import default_rate

    sp = schedule_speeds(aero)
    sch = Schedule(sp[0], sp[-1], aero=aero, rate=default_rate(aero))
    out = {"source": "flown here (hawksim.control.closed_loop.fly_closed_loop)", "rate": sch.rate}
    pert = np.zeros(9)
    pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)
    gust = Gust(np.array([0.0, 0.5, 0.0]), 5, 2)
    for key, beats, kw in (("from_orbit_100", 100, {}), ("perturbed_start_100", 100, {"perturbation": pert}),
                           ("gust_0.5_lateral_30", 30, {"gusts": [gust]})):
        try:
            cl = fly_closed_loop(speed, beats, schedule=sch, aero=aero, **kw)
        except FloatingPointError as exc:
            out[key] = {"diverged": str(exc)}
            continue
        ok = [within(b) for b in cl.beats]
        settle = next((cl.beats[k]["beat"] for k in range(len(ok)) if all(ok[k:])), None)
        out[key] = {"worst": _worst(cl.beats), "within_bounds_from_beat": settle,
                    "mean_P_plus": float(np.mean([b["P_plus"] for b in cl.beats]))}
        if key.startswith("gust"):
            out[key]["recovered_beats_after_gust"] = None if settle is None else max(0, settle - 6)
    return out


def compare(out_dir: Path, log=print) -> dict:
    """The comparison (module docstring) as one dict."""
    from hawksim import __version__

    res = {"command": "hawksim reproduce --only backends", "seed": None,
           "seed_note": "deterministic: no random process", "hawksim_version": __version__,
           "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "loadavg_start": list(os.getloadavg()),
           "hold_tolerance": {"speed_m_s": HOLD_SPEED, "pitch_deg": HOLD_PITCH_DEG}, "bounds": BOUNDS, "rows": []}
    for v in SPEEDS:
        for aero in AEROS:
            log(f"backends: {aero} at {v:g} m/s ...")
            t0 = time.perf_counter()
            row = {"speed": v, "aero": aero, **open_loop(aero, v), "floquet": floquet(aero, v, out_dir)}
            row["controlled"] = controlled(aero, v, out_dir)
            row["step_wall_s"] = time.perf_counter() - t0
            res["rows"].append(row)
    res["loadavg_end"] = list(os.getloadavg())
    for v in SPEEDS:
        qs = next(r for r in res["rows"] if r["speed"] == v and r["aero"] == "quasi-steady")
        for r in res["rows"]:
            if r["speed"] == v and "wall_time_per_beat_s" in r and "wall_time_per_beat_s" in qs:
                r["wall_time_per_beat_vs_quasi_steady"] = r["wall_time_per_beat_s"] / qs["wall_time_per_beat_s"]
    return res


def _mu(ms, n=2) -> str:
    """The ``n`` largest distinct multipliers (a complex pair once, marked c; * if flagged not resolved)."""
    if not ms:
        return "-"
    out = []
    for m in ms:
        z = m["multiplier"] if isinstance(m, dict) else m
        if z[1] < -1e-9:  # the conjugate of a pair already listed
            continue
        s = f"{abs(complex(*z)):.2f}" + ("c" if abs(z[1]) > 1e-9 else "")
        if isinstance(m, dict) and not m["resolved"]:
            s += "*"
        out.append(s)
        if len(out) == n:
            break
    return ", ".join(out)


def markdown(res: dict) -> str:
    """The table (README and docs/backends.md)."""
    head = ("| V (m/s) | backend | orbit f (Hz) / phi0 (deg) / residual | L+ / P+ (orbit beat) | "
            "Floquet \\|mu\\| long; lat | trim holds (beats) | controlled: worst speed error (m/s) / pitch / roll "
            "(deg) | gust 0.5 m/s: recovered after | wall s / beat (x quasi-steady) |")
    lines = [head, "|" + "---|" * 9]
    for r in res["rows"]:
        o = r.get("orbit") or {}
        k = o.get("kinematics", {})
        nan = float("nan")
        orb = f"{k.get('f', nan):.2f} / {k.get('phi0', nan):.2f} / {o.get('residual', nan):.1e}"
        if o and not o.get("converged"):
            orb += " (not converged)"
        if o and o.get("far_wake"):
            orb += " (far wake)"
        lp = (f"{r['L_plus_orbit_beat']:.3f} / {r['P_plus_orbit_beat']:.3f}" if "L_plus_orbit_beat" in r
              else f"- / {o.get('P_plus', float('nan')):.3f}")
        fq = r["floquet"]
        mu = f"{_mu(fq.get('longitudinal'))}; {_mu(fq.get('lateral'))}"
        if fq.get("not_resolved"):
            mu = f"not resolved ({mu})"
        hold = ("-" if "holds_beats" not in r else
                f"{r['holds_beats']}{'+' if r['holds_all_flown'] else ''}")
        c = r["controlled"]
        if "worst" in c:
            ctl = (f"{c['worst']['speed_error']:.1e} / {c['worst']['pitch_error_deg']:.1e} / "
                   f"{c['worst']['roll_deg']:.1e} ({c['beats']} beats)")
            g = c.get("gust_0.5_lateral_20")
            gust = ("not flown" if g is None else "not within 20 beats" if g["recovered_beats_after_gust"] is None
                    else f"{g['recovered_beats_after_gust']} beats (20 flown)")
        elif "from_orbit_100" in c:
            f = c["from_orbit_100"]
            pp = c["perturbed_start_100"]
            ctl = ("diverged" if "diverged" in f else
                   f"{f['worst']['speed_error']:.1e} / {f['worst']['pitch_error_deg']:.1e} / "
                   f"{f['worst']['roll_deg']:.1e} (100 beats); perturbed start: "
                   + ("diverged" if "diverged" in pp else
                      f"within bounds from beat {pp['within_bounds_from_beat']}"))
            g = c["gust_0.5_lateral_30"]
            gust = ("diverged" if "diverged" in g else
                    "not within 30 beats" if g["recovered_beats_after_gust"] is None
                    else f"{g['recovered_beats_after_gust']} beats")
        else:
            ctl, gust = c.get("note", "-"), "-"
        wall = "-" if "wall_time_per_beat_s" not in r else (
            f"{r['wall_time_per_beat_s']:.3f} ({r.get('wall_time_per_beat_vs_quasi_steady', float('nan')):.2g})")
        lines.append(f"| {r['speed']:g} | {r['aero']} | {orb} | {lp} | {mu} | {hold} | {ctl} | {gust} | {wall} |")
    lines.append("")
    lines.append(f"`hawksim reproduce --only backends`, {res['date']}, load average {res['loadavg_start'][0]:.1f} to "
                 f"{res['loadavg_end'][0]:.1f}. L+ of the orbit beat is 1 by periodicity (a check); far wake: the "
                 "orbit flies the UVLM's prescribed far wake (docs/free_flight.md). Floquet: the two "
                 "largest distinct |mu| per beat of each system (c: a complex pair; *: flagged not resolved by the "
                 "UVLM's reach test). Trim holds: open-loop beats from the orbit beat within "
                 f"{HOLD_SPEED} m/s and {HOLD_PITCH_DEG} deg of it (+: every beat flown). Controlled: issue 20's "
                 "LQR at each backend's default rate (per beat; the surrogate per half-stroke); the UVLM's 20 beats "
                 "from results/control/control_uvlm.json. Wall time: the open-loop "
                 "flight's loop (recording included) per beat, and its ratio to the quasi-steady flight's at that "
                 "speed in the same sitting.")
    lines += ["", "The orbits' kinematics (Hz, deg; f and phi0 solved by Newton, the other five the start's: the "
              "held-body trim for the quasi-steady model and the UVLM, the UVLM orbit's for the surrogate):", "",
              "| V (m/s) | backend | f | beta | phi0 | theta0 | alpha0 | phi_a | alpha_a | P+ |", "|" + "---|" * 10]
    for r in res["rows"]:
        o = r.get("orbit") or {}
        k = o.get("kinematics")
        if k:
            lines.append(f"| {r['speed']:g} | {r['aero']} | " + " | ".join(f"{k[n]:.2f}" for n in (
                "f", "beta", "phi0", "theta0", "alpha0", "phi_a", "alpha_a")) + f" | {o['P_plus']:.3f} |")
    return "\n".join(lines) + "\n"


def write_backends(out_dir: Path, log=print) -> dict:
    """Run :func:`compare` and write ``backends.json`` and ``backends.md`` into ``out_dir``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = compare(out_dir, log=log)
    write_text(out_dir / "backends.json", json.dumps(res, indent=1, default=float) + "\n", "backend comparison")
    write_text(out_dir / "backends.md", markdown(res), "backend comparison table")
    return {"path": str(out_dir / "backends.json"), "table": str(out_dir / "backends.md")}
