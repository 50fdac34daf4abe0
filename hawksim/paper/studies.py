"""The paper's stability studies (Figs. 15-19) from per-speed stability reports, as JSON + figures (PNG, PDF).

* Fig. 15: eigenvalues of A_long+ and A_lat+ against the ascent speed;
* Fig. 16: nondimensional derivatives against the speed;
* Figs. 17-18: eigenvalues with the derivatives frozen at one speed's values while w_e+ sweeps 0 -> 2 m/s;
* Fig. 19: lateral eigenvalues with the hover derivatives but N_r+ taken from each speed.
Pure functions of the reports (dicts as printed by `hawksim stability --json`) plus plotting at the edge.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from hawksim.atomic import write_text
from hawksim.stability.system import a_lat, a_long


def _scalars(rep: dict) -> dict:
    return rep["nondimensional"]


def _eig(A: np.ndarray) -> list[list[float]]:
    w = np.linalg.eigvals(A)
    w = w[np.lexsort((-w.imag, w.real))]
    return [[float(x.real), float(x.imag)] for x in w]


def w_e_sweep(rep: dict, speeds: np.ndarray) -> dict:
    """Eigenvalues with rep's derivatives frozen and w_e+ = -V / U for V in speeds (Figs. 17-18)."""
    s = _scalars(rep)
    dl, dt = rep["longitudinal"]["derivatives"], rep["lateral"]["derivatives"]
    out = {"speeds": list(map(float, speeds)), "longitudinal": [], "lateral": []}
    for V in speeds:
        w_e = -V / s["U"]
        out["longitudinal"].append(_eig(a_long(dl, s["m_plus"], s["Iy_plus"], s["g_plus"], w_e)))
        out["lateral"].append(_eig(a_lat(dt, s["m_plus"], s["Ix_plus"], s["Iz_plus"], s["Ixz_plus"], s["g_plus"], w_e)))
    return out


def nr_sweep(hover: dict, reports: list[dict]) -> dict:
    """Lateral eigenvalues with hover's derivatives and w_e but N_r+ from each report (Fig. 19)."""
    s = _scalars(hover)
    out = {"speeds": [r["speed"] for r in reports], "Nr_plus": [], "lateral": []}
    for r in reports:
        d = dict(hover["lateral"]["derivatives"], Nr=r["lateral"]["derivatives"]["Nr"])
        out["Nr_plus"].append(d["Nr"])
        out["lateral"].append(_eig(a_lat(d, s["m_plus"], s["Ix_plus"], s["Iz_plus"], s["Ixz_plus"], s["g_plus"],
                                         s["w_e_plus"])))
    return out


def summarize(reports: list[dict]) -> dict:
    """All studies from the per-speed reports (sorted by speed)."""
    reports = sorted(reports, key=lambda r: r["speed"])
    sweep = np.linspace(0.0, 2.0, 21)
    return {
        "speeds": [r["speed"] for r in reports],
        "fig15": {"longitudinal": [r["longitudinal"]["eigenvalues"] for r in reports],
                  "lateral": [r["lateral"]["eigenvalues"] for r in reports],
                  "modes": [{"speed": r["speed"],
                             "longitudinal": [(m["kind"], m["stable"]) for m in r["longitudinal"]["modes"]],
                             "lateral": [(m["kind"], m["stable"]) for m in r["lateral"]["modes"]]} for r in reports]},
        "fig16": {"longitudinal": {k: [r["longitudinal"]["derivatives"][k] for r in reports]
                                   for k in reports[0]["longitudinal"]["derivatives"]},
                  "lateral": {k: [r["lateral"]["derivatives"][k] for r in reports]
                              for k in reports[0]["lateral"]["derivatives"]}},
        "fig17_18": [{"frozen_at": r["speed"], **w_e_sweep(r, sweep)} for r in reports],
        "fig19": nr_sweep(reports[0], reports),
    }


DERIV_GROUPS = {"longitudinal": (("force derivatives", "XZ"), ("moment derivatives", "M")),
                "lateral": (("force derivatives", "Y"), ("moment derivatives", "LN"))}
"""Fig. 16's panels: derivatives grouped by the load they belong to (first letter of the name)."""
MARKERS = "osD^v<>ph"


def _deriv_tex(name: str) -> str:
    """'Xu' -> '$X_u^+$'."""
    return f"${name[0]}_{{{name[1:]}}}^+$"


