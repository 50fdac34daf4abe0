"""Quasi-steady minimum-power trims in forward flight (issue 51, items 2, 3 and 6): at each forward speed U (level
flight, V = 0 by default) the GA + Nelder-Mead minimum of Eq. 3 on the quasi-steady model, balanced on it
(:func:`hawksim.trim.model_search.trim_on_model`), with per speed: f, the stroke amplitude 2 phi_a, the stroke-plane
angle beta, the body angle chi, the mean lift coefficient C_L and the mid-downstroke incidence as Willmott &
Ellington (1997) define them (:mod:`hawksim.flight.lift_coefficient`), P+ (the power curve) and the body's share of
the force balance (:mod:`hawksim.insect.body_aero`). Deterministic for a seed. Prints one JSON object.

    python -m scripts.studies.forward_trims --out results/forward_flight/qs_trims.json      # ~3 min a speed
    python -m scripts.studies.forward_trims --best-of A.json B.json --out results/forward_flight/qs_trims.json
    python -m scripts.studies.forward_trims --from results/forward_flight/qs_trims.json \\
        --plot docs/images/forward_flight_qs.png                                               # the figure only

The GA's population is small (80: each evaluation is a model run), so one search may stop in a local minimum;
``--best-of`` keeps, per speed, the balanced trim of lowest P+ among several searches' files (other seeds or Eq. 3
penalties), each row naming the file it came from and listing every candidate's P+.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

from hawksim import __version__
from hawksim.atomic import write_text
from hawksim.backends.held import body_averages
from hawksim.flight.lift_coefficient import mean_lift_coefficient, mid_downstroke_incidence
from hawksim.trim.model_search import BALANCE_RESOLUTION, SEARCH_CONFIG, SEARCH_RESOLUTION, trim_on_model
from hawksim.trim.search import R_PENALTY

SPEEDS = (0.0, 1.0, 2.0, 3.0, 4.0, 5.0)
"""Forward speeds [m/s] of the study (issue 51: hover to 5 m/s)."""


def trim_row(t, U: float, V: float) -> dict:
    """The table's quantities of a held-body trim ``t`` at (U, V) [m/s]: kinematics, the W&E quantities, the averages,
    the body's share, whether it balanced (shared by the UVLM trims, ``scripts.studies.forward_uvlm_trims``)."""
    k = t.kinematics
    body = body_averages(k, V, U)
    return {"forward_speed": U, "speed": V, "kinematics": k.to_edge(), "f_hz": k.f,
            "stroke_amplitude_deg": 2 * math.degrees(k.phi_a), "stroke_plane_deg": math.degrees(k.beta),
            "body_angle_deg": math.degrees(k.chi), **t.outputs, "power_W": t.averages.power_W,
            "lift_coefficient": mean_lift_coefficient(k, V, U),
            "mid_downstroke_incidence_deg": math.degrees(mid_downstroke_incidence(k, V, U)),
            "body": {"L_plus": body.L_plus, "D_plus": body.D_plus, "M_plus": body.M_plus},
            "converged": t.converged, "tolerance": t.tolerance}


def row(U: float, V: float, seed: int, population: int | None, penalty: float = R_PENALTY) -> dict:
    cfg = SEARCH_CONFIG if population is None else replace(SEARCH_CONFIG, population=population)
    t = trim_on_model(V, forward_speed=U, seed=seed, cfg=cfg, penalty=penalty)
    return {**trim_row(t, U, V), "fitness": t.fitness,
            "search_optimum": {"kinematics": t.start.kinematics.to_edge(), **t.start.outputs},
            "generations": t.search.generations, "evaluations": t.evaluations, "wall_time_s": t.wall_time_s,
            "seed": seed, "population": cfg.population, "penalty": penalty}


def _residual(r: dict) -> float:
    return max(abs(r["L_plus"] - 1), abs(r["D_plus"]), abs(r["M_plus"]))


