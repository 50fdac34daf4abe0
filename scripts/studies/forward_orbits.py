"""Free-body periodic orbits, Floquet multipliers beside the cycle-averaged modes, and perturbed flights in level
forward flight (issue 51, item 4; docs/forward_flight.md, "Periodic orbits and Floquet multipliers").

Per forward speed U (V = 0):

- the periodic orbit of the free body (:func:`hawksim.flight.orbit.periodic_orbit` with ``forward_speed=U``), solved
  from the quasi-steady minimum-power trim (results/forward_flight/qs_trims.json) for the quasi-steady backend, from
  the UVLM balance (results/forward_flight/uvlm_balance.json) for the UVLM;
- its Floquet multipliers (:func:`hawksim.stability.floquet.monodromy`) and the cycle-averaged model of the same
  backend at the orbit's kinematics and condition (quasi-steady: :func:`hawksim.stability.floquet.quasi_steady_system`;
  UVLM: :func:`hawksim.stability.report.stability_report`), its eigenvalues lambda+ mapped to per-beat multipliers
  mu = exp(lambda+) and paired with the Floquet exponents (least total distance, as for vertical ascent);
- quasi-steady: the perturbed open-loop free flights of :func:`hawksim.stability.validation.run_speed` (modal fits of
  the nonlinear deviation against the Floquet exponents and the averaged eigenvalues).

Where the averaged model holds (:data:`HOLD_REL`): per system, it predicts the same number of unstable modes as
Floquet and every unstable Floquet exponent within HOLD_REL (relative), counting the resolved Floquet modes only
(:data:`hawksim.stability.floquet.REACH_MIN`: a UVLM mode the launches do not reach is the launch family's
extrapolation); the verdict is in each row (null where no mode of the system is resolved).

Results: one row per (aero, U) in ``--out`` (default results/forward_flight/orbits.json), written as each speed
finishes; a row already there is kept (resumable) unless ``--force``. ``--plot`` draws the largest |mu| per system
against U (Floquet and averaged; quasi-steady and UVLM); ``--markdown`` prints the docs' tables.

    python -m scripts.studies.forward_orbits --aero quasi-steady --speeds 1 2 3 4
    python -m scripts.studies.forward_orbits --aero uvlm --speeds 2 3        # minutes per speed
    python -m scripts.studies.forward_orbits --plot docs/images/forward_orbits.png --markdown
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

RESULTS = Path("results/forward_flight")
QS_TRIMS = RESULTS / "qs_trims.json"
UVLM_BALANCE = RESULTS / "uvlm_balance.json"
OUT = RESULTS / "orbits.json"

UVLM_TOL = 1e-3
"""The UVLM orbit's tolerance here (max abs normalized residual: velocities / U_ref, q T, rad). The UVLM's own
(:data:`hawksim.backends.builtin.UVLM_TOL_VELOCITY`, ``UVLM_TOL_RATE``: 1e-3 m/s, 1e-2 rad/s) sits at the wake's
beat-to-beat floor in forward flight: at 2 m/s Newton went 8.1e-2, 4.2e-2, 2.3e-3, 4.9e-4, 4.2e-4 and then stalled
(line search down to 5e-4 of a step) at 4.2e-4, just outside the rate tolerance (4.2e-4 / T = 0.011 rad/s). The orbit's
``floor`` (the next beat's residual) is reported beside it."""

UVLM_MAX_ITER = 8
"""Newton iterations of a UVLM orbit here (each 7 flights of 3 beats, minutes on the shared host)."""

HOLD_REL = 0.10
"""The averaged model holds in a system where it has as many unstable modes as Floquet and each unstable Floquet
exponent ln(mu) is matched within this relative error (the criterion docs/free_flight.md applied to vertical ascent:
"unstable exponents within ~10 %")."""


def start_kinematics(aero: str, forward_speed: float, path: Path | None = None):
    """The kinematics (SI) the orbit starts from: the quasi-steady trim's row, or the UVLM balance's, at U (or the
    row at U of ``path``, e.g. the UVLM minimum-power trims of scripts/studies/forward_uvlm_trims.py)."""
    from hawksim.insect.kinematics import Kinematics

    if path is None:
        path = QS_TRIMS if aero == "quasi-steady" else UVLM_BALANCE
    rows = {float(r["forward_speed"]): r for r in json.loads(path.read_text())["rows"]}
    if forward_speed not in rows:
        raise ValueError(f"no row at forward_speed {forward_speed:g} m/s in {path}")
    return Kinematics.from_edge(rows[forward_speed]["kinematics"], check_bounds=False), str(path)


def _c(z) -> list[float]:
    z = complex(z)
    return [float(z.real), float(z.imag)]


def _system(fq_mu, fq_reach, A) -> dict:
    """One system's Floquet multipliers and averaged eigenvalues, paired, with the verdict of :data:`HOLD_REL`."""
    from hawksim.stability.floquet import REACH_MIN
    from hawksim.stability.validation import pair_exponents

    lam_f = np.log(np.asarray(fq_mu).astype(complex))
    lam_a = np.linalg.eigvals(np.asarray(A, float))
    pair = pair_exponents(lam_f, lam_a)
    rel = [float(abs(lam_a[pair[i]] - lam_f[i]) / abs(lam_f[i])) for i in range(4)]
    resolved = [r >= REACH_MIN for r in fq_reach]
    unst_f = [i for i in range(4) if abs(fq_mu[i]) > 1 and resolved[i]]
    n_unst_a = int(sum(abs(np.exp(z)) > 1 for z in lam_a))
    holds = (len(unst_f) == n_unst_a and all(rel[i] <= HOLD_REL for i in unst_f)) if any(resolved) else None
    return {"floquet_multipliers": [_c(m) for m in fq_mu], "abs_floquet": [float(abs(m)) for m in fq_mu],
            "floquet_exponents": [_c(z) for z in lam_f], "reach": [float(r) for r in fq_reach],
            "averaged_eigenvalues": [_c(lam_a[pair[i]]) for i in range(4)],
            "averaged_multipliers": [_c(np.exp(lam_a[pair[i]])) for i in range(4)],
            "abs_averaged": [float(abs(np.exp(lam_a[pair[i]]))) for i in range(4)],
            "rel_error_averaged_vs_floquet": rel, "unstable_floquet": len(unst_f), "unstable_averaged": n_unst_a,
            "max_abs_resolved_floquet": max((float(abs(fq_mu[i])) for i in range(4) if resolved[i]), default=None),
            "averaged_holds": None if holds is None else bool(holds)}


def rejudge(doc: dict) -> None:
    """Recompute every row's per-system comparison (:func:`_system`) from its stored multipliers, reaches and A (the
    verdict's rule may have changed since the row was written; the inputs are the row's own)."""
    for r in doc["rows"]:
        if "A" not in r:
            continue
        for name, s in r["systems"].items():
            mu = [complex(*m) for m in s["floquet_multipliers"]]
            r["systems"][name] = _system(mu, s["reach"], r["A"][name])


def run(aero: str, forward_speed: float, *, validate: bool = True, averaged: bool = True, log=print,
        start_from: Path | None = None) -> dict:
    """One row: orbit, Floquet, averaged model, (quasi-steady) perturbed flights (the orbit solved from
    :func:`start_kinematics`)."""
    from hawksim.flight.orbit import periodic_orbit
    from hawksim.stability.floquet import monodromy, quasi_steady_system

    kin0, src = start_kinematics(aero, forward_speed, start_from)
    t0 = time.perf_counter()
    solve = {"tol": UVLM_TOL, "max_iter": UVLM_MAX_ITER} if aero == "uvlm" else {}
    orbit = periodic_orbit(0.0, aero, kinematics=kin0, forward_speed=forward_speed,
                           log=lambda m: log(f"{aero} U={forward_speed:g}: {m}"), **solve)
    log(f"{aero} U={forward_speed:g}: orbit residual {orbit.residual:.2e} converged {orbit.converged} "
        f"({orbit.wall_time_s:.0f} s)")
    t = time.perf_counter()
    fq = monodromy(orbit)
    t_mono = time.perf_counter() - t
    log(f"{aero} U={forward_speed:g}: |mu| long {np.round(np.abs(fq.multipliers_long), 3)} "
        f"lat {np.round(np.abs(fq.multipliers_lat), 3)} ({t_mono:.0f} s)")
    row = {"aero": aero, "forward_speed": forward_speed, "speed": 0.0, "start": {"from": src,
                                                                                "kinematics": kin0.to_edge()},
           "orbit": orbit.to_json(), "orbit_tolerance": solve.get("tol", "the backend's"), "f_hz": orbit.kinematics.f,
           "phi0_deg": float(np.degrees(orbit.kinematics.phi0)), "floquet_coupling": float(fq.coupling),
           "wall_times_s": {"orbit": orbit.wall_time_s, "monodromy": t_mono}}
    A = None
    if averaged:
        t = time.perf_counter()
        if aero == "quasi-steady":
            av = quasi_steady_system(orbit.kinematics, 0.0, forward_speed=forward_speed)
            A, scalars = {"longitudinal": av.A_long, "lateral": av.A_lat}, av.scalars
        else:
            from hawksim.stability.report import stability_report

            rep = stability_report(0.0, kinematics=orbit.kinematics, forward_speed=forward_speed)
            A = {k: np.array(rep[k]["matrix"]) for k in ("longitudinal", "lateral")}
            scalars = rep["nondimensional"]
        row["wall_times_s"]["averaged"] = time.perf_counter() - t
        row["nondimensional"] = scalars
        row["A"] = {k: np.asarray(v).tolist() for k, v in A.items()}
        row["systems"] = {
            "longitudinal": _system(fq.multipliers_long, fq.reach_long, A["longitudinal"]),
            "lateral": _system(fq.multipliers_lat, fq.reach_lat, A["lateral"])}
    else:
        row["systems"] = {name: {"floquet_multipliers": [_c(m) for m in mu], "abs_floquet": np.abs(mu).tolist(),
                                 "floquet_exponents": [_c(z) for z in np.log(np.asarray(mu).astype(complex))],
                                 "reach": list(reach)}
                          for name, mu, reach in (("longitudinal", fq.multipliers_long, fq.reach_long),
                                                  ("lateral", fq.multipliers_lat, fq.reach_lat))}
    if validate and A is not None:
        from hawksim.stability.validation import validate_speed

        t = time.perf_counter()
        res = validate_speed(orbit, fq, A, log=log)
        row["wall_times_s"]["flights"] = time.perf_counter() - t
        row["flights"] = {"fit_window_beats": res["fit_window_beats"], "beats": res["beats"],
                          "systems": {k: {"amplitude": v["amplitude"], "modes": v["modes"],
                                          **({"nonlinear_map": v["nonlinear_map"]} if "nonlinear_map" in v else {})}
                                      for k, v in res["systems"].items()}}
        worst = max(m["rel_error_nonlinear_vs_floquet"] for s in res["systems"].values() for m in s["modes"])
        row["flights"]["max_rel_error_nonlinear_vs_floquet"] = float(worst)
        log(f"{aero} U={forward_speed:g}: flights confirm Floquet within {worst:.2%}")
    row["wall_times_s"]["total"] = time.perf_counter() - t0
    return row


def flights_of_row(row: dict, *, log=print) -> dict:
    """The perturbed flights of a stored row (the UVLM's, run apart: minutes per mode): its orbit rebuilt from the
    row's JSON, its monodromy again (the eigenvectors the modal fits project on), the unstable modes only and no
    per-state flights (:func:`hawksim.stability.validation.validate_speed` with ``modes="unstable"``,
    ``state_flights=False``), against the row's averaged A."""
    from hawksim.stability.floquet import monodromy
    from hawksim.stability.validation import validate_speed
    from hawksim.trim.point import OperatingPoint

    orbit = OperatingPoint.from_json(row["orbit"])
    t = time.perf_counter()
    fq = monodromy(orbit)
    res = validate_speed(orbit, fq, {k: np.array(v) for k, v in row["A"].items()}, modes="unstable",
                         state_flights=False, log=log)
    modes = [m for s in res["systems"].values() for m in s["modes"]]
    resolved = [m["rel_error_nonlinear_vs_floquet"] for m in modes if m["resolved"]]
    return {"fit_window_beats": res["fit_window_beats"], "beats": res["beats"], "modes": "unstable",
            "systems": {k: {"amplitude": v["amplitude"], "modes": v["modes"]} for k, v in res["systems"].items()},
            "max_rel_error_nonlinear_vs_floquet": max(resolved) if resolved else None,
            "wall_time_s": time.perf_counter() - t}


LQR_BEATS = 100
"""Beats of the LQR check (issue 51, item 5: each forward speed held for 100 beats)."""

LQR_PERTURBATION = {"theta": 2.0, "phi": 2.0}
"""The LQR check's start: the orbit's launch state pitched and banked by 2 deg (the CLI's units, deg)."""


def lqr_of_row(row: dict, *, log=print) -> dict:
    """The per-beat LQR about a stored quasi-steady row's orbit (:meth:`hawksim.control.schedule.Schedule.of_orbit`)
    flown :data:`LQR_BEATS` beats from :data:`LQR_PERTURBATION`: held or not, the last beat's errors, the gains'
    closed-loop spectral radii."""
    from hawksim.control.controller import LQR
    from hawksim.control.schedule import Schedule
    from hawksim.flight.loop import fly
    from hawksim.trim.point import OperatingPoint

    orbit = OperatingPoint.from_json(row["orbit"])
    t = time.perf_counter()
    sch = Schedule.of_orbit(orbit)
    r = fly(orbit, cycles=LQR_BEATS, controller=LQR(sch, orbit.forward_speed), perturb=LQR_PERTURBATION)
    beats = r.beat_table()
    last = beats[-1]
    pt = sch.points[0]
    out = {"beats": LQR_BEATS, "perturbation_deg": LQR_PERTURBATION, "departed_at_beat": r.departed_at_beat(),
           "last_beat": {k: last[k] for k in ("horizontal_speed", "mean_vertical_speed", "pitch_error_deg", "roll_deg",
                                              "yaw_deg", "horizontal_drift_m") if k in last},
           "max_abs_pitch_error_deg": float(max(abs(b["pitch_error_deg"]) for b in beats)),
           "closed_loop_spectral_radius_long": pt.long.spectral_radius,
           "closed_loop_spectral_radius_lat": pt.lat.spectral_radius, "wall_time_s": time.perf_counter() - t}
    log(f"{row['aero']} U={row['forward_speed']:g}: LQR departed at {out['departed_at_beat']}, last beat "
        f"{out['last_beat']}")
    return out


def load(path: Path) -> dict:
    return json.loads(path.read_text()) if path.is_file() else {"rows": []}


def save(path: Path, doc: dict) -> None:
    from hawksim import __version__
    from hawksim.atomic import write_text

    doc["rows"] = sorted(doc["rows"], key=lambda r: (r["aero"], r["forward_speed"]))
    doc.update({"source": "python -m scripts.studies.forward_orbits (issue 51, item 4)", "hawksim_version": __version__,
                "hold_rel": HOLD_REL, "units": "multipliers per wingbeat; exponents ln(mu) per beat (t+ = t/T); "
                                               "states normalized u/U_ref, qT, rad; U_ref = 2 phi_a f r2"})
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text(path, json.dumps(doc, indent=1), "forward orbits")


def _fmt(z) -> str:
    re, im = z
    return f"{re:.3f}" if abs(im) < 5e-4 else f"{re:.3f}+-{abs(im):.3f}i"


def _modes(zs) -> str:
    out, seen = [], set()
    for z in zs:
        key = (round(z[0], 6), round(abs(z[1]), 6))
        if key in seen:
            continue
        seen.add(key)
        out.append(_fmt(z))
    return ", ".join(out)


def _verdict(system: dict) -> str:
    h = system["averaged_holds"]
    return "unresolved" if h is None else "yes" if h else "no"


def markdown(doc: dict) -> str:
    lines = ["| aero | U [m/s] | orbit residual | f [Hz] (trim) | phi0 [deg] | P+ | longitudinal ln mu | "
             "longitudinal eig(A) | lateral ln mu | lateral eig(A) | max abs mu (Floquet / averaged) | averaged holds "
             "(lon, lat) | flights vs Floquet |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in doc["rows"]:
        s = r["systems"]
        lo, la = s["longitudinal"], s["lateral"]
        has_avg = "averaged_eigenvalues" in lo
        mx_f = max((v for v in (lo.get("max_abs_resolved_floquet"), la.get("max_abs_resolved_floquet"))
                    if v is not None), default=float("nan"))
        mx_a = max(max(lo["abs_averaged"]), max(la["abs_averaged"])) if has_avg else float("nan")
        fl = r.get("flights", {}).get("max_rel_error_nonlinear_vs_floquet")
        lines.append(
            f"| {r['aero']} | {r['forward_speed']:g} | {r['orbit']['residual']:.1e} | {r['f_hz']:.2f} "
            f"({r['start']['kinematics']['f']:.2f}) | {r['phi0_deg']:.1f} | {r['orbit']['P_plus']:.3f} | "
            f"{_modes(lo['floquet_exponents'])} | "
            f"{_modes(lo['averaged_eigenvalues']) if has_avg else '-'} | "
            f"{_modes(la['floquet_exponents'])} | "
            f"{_modes(la['averaged_eigenvalues']) if has_avg else '-'} | {mx_f:.3f} / {mx_a:.3f} | "
            f"{_verdict(lo) if has_avg else '-'}, {_verdict(la) if has_avg else '-'} | "
            f"{'-' if fl is None else f'{fl:.1%}'} |")
    return "\n".join(lines)


def plot(doc: dict, path: Path) -> None:
    from hawksim import plotting

    plt = plotting.pyplot()
    fig, axs = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, name in zip(axs, ("longitudinal", "lateral")):
        for aero, col in (("quasi-steady", "C0"), ("uvlm", "C3")):
            rows = [r for r in doc["rows"] if r["aero"] == aero]
            if not rows:
                continue
            U = [r["forward_speed"] for r in rows]
            ax.plot(U, [r["systems"][name].get("max_abs_resolved_floquet") or np.nan for r in rows], "o-", color=col,
                    label=f"{aero}: Floquet (resolved modes)")
            if all("abs_averaged" in r["systems"][name] for r in rows):
                ax.plot(U, [max(r["systems"][name]["abs_averaged"]) for r in rows], "s--", color=col, mfc="none",
                        label=f"{aero}: averaged exp(lambda+)")
        ax.axhline(1.0, color="0.6", lw=0.8)
        ax.set_xlabel("forward speed U (m/s), V = 0")
        ax.set_title(f"{name}: largest |mu| per wingbeat")
    axs[0].set_ylabel("|mu|")
    axs[0].legend(fontsize=8)
    fig.tight_layout()
    import io

    from hawksim.atomic import write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=150)
    write_bytes(path, buf.getvalue(), "figure")
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--aero", choices=("quasi-steady", "uvlm"))
    ap.add_argument("--speeds", type=float, nargs="+", default=[])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--force", action="store_true", help="recompute rows already in --out")
    ap.add_argument("--start-from", type=Path, help="start the orbits from this trims JSON's rows (default: the "
                    "quasi-steady trims, or the UVLM balance for --aero uvlm)")
    ap.add_argument("--no-flights", action="store_true", help="skip the perturbed flights (quasi-steady)")
    ap.add_argument("--no-averaged", action="store_true", help="skip the averaged model (UVLM: 14 held runs)")
    ap.add_argument("--flights-of", type=float, nargs="+", default=[], metavar="U",
                    help="the perturbed flights of the stored --aero rows at these speeds (the UVLM's: run apart)")
    ap.add_argument("--lqr-of", type=float, nargs="+", default=[], metavar="U",
                    help="fly the per-beat LQR about the stored quasi-steady rows' orbits at these speeds (item 5)")
    ap.add_argument("--rejudge", action="store_true", help="recompute the rows' verdicts from their stored data")
    ap.add_argument("--plot", type=Path)
    ap.add_argument("--markdown", action="store_true")
    a = ap.parse_args(argv)

    def log(m):
        print(m, file=sys.stderr, flush=True)

    for U in a.speeds:
        if a.aero is None:
            ap.error("--speeds needs --aero")
        doc = load(a.out)
        if not a.force and any(r["aero"] == a.aero and r["forward_speed"] == U for r in doc["rows"]):
            log(f"{a.aero} U={U:g}: in {a.out}, skipped")
            continue
        row = run(a.aero, U, validate=not a.no_flights and a.aero == "quasi-steady", averaged=not a.no_averaged,
                  log=log, start_from=a.start_from)
        doc = load(a.out)  # another process may have written meanwhile
        doc["rows"] = [r for r in doc["rows"] if not (r["aero"] == a.aero and r["forward_speed"] == U)] + [row]
        save(a.out, doc)
    for U in a.flights_of:
        row = next(r for r in load(a.out)["rows"] if r["aero"] == a.aero and r["forward_speed"] == U)
        if "flights" in row and not a.force:
            log(f"{a.aero} U={U:g}: flights in {a.out}, skipped")
            continue
        fl = flights_of_row(row, log=log)
        doc = load(a.out)
        next(r for r in doc["rows"] if r["aero"] == a.aero and r["forward_speed"] == U)["flights"] = fl
        save(a.out, doc)
    for U in a.lqr_of:
        doc = load(a.out)
        row = next(r for r in doc["rows"] if r["aero"] == "quasi-steady" and r["forward_speed"] == U)
        row["lqr"] = lqr_of_row(row, log=log)
        save(a.out, doc)
    doc = load(a.out)
    if a.rejudge:
        rejudge(doc)
        save(a.out, doc)
    if a.plot:
        plot(doc, a.plot)
    if a.markdown:
        print(markdown(doc))
    return 0


if __name__ == "__main__":
    sys.exit(main())