def trims_label(reports: list[dict]) -> str:
    """What the reports were linearised about, for the figures' captions."""
    src = {r.get("trim", {}).get("source", "") for r in reports}
    if src == {"given"}:
        return "the kinematics of the paper's Table 3"
    return "the shipped UVLM-balanced minimum-power trims (hawksim/insects/hawkmoth/data/trim_table.json)"


def plot(studies: dict, out_dir: Path, trims: str | None = None) -> list[Path]:
    """Figures like the paper's Figs. 15-19 into out_dir, PNG (300 dpi) and PDF beside each (:mod:`hawksim.plotting`);
    returns the PNG paths. ``trims``: what the derivatives were computed about, said in the captions."""
    from hawksim import plotting

    with plotting.style():
        return _plot(studies, Path(out_dir), trims, plotting)


def _plot(studies: dict, out_dir: Path, trims: str | None, plotting) -> list[Path]:
    import matplotlib as mpl

    plt = plotting.pyplot()
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    speeds = studies["speeds"]
    cmap = plt.get_cmap("viridis")
    about = f" Linearised about {trims}." if trims else ""
    lam = plotting.LAMBDA
    sp_colors = [cmap(0.9 * i / max(1, len(speeds) - 1)) for i in range(len(speeds))]

    def axes_eig(ax):
        ax.axvline(0, color="k", lw=0.5, zorder=0)
        ax.axhline(0, color="k", lw=0.5, zorder=0)
        ax.set_xlabel(plotting.RE_LAMBDA)
        ax.set_ylabel(plotting.IM_LAMBDA)

    def scatter(ax, eigs_by_speed, colors, labels):
        for i, eigs in enumerate(eigs_by_speed):
            e = np.asarray(eigs)
            ax.scatter(e[:, 0], e[:, 1], color=colors[i], label=labels[i] if labels else None, s=22,
                       edgecolor="k", linewidth=0.3, zorder=2)
        axes_eig(ax)

    # Fig. 15
    fig, axs = plt.subplots(1, 2, figsize=(plotting.WIDE, 3.8))
    for ax, key in zip(axs, ("longitudinal", "lateral")):
        scatter(ax, studies["fig15"][key], sp_colors, [f"V = {v:g} m/s" for v in speeds])
    axs[0].legend(title="ascent speed")
    plotting.panel_letters(axs, (r"longitudinal, $A^+_{long}$", r"lateral, $A^+_{lat}$"))
    paths.append(plotting.save(
        fig, out_dir / "fig15_eigenvalues.png",
        title=plotting.title(15, "eigenvalues of the cycle-averaged system against the ascent speed"),
        caption=f"{plotting.cite(15)} Eigenvalues ${lam}$ of $A^+_{{long}}$ (Eq. 11) and $A^+_{{lat}}$ (Eq. 12, "
                f"Etkin's form) in nondimensional time $t^+ = t/T$, four per system and speed; Re ${lam}$ > 0 is "
                f"unstable.{about}"))

    # Fig. 16
    fig, axs = plt.subplots(1, 4, figsize=(plotting.WIDE, 3.9))
    labels = []
    for j, key in enumerate(("longitudinal", "lateral")):
        for k, (what, letters) in enumerate(DERIV_GROUPS[key]):
            ax = axs[2 * j + k]
            names = [n for n in studies["fig16"][key] if n[0] in letters]
            for i, name in enumerate(names):
                ax.plot(speeds, studies["fig16"][key][name], marker=MARKERS[i % len(MARKERS)], ms=4,
                        ls="-" if i < 3 else "--", color=f"C{i}", label=_deriv_tex(name))
            ax.axhline(0, color="k", lw=0.5, zorder=0)
            ax.set_xlabel("ascent speed V (m/s)")
            ax.set_ylabel("nondimensional derivative (\u2013)")
            h, lab = ax.get_legend_handles_labels()
            order = [i for j in range(3) for i in range(j, len(h), 3)]  # row-major: X-row above Z-row
            ax.legend([h[i] for i in order], [lab[i] for i in order], ncol=3, fontsize=7, loc="upper center",
                      bbox_to_anchor=(0.5, -0.2), handlelength=2.5, columnspacing=0.8, borderaxespad=0)
            labels.append(f"{key} {what.split()[0]}")
    plotting.panel_letters(axs, labels)
    paths.append(plotting.save(
        fig, out_dir / "fig16_derivatives.png",
        title=plotting.title(16, "nondimensional stability derivatives against the ascent speed"),
        caption=f"{plotting.cite(16)} Derivatives of the cycle-averaged loads, nondimensionalised by Eq. 8 (forces "
                r"by $\frac{1}{2}\rho U^2 S_t$, moments by $\frac{1}{2}\rho U^2 S_t \bar{c}$, velocities by $U$, "
                f"rates by 1/T); markers at the "
                f"five computed speeds, lines only join them.{about}"))

    # Figs. 17-18
    for key, n, name in (("longitudinal", 17, "fig17"), ("lateral", 18, "fig18")):
        runs = studies["fig17_18"]
        sweep = np.asarray(runs[0]["speeds"])
        norm = mpl.colors.Normalize(vmin=float(sweep.min()), vmax=float(sweep.max()))
        ncol = min(3, len(runs))
        nrow = -(-len(runs) // ncol)
        fig, axs = plt.subplots(nrow, ncol, figsize=(plotting.WIDE, 3.0 * nrow + 0.4), squeeze=False)
        for ax, run in zip(axs.flat, runs):
            scatter(ax, run[key], [cmap(norm(v)) for v in run["speeds"]], None)
        for ax in list(axs.flat)[len(runs):]:
            ax.set_visible(False)
        plotting.panel_letters(list(axs.flat)[:len(runs)],
                               [f"derivatives frozen at V = {run['frozen_at']:g} m/s" for run in runs])
        fig.colorbar(mpl.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axs, shrink=0.8, aspect=30,
                     label=r"swept speed $V$ (m/s), $w_e^+ = -V/U$")
        paths.append(plotting.save(
            fig, out_dir / f"{name}_we_sweep_{key}.png",
            title=plotting.title(n, f"{key} eigenvalues as $w_e^+$ sweeps, derivatives frozen"),
            caption=f"{plotting.cite(n)} Eigenvalues of $A^+_{{{'long' if key == 'longitudinal' else 'lat'}}}$ "
                    f"with each panel's derivatives and mass properties held at one speed's values while only the "
                    f"equilibrium vertical velocity $w_e^+ = -V/U$ is swept over V = {sweep.min():g}-{sweep.max():g} "
                    f"m/s ({len(sweep)} values, colour); $U$ is that speed's reference velocity.{about}"))

    # Fig. 19
    f19 = studies["fig19"]
    fig, axs = plt.subplots(1, 2, figsize=(plotting.WIDE, 3.8), width_ratios=(1.6, 1))
    labels19 = [f"$N_r^+$ = {nr:.2f} (V = {v:g} m/s)" for v, nr in zip(f19["speeds"], f19["Nr_plus"])]
    for ax in axs:
        scatter(ax, f19["lateral"], sp_colors, labels19)
    axs[0].legend(title=r"$N_r^+$ taken from", fontsize=7)
    pair = np.array([max((e for e in eigs if e[1] > 0), key=lambda e: e[0], default=(np.nan, np.nan))
                     for eigs in f19["lateral"]])
    zoom = ""
    if np.isfinite(pair).all():
        pad = np.maximum(0.4 * np.ptp(pair, axis=0), 2e-4)
        axs[1].set_xlim(pair[:, 0].min() - pad[0], pair[:, 0].max() + pad[0])
        axs[1].set_ylim(pair[:, 1].min() - pad[1], pair[:, 1].max() + pad[1])
        axs[1].locator_params(nbins=5)
        zoom = (f" (b) Zoom on the oscillatory pair's upper eigenvalue, which moves by only "
                f"{np.ptp(pair[:, 0]):.1g} in Re and {np.ptp(pair[:, 1]):.1g} in Im (in (a) its markers overlap); "
                f"its conjugate is the mirror image.")
    else:
        axs[1].set_visible(False)
    plotting.panel_letters(axs if zoom else axs[:1], ("all four eigenvalues", "oscillatory mode, zoomed"))
    paths.append(plotting.save(
        fig, out_dir / "fig19_nr_sweep.png",
        title=plotting.title(19, r"lateral eigenvalues, hover derivatives, $N_r^+$ varied"),
        caption=f"{plotting.cite(19)} Eigenvalues of $A^+_{{lat}}$ with every derivative, mass property and "
                f"$w_e^+$ from hover (V = {f19['speeds'][0]:g} m/s) except $N_r^+$, which is taken from each speed in "
                f"turn.{zoom}{about}"))
    return paths


def write(reports: list[dict], out_dir: Path) -> dict:
    """Write stability_reports.json, stability_studies.json and the figures; return the studies."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    studies = summarize(reports)
    write_text(out_dir / "stability_reports.json", json.dumps(reports, indent=1), "stability reports")
    write_text(out_dir / "stability_studies.json", json.dumps(studies, indent=1), "stability studies")
    plot(studies, out_dir, trims_label(reports))
    return studies
