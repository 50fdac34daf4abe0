"""What `hawksim aero` and `hawksim predict` print without ``--json``: the cycle-averaged loads of one kinematics at
one ascent speed, from the held-body model (with its resolution, the error stated for it and whether the loads had
settled) or from the surrogate network (with the network it came from). docs/output.md shows both."""

from __future__ import annotations

from hawksim.cli.summary import kinematics_text, line, loads_text, num, resolution_text

DEFAULT_ERROR = "within 1.4 % in L+ and 0.4 % in P+ of the refined limit"
"""The default UVLM resolution's error (hawksim.backends.resolution.DEFAULT: 6 x 12 rings, 40 steps per beat) at 1-2
m/s, against the Richardson limit of the lattice and step refined together (results/uvlm_resolution.json,
docs/validation.md section 4; `hawksim aero --help` states it too, with the lift peak's)."""
ERROR_SPEEDS = (1.0, 2.0)
"""Ascent speeds [m/s] between which :data:`DEFAULT_ERROR` was measured."""
DEFAULT_GRID = {"aero": "uvlm", "n_chord": 6, "n_span": 12, "steps_per_cycle": 40}
"""The fields of the default resolution that its stated error is about (the wingbeats only decide the settling)."""


def resolution_error(res: dict, speed: float) -> str:
    """What is known of the error of a held-body run at resolution ``res`` (a ``resolution`` object) and ``speed``
    [m/s], in words: the stated error of the default lattice, hover's lack of a converged limit, or that it is not
    measured."""
    if res["aero"] != "uvlm":
        return "quasi-steady blade elements: no lattice to refine (its error is a model error, docs/backends.md)"
    if any(res[k] != v for k, v in DEFAULT_GRID.items()):
        return ("not the default (6 x 12 rings, 40 steps): error not measured; refine --n-chord, --n-span and "
                "--steps-per-cycle together to see it")
    if speed == 0:
        return "the default; at hover it has no converged limit (docs/validation.md, section 4)"
    where = ("" if ERROR_SPEEDS[0] <= speed <= ERROR_SPEEDS[1]
             else f" (measured at {ERROR_SPEEDS[0]:g}-{ERROR_SPEEDS[1]:g} m/s, not at {speed:g})")
    return f"the default, {DEFAULT_ERROR}{where} (docs/validation.md, section 4)"


def render_aero(out: dict) -> str:
    """`hawksim aero`'s summary: the run (model, speed, resolution), the kinematics, the averages with the power in
    mW, the per-beat L+ and P+ with the settling verdict, the resolution's stated error, the wall time."""
    res = out["resolution"]
    lines = [f"hawksim aero: body held at {out['speed']:g} m/s ascent; {resolution_text(res)}",
             line("kinematics", f"{kinematics_text(out['kinematics'])}; body angle chi {num(out['chi_deg'])} deg"),
             line("loads", f"{loads_text(out)} (L/W, D/W, M/(W c), P/P0); power {num(out['power_W'] * 1e3)} mW")]
    beats = out.get("per_cycle") or []
    per_beat = (f"; per beat L+ {', '.join(num(c['L_plus'], 3) for c in beats)}; "
                f"P+ {', '.join(num(c['P_plus'], 3) for c in beats)}") if len(beats) > 1 else ""
    if out["status"] == "ok":
        verdict = "settled (within 0.1 of the beat before)"
    elif out["status"] == "unsettled":
        verdict = "UNSETTLED: changed by more than 0.1 from the beat before (ask more --cycles)"
    else:
        verdict = out["status"].upper()
    lines.append(line("settling", verdict + per_beat))
    lines.append(line("resolution", resolution_error(res, out["speed"])))
    lines.append(line("wall time", f"{out['wall_time_s']:.1f} s"))
    return "\n".join(lines)


def render_predict(out: dict) -> str:
    """`hawksim predict`'s summary: the network (which family, for which speed, the command that trained it), the
    kinematics and the four averages."""
    which = {"shipped": "the shipped network", "reference": "the reference network (shipped, corrected to `hawksim "
                                                            "aero`'s default lattice)"}.get(out["network"],
                                                                                         "the network file")
    for_speed = (f"for {out['model_speed']:g} m/s" if out.get("model_speed") is not None
                 else "with the ascent speed as an input")
    return "\n".join([
        f"hawksim predict: the cycle-mean surrogate at {out['speed']:g} m/s ascent; {which} {for_speed}",
        line("kinematics", f"{kinematics_text(out['kinematics'])}; body angle chi {num(out['chi_deg'])} deg"),
        line("loads", f"{loads_text(out)} (L/W, D/W, M/(W c), P/P0)"),
        line("model", str(out["model"]))])