def best_of(files: list[Path]) -> dict:
    """Per forward speed, the converged row of lowest P+ among ``files`` (none converged: the smallest residual)."""
    runs = [(f, json.loads(f.read_text())) for f in files]
    by_speed: dict[float, list] = {}
    for f, d in runs:
        for r in d["rows"]:
            by_speed.setdefault(r["forward_speed"], []).append((f, d["command"], r))
    rows = []
    for U in sorted(by_speed):
        cands = by_speed[U]
        f, command, best = min(cands, key=lambda c: (not c[2]["converged"], c[2]["P_plus"] if c[2]["converged"]
                                                     else _residual(c[2])))
        rows.append(best | {"chosen_from": command, "candidates": [
            {"command": c, "converged": r["converged"], "P_plus": r["P_plus"], "penalty": r.get("penalty"),
             "seed": r["seed"], "residual": _residual(r)} for _, c, r in cands]})
    return {"command": " ".join(["python -m scripts.studies.forward_trims", *sys.argv[1:]]),
            "hawksim_version": __version__, "created": time.strftime("%Y-%m-%d"),
            "sources": [d["command"] for _, d in runs], "rows": rows}


def markdown(data: dict) -> str:
    """The table of docs/forward_flight.md."""
    lines = ["| U [m/s] | f [Hz] | stroke amplitude [deg] | stroke plane beta [deg] | body angle chi [deg] | C_L | "
             "mid-downstroke incidence [deg] | P+ | balanced | body D+, L+ [% W] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(data["rows"], key=lambda r: r["forward_speed"]):
        bal = "yes" if r["converged"] else f"no ({_residual(r):.3f})"
        lines.append(f"| {r['forward_speed']:g} | {r['f_hz']:.1f} | {r['stroke_amplitude_deg']:.1f} | "
                     f"{r['stroke_plane_deg']:.1f} | {r['body_angle_deg']:.1f} | {r['lift_coefficient']:.2f} | "
                     f"{r['mid_downstroke_incidence_deg']:.1f} | {r['P_plus']:.3f} | {bal} | "
                     f"{100 * r['body']['D_plus']:.2f}, {100 * r['body']['L_plus']:.2f} |")
    return "\n".join(lines)


def plot(data: dict, path: Path) -> None:
    from hawksim import plotting

    rows = sorted(data["rows"], key=lambda r: r["forward_speed"])
    U = [r["forward_speed"] for r in rows]
    with plotting.style():
        plt = plotting.pyplot()
        fig, ax = plt.subplots(1, 3, figsize=(plotting.WIDE, 3.0))
        ok = [r["converged"] for r in rows]
        ax[0].plot(U, [r["P_plus"] for r in rows], "-", color="k")
        ax[0].plot([u for u, c in zip(U, ok) if c], [r["P_plus"] for r, c in zip(rows, ok) if c], "o", color="k",
                   label="lowest balanced trim")
        ax[0].plot([u for u, c in zip(U, ok) if not c], [r["P_plus"] for r, c in zip(rows, ok) if not c], "o",
                   mfc="none", color="k", label="not balanced (Table 2's box)")
        cand = [(r["forward_speed"], c["P_plus"]) for r in rows for c in r.get("candidates", []) if c["converged"]]
        if cand:
            ax[0].plot(*zip(*cand), ".", color="grey", label="other searches (balanced)")
        ax[0].legend()
        ax[0].set(xlabel="forward speed U [m/s]", ylabel="P+ (required power / P0)", title="power curve")
        ax[1].plot(U, [r["lift_coefficient"] for r in rows], "o-", label="C_L (quasi-steady trims)")
        ax[1].axhline(0.71, ls=":", color="grey", label="steady-state maximum 0.71 (W&E 1997)")
        ax[1].set(xlabel="forward speed U [m/s]", ylabel="mean lift coefficient", title="mean lift coefficient")
        ax[1].legend(loc="upper right")
        ax[2].plot(U, [r["stroke_plane_deg"] for r in rows], "o-", label="stroke plane beta")
        ax[2].plot(U, [r["body_angle_deg"] for r in rows], "s-", label="body angle chi")
        ax[2].plot(U, [r["stroke_amplitude_deg"] for r in rows], "^-", label="stroke amplitude 2 phi_a")
        ax[2].plot(U, [r["mid_downstroke_incidence_deg"] for r in rows], "v-", label="mid-downstroke incidence")
        ax[2].set(xlabel="forward speed U [m/s]", ylabel="deg", title="kinematics")
        ax[2].legend(loc="center right")
        plotting.panel_letters(ax)
        plotting.save(fig, path, title="Quasi-steady minimum-power trims in level forward flight",
                      caption="GA + Nelder-Mead minimum of Eq. 3 on the quasi-steady model, balanced to 0.01 "
                              f"(body loads counted); {data['command']}. C_L and the incidence as in "
                              "hawksim.flight.lift_coefficient.")


SHIPPED_KEYS = ("forward_speed", "speed", "kinematics", "L_plus", "D_plus", "M_plus", "P_plus", "power_W", "converged",
                "tolerance", "seed", "penalty", "chosen_from")


def shipped(data: dict, command: str) -> dict:
    """The shipped forward-trim table of a best-of file ``data``: per row the kinematics (edge units), the held-body
    averages, whether it balanced and the search that found it (its seed and command)."""
    return {"source": "quasi-steady minimum-power trims in level forward flight (GA + Nelder-Mead on Eq. 3, "
                      "docs/forward_flight.md)", "command": command, "made_from": data["command"],
            "sources": data.get("sources", [data["command"]]), "hawksim_version": __version__,
            "created": time.strftime("%Y-%m-%d"), "aero": "quasi-steady",
            "rows": [{k: r[k] for k in SHIPPED_KEYS} for r in data["rows"]]}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS), help="forward speeds U [m/s]")
    ap.add_argument("--vertical-speed", type=float, default=0.0, help="V [m/s] (0: level flight)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--population", type=int, default=None, help=f"GA population ({SEARCH_CONFIG.population})")
    ap.add_argument("--penalty", type=float, default=R_PENALTY, help=f"Eq. 3's r ({R_PENALTY:g}, the paper's)")
    ap.add_argument("--out", type=Path, help="write the JSON here (after each speed)")
    ap.add_argument("--from", dest="source", type=Path, help="read the rows from this JSON instead of computing")
    ap.add_argument("--plot", type=Path, help="draw the figure to this PNG (and PDF)")
    ap.add_argument("--markdown", action="store_true", help="print the docs' table instead of the JSON")
    ap.add_argument("--best-of", type=Path, nargs="+", help="merge these files: per speed the lowest-P+ balanced trim")
    ap.add_argument("--ship", type=Path, metavar="PATH", help="also write the shipped table (the rows' kinematics and "
                    "averages, the sources' commands): hawksim/insects/hawkmoth/data/forward_trim_table_quasi_steady"
                    ".json, read by hawksim.trim.tables.forward_trim")
    a = ap.parse_args()
    if a.best_of:
        data = best_of(a.best_of)
        if a.out is not None:
            a.out.parent.mkdir(parents=True, exist_ok=True)
            a.out.write_text(json.dumps(data, indent=1))
    elif a.source is not None:
        data = json.loads(a.source.read_text())
    else:
        data = {"command": " ".join(["python -m scripts.studies.forward_trims", *sys.argv[1:]]),
                "hawksim_version": __version__, "created": time.strftime("%Y-%m-%d"),
                "search_resolution": SEARCH_RESOLUTION.to_dict(), "balance_resolution": BALANCE_RESOLUTION.to_dict(),
                "search_config": {k: getattr(SEARCH_CONFIG, k) for k in SEARCH_CONFIG.__dataclass_fields__},
                "rows": []}
        for U in a.speeds:
            data["rows"].append(row(U, a.vertical_speed, a.seed, a.population, a.penalty))
            print(json.dumps(data["rows"][-1]), file=sys.stderr, flush=True)
            if a.out is not None:
                a.out.parent.mkdir(parents=True, exist_ok=True)
                a.out.write_text(json.dumps(data, indent=1))
    if a.plot is not None:
        plot(data, a.plot)
    if a.ship is not None:
        write_text(a.ship, json.dumps(shipped(data, " ".join(["python -m scripts.studies.forward_trims",
                                                              *sys.argv[1:]])), indent=1) + "\n")
    print(markdown(data) if a.markdown else json.dumps(data))


if __name__ == "__main__":
    main()
