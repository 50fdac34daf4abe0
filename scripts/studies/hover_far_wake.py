"""A periodic UVLM orbit at hover: the free wake free only while young (issue 49, item 4).

At hover the free wake stays under the wings and is met again by them: a 1e-5 change of the flight grows ~300-fold
within three beats (docs/free_flight.md, "Why 4 beats"), so the one-beat map the orbit solver differentiates is not
smooth and Newton stalls at the map's irregularity. Here the wake is free only while younger than ``--free-beats``
wingbeats (``aero.uvlm.UVLMConfig.free_wake_age``); older corners move with the air plus a uniform downwash, momentum
theory's for an actuator disk of the stroke's swept area (:mod:`hawksim.backends.far_wake`; a model choice for the
far wake's mean motion, not a measurement). Sections (prints ONE JSON object):

* ``smoothness``: the finite-difference derivative of the orbit residual with respect to the relative frequency at
  steps 1e-5 .. 1e-2 (scripts/studies/uvlm_orbit_floor.py's measure) at the shipped hover iterate, for each
  ``--free-beats`` value; a smooth map gives the same derivative at the small steps.
* ``scan``: the orbit residual at ``--scan-steps`` relative frequency changes in [-2e-3, 2e-3] about the same
  iterate, and its RMS scatter about a straight line (a smooth map: small against the change along the line).
* ``lateral_scan``: the same for the lateral map (both wings solved): the launch sideslip v moved over
  [-2e-3, 2e-3] U, the lateral states at the end of the periodic beat and their scatter about a straight line.
* ``averages``: the held-body cycle averages (`hawksim aero`'s evaluation, the reference lattice) with the whole
  wake free and with the prescribed far wake, at ``--speeds``: what the definition costs in fidelity.
* ``validate`` (with or without ``orbit``): the orbit below, then its Floquet multipliers against perturbed
  nonlinear flights (every flight with the same far wake) and the averaged model, as for 1-2 m/s.
* ``orbit``: Newton shooting (:func:`hawksim.flight.orbit.periodic_orbit`) at ``--orbit-speed`` with the prescribed
  far wake at the first ``--free-beats`` value; its residual, floor and iterations.

    python -m scripts.studies.hover_far_wake --sections smoothness --free-beats 0.5 1 --out results/hover_far_wake.json
"""

from __future__ import annotations

import argparse
import datetime
import os
import shlex
import sys
import time

import numpy as np

from hawksim.backends.far_wake import FarWake, momentum_downwash
from hawksim.flight.orbit import (OrbitFlight, orbit_residual, periodic_orbit, scales, shipped_orbit,
                                  unpack_unknowns)
from hawksim.insect.folder import default_insect
from hawksim.jsonout import emit
from hawksim.trim.tables import trim_kinematics


def far_wake(speed: float, free_beats: float | None, kin) -> FarWake | None:
    """The prescribed far wake after ``free_beats`` wingbeats with the momentum downwash (None: all free)."""
    if free_beats is None:
        return None
    return FarWake(free_beats, momentum_downwash(speed, kin, default_insect().morphology))


def residual_map(speed: float, free_beats: float | None):
    """(F, z0): the orbit solver's normalized residual as a function of its unknowns z (u/U, w/U, q T, theta,
    f/f_ref, phi0) at the shipped UVLM iterate of ``speed`` (the free wake's), every flight with the far wake."""
    orb = shipped_orbit(speed, "uvlm")
    base, w, x0 = orb.kinematics, orb.warm_beats, orb.launch_state.as_array()
    fl = OrbitFlight("uvlm", symmetric=True, far_wake=far_wake(speed, free_beats, base))
    U, T = scales(base)
    z0 = np.array([x0[0] / U, x0[2] / U, x0[4] * T, x0[7], 1.0, base.phi0])

    def F(zz):
        kin, x = unpack_unknowns(zz, base, base.f)
        return orbit_residual(kin, speed, fl.fly(kin, x, w + 1, base.chi), w)

    return F, z0


