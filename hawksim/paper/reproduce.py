"""`hawksim reproduce`: regenerate the paper's tables and figures from the pipeline into a directory.

What it produces (each step skips with a note if a piece it needs is missing, e.g. no shipped surrogate):
* ``uvlm_table4.json``: Table 3's kinematics evaluated by our UVLM next to the paper's Table 4;
* ``stability/``: per-speed stability reports and the studies of Figs. 15-19 (JSON + PDF + 300 dpi PNG);
* ``trim/``: the trim tables (Tables 3-4) and Figs. 9, 11, 13, 14 when the trim pipeline is available;
* ``forward_flight/``: the shipped forward trims re-flown and the quasi-steady forward orbits checked against the
  study (:mod:`hawksim.paper.forward`; issue 51, beyond the paper).
"""

from __future__ import annotations

import json
import os
from dataclasses import replace
from pathlib import Path

from hawksim.atomic import write_text
from hawksim.paper.reference import PAPER_TABLE4 as TABLE4


def table4_comparison(cycles: int = 4) -> dict:
    """Our UVLM at Table 3's kinematics, all but the first wingbeat averaged, next to Table 4."""
    from hawksim.backends.held import run
    from hawksim.backends.resolution import DEFAULT
    from hawksim.insect.kinematics import TABLE3_SPEEDS, table3_kinematics

    res = replace(DEFAULT, cycles=cycles, average_cycles=cycles - 1)
    rows = []
    for i, v in enumerate(TABLE3_SPEEDS):
        r = run(table3_kinematics(v), v, res)
        rows.append({"speed": v, **{k: getattr(r.averages, k) for k in TABLE4},
                     "paper": {k: TABLE4[k][i] for k in TABLE4},
                     "per_cycle": [[c.L_plus, c.D_plus, c.M_plus, c.P_plus] for c in r.per_cycle],
                     "wall_time_s": r.wall_time_s})
    return {"resolution": res.to_dict(), "note": "averages over all but the first wingbeat", "rows": rows}


def stability_all(out_dir: Path, *, table3: bool = False) -> dict:
    """Stability reports and studies at the five speeds, at the default trims (or Table 3's kinematics)."""
    from hawksim.cluster import dask_client
    from hawksim.insect.kinematics import TABLE3_SPEEDS, table3_kinematics
    from hawksim.paper.studies import write
    from hawksim.stability.report import stability_report

    with dask_client() as client:
        reports = [stability_report(v, kinematics=table3_kinematics(v) if table3 else None, client=client)
                   for v in TABLE3_SPEEDS]
    studies = write(reports, out_dir)
    return {"speeds": studies["speeds"], "modes": studies["fig15"]["modes"]}


PARTIAL_SUFFIX = ".partial.json"
"""Suffix of a table being filled speed by speed (``orbit_table_uvlm.partial.json``): each solved speed is written
there at once (so that an interrupted run resumes where it stopped), and the table appears under its final name only
when every speed is in it (issue 53, defect 14: an interrupted `hawksim reproduce` left a table with only some speed
rows under its final name, which a reader could take for the whole)."""


def partial_path(path: Path) -> Path:
    """Where the table ``path`` is kept while incomplete (:data:`PARTIAL_SUFFIX`)."""
    return path.with_name(path.name.removesuffix(".json") + PARTIAL_SUFFIX)


def _complete(partial: Path, path: Path, ours: bool) -> None:
    """The table is complete: move the partial table to its final name (one rename, all or nothing) when this run
    read or wrote it (``ours``; a partial table beside a complete one this run did not read is left alone)."""
    if ours and partial.is_file():
        os.replace(partial, path)


def orbits_all(out_dir: Path, log=print, aeros=("quasi-steady", "uvlm"), speeds=None) -> dict:
    """Periodic orbits of the free body at the study's five speeds for each backend, into
    ``out_dir/orbit_table_<aero>.json`` (:func:`hawksim.flight.orbit.orbit_table`; copy them to ``hawksim/data`` to
    ship them). Resumable: a speed already in the file is kept, each new one is written as soon as it is solved."""
    from hawksim.backends.registry import descriptor
    from hawksim.flight.orbit import Orbit, orbit_table, periodic_orbit
    from hawksim.insect.kinematics import TABLE3_SPEEDS

    out_dir.mkdir(parents=True, exist_ok=True)
    done = {}
    for aero in aeros:
        path = out_dir / descriptor(aero).orbit_table
        partial = partial_path(path)
        source = path if path.is_file() else partial
        rows = ({r["speed"]: Orbit.from_json(r) for r in json.loads(source.read_text())["rows"]}
                if source.is_file() else {})
        for v in (speeds if speeds is not None else TABLE3_SPEEDS):
            if v in rows:
                continue
            log(f"orbit {aero} V={v:g} ...")
            rows[v] = periodic_orbit(v, aero, log=lambda m, a=aero, s=v: log(f"  {a} V={s:g}: {m}"))
            table = orbit_table([rows[k] for k in sorted(rows)], "hawksim reproduce --only orbits")
            write_text(partial, json.dumps(table, indent=1), "orbit table (partial)")
            source = partial
        _complete(partial, path, source == partial)
        done[aero] = {"path": str(path), "converged": {f"{k:g}": rows[k].converged for k in sorted(rows)},
                      "residual": {f"{k:g}": rows[k].residual for k in sorted(rows)}}
    return done


