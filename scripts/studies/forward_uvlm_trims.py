"""Minimum-power trims on the UVLM in level forward flight (issue 51, item 3, UVLM part).

A population search on the UVLM (the quasi-steady trims' GA + Nelder-Mead, population 80) costs hours per speed
here (1.5-4 s a UVLM run on the shared host), so this is the local route: at each forward speed U,
:func:`hawksim.trim.model_search.refine_on_model` (trust-region sequential linear programming on P+ + 10 (|L+ - 1| +
|D+| + |M+|) in Table 2's box, forward-difference gradients; then the UVLM balance where it ends outside 0.01) at
:data:`hawksim.trim.balance.TRIM_RESOLUTION` (the UVLM balance's resolution, as for the paper's trims: ``hawksim
aero``'s lattice and 40 steps a beat, 4 beats with the last 3 averaged), from each of these starts:

- ``qs``: the quasi-steady minimum-power trim at U (results/forward_flight/qs_trims.json);
- ``balance``: the UVLM balance of that trim (results/forward_flight/uvlm_balance.json), where it exists;
- ``previous``, ``next``: the UVLM trim found at the nearest lower (higher) speed in the output file, where it
  exists (a continuation in speed; the row records which start it came from);
- ``self``: the row already in the output at U (a search continued where one stopped on its budget; the better of
  the two rows is kept, with every candidate);
- ``file:PATH``: the row at U of another trims file (e.g. hawksim 0.2's hawkmoth's, results/forward_flight/
  uvlm_trims.json).

Per speed the row is the start's answer of lowest P+ among the balanced ones (none balanced: the smallest residual),
with the table's quantities (``scripts.studies.forward_trims.trim_row``: f, stroke amplitude, beta, chi, the mean
lift coefficient and mid-downstroke incidence of :mod:`hawksim.flight.lift_coefficient`, P+, the body's share) and
every start's outcome. Resumable: speeds already in ``--out`` are skipped; the file is rewritten (all or nothing,
under a lock, so that processes running other speeds can share it) after every speed; its ``commands`` lists every
command that wrote it.

    python -m scripts.studies.forward_uvlm_trims --out results/forward_flight/uvlm_trims.json   # 5-15 min a speed
    python -m scripts.studies.forward_uvlm_trims --from results/forward_flight/uvlm_trims.json --markdown

``--polish RUNS`` balances the rows that missed the tolerance once more from their kinematics (the balance inside
the search stops after 30 + 20 runs).
"""

from __future__ import annotations

import argparse
import fcntl
import json
import os
import sys
import time
from pathlib import Path

from hawksim import __version__
from hawksim.atomic import write_text
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.morphology import Morphology
from hawksim.trim.balance import TRIM_RESOLUTION, balance_on_uvlm
from hawksim.trim.model_search import (REFINE_DIFF_STEP, REFINE_MAX_EVALS, REFINE_PENALTY, REFINE_RADIUS,
                                       refine_on_model)
from scripts.studies.forward_trims import trim_row

SPEEDS = (1.0, 2.0, 3.0, 4.0, 5.0)
"""Forward speeds [m/s] (level flight); hover's UVLM trim is the shipped table's."""
QS_TRIMS = Path("results/forward_flight/qs_trims.json")
UVLM_BALANCE = Path("results/forward_flight/uvlm_balance.json")
STARTS = ("qs", "balance", "previous", "next", "self")
OUTPUTS = ("L_plus", "D_plus", "M_plus", "P_plus")


def _rows(path: Path) -> dict[float, dict]:
    return {r["forward_speed"]: r for r in json.loads(path.read_text())["rows"]} if path.exists() else {}


def _residual(r: dict) -> float:
    return max(abs(r["L_plus"] - 1), abs(r["D_plus"]), abs(r["M_plus"]))


def starts(U: float, names, out: Path | None) -> dict[str, Kinematics]:
    """The start kinematics at U by name (those that exist)."""
    found = {}
    for name in names:
        if name == "qs":
            r = _rows(QS_TRIMS).get(U)
        elif name == "balance":
            r = _rows(UVLM_BALANCE).get(U)
        elif name == "self":
            r = (_rows(out) if out is not None else {}).get(U)
        elif name.startswith("file:"):  # the row at U of another trims file (e.g. another hawkmoth's)
            r = _rows(Path(name.removeprefix("file:"))).get(U)
        else:  # the UVLM trim found at the nearest lower ("previous") or higher ("next") speed
            done = _rows(out) if out is not None else {}
            near = [u for u in done if (u < U if name == "previous" else u > U)]
            r = done[(max if name == "previous" else min)(near)] if near else None
        if r is not None:
            found[name] = Kinematics.from_edge(r["kinematics"])
    return found


