"""`hawksim fly --control lqr`: the closed-loop flight behind the command line, and the parsing of its options
(plain ValueError naming the option; :mod:`hawksim.cli.fly` turns them into exit status 2)."""

from __future__ import annotations

import math
import sys

import numpy as np

from hawksim.control.closed_loop import Gust, fly_closed_loop
from hawksim.insect.kinematics import SPEED_RANGE

CONTROL_CHOICES = ("lqr", "clqr", "none")
"""lqr: the per-beat LQR; clqr: the constrained LQR (hawksim.control.constrained: plans within Table 2, per
beat, quasi-steady or surrogate); none: open loop."""


def parse_forward_profile(text: str) -> list[tuple[float, int]]:
    """``U:BEATS,U:BEATS,...`` (forward speeds [m/s] within :data:`hawksim.condition.FORWARD_SPEED_RANGE`,
    wingbeats) -> [(forward speed, beats)]."""
    from hawksim.condition import FORWARD_SPEED_RANGE

    return parse_profile(text, FORWARD_SPEED_RANGE, "--forward-profile")


def parse_profile(text: str, bounds: tuple[float, float] = SPEED_RANGE,
                  option: str = "--ascent-profile") -> list[tuple[float, int]]:
    """``SPEED:BEATS,SPEED:BEATS,...`` (m/s within ``bounds``, wingbeats) -> [(speed, beats)]; ValueError naming
    ``option``."""
    out = []
    lo, hi = bounds
    for item in filter(None, (s.strip() for s in text.split(","))):
        v, sep, n = item.partition(":")
        try:
            speed, beats = float(v), int(n)
        except ValueError:
            raise ValueError(f"{option} item {item!r} is not SPEED:BEATS (m/s, wingbeats)") from None
        if not sep or not math.isfinite(speed) or not (lo <= speed <= hi):
            raise ValueError(f"{option} item {item!r}: speed must be in [{lo:g}, {hi:g}] m/s")
        if beats < 1:
            raise ValueError(f"{option} item {item!r}: beats must be >= 1")
        out.append((speed, beats))
    if not out:
        raise ValueError(f"{option} {text!r} is empty; expected SPEED:BEATS,...")
    return out


def parse_gust(text: str) -> Gust:
    """``VX,VY,VZ@START:BEATS`` (m/s world, wingbeat numbers from 1) -> :class:`Gust`."""
    vel, sep, when = text.partition("@")
    start, sep2, beats = when.partition(":")
    try:
        v = np.array([float(c) for c in vel.split(",")])
        s, n = int(start), int(beats)
    except ValueError:
        raise ValueError(f"--gust {text!r} is not VX,VY,VZ@START:BEATS (m/s, wingbeats)") from None
    if not sep or not sep2 or v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"--gust {text!r} is not VX,VY,VZ@START:BEATS (m/s, wingbeats)")
    if s < 1 or n < 1:
        raise ValueError(f"--gust {text!r}: START (the first gusty wingbeat, from 1) and BEATS must be >= 1")
    return Gust(v, s, n)


def default_control(aero: str, kinematics, steps_per_cycle: int, start: str | None, spc_default: int) -> str:
    """The backend descriptor's ``default_control`` ("lqr" where the controller applies at every speed of 0-2 m/s:
    quasi-steady and the per-step surrogate) from the orbit (no given kinematics, the orbit's steps per beat, no
    --start trim), none otherwise (the UVLM's flights are slow: asked for, not by default)."""
    from hawksim.backends.registry import descriptor

    ok = (descriptor(aero).default_control == "lqr" and kinematics is None and steps_per_cycle == spc_default
          and start in (None, "orbit"))
    return "lqr" if ok else "none"


def check_shipped_control(speed: float, profile, aero: str) -> None:
    """ValueError (one line naming the option) unless a controlled flight of a backend whose schedule is its shipped
    orbits (descriptor ``shipped_orbits_only``: the UVLM, the per-step surrogate) can fly this: there are such
    orbits (the surrogate's: for the shipped network, :func:`hawksim.control.schedule.shipped_schedule_speeds`),
    the start speed is one of them where the backend's memory is a wake (the flight is launched from the orbit's
    launch; otherwise it lies within their range: the start between two grid speeds is the interpolated reference,
    as for the quasi-steady schedule), and every commanded speed lies within their range (the gains are
    interpolated between those orbits only)."""
    from hawksim.backends.memory import WAKE
    from hawksim.backends.registry import descriptor
    from hawksim.control.schedule import shipped_schedule_speeds

    desc = descriptor(aero)
    sp = shipped_schedule_speeds(aero)
    if not sp:
        raise ValueError(f"--aero {aero} under control: no shipped {aero} orbit for this backend "
                         f"(hawksim/insects/hawkmoth/data/{desc.orbit_table} was solved with another network)")
    lo, hi = sp[0], sp[-1]
    grid = ", ".join(f"{v:g}" for v in sp)
    if desc.memory == WAKE:
        if not any(abs(speed - v) < 1e-9 for v in sp):
            raise ValueError(f"--speed {speed:g} with --aero {aero} under control: the {aero} schedule starts on its "
                             f"shipped converged orbits only ({grid} m/s)")
    elif not (lo - 1e-9 <= speed <= hi + 1e-9):
        raise ValueError(f"--speed {speed:g} with --aero {aero} under control: the {aero} schedule covers "
                         f"{lo:g} to {hi:g} m/s (its shipped orbits at {grid} m/s)")
    bad = [v for v, _ in profile or [] if not (lo - 1e-9 <= v <= hi + 1e-9)]
    if bad:
        raise ValueError(f"--ascent-profile speed {bad[0]:g} m/s with --aero {aero}: the {aero} schedule "
                         f"covers {lo:g} to {hi:g} m/s")