def smoothness(speed: float, free_beats: float | None) -> dict:
    """scripts/studies/uvlm_orbit_floor.py's measure (the derivative of the residual with respect to the relative
    frequency by forward differences at steps 1e-5 .. 1e-2) with the far wake prescribed after ``free_beats``."""
    from scripts.studies.uvlm_orbit_floor import smoothness as measure

    t0 = time.perf_counter()
    fw = far_wake(speed, free_beats, shipped_orbit(speed, "uvlm").kinematics)
    out = measure(speed, far_wake=fw)
    return {"free_beats": free_beats, **out,
            "d_u_periodicity_by_step": {k: v[0] for k, v in out["d_residual_d_f_rel_by_step"].items()},
            "wall_time_s": time.perf_counter() - t0}


def scan(speed: float, free_beats: float | None, steps) -> dict:
    """The orbit residual at relative frequency changes ``steps`` about the shipped iterate (the solver's other
    unknowns fixed): a smooth map gives a smooth curve; an irregular one scatters."""
    t0 = time.perf_counter()
    F, z = residual_map(speed, free_beats)
    rows = []
    for step in steps:
        zz = z.copy()
        zz[4] += step
        rows.append(F(zz).tolist())
    r = np.asarray(rows)
    # scatter about the best straight line through the scan, per residual component (normalized units)
    A = np.vstack([np.ones_like(steps), steps]).T
    fit = np.linalg.lstsq(A, r, rcond=None)[0]
    return {"free_beats": free_beats, "steps": list(map(float, steps)), "residuals": rows,
            "slope": fit[1].tolist(), "rms_about_line": np.sqrt(((r - A @ fit) ** 2).mean(0)).tolist(),
            "wall_time_s": time.perf_counter() - t0}


def lateral_scan(speed: float, free_beats: float | None, steps, state: str = "v") -> dict:
    """The lateral map's smoothness: both wings solved, the launch state's ``state`` (v [U], p, r [1/T], phi [rad])
    moved by ``steps`` (normalized) from the shipped iterate, and the lateral states (v/U, p T, r T, phi) at the end
    of the periodic beat; their RMS scatter about a straight line (a smooth map: small against the change along it)."""
    from hawksim.flight.orbit import STATE_NAMES

    orb = shipped_orbit(speed, "uvlm")
    base, w, x0 = orb.kinematics, orb.warm_beats, orb.launch_state.as_array()
    fl = OrbitFlight("uvlm", symmetric=False, far_wake=far_wake(speed, free_beats, base))
    U, T = scales(base)
    unit = {"u": U, "v": U, "w": U, "p": 1 / T, "q": 1 / T, "r": 1 / T, "phi": 1.0, "theta": 1.0, "psi": 1.0}
    j = STATE_NAMES.index(state)
    lat = [STATE_NAMES.index(n) for n in ("v", "p", "r", "phi")]
    scale = np.array([unit[STATE_NAMES[k]] for k in lat])
    t0 = time.perf_counter()
    rows = []
    for step in steps:
        x = x0.copy()
        x[j] += step * unit[state]
        rows.append((fl.fly(base, x, w + 1, base.chi).states[w + 1][lat] / scale).tolist())
    r = np.asarray(rows)
    A = np.vstack([np.ones_like(steps), steps]).T
    fit = np.linalg.lstsq(A, r, rcond=None)[0]
    return {"free_beats": free_beats, "state": state, "steps": list(map(float, steps)), "lateral_states": rows,
            "slope": fit[1].tolist(), "rms_about_line": np.sqrt(((r - A @ fit) ** 2).mean(0)).tolist(),
            "wall_time_s": time.perf_counter() - t0}


def averages(speed: float, free_beats: float | None) -> dict:
    """The held-body cycle averages at the shipped UVLM trim of ``speed`` at the reference lattice."""
    from hawksim.backends import backend_for
    from hawksim.backends.held import held_flight
    from hawksim.backends.resolution import REFERENCE
    kin = trim_kinematics(speed, "uvlm")
    backend = backend_for(REFERENCE)
    fw = far_wake(speed, free_beats, kin)
    if fw is not None:
        fw.apply(backend, kin)
    r = held_flight(kin, speed, backend, cycles=REFERENCE.cycles, steps_per_cycle=REFERENCE.steps_per_cycle)
    return {"speed": speed, "free_beats": free_beats, **r.averages.to_dict()}


