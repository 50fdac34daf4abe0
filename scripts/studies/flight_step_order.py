"""Order of the flight loop's time stepping (issue 48, item 5; docs/free_flight.md, "Order of the time step").

The loop holds the backend's loads over each RK4 step (zero-order hold), so the coupled flight is first order in
dt whatever RK4 does with the body. This measures it with the quasi-steady backend (loads every step,
``aero_every`` = 1) at 1 m/s:

* ``free``: the free flight from the shipped quasi-steady orbit
  (``hawksim/insects/hawkmoth/data/orbit_table_quasi_steady.json``, launched as `hawksim fly --start orbit` does) for
  ``--beats`` wingbeats at each steps-per-beat N; per N the last beat's mean L+ (lift of the applied loads / W), P+
  (:func:`hawksim.flight.power.P_plus`) and the body state at its end: vertical velocity w [m/s] (world z, up) and pitch
  [rad] (dynamics, not only loads).
* ``held``: the held body (:func:`hawksim.backends.held.held_flight`, 3 beats, the last one) at the same N: the
  backend's own sampling (its added-mass rates are backward differences over dt), no body dynamics.
* ``free_minus_held``: the difference at each N (L+, P+).

For each series and quantity q: the successive differences d_k = q(N_k) - q(2 N_k) and the observed order
log2(d_k / d_{k+1}) (1: first order, 2: second). Prints one JSON object. Usage:

    python scripts/studies/flight_step_order.py [--steps 100 200 400 800 1600] [--beats 2] [--speed 1.0]

About 1 min on the shared 2-core machine.
"""

from __future__ import annotations

import argparse
import json
import math
import time


from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.flight.fly import fly
from hawksim.flight.orbit import shipped_orbit
from hawksim.flight.power import P_plus
from hawksim.frames import pitch_of
from hawksim.insect.model import load_model
from hawksim.insect.morphology import HAWKMOTH
from hawksim.trim.point import Trim


def free_beat(orbit, speed: float, steps: int, beats: int) -> dict:
    """The last of ``beats`` wingbeats of the free flight from ``orbit`` at ``steps`` steps per beat."""
    trim = Trim(float(speed), orbit.kinematics, model="quasi-steady", source="shipped periodic orbit")
    r = fly(trim, QuasiSteadyBackend(), beats, model=load_model(), steps_per_cycle=steps,
            start_state=(orbit.launch_state.as_array(), orbit.chi_ref))
    last = slice(len(r.t) - steps, len(r.t))
    lift, _ = r.lift_drag()
    # the state after the beat: velocity by the last step's end (end_pos is the centre of mass after it)
    w_end = float((r.end_pos[2] - r.body_pos[-1, 2]) / (r.end_t - r.t[-1]))
    return {"L_plus": float(lift[last].mean() / HAWKMOTH.weight),
            "P_plus": P_plus(r.power_joint[last], r.aero_every, first=last.start),
            "w_end": w_end, "pitch_end": float(pitch_of(r.body_R[-1:])[0])}


def held_beat(orbit, speed: float, steps: int) -> dict:
    """The last of 3 held-body wingbeats at ``steps`` steps per beat (the orbit's kinematics)."""
    a = held_flight(orbit.kinematics, speed, QuasiSteadyBackend(), cycles=3, steps_per_cycle=steps).averages
    return {"L_plus": a.L_plus, "P_plus": a.P_plus}


def orders(steps: list[int], rows: list[dict]) -> dict:
    """Per quantity: the values, successive differences q(N_k) - q(N_{k+1}) and observed orders (steps doubling)."""
    out = {}
    for q in rows[0]:
        v = [r[q] for r in rows]
        d = [a - b for a, b in zip(v, v[1:])]
        ratio = [math.log(abs(a / b), steps[k + 1] / steps[k]) if b != 0 and a != 0 else None
                 for k, (a, b) in enumerate(zip(d, d[1:]))]
        out[q] = {"values": v, "differences": d, "observed_order": ratio}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, nargs="+", default=[100, 200, 400, 800, 1600])
    ap.add_argument("--beats", type=int, default=2)
    ap.add_argument("--speed", type=float, default=1.0)
    a = ap.parse_args()
    orbit = shipped_orbit(a.speed, "quasi-steady")
    if orbit is None:
        raise SystemExit(f"no shipped quasi-steady orbit at {a.speed} m/s")
    t0 = time.perf_counter()
    free = [free_beat(orbit, a.speed, n, a.beats) for n in a.steps]
    held = [held_beat(orbit, a.speed, n) for n in a.steps]
    diff = [{q: f[q] - h[q] for q in h} for f, h in zip(free, held)]
    print(json.dumps({"speed": a.speed, "beats": a.beats, "steps_per_beat": a.steps, "backend": "quasi-steady",
                      "free": orders(a.steps, free), "held": orders(a.steps, held),
                      "free_minus_held": orders(a.steps, diff), "wall_time_s": time.perf_counter() - t0},
                     indent=1))


if __name__ == "__main__":
    main()
