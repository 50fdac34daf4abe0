"""Periodic orbits and Floquet multipliers of the free body with the per-step surrogate (`--aero surrogate`)
against the UVLM's (issue 21, item 5).

For each speed: Newton shooting on the surrogate's one-beat map (:func:`hawksim.flight.orbit.periodic_orbit`,
started from the shipped UVLM orbit), its monodromy by central differences (:func:`hawksim.stability.floquet.
monodromy`), and beside them the shipped UVLM orbit (insects/hawkmoth/data/orbit_table_uvlm.json) and the UVLM's Floquet
multipliers (results/free_flight/validation.json, `hawksim reproduce --only validation_uvlm`).

    python scripts/studies/step_surrogate_orbits.py --speeds 1 2 --out results/surrogate/step_orbits.json \
        [--table hawksim/insects/hawkmoth/data/orbit_table_surrogate.json]

At a speed with no shipped UVLM orbit (0.5 m/s) Newton starts from the linear interpolation (kinematics and launch
state) of the neighbouring shipped surrogate orbits; ``--merge`` keeps the table's other rows (a row at the same
speed is replaced) and appends this command to the table's ``command``:

    python scripts/studies/step_surrogate_orbits.py --speeds 0.5 --out results/surrogate/step_orbits_0.5.json \
        --table hawksim/insects/hawkmoth/data/orbit_table_surrogate.json --merge

For a network with history lags (the shipped one since 2026-12-02: docs/surrogate.md, "History inputs, shipped") the
orbit is periodic in the body state and the record of past calls (:attr:`hawksim.flight.orbit.Orbit.record`), and
the monodromy is also taken on that augmented state (:func:`hawksim.stability.history_floquet.history_monodromy`,
``floquet_augmented``: the flight's multipliers), beside the record-held one (``floquet``).

Prints (and writes) one JSON object.
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from hawksim.backends.step_surrogate import memory_beats
from hawksim.flight.orbit import orbit_table, periodic_orbit, shipped_orbit
from hawksim.jsonout import host_info
from hawksim.stability.floquet import monodromy

ROOT = Path(__file__).resolve().parents[2]


def uvlm_multipliers(speed):
    p = ROOT / "results" / "free_flight" / "validation.json"
    if not p.is_file():
        return None
    out = {"longitudinal": [], "lateral": []}
    for e in json.loads(p.read_text())["entries"]:
        if e["aero"] == "uvlm" and abs(e["speed"] - speed) < 1e-9:
            out[e["system"]].append(e["multiplier"])
    return out


def interpolated_start(speed):
    """(kinematics, launch state (9,)) interpolated linearly between the shipped surrogate orbits around ``speed``,
    or (None, None) if ``speed`` has a shipped UVLM orbit (periodic_orbit starts there) or no neighbours."""
    from hawksim.insect.kinematics import TABLE3_SPEEDS, Kinematics

    if shipped_orbit(speed, "uvlm") is not None:
        return None, None
    rows = [(v, shipped_orbit(v, "surrogate")) for v in TABLE3_SPEEDS]
    rows = [(v, o) for v, o in rows if o is not None and o.converged and abs(v - speed) > 1e-9]
    lo = [r for r in rows if r[0] < speed]
    hi = [r for r in rows if r[0] > speed]
    if not lo or not hi:
        return None, None
    (v0, o0), (v1, o1) = lo[-1], hi[0]
    a = (speed - v0) / (v1 - v0)
    kin = Kinematics.from_array((1 - a) * o0.kinematics.as_array() + a * o1.kinematics.as_array())
    return kin, (1 - a) * o0.launch_state.as_array() + a * o1.launch_state.as_array()


def c2(z):
    return [float(np.real(z)), float(np.imag(z))]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=float, nargs="+", default=[1.0, 2.0])
    ap.add_argument("--out")
    ap.add_argument("--table", help="also write the orbits as a shipped orbit table")
    ap.add_argument("--merge", action="store_true", help="keep the --table file's rows at other speeds")
    ap.add_argument("--no-floquet", action="store_true")
    ap.add_argument("--validate", action="store_true",
                    help="also perturbed surrogate flights along each Floquet mode (hawksim.stability.validation, "
                         "amplitude 1e-3 normalized as for the UVLM; the averaged columns are not computed)")
    a = ap.parse_args()
    res = {"host": host_info(), "command": "python scripts/studies/step_surrogate_orbits.py " + " ".join(sys.argv[1:]),
           "speeds": []}
    orbits = []
    for v in a.speeds:
        t0 = time.perf_counter()
        kin0, x0 = interpolated_start(v)
        o = periodic_orbit(v, "surrogate", kinematics=kin0, x0=x0,
                           log=lambda s, v=v: print(f"V={v:g}: {s}", file=sys.stderr, flush=True))
        orbits.append(o)
        row = {"speed": v, "orbit": o.to_json(), "orbit_wall_s": time.perf_counter() - t0}
        u = shipped_orbit(v, "uvlm")
        if u is not None:
            ks, ku = o.kinematics.to_edge(), u.kinematics.to_edge()
            row["uvlm_orbit"] = {"kinematics": ku, "P_plus": u.P_plus, "converged": u.converged,
                                 "initial_state": u.initial_state.to_dict()}
            row["kinematics_rel_diff"] = {k: (ks[k] - ku[k]) / abs(ku[k]) if ku[k] else None for k in ("f",)}
            row["kinematics_abs_diff_deg"] = {"phi0": ks["phi0"] - ku["phi0"]}
            row["P_plus_diff"] = o.P_plus - u.P_plus
        if not a.no_floquet:
            fq = monodromy(o)
            row["floquet"] = {"longitudinal": [c2(z) for z in fq.multipliers_long],
                              "lateral": [c2(z) for z in fq.multipliers_lat], "coupling": fq.coupling,
                              "wall_s": fq.wall_time_s, "delta": fq.delta}
            row["uvlm_floquet"] = uvlm_multipliers(v)
            if memory_beats():  # a history network: the exact Floquet analysis on the augmented state as well
                from hawksim.stability.history_floquet import history_monodromy

                hf = history_monodromy(o)
                row["floquet_augmented"] = {
                    "body_modes_longitudinal": [c2(z) for z in hf.body_modes("long")],
                    "body_modes_lateral": [c2(z) for z in hf.body_modes("lat")],
                    "largest_longitudinal": [c2(z) for z in hf.multipliers_long[:6]],
                    "largest_lateral": [c2(z) for z in hf.multipliers_lat[:6]],
                    "body_share_longitudinal": hf.body_share_long[:6].tolist(),
                    "body_share_lateral": hf.body_share_lat[:6].tolist(), "records": hf.records,
                    "coupling": hf.coupling, "residual": hf.residual, "record_mismatch": hf.record_mismatch,
                    "delta": hf.delta, "wall_s": hf.wall_time_s}
            if a.validate:
                from hawksim.stability.validation import validate_speed

                zero = {"longitudinal": np.zeros((4, 4)), "lateral": np.zeros((4, 4))}
                val = validate_speed(o, fq, zero, eps=1e-3, state_flights=False)
                row["validation"] = {name: [{"floquet": m["floquet"], "nonlinear": m["nonlinear"],
                                             "rel_error": m["rel_error_nonlinear_vs_floquet"]}
                                            for m in sysout["modes"]] for name, sysout in val["systems"].items()}
                row["validation_fit_window_beats"] = val["fit_window_beats"]
        print(json.dumps({k: row[k] for k in row if k != "orbit"}), file=sys.stderr, flush=True)
        res["speeds"].append(row)
    text = json.dumps(res, indent=1)
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(text + "\n")
    if a.table:
        from hawksim.backends.step_network import network_sha256

        command = res["command"]
        if a.merge and Path(a.table).is_file():
            from hawksim.flight.orbit import Orbit

            old = json.loads(Path(a.table).read_text())
            if old.get("network_sha256") != network_sha256():
                raise SystemExit(f"--merge: {a.table} was made with another network")
            new = {o.speed for o in orbits}
            orbits = sorted([Orbit.from_json(r) for r in old["rows"] if r["speed"] not in new] + orbits,
                            key=lambda o: o.speed)
            command = f"{old['command']}; then {command}"
        table = {**orbit_table(orbits, command), "network_sha256": network_sha256()}
        Path(a.table).write_text(json.dumps(table, indent=1) + "\n")
    print(text)


if __name__ == "__main__":
    main()