def solve(speed: float, free_beats: float, validate: bool = False, from_table: bool = False) -> dict:
    """The UVLM orbit with the prescribed far wake; with ``validate``, its Floquet multipliers against perturbed
    nonlinear flights and the averaged model (:func:`hawksim.stability.validation.validate_speed`, as
    `hawksim reproduce --only validation_uvlm` does at 1-2 m/s), every flight with the same far wake. ``from_table``:
    the shipped orbit of that speed (solved with the same far wake) instead of a new solve."""
    t0 = time.perf_counter()
    fw = far_wake(speed, free_beats, trim_kinematics(speed, "uvlm"))
    o = shipped_orbit(speed, "uvlm") if from_table else None
    if o is not None and (o.far_wake is None or o.far_wake.free_beats != free_beats):
        raise ValueError(f"the shipped UVLM orbit at {speed:g} m/s has far wake {o.far_wake}, not {free_beats} beats")
    if o is None:
        o = periodic_orbit(speed, "uvlm", far_wake=fw, log=lambda *a: print(*a, file=sys.stderr))
    val = None
    if validate and o.converged:
        from hawksim.stability.floquet import monodromy
        from hawksim.stability.validation import averaged_A_uvlm, validate_speed

        fq = monodromy(o, lateral=True)
        A, _ = averaged_A_uvlm(o)
        val = validate_speed(o, fq, A, systems=("longitudinal", "lateral"), log=lambda *a: print(*a, file=sys.stderr))
        val["multipliers"] = {k: [[float(m.real), float(m.imag)] for m in getattr(fq, f"multipliers_{k}")]
                              for k in ("long", "lat")}
    out = {"validation": val} if validate else {}
    return {**out, "speed": speed, "free_beats": free_beats, "converged": o.converged, "residual": o.residual,
            "floor": o.floor, "iterations": o.iterations, "kinematics": o.kinematics.to_edge(),
            "launch_state": o.launch_state.as_array().tolist(), "wall_time_s": time.perf_counter() - t0}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sections", nargs="+", default=["smoothness"],
                    choices=["smoothness", "scan", "lateral_scan", "averages", "orbit", "validate"])
    ap.add_argument("--scan-steps", type=int, default=21, help="relative frequency changes in [-2e-3, 2e-3]")
    ap.add_argument("--free-beats", type=float, nargs="+", default=[0.5, 1.0])
    ap.add_argument("--speed", type=float, default=0.0, help="speed of the smoothness section [m/s]")
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.0, 1.0, 2.0])
    ap.add_argument("--orbit-speed", type=float, default=0.0)
    ap.add_argument("--from-table", action="store_true", help="orbit/validate: the shipped orbit, not a new solve")
    ap.add_argument("--out")
    a = ap.parse_args(argv)
    out = {"command": shlex.join(["python", "-m", "scripts.studies.hover_far_wake", *(argv or sys.argv[1:])]),
           "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "loadavg": list(os.getloadavg())}
    if "smoothness" in a.sections:
        out["smoothness"] = [smoothness(a.speed, fb) for fb in [None, *a.free_beats]]
    if "scan" in a.sections:
        steps = np.linspace(-2e-3, 2e-3, a.scan_steps)
        out["scan"] = [scan(a.speed, fb, steps) for fb in [None, *a.free_beats]]
    if "lateral_scan" in a.sections:
        steps = np.linspace(-2e-3, 2e-3, a.scan_steps)
        out["lateral_scan"] = [lateral_scan(a.speed, fb, steps) for fb in [None, *a.free_beats]]
    if "averages" in a.sections:
        out["averages"] = [averages(v, fb) for v in a.speeds for fb in [None, *a.free_beats]]
    if "orbit" in a.sections or "validate" in a.sections:
        out["orbit"] = solve(a.orbit_speed, a.free_beats[0], validate="validate" in a.sections,
                             from_table=a.from_table)
    out["momentum_downwash"] = {f"{v:g}": momentum_downwash(v, trim_kinematics(v, "uvlm"),
                                                            default_insect().morphology) for v in a.speeds}
    emit(out, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
