"""The body velocities and rates free and controlled flights visit (issue 21: the ranges the per-step surrogate's
data must cover), from quasi-steady flights: open loop from the orbit with a perturbation along each state until
departure (0.1 m/s or 10 deg, hawksim.flight.result), and under the LQR with a 0.5 m/s gust and an ascent profile.

    python scripts/studies/flight_state_ranges.py --out results/surrogate/flight_state_ranges.json

Prints one JSON object: per case the 0.5 / 50 / 99.5 percentiles of the body-axes velocity [m/s] and angular
velocity [rad/s], over the flight before departure.
"""

import argparse
import json
from pathlib import Path

import numpy as np

from hawksim.control.closed_loop import fly_closed_loop
from hawksim.control.closed_loop import Gust
from hawksim.flight.orbit import periodic_orbit
from hawksim.flight.fly import fly
from hawksim.backends import flight_backend
from hawksim.jsonout import host_info
from hawksim.trim.point import Trim


def pct(r, n_steps=None):
    R = r.body_R
    n = len(r.t) if n_steps is None else n_steps
    vb = np.einsum("nji,nj->ni", R[:n], r.body_v[:n])
    wb = np.einsum("nji,nj->ni", R[:n], r.body_omega[:n])
    return {"v_body_m_s": np.percentile(vb, [0.5, 50, 99.5], axis=0).round(3).tolist(),
            "omega_body_rad_s": np.percentile(wb, [0.5, 50, 99.5], axis=0).round(2).tolist()}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out")
    a = ap.parse_args()
    out = {"host": host_info(), "cases": {}}
    for v in (0.0, 1.0, 2.0):
        o = periodic_orbit(v, "quasi-steady")
        tr = Trim(v, o.kinematics, model="quasi-steady", source="orbit")
        for name, pert in (("u", {"u": 0.05}), ("w", {"w": 0.05}), ("q", {"q": 30.0}), ("v", {"v": 0.05}),
                           ("p", {"p": 30.0})):
            be = flight_backend("quasi-steady", kinematics=o.kinematics)
            r = fly(tr, be, 30, perturb=pert, start_state=(o.launch_state.as_array(), o.chi_ref))
            dep = r.departed_at_beat()
            n = None if dep is None else dep * r.steps_per_cycle
            out["cases"][f"open_{v:g}_{name}"] = {"departed_at_beat": dep, **pct(r, n)}
        cl = fly_closed_loop(v, 20, gusts=[Gust(np.array([0.5, 0.0, 0.0]), 5, 2)], record=True)
        out["cases"][f"lqr_gust_{v:g}"] = pct(cl.result)
    cl = fly_closed_loop(0.0, 30, profile=[(0.0, 2), (1.0, 10), (2.0, 18)], record=True)
    out["cases"]["lqr_profile_0_1_2"] = pct(cl.result)
    text = json.dumps(out, indent=1)
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