def control_models_all(out_dir: Path, log=print, aero: str = "uvlm", speeds=None) -> dict:
    """One-beat control derivatives (:func:`hawksim.control.derivatives.linearize`) about the shipped orbits of
    ``aero`` (uvlm or surrogate) at its schedule's speeds (:func:`hawksim.control.schedule.schedule_speeds`), into
    ``out_dir/control_models_<aero>.json`` (:func:`hawksim.control.schedule.control_model_table`; copy it to
    ``hawksim/data`` to ship it: the gains of `hawksim fly --control lqr --aero uvlm|surrogate` come from it).
    Resumable: a speed already in the file about the same orbit (and, for the surrogate, network) is kept, each new
    one is written as soon as it is done. Deterministic (no random process): no seed."""
    from hawksim.control.derivatives import BeatMapModel, linearize
    from hawksim.backends.registry import descriptor
    from hawksim.control.schedule import control_model_table, schedule_speeds
    from hawksim.flight.orbit import shipped_orbit

    desc = descriptor(aero)
    if desc.control_model_table is None:
        raise ValueError(f"aero={aero!r} ships no control models (its descriptor's control_model_table)")
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / desc.control_model_table
    rows = {}
    partial = partial_path(path)
    source = path if path.is_file() else partial
    old = json.loads(source.read_text()) if source.is_file() else {"rows": []}
    if not desc.tables_hold(old):  # made for another network
        old = {"rows": []}
    for r in old["rows"]:
        orb = shipped_orbit(r["speed"], aero)
        if orb is not None and r["orbit_f_hz"] == orb.kinematics.f and r["orbit_residual"] == orb.residual:
            rows[r["speed"]] = BeatMapModel.from_json(r, orb)
    for v in (speeds if speeds is not None else schedule_speeds(aero)):
        if v in rows:
            continue
        orb = shipped_orbit(v, aero)
        if orb is None or not orb.converged:
            raise ValueError(f"no converged shipped {aero} orbit at {v:g} m/s")
        log(f"control derivatives {aero} V={v:g} (44 one-beat flights) ...")
        rows[v] = linearize(orb)
        log(f"  {aero} V={v:g}: {rows[v].wall_time_s:.0f} s, cross-coupling {rows[v].coupling:.1e}")
        table = control_model_table([rows[k] for k in sorted(rows)], f"hawksim reproduce --only control_{aero}")
        write_text(partial, json.dumps(table, indent=1), "control model table (partial)")
        source = partial
    _complete(partial, path, source == partial)
    return {"path": str(path), "speeds": sorted(rows), "wall_time_s": {f"{k:g}": rows[k].wall_time_s for k in rows}}


STEPS = ("uvlm_table4", "stability", "stability_table3", "orbits", "validation", "validation_uvlm", "control_uvlm",
         "control_surrogate", "backends", "trim", "forward_flight")
"""Parts of `hawksim reproduce`, in the order they run."""


def run_all(out_dir: Path, log=print, only: tuple[str, ...] = STEPS) -> dict:
    """`hawksim reproduce`: the parts ``only`` (:data:`STEPS`) written under ``out_dir``; {part: path written}."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    done = {}
    if "uvlm_table4" in only:
        log("uvlm_table4 ...")
        write_text(out_dir / "uvlm_table4.json", json.dumps(table4_comparison(), indent=1), "table")
        done["uvlm_table4"] = str(out_dir / "uvlm_table4.json")
    if "stability" in only:
        log("stability ...")
        done["stability"] = stability_all(out_dir / "stability")
    if "stability_table3" in only:
        log("stability_table3 ...")
        done["stability_table3"] = stability_all(out_dir / "stability_table3", table3=True)
    if "orbits" in only:
        log("orbits ...")
        done["orbits"] = orbits_all(out_dir / "orbits", log=log)
    if "validation" in only:
        log("validation (quasi-steady, 5 speeds) ...")
        from hawksim.stability.validation import reproduce as validation
        done["validation"] = validation(out_dir / "free_flight", aero="quasi-steady", log=log)
    if "validation_uvlm" in only:
        log("validation_uvlm (UVLM, 0, 1, 2 m/s; many minutes) ...")
        from hawksim.cluster import dask_client
        from hawksim.stability.validation import reproduce as validation

        with dask_client() as client:
            done["validation_uvlm"] = validation(out_dir / "free_flight", aero="uvlm", log=log, client=client)
    if "control_uvlm" in only:
        log("control_uvlm (UVLM one-beat control derivatives at 1, 1.5, 2 m/s; minutes per speed) ...")
        done["control_uvlm"] = control_models_all(out_dir / "control", log=log)
    if "control_surrogate" in only:
        log("control_surrogate (per-step surrogate one-beat control derivatives at its shipped orbits; seconds per "
            "speed) ...")
        done["control_surrogate"] = control_models_all(out_dir / "control", log=log, aero="surrogate")
    if "backends" in only:
        log("backends (quasi-steady, surrogate, UVLM compared on the same flights at 0, 1, 2 m/s) ...")
        from hawksim.paper.backends import write_backends

        done["backends"] = write_backends(out_dir, log=log)
    if "forward_flight" in only:
        log("forward_flight (the shipped quasi-steady forward trims re-flown; orbits and Floquet at 1-3 m/s against "
            "results/forward_flight/orbits.json; 20 s) ...")
        from hawksim.paper.forward import forward_flight_all

        done["forward_flight"] = forward_flight_all(out_dir / "forward_flight", log=log)
    if "trim" not in only:
        return done
    from hawksim.backends.network import SHIPPED_SPEEDS, shipped_path
    from hawksim.paper.trims import write_trim_results

    missing = [str(shipped_path(v)) for v in SHIPPED_SPEEDS if not shipped_path(v).is_file()]
    if missing:
        done["trim"] = f"skipped: no shipped surrogate {missing[0]}"
    else:
        log("trim ...")
        done["trim"] = write_trim_results(out_dir / "trim", log=log)
    return done