def _start_name(text: str) -> str:
    """A --starts item: one of STARTS or file:PATH (an existing file)."""
    if text in STARTS or (text.startswith("file:") and Path(text.removeprefix("file:")).is_file()):
        return text
    raise argparse.ArgumentTypeError(f"{text!r}: choose {', '.join(STARTS)} or file:PATH of an existing file")


def _progress(label: str):
    def show(n, a):
        print(f"{label} run {n}: L+ {a.L_plus:.4f} D+ {a.D_plus:.4f} M+ {a.M_plus:.4f} P+ {a.P_plus:.4f}",
              file=sys.stderr, flush=True)
    return show


def _rank(r: dict) -> tuple:
    """Balanced before unbalanced; then the lower P+ (balanced) or the smaller residual."""
    return not r["converged"], r["P_plus"] if r["converged"] else r["residual"]


def speed_row(U: float, V: float, kins: dict[str, Kinematics], max_evals: int) -> dict:
    """Refine from every start; the best balanced answer (else the smallest residual) with every start's outcome."""
    if not kins:
        raise SystemExit(f"forward_uvlm_trims: no start at U = {U:g} m/s (the starts asked for are not in their "
                         "files: 'previous'/'next'/'self' read --out)")
    tried = []
    for name, kin in kins.items():
        t = refine_on_model(kin, V, TRIM_RESOLUTION, forward_speed=U, max_evals=max_evals,
                            progress=_progress(f"U={U:g} {name}"))
        r = trim_row(t, U, V) | {"residual": _residual(t.outputs), "evaluations": t.evaluations,
                                 "wall_time_s": t.wall_time_s, "outcome": t.source, "start_name": name,
                                 "start": {"kinematics": t.start.kinematics.to_edge(), **t.start.outputs}}
        tried.append(r)
        print(json.dumps(r), file=sys.stderr, flush=True)
    best = min(tried, key=_rank)
    return best | {"candidates": [{k: r[k] for k in ("start_name", "converged", "P_plus", "residual", "evaluations",
                                                      "wall_time_s", "outcome")} | {"start_P_plus":
                                                                                    r["start"]["P_plus"]}
                                  for r in tried]}


def polish(r: dict, max_evals: int) -> dict:
    """A row whose best answer missed the tolerance, balanced once more from it (:func:`balance_on_uvlm`,
    ``max_evals`` runs, its four parameters): the new row where that balances, the old one kept as a candidate; else
    the old row with the attempt added to its candidates."""
    U, V = r["forward_speed"], r["speed"]
    b = balance_on_uvlm(Kinematics.from_edge(r["kinematics"]), V, TRIM_RESOLUTION, max_evals=max_evals,
                        forward_speed=U)
    new = trim_row(b, U, V) | {"residual": _residual(b.outputs), "evaluations": b.evaluations,
                               "wall_time_s": b.wall_time_s, "outcome": f"polished: {b.source}",
                               "start_name": f"polish of {r['start_name']}",
                               "start": {"kinematics": r["kinematics"], **{k: r[k] for k in OUTPUTS}}}
    cand = {k: new[k] for k in ("start_name", "converged", "P_plus", "residual", "evaluations", "wall_time_s",
                                "outcome")} | {"start_P_plus": r["P_plus"]}
    print(json.dumps(new), file=sys.stderr, flush=True)
    if b.converged:
        return new | {"candidates": [*r["candidates"], cand]}
    return r | {"candidates": [*r["candidates"], cand]}


def save(out: Path, row: dict, header: dict) -> None:
    """Add ``row`` to ``out`` (re-read under a lock: other processes may have added speeds), all or nothing."""
    out.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(out.parent, os.O_RDONLY)  # the folder is the lock (no lock file left behind)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        data = json.loads(out.read_text()) if out.exists() else header
        data["commands"] = list(dict.fromkeys([*data.get("commands", [data["command"]]), header["command"]]))
        data["rows"] = sorted([r for r in data["rows"] if r["forward_speed"] != row["forward_speed"]] + [row],
                              key=lambda r: r["forward_speed"])
        write_text(out, json.dumps(data, indent=1))
    finally:
        os.close(fd)


def _stop(outcome: str) -> str:
    """How a search stopped, in a few words (from the trim's source)."""
    words = ("trust region below", "evaluation budget", "no predicted descent", "linear program failed")
    short = {"trust region below": "radius", "evaluation budget": "budget", "no predicted descent": "stationary",
             "linear program failed": "LP failed"}
    if outcome.startswith("polished"):
        return "balance"
    found = next((short[w] for w in words if w in outcome), "?")
    return found + (" + balance" if "then balanced" in outcome else "")