def check_uvlm_control(speed: float, profile) -> None:
    """:func:`check_shipped_control` of the UVLM."""
    check_shipped_control(speed, profile, "uvlm")


def check_surrogate_control(speed: float, profile) -> None:
    """:func:`check_shipped_control` of the per-step surrogate."""
    check_shipped_control(speed, profile, "surrogate")


def fly_command(speed: float, cycles: int, *, control: str, profile=None, gusts=None, delay: int = 0,
                perturb: dict | None = None, model_path=None, progress=None, log=None,
                aero: str = "quasi-steady", rate: str = "beat", partial_on_interrupt: bool = False, insect=None):
    """The closed-loop flight of a `hawksim fly` under control (or open loop with a gust), recorded
    (:class:`hawksim.control.closed_loop.ClosedLoop` with ``result``). ``partial_on_interrupt``: a Ctrl-C or
    SIGTERM turned into KeyboardInterrupt during the beats returns the steps flown (see
    :func:`hawksim.control.closed_loop.fly_closed_loop`). ``insect``: the insect flown (default the hawkmoth; its
    MJCF unless ``model_path`` is given)."""
    from hawksim.flight.orbit import STATE_NAMES
    from hawksim.flight.start import parse_perturbations
    from hawksim.insect.model import load_model

    if control == "none" and profile:
        raise ValueError("--ascent-profile needs --control lqr (an open-loop flight cannot follow it)")
    x = np.zeros(9)
    deg = np.pi / 180
    for k, v in parse_perturbations(perturb or {}).items():
        x[STATE_NAMES.index(k)] += v * (deg if k in ("p", "q", "r", "theta", "phi") else 1.0)
    from hawksim.backends.registry import descriptor

    if descriptor(aero).shipped_orbits_only:
        check_shipped_control(speed, profile, aero)
    return fly_closed_loop(speed, cycles, profile=profile, gusts=gusts, delay=delay, control=control, perturbation=x,
                           model=load_model(model_path) if model_path is not None or insect is None else None,
                           record=True, log=log, progress=progress, aero=aero, rate=rate,
                           partial_on_interrupt=partial_on_interrupt, insect=insect)


def command_summary(cl, cycles: int, control: str, aero: str = "quasi-steady", rate: str = "beat") -> dict:
    """The JSON object of a complete controlled flight ``cl``: the FlightResult summary (the CLI contract's keys)
    plus ``control`` (:meth:`ClosedLoop.to_json`: schedule, gains, closed-loop multipliers, per-beat commands and
    tracking errors, ``last_beats_max_abs``); says on stderr in one line whether the flight held or departed."""
    out = cl.result.summary()
    ctl = cl.to_json()
    b = cl.beats
    last = b[-min(10, len(b)):]
    ctl["last_beats_max_abs"] = {
        "speed_error": max(abs(e["speed_error"]) for e in last), "pitch_error_deg": max(abs(e["pitch_error_deg"])
                                                                                      for e in last),
        "roll_deg": max(abs(e["roll_deg"]) for e in last), "horizontal_drift_m": max(e["horizontal_drift_m"]
                                                                                    for e in last)}
    out["control"] = ctl
    if out["departed_at_beat"] is not None:
        e = out["beats"][out["departed_at_beat"] - 1]
        print(f"fly: departed at beat {out['departed_at_beat']} of {cycles} (mean vertical speed "
              f"{e['mean_vertical_speed']:.3f} m/s; pitch {e['pitch_deg']:.1f} deg) under --control {control}",
              file=sys.stderr)
    elif control in ("lqr", "clqr"):
        m = ctl["last_beats_max_abs"]
        name = "LQR" if control == "lqr" else "constrained-LQR"
        print(f"fly: held under {name} control for {cycles} wingbeats ({aero}, updated per {rate}); last {len(last)} "
              "beats: speed error <= "
              f"{m['speed_error']:.4f} m/s, pitch error <= {m['pitch_error_deg']:.2f} deg, roll <= "
              f"{m['roll_deg']:.2f} deg, drift <= {m['horizontal_drift_m'] * 1e3:.1f} mm "
              f"(body length {ctl['body_length_m'] * 1e3:.1f} mm)", file=sys.stderr)
    return out
