"""Minimum-power trims at the study's five ascent speeds and the paper's Tables 3-4 and Figs. 9, 11, 13, 14.

For each speed V (Nguyen et al. 2020, Sec. 3):

1. the GA + Nelder-Mead minimum of Eq. 3 on the shipped surrogate (:func:`hawksim.trim.search.trim_on_surrogate`);
2. the UVLM at that optimum (``hawksim trim --verify``; :data:`hawksim.backends.resolution.DEFAULT` resolution) — the
   paper's Table 4 lists these UVLM values with the ANN's in parentheses;
3. beyond the paper, the optimum balanced on the UVLM itself (:func:`hawksim.trim.balance.balance_on_uvlm`:
   f, beta, phi0, alpha0 adjusted until |L+ - 1|, |D+|, |M+| <= 0.01), and how much P+ moves; the time series
   of that balanced trim (last wingbeat) give Figs. 11, 13b and 14b.

Mean power against V is fitted by least squares, P = a + b V [W], as the paper's P = 0.0702 + 0.0215 V; the
energy per unit ascent distance is E = P / V [J/m], whose fit follows from the same coefficients
(E = a / V + b, the paper's E = 0.0702 / V + 0.0215).

:func:`compute` is the numerical part (returns plain dicts); :func:`write_trim_results` writes JSON, Markdown
tables and figures (PNG at 300 dpi and PDF) into a directory (`hawksim reproduce` calls it).
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from hawksim.atomic import write_text
from hawksim.backends.averages import OUTPUTS as LOADS
from hawksim.insect.kinematics import PARAM_NAMES, TABLE3_DEG, TABLE3_SPEEDS, Kinematics
from hawksim.paper.reference import PAPER_POWER_FIT_W, PAPER_TABLE4


def _loads(a) -> dict:
    return a.to_dict()


def trim_speed(speed: float, *, seed: int = 0, population: int = 100_000, balance: bool = True,
               progress=None) -> dict:
    """Steps 1-3 of the module docstring at one ascent speed [m/s]; angles in degrees in the returned dict."""
    from hawksim.backends.held import evaluate, run
    from hawksim.backends.network import default_for_speed
    from hawksim.backends.resolution import DEFAULT
    from hawksim.trim.balance import TRIM_RESOLUTION, balance_on_uvlm
    from hawksim.trim.search import GAConfig, trim_on_surrogate

    sur = default_for_speed(speed)
    r = trim_on_surrogate(sur, speed, seed=seed, cfg=replace(GAConfig(), population=population), progress=progress)
    row = {"speed": float(speed),
           "surrogate": {"model": sur.meta.get("command", "shipped"), "model_speed": sur.inputs.speed,
                         "kinematics": r.kinematics.to_edge(), "chi": math.degrees(r.kinematics.chi),
                         "ann": dict(r.outputs), "fitness": r.fitness, "generations": r.search.generations,
                         "nm_evaluations": r.evaluations, "wall_time_s": r.wall_time_s, "seed": seed,
                         "population": population},
           "uvlm_at_optimum": {**_loads(evaluate(r.kinematics, speed, DEFAULT)), "resolution": DEFAULT.to_dict()}}
    if balance:
        b = balance_on_uvlm(r.kinematics, speed)
        h = run(b.kinematics, speed, TRIM_RESOLUTION)
        last = slice(len(h.t) - h.steps_per_cycle, len(h.t))
        row["balanced"] = {"kinematics": b.kinematics.to_edge(), "chi": math.degrees(b.kinematics.chi),
                           "uvlm": _loads(h.averages), "converged": b.converged, "evaluations": b.evaluations,
                           "wall_time_s": b.wall_time_s, "resolution": TRIM_RESOLUTION.to_dict(),
                           "P_plus_change": float(h.averages.P_plus - row["uvlm_at_optimum"]["P_plus"]),
                           "series": {"t_over_T": ((h.t[last] - h.t[last][0]) / b.kinematics.period).tolist(),
                                      "lift_N": h.lift[last].tolist(), "drag_N": h.drag[last].tolist(),
                                      "power_W": (h.power_aero[last] + h.power_inertial[last]).tolist()}}
    return row


def power_fit(speeds, power_W) -> tuple[float, float]:
    """Least-squares (a, b) of P = a + b V [W] (NaN with fewer than two speeds)."""
    if len(np.unique(np.asarray(speeds, float))) < 2:
        return float("nan"), float("nan")
    b, a = np.polyfit(np.asarray(speeds, float), np.asarray(power_W, float), 1)
    return float(a), float(b)


def _model_sha256(speed: float) -> str:
    import hashlib

    from hawksim.backends.network import default_for_speed, shipped_path

    net = default_for_speed(speed)
    path = shipped_path(net.inputs.speed)
    return hashlib.sha256(path.read_bytes()).hexdigest()


def compute(speeds=TABLE3_SPEEDS, *, seed: int = 0, population: int = 100_000, log=print,
            rows_dir: Path | None = None) -> dict:
    """Trims at ``speeds``. With ``rows_dir``, each speed's row is kept there as it is computed and reused by a
    later call with the same network file (SHA-256), seed, population and UVLM constants: an interrupted run
    continues."""
    from dataclasses import asdict

    from aero.uvlm import UVLMConfig

    uvlm = asdict(UVLMConfig())  # the solver constants the UVLM runs used: a change invalidates the cached rows
    rows = []
    for v in speeds:
        sha = _model_sha256(v)
        cached = None if rows_dir is None else Path(rows_dir) / f"v{int(round(v * 1000)):04d}.json"
        if cached is not None and cached.is_file():
            row = json.loads(cached.read_text())
            s = row.get("surrogate", {})
            if (s.get("model_sha256"), s.get("seed"), s.get("population"), row.get("uvlm_config")) == \
                    (sha, seed, population, uvlm):
                log(f"trim at {v:g} m/s: reused {cached}")
                rows.append(row)
                continue
        log(f"trim at {v:g} m/s ...")
        row = trim_speed(v, seed=seed, population=population)
        row["surrogate"]["model_sha256"] = sha
        row["uvlm_config"] = uvlm
        if cached is not None:
            cached.parent.mkdir(parents=True, exist_ok=True)
            write_text(cached, json.dumps(row), "trim row")
        rows.append(row)
    sp = [r["speed"] for r in rows]
    fits = {"uvlm_balanced": power_fit(sp, [r["balanced"]["uvlm"]["power_W"] for r in rows]),
            "uvlm_at_optimum": power_fit(sp, [r["uvlm_at_optimum"]["power_W"] for r in rows]),
            "paper": PAPER_POWER_FIT_W}
    return {"rows": rows, "power_fit_W": {k: {"a": a, "b": b} for k, (a, b) in fits.items()},
            "seed": seed, "population": population}


# ------------------------------------------------------------------------------------------------ writing


def table3_markdown(res: dict) -> str:
    head = "| V (m/s) | source | f (Hz) | beta | phi0 | theta0 | alpha0 | phi_a | alpha_a | chi |\n" + \
           "|---|---|---|---|---|---|---|---|---|---|\n"
    lines = []
    for r in res["rows"]:
        v = r["speed"]
        srcs = [("surrogate optimum", r["surrogate"]["kinematics"], r["surrogate"]["chi"])]
        if "balanced" in r:
            srcs.append(("UVLM-balanced", r["balanced"]["kinematics"], r["balanced"]["chi"]))
        if v in TABLE3_SPEEDS:
            i = TABLE3_SPEEDS.index(v)
            srcs.append(("paper Table 3", {k: TABLE3_DEG[k][i] for k in PARAM_NAMES}, 60.0 - TABLE3_DEG["beta"][i]))
        for name, k, chi in srcs:
            lines.append(f"| {v:g} | {name} | " + " | ".join(f"{k[p]:.1f}" for p in PARAM_NAMES) + f" | {chi:.1f} |")
    return head + "\n".join(lines) + "\n\nAngles in degrees; chi = 60 deg - beta.\n"


def table4_markdown(res: dict) -> str:
    """Table 4 as Markdown: per speed the trims' UVLM (and surrogate) L+, D+, M+, P+ beside the paper's P+."""
    head = ("| V (m/s) | L+ UVLM (ANN) | D+ UVLM (ANN) | M+ UVLM (ANN) | P+ UVLM (ANN) | paper P+ | "
            "balanced L+, D+, M+, P+ | P+ change |\n|---|---|---|---|---|---|---|---|\n")
    lines = []
    for r in res["rows"]:
        u, a = r["uvlm_at_optimum"], r["surrogate"]["ann"]
        cells = [f"{u[k]:.3f} ({a[k]:.3f})" for k in LOADS]
        i = TABLE3_SPEEDS.index(r["speed"]) if r["speed"] in TABLE3_SPEEDS else None
        paper = f"{PAPER_TABLE4['P_plus'][i]:.2f}" if i is not None else "-"
        if "balanced" in r:
            b = r["balanced"]["uvlm"]
            bal = ", ".join(f"{b[k]:.3f}" for k in LOADS) + ("" if r["balanced"]["converged"] else " (not converged)")
            dp = f"{r['balanced']['P_plus_change']:+.3f}"
        else:
            bal, dp = "-", "-"
        lines.append(f"| {r['speed']:g} | " + " | ".join(cells) + f" | {paper} | {bal} | {dp} |")
    return head + "\n".join(lines) + "\n"


SAMPLES_NOTE = "{n} samples per beat (the UVLM's time step), joined by straight lines, not interpolated"
"""Caption text of the time series (Figs. 11, 13b, 14b): what the stored series hold."""


def figures(res: dict, out_dir: Path) -> list[Path]:
    """Figs. 9, 11, 13 and 14 from :func:`compute`'s result into out_dir: PNG (300 dpi) and PDF beside each
    (:mod:`hawksim.plotting`); returns the PNG paths."""
    from hawksim import plotting

    with plotting.style():
        return _figures(res, Path(out_dir), plotting)


def _figures(res: dict, out_dir: Path, plotting) -> list[Path]:
    plt = plotting.pyplot()
    rows = [r for r in res["rows"] if "balanced" in r]
    left_out = [f"{r['speed']:g}" for r in res["rows"] if "balanced" not in r]
    missing = f" No UVLM-balanced trim at V = {', '.join(left_out)} m/s (not shown)." if left_out else ""
    paths = []
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
    vlab = [f"V = {r['speed']:g} m/s" for r in rows]
    n_samples = sorted({len(r["balanced"]["series"]["t_over_T"]) for r in rows})
    samples = SAMPLES_NOTE.format(n="/".join(map(str, n_samples)))
    cyc = rows[0]["balanced"].get("resolution", {}).get("cycles") if rows else None
    beat = f"wingbeat {cyc} (the last) of the UVLM run" if cyc else "the last wingbeat of the UVLM run"

    # Fig. 9: wing kinematic functions over one wingbeat
    fig, axes = plt.subplots(1, 3, figsize=(plotting.WIDE, 3.2))
    tt = np.linspace(0, 1, 201)
    for r, c, lab in zip(rows, colors, vlab):
        kin = Kinematics.from_edge(r["balanced"]["kinematics"])
        ang = np.degrees(kin.angles(tt * kin.period))
        for j, ax in enumerate(axes):
            ax.plot(tt, ang[j], color=c, label=lab)
    for ax, name in zip(axes, (r"sweep $\phi$", r"elevation $\theta$", r"rotation $\alpha$")):
        ax.set_xlabel("t / T")
        ax.set_ylabel(f"{name} (deg)")
        ax.set_xlim(0, 1)
        plotting.min_span(ax, 20.0)
    axes[0].legend(loc="lower center")
    plotting.panel_letters(axes, ("sweep", "elevation", "rotation"))
    theta0 = ", ".join(f"{r['balanced']['kinematics']['theta0']:.1f}" for r in rows)
    vlist = ", ".join(f"{r['speed']:g}" for r in rows)
    paths.append(plotting.save(
        fig, out_dir / "fig09_kinematics.png",
        title=plotting.title(9, "wing kinematics of the UVLM-balanced minimum-power trims"),
        caption=f"{plotting.cite(9)} Eq. 1 evaluated from each trim's parameters over one wingbeat (t/T). The "
                rf"elevation is constant in the kinematics ($\theta = \theta_0$ = {theta0} deg at V = {vlist} "
                f"m/s); every panel spans at least 20 deg so a constant is drawn flat.{missing}"))

    # Fig. 11: lift and drag over one wingbeat
    fig, axes = plt.subplots(1, 2, figsize=(plotting.WIDE, 3.4))
    for r, c, lab in zip(rows, colors, vlab):
        s = r["balanced"]["series"]
        for ax, key in zip(axes, ("lift_N", "drag_N")):
            ax.plot(s["t_over_T"], 1e3 * np.asarray(s[key]), "o-", ms=2.5, lw=1.0, color=c, label=lab)
    axes[0].set_ylabel("lift (mN)")
    axes[1].set_ylabel("drag (mN)")
    for ax in axes:
        ax.set_xlabel("t / T")
        ax.set_xlim(0, 1)
        ax.axhline(0, color="k", lw=0.5)
    axes[0].legend()
    plotting.panel_letters(axes, ("lift", "drag"))
    paths.append(plotting.save(
        fig, out_dir / "fig11_forces.png",
        title=plotting.title(11, "UVLM lift and drag over a wingbeat at the balanced trims"),
        caption=f"{plotting.cite(11)} Instantaneous aerodynamic forces of {beat}: {samples}.{missing}"))

    # Figs. 13 and 14: mean power and energy per unit distance against V, with fits; distributions in a cycle
    sp = np.array([r["speed"] for r in rows])
    p_bal = np.array([r["balanced"]["uvlm"]["power_W"] for r in rows])
    p_opt = np.array([r["uvlm_at_optimum"]["power_W"] for r in res["rows"]])
    sp_opt = np.array([r["speed"] for r in res["rows"]])
    vv = np.linspace(0, max(2.0, sp.max()), 100)
    fb, fp = res["power_fit_W"]["uvlm_balanced"], res["power_fit_W"]["paper"]
    for kind in ("power", "energy"):
        fig, axes = plt.subplots(1, 2, figsize=(plotting.WIDE, 3.6))
        ax = axes[0]
        if kind == "power":
            ax.plot(sp, 1e3 * p_bal, "o", color="C0", label="UVLM, balanced trims")
            ax.plot(sp_opt, 1e3 * p_opt, "s", mfc="none", color="C2", label="UVLM at the surrogate optima")
            ax.plot(vv, 1e3 * (fb["a"] + fb["b"] * vv), "-", color="C0",
                    label=f"fit P = {fb['a']:.4f} + {fb['b']:.4f} V (W)")
            ax.plot(vv, 1e3 * (fp["a"] + fp["b"] * vv), "--", color="k",
                    label=f"paper P = {fp['a']:.4f} + {fp['b']:.4f} V (W)")
            ax.set_ylabel("mean power P (mW)")
        else:
            m = sp > 0
            v2 = vv[vv >= 0.25]
            ax.plot(sp[m], 1e3 * p_bal[m] / sp[m], "o", color="C0", label="UVLM, balanced trims")
            ax.plot(v2, 1e3 * (fb["a"] / v2 + fb["b"]), "-", color="C0",
                    label=f"fit E = {fb['a']:.4f}/V + {fb['b']:.4f} (J/m)")
            ax.plot(v2, 1e3 * (fp["a"] / v2 + fp["b"]), "--", color="k",
                    label=f"paper E = {fp['a']:.4f}/V + {fp['b']:.4f} (J/m)")
            ax.set_ylabel("energy per unit distance E = P/V (mJ/m)")
            ax.set_xlim(0, None)
        ax.set_xlabel("ascent speed V (m/s)")
        ax.legend(fontsize=7)
        for r, c, lab in zip(rows, colors, vlab):
            s = r["balanced"]["series"]
            p = 1e3 * np.asarray(s["power_W"])
            if kind == "power":
                axes[1].plot(s["t_over_T"], p, "o-", ms=2.5, lw=1.0, color=c, label=lab)
            elif r["speed"] > 0:
                axes[1].plot(s["t_over_T"], p / r["speed"], "o-", ms=2.5, lw=1.0, color=c, label=lab)
        axes[1].set_xlabel("t / T")
        axes[1].set_xlim(0, 1)
        axes[1].set_ylabel("power (mW)" if kind == "power" else "power / V (mJ/m)")
        axes[1].legend(fontsize=7)
        if kind == "power":
            plotting.panel_letters(axes, ("mean power against ascent speed", "power over a wingbeat"))
            paths.append(plotting.save(
                fig, out_dir / "fig13_power.png",
                title=plotting.title(13, "required aerodynamic power of the minimum-power trims"),
                caption=f"{plotting.cite(13)} (a) Cycle-averaged power of the UVLM at the balanced trims and at the "
                        f"surrogate's optima, least-squares line through the balanced trims, and the paper's fit. "
                        f"(b) Instantaneous power over {beat} at the balanced trims: {samples}.{missing}"))
        else:
            hover = ", ".join(f"{v:g}" for v in sp[sp <= 0])
            omit = (f" V = {hover} m/s (hover) is not shown: the energy per unit ascent distance P/V is infinite "
                    "there; the fit curves start at V = 0.25 m/s.") if hover else ""
            plotting.panel_letters(axes, ("energy per unit distance against ascent speed",
                                          "power / V over a wingbeat"))
            paths.append(plotting.save(
                fig, out_dir / "fig14_energy.png",
                title=plotting.title(14, "energy per unit ascent distance of the minimum-power trims"),
                caption=f"{plotting.cite(14)} (a) E = P/V of the UVLM at the balanced trims, with E = a/V + b from "
                        f"the power fits of Fig. 13. (b) Instantaneous power divided by V over {beat}: "
                        f"{samples}.{omit}{missing}"))
    return paths


def trim_table(res: dict, command: str) -> dict:
    """The UVLM-balanced trims in the layout of ``insects/hawkmoth/data/trim_table.json`` (what `hawksim fly` uses)."""
    from hawksim import __version__
    from hawksim.trim.balance import FREE, TRIM_RESOLUTION

    rows = [{"speed": r["speed"], "kinematics": r["balanced"]["kinematics"], "chi": r["balanced"]["chi"],
             "uvlm": {k: r["balanced"]["uvlm"][k] for k in LOADS},
             "start": {"source": "GA + Nelder-Mead minimum of Eq. 3 on the shipped surrogate",
                       "kinematics": r["surrogate"]["kinematics"],
                       "uvlm": {k: r["uvlm_at_optimum"][k] for k in LOADS}},
             "converged": r["balanced"]["converged"], "evaluations": r["balanced"]["evaluations"],
             "wall_time_s": r["balanced"]["wall_time_s"]} for r in res["rows"] if "balanced" in r]
    return {"source": "UVLM balance of the surrogate's minimum-power trim (f, beta, phi0, alpha0 adjusted)",
            "command": command, "seed": res["seed"], "hawksim_version": __version__, "free_parameters": list(FREE),
            "resolution": TRIM_RESOLUTION.to_dict(), "tolerance": 0.01, "rows": rows}


def write_trim_results(out_dir: str | Path, speeds=TABLE3_SPEEDS, *, seed: int = 0, population: int = 100_000,
                       log=print) -> dict:
    """Compute and write ``trim_results.json``, ``table3.md``, ``table4.md``, ``trim_table.json`` and the figures
    into ``out_dir``; returns a summary."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = compute(speeds, seed=seed, population=population, log=log, rows_dir=out_dir / "rows")
    res["command"] = f"hawksim reproduce --out {out_dir.parent}"
    write_text(out_dir / "trim_results.json", json.dumps(res, indent=1), "trim results")
    write_text(out_dir / "table3.md", table3_markdown(res), "table")
    write_text(out_dir / "table4.md", table4_markdown(res), "table")
    write_text(out_dir / "trim_table.json", json.dumps(trim_table(res, res["command"]), indent=1), "trim table")
    figs = figures(res, out_dir)
    return {"dir": str(out_dir), "power_fit_W": res["power_fit_W"], "figures": [str(p) for p in figs],
            "balanced_converged": [r["balanced"]["converged"] for r in res["rows"] if "balanced" in r]}
