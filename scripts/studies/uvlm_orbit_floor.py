"""Why the UVLM's free-flight orbit holds 4 beats open loop and not 5, and why hover does not converge (issue 19).

Three measurements, printed as JSON (each takes minutes on the 2 cores):

* ``--wake-beats L [--resolve]``: the open-loop flight from the shipped UVLM orbit (or, with ``--resolve``, from the
  orbit re-solved with the flight's wake truncated at L beats): per beat, the max normalized change of (u, w, q,
  theta) over the beat (the periodicity the orbit's ``floor`` measures) and the cycle-mean vertical speed and pitch.
* ``--smoothness``: the finite-difference derivative of the orbit's residual (hawksim.flight.orbit.orbit_residual) with
  respect to the relative frequency at steps 1e-5 .. 1e-2, at the shipped orbit: a smooth map gives the same
  derivative at every small step; at hover it falls as 1/step (the residual jumps by ~3e-3 for any step).

    python scripts/studies/uvlm_orbit_floor.py --speed 1 --wake-beats 2 --resolve --beats 8
    python scripts/studies/uvlm_orbit_floor.py --speed 0 --smoothness
"""

from __future__ import annotations

import argparse
import json

import numpy as np

import hawksim.backends as backends
from hawksim.flight.orbit import (OrbitFlight, fly_orbit, orbit_residual, periodic_orbit, scales, shipped_orbit,
                                  unpack_unknowns)
from hawksim.stability.floquet import state_scale


def flight(speed: float, wake_beats: int, beats: int, resolve: bool) -> dict:
    backends.FLY_WAKE_CYCLES = wake_beats  # the flight backend's wake length (hawksim.backends.flight_backend)
    orb = shipped_orbit(speed, "uvlm")
    out = {"speed": speed, "wake_beats": wake_beats, "resolved_orbit": resolve}
    if resolve:
        orb = periodic_orbit(speed, "uvlm", kinematics=orb.kinematics, x0=orb.launch_state.as_array())
        out.update(residual=orb.residual, floor=orb.floor, iterations=orb.iterations, converged=orb.converged)
    b = fly_orbit(orb, beats)
    X = b.states[:, :8] / state_scale(orb.kinematics)
    out["per_beat_change"] = [float(np.abs((X[k + 1] - X[k])[[0, 2, 4, 7]]).max()) for k in range(beats)]
    out["mean_vertical_speed"] = b.mean_velocity[:, 2].tolist()
    out["pitch_deg"] = np.degrees(b.mean_pitch).tolist()
    return out


def smoothness(speed: float, far_wake=None) -> dict:
    """At the shipped orbit, or where none is shipped (0.5 m/s) at the Newton solver's start (the held-body trim and
    its calibrated launch state, hawksim.flight.orbit.initial_guess); ``far_wake``: the flights' prescribed far wake
    (:class:`hawksim.backends.far_wake.FarWake`; None: the whole wake free)."""
    orb = shipped_orbit(speed, "uvlm")
    fl = OrbitFlight("uvlm", symmetric=True, far_wake=far_wake)
    if orb is not None:
        base, w, x0 = orb.kinematics, orb.warm_beats, orb.launch_state.as_array()
    else:
        from hawksim.flight.orbit import UVLM_WARM_BEATS, initial_guess
        from hawksim.trim.tables import trim_kinematics

        base, w = trim_kinematics(speed, "uvlm"), UVLM_WARM_BEATS
        x0 = initial_guess(base, speed, fl, 0)
    U, T = scales(base)
    z = np.array([x0[0] / U, x0[2] / U, x0[4] * T, x0[7], 1.0, base.phi0])

    def F(zz):
        kin, x = unpack_unknowns(zz, base, base.f)
        return orbit_residual(kin, speed, fl.fly(kin, x, w + 1, base.chi), w)

    r0 = F(z)
    rows = {}
    for s in (1e-5, 1e-4, 1e-3, 1e-2):
        zz = z.copy()
        zz[4] += s
        rows[f"{s:g}"] = ((F(zz) - r0) / s).tolist()
    return {"speed": speed, "residual": r0.tolist(), "d_residual_d_f_rel_by_step": rows,
            "residual_order": "periodicity u, w, q, theta; mean velocity x, z (normalized)"}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--speed", type=float, default=1.0)
    p.add_argument("--wake-beats", type=int, default=3)
    p.add_argument("--beats", type=int, default=8)
    p.add_argument("--resolve", action="store_true")
    p.add_argument("--smoothness", action="store_true")
    a = p.parse_args()
    print(json.dumps(smoothness(a.speed) if a.smoothness else flight(a.speed, a.wake_beats, a.beats, a.resolve),
                     indent=1))


if __name__ == "__main__":
    main()
