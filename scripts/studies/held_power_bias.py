"""The required power's zero-order-hold bias and its removal (issue 48, item 5; docs/free_flight.md).

Part 1, heavy body (the check of tests/hawksim/test_heavy_body.py, whose flight it repeats): a free flight whose
body mass and inertia are 1e4 times larger, gravity off, at the 1 m/s trim, 200 steps per beat, the backend every
``aero_every`` steps, against the held body (:func:`hawksim.backends.held.held_flight`) at the backend's rate
(200 / aero_every steps per beat): L+, D+, M+ and P+ of the last of 3 beats, P+ with both samplings of
:func:`hawksim.flight.power.P_plus` ("updates", the fix; "steps", the estimate before it) and their relative
errors against the held P+. Cases: quasi-steady every 1 and 5 steps, the UVLM (6 x 12 rings) every 5, the per-step
surrogate (shipped network, in the native callback) every 5.

Part 2 (``--orbits``): the shipped UVLM and surrogate orbits
(``hawksim/insects/hawkmoth/data/orbit_table_{uvlm,surrogate}.json``) flown as `hawksim fly --start orbit` does, P+ of
the periodic beat with both samplings against the table's ``P_plus`` (which was computed with "steps").

Prints one JSON object. Usage: python scripts/studies/held_power_bias.py [--orbits]   (~15 s; --orbits ~1 min)
"""

from __future__ import annotations

import argparse
import json
import time


from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.flight.power import SAMPLINGS, P_plus
from hawksim.flight.heavy_body import CYCLES, HEAVY, heavy_free_flight
from hawksim.insect.model import load_model
from hawksim.trim.tables import trim_kinematics



def held_averages(kin, speed, backend, *, steps_per_cycle, cycles=CYCLES, power=False):
    """(L+, D+, M+) of the held body's last wingbeat (and P+ after them where ``power``)."""
    a = held_flight(kin, speed, backend, cycles=cycles, steps_per_cycle=steps_per_cycle).averages
    return (a.L_plus, a.D_plus, a.M_plus) + ((a.P_plus,) if power else ())


SPEED = 1.0
"""Ascent speed of the heavy-body cases [m/s] (the trims of the test)."""
STEPS = 200
"""Integrator steps per wingbeat (`hawksim fly`'s)."""


def heavy_case(name: str, kin, make_backend, aero_every: int) -> dict:
    """Part 1 for one backend (``make_backend()`` a fresh one per flight)."""
    t0 = time.perf_counter()
    free = heavy_free_flight(kin, SPEED, make_backend(), steps_per_cycle=STEPS, aero_every=aero_every)
    L, D, M, P = held_averages(kin, SPEED, make_backend(), steps_per_cycle=STEPS // aero_every, power=True)
    return {"case": name, "aero_every": aero_every,
            "held": {"L_plus": L, "D_plus": D, "M_plus": M, "P_plus": P},
            "free": {"L_plus": float(free["L"]), "D_plus": float(free["D"]), "M_plus": float(free["M"]),
                     **{f"P_plus_{s}": free[f"P_{s}"] for s in SAMPLINGS}},
            "P_plus_relative_error": {s: free[f"P_{s}"] / P - 1 for s in SAMPLINGS},
            "wall_time_s": time.perf_counter() - t0}


def orbit_case(aero: str, speed: float) -> dict | None:
    """Part 2 for one shipped orbit (None where there is none)."""
    from hawksim.backends import flight_backend
    from hawksim.flight.fly import fly
    from hawksim.flight.orbit import shipped_orbit
    from hawksim.trim.point import Trim

    orb = shipped_orbit(speed, aero)
    if orb is None or not orb.converged:
        return None
    backend = flight_backend(aero, kinematics=orb.kinematics)
    orb.seed(backend)
    w = orb.warm_beats
    r = fly(Trim(speed, orb.kinematics, model=aero, source="shipped orbit"), backend, w + 1, model=load_model(),
            start_state=(orb.launch_state.as_array(), orb.chi_ref))
    n = r.steps_per_cycle
    beat = slice(w * n, (w + 1) * n)
    return {"aero": aero, "speed": speed, "aero_every": r.aero_every, "table_P_plus": orb.P_plus,
            **{f"P_plus_{s}": P_plus(r.power_joint[beat], r.aero_every, first=beat.start, sampling=s)
               for s in SAMPLINGS}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--orbits", action="store_true", help="also the shipped UVLM and surrogate orbits (part 2)")
    a = ap.parse_args()
    from hawksim.backends.step_surrogate import StepSurrogateBackend
    from hawksim.backends.uvlm import UVLMBackend

    qs, uv = trim_kinematics(SPEED, "quasi-steady"), trim_kinematics(SPEED, "uvlm")
    out = {"heavy": HEAVY, "speed": SPEED, "steps_per_beat": STEPS, "heavy_body": [
        heavy_case("quasi-steady", qs, QuasiSteadyBackend, 1),
        heavy_case("quasi-steady", qs, QuasiSteadyBackend, 5),
        heavy_case("uvlm 6x12", uv, lambda: UVLMBackend(n_chord=6, n_span=12), 5),
        heavy_case("surrogate", uv, lambda: StepSurrogateBackend(uv), 5),
    ]}
    if a.orbits:
        rows = [orbit_case(aero, v) for aero in ("uvlm", "surrogate") for v in (0.5, 1.0, 1.5, 2.0)]
        out["shipped_orbits"] = [r for r in rows if r is not None]
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
