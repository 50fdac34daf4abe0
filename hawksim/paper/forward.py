"""`hawksim reproduce --only forward_flight`: the cheap, checkable part of the forward-flight study (issue 51,
docs/forward_flight.md), re-run and compared with what is shipped and recorded.

1. The shipped quasi-steady forward trims (:data:`hawksim.trim.tables.FORWARD_TRIM_TABLE`): each balanced row
   re-flown on the held body at the balance's resolution (:data:`hawksim.trim.model_search.BALANCE_RESOLUTION`, the
   body's loads counted) gives the averages the table records (within :data:`TRIM_RTOL`) and meets its tolerance.
2. The quasi-steady free body's periodic orbits and Floquet multipliers at :data:`ORBIT_SPEEDS` from those trims
   (:func:`hawksim.flight.orbit.periodic_orbit`, :func:`hawksim.stability.floquet.monodromy`), compared with the
   study's rows (``results/forward_flight/orbits.json``, ``python -m scripts.studies.forward_orbits --aero
   quasi-steady``, which starts from the same kinematics): the solved f within :data:`F_RTOL` and the largest
   multiplier of each block within :data:`MU_RTOL`. Without that file (an installed package) the orbits are
   written uncompared.

Deterministic (no random process). 20 s on the shared 2-core host at load 2 (`hawksim reproduce --only
forward_flight`, a fresh cache, 2026-12-07).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from hawksim.atomic import write_text

ORBIT_SPEEDS = (1.0, 2.0, 3.0)
"""Forward speeds [m/s] (level flight) of the orbits re-solved: the study's converged quasi-steady orbits (4 m/s
stalls near 1.8e-7 against the 1e-8 tolerance, docs/forward_flight.md)."""

REFERENCE = Path(__file__).resolve().parents[2] / "results" / "forward_flight" / "orbits.json"
"""The forward-orbit study's results (a source checkout's; absent from an installed package)."""

TRIM_RTOL = 1e-6
"""Relative (of max(1, |value|)) agreement of a re-flown trim's L+, D+, M+, P+ with the table's (the same
deterministic run; a change of the model or the integrator shows here)."""

F_RTOL = 1e-6
"""Relative agreement of a re-solved orbit's f with the study's (Newton from the same start to 1e-8)."""

MU_RTOL = 1e-4
"""Relative agreement of the largest Floquet multiplier of each block with the study's (central differences about
orbits that agree to their tolerance)."""


def check_trims() -> list[dict]:
    """Each shipped balanced forward trim re-flown (module docstring, step 1): its row's averages, the re-flown ones,
    the largest relative difference, the residual max(|L+ - 1|, |D+|, |M+|) and whether both checks hold."""
    from hawksim.backends.held import run
    from hawksim.trim.model_search import BALANCE_RESOLUTION
    from hawksim.trim.tables import forward_trim, forward_trim_speeds

    rows = []
    for u in forward_trim_speeds():
        t = forward_trim(u)
        a = run(t.kinematics, t.speed, BALANCE_RESOLUTION, forward_speed=u).averages
        table = {k: getattr(t.averages, k) for k in ("L_plus", "D_plus", "M_plus", "P_plus")}
        again = {k: getattr(a, k) for k in table}
        diff = max(abs(again[k] - v) / max(1.0, abs(v)) for k, v in table.items())
        residual = max(abs(a.L_plus - 1.0), abs(a.D_plus), abs(a.M_plus))
        rows.append({"forward_speed": u, "table": table, "reflown": again, "max_rel_diff": diff,
                     "residual": residual, "tolerance": t.tolerance,
                     "agrees": bool(diff <= TRIM_RTOL and residual <= t.tolerance)})
    return rows


def _reference_rows(path: Path) -> dict[float, dict]:
    if not path.is_file():
        return {}
    return {float(r["forward_speed"]): r for r in json.loads(path.read_text())["rows"] if r["aero"] == "quasi-steady"}


def check_orbits(speeds=ORBIT_SPEEDS, reference: Path = REFERENCE, log=print) -> list[dict]:
    """The quasi-steady orbit and Floquet multipliers at each forward speed in ``speeds`` [m/s] (module docstring,
    step 2), beside the study's row where ``reference`` has one (``agrees`` None where it has none)."""
    from hawksim.flight.orbit import periodic_orbit
    from hawksim.stability.floquet import monodromy
    from hawksim.trim.tables import forward_trim

    ref = _reference_rows(reference)
    rows = []
    for u in speeds:
        log(f"forward_flight: quasi-steady orbit at U = {u:g} m/s ...")
        o = periodic_orbit(0.0, "quasi-steady", kinematics=forward_trim(u).kinematics, forward_speed=u)
        fq = monodromy(o)
        mu = {"longitudinal": float(np.abs(fq.multipliers_long).max()),
              "lateral": float(np.abs(fq.multipliers_lat).max())}
        row = {"forward_speed": u, "converged": o.converged, "residual": o.residual, "iterations": o.iterations,
               "f_hz": o.kinematics.f, "phi0_deg": float(np.degrees(o.kinematics.phi0)), "P_plus": o.P_plus,
               "max_abs_floquet": mu, "wall_time_s": o.wall_time_s, "reference": None, "agrees": None}
        r = ref.get(u)
        if r is not None:
            mu_ref = {k: r["systems"][k]["max_abs_resolved_floquet"] for k in mu}
            f_ok = abs(o.kinematics.f - r["f_hz"]) <= F_RTOL * r["f_hz"]
            mu_ok = all(abs(mu[k] - mu_ref[k]) <= MU_RTOL * mu_ref[k] for k in mu)
            row["reference"] = {"f_hz": r["f_hz"], "residual": r["orbit"]["residual"], "max_abs_floquet": mu_ref}
            row["agrees"] = bool(o.converged == r["orbit"]["converged"] and f_ok and mu_ok)
        log(f"forward_flight: U = {u:g} m/s: residual {o.residual:.1e}, f {o.kinematics.f:.4f} Hz, max |mu| "
            f"{mu['longitudinal']:.4f} (lon) {mu['lateral']:.4f} (lat); agrees with the study: {row['agrees']}")
        rows.append(row)
    return rows


def forward_flight_all(out_dir: Path, log=print, speeds=ORBIT_SPEEDS, reference: Path = REFERENCE) -> dict:
    """Both checks into ``out_dir/forward_flight.json``; returns {path, trims_agree, orbits_agree} (``orbits_agree``
    None where no reference file was read)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    log("forward_flight: the shipped forward trims re-flown ...")
    trims = check_trims()
    orbits = check_orbits(speeds, reference, log=log)
    compared = [r["agrees"] for r in orbits if r["agrees"] is not None]
    doc = {"command": "hawksim reproduce --only forward_flight", "trims": trims, "orbits": orbits,
           "reference": str(reference) if reference.is_file() else None,
           "tolerances": {"trim_rtol": TRIM_RTOL, "f_rtol": F_RTOL, "mu_rtol": MU_RTOL}}
    path = out_dir / "forward_flight.json"
    write_text(path, json.dumps(doc, indent=1), "forward-flight check")
    return {"path": str(path), "trims_agree": all(r["agrees"] for r in trims),
            "orbits_agree": all(compared) if compared else None}