def markdown(data: dict) -> str:
    """The docs' table: the quasi-steady table's columns, then the residual, the runs (of the answer's search or
    balance, of all the speed's), the start and how it stopped (radius: the trust region shrank below its floor, a
    local minimum at the UVLM's resolution; budget: the runs ran out; + balance: no run balanced and the balance
    finished it; polish: ``--polish``'s balance of the best unbalanced answer)."""
    qs, bal = _rows(QS_TRIMS), _rows(UVLM_BALANCE)
    lines = ["| U [m/s] | f [Hz] | stroke amplitude [deg] | beta [deg] | chi [deg] | C_L | mid-downstroke incidence "
             "[deg] | P+ | balanced (residual) | runs | start (stop) | P+ QS trim, UVLM balance |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(data["rows"], key=lambda r: r["forward_speed"]):
        U = r["forward_speed"]
        q, b = qs.get(U), bal.get(U)
        ref = f"{q['P_plus']:.3f}" if q else "-"
        ref += f", {b['P_plus']:.3f}{'' if b['converged'] else ' (unbalanced)'}" if b else ", -"
        runs = sum(c["evaluations"] for c in r["candidates"])
        lines.append(f"| {U:g} | {r['f_hz']:.1f} | {r['stroke_amplitude_deg']:.1f} | {r['stroke_plane_deg']:.1f} | "
                     f"{r['body_angle_deg']:.1f} | {r['lift_coefficient']:.2f} | "
                     f"{r['mid_downstroke_incidence_deg']:.1f} | {r['P_plus']:.3f} | "
                     f"{'yes' if r['converged'] else 'no'} ({r['residual']:.3f}) | {r['evaluations']} of {runs} | "
                     f"{r['start_name']} ({_stop(r['outcome'])}) | {ref} |")
    return "\n".join(lines)


def candidates_markdown(data: dict) -> str:
    """Every start's outcome per speed."""
    lines = ["| U [m/s] | start | P+ at the start | P+ found | balanced (residual) | runs | stop |",
             "|---|---|---|---|---|---|---|"]
    for r in sorted(data["rows"], key=lambda r: r["forward_speed"]):
        for c in r["candidates"]:
            lines.append(f"| {r['forward_speed']:g} | {c['start_name']} | {c['start_P_plus']:.3f} | "
                         f"{c['P_plus']:.3f} | {'yes' if c['converged'] else 'no'} ({c['residual']:.3f}) | "
                         f"{c['evaluations']} | {_stop(c['outcome'])} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS), help="forward speeds U [m/s]")
    ap.add_argument("--vertical-speed", type=float, default=0.0, help="V [m/s] (0: level flight)")
    ap.add_argument("--starts", nargs="+", type=_start_name, default=["qs", "balance"],
                    help=f"{', '.join(STARTS)}, or file:PATH (the row at U of another trims file)")
    ap.add_argument("--max-evals", type=int, default=REFINE_MAX_EVALS, help="UVLM runs of one start's search")
    ap.add_argument("--polish", type=int, metavar="RUNS", help="instead of searching: balance the unbalanced rows of "
                    "--out (at --speeds) once more from their kinematics, with this many UVLM runs")
    ap.add_argument("--out", type=Path, help="the JSON (resumed: its speeds are skipped; rewritten after each speed)")
    ap.add_argument("--from", dest="source", type=Path, help="read the rows from this JSON instead of computing")
    ap.add_argument("--markdown", action="store_true", help="print the docs' table instead of the JSON")
    a = ap.parse_args()
    if a.source is not None:
        data = json.loads(a.source.read_text())
    else:
        header = {"command": " ".join(["python -m scripts.studies.forward_uvlm_trims", *sys.argv[1:]]),
                  "hawksim_version": __version__, "created": time.strftime("%Y-%m-%d"),
                  "morphology": Morphology().name, "resolution": TRIM_RESOLUTION.to_dict(),
                  "method": "refine_on_model (trust-region SLP on P+ + mu "
                  "x residuals; then balance_on_uvlm where outside the tolerance)", "diff_step": REFINE_DIFF_STEP,
                  "mu": REFINE_PENALTY, "radius": list(REFINE_RADIUS), "max_evals": a.max_evals, "rows": []}
        for U in a.speeds if a.polish else ():
            r = _rows(a.out).get(U)
            if r is not None and not r["converged"]:
                save(a.out, polish(r, a.polish), header)
        for U in a.speeds if not a.polish else ():
            old = _rows(a.out).get(U) if a.out is not None else None
            if old is not None and "self" not in a.starts:
                print(f"U={U:g}: in {a.out}, skipped", file=sys.stderr)
                continue
            row = speed_row(U, a.vertical_speed, starts(U, a.starts, a.out), a.max_evals)
            if old is not None:  # a search continued from the row itself: the better of the two, every candidate
                row = min((old, row), key=_rank) | {"candidates": [*old["candidates"], *row["candidates"]]}
            if a.out is not None:
                save(a.out, row, header)
            header["rows"].append(row)
        data = json.loads(a.out.read_text()) if a.out is not None else header
    print(markdown(data) + "\n\n" + candidates_markdown(data) if a.markdown else json.dumps(data))


if __name__ == "__main__":
    main()
