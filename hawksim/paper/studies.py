"""The paper's stability studies (Figs. 15-19) from per-speed stability reports, as JSON + PNG.

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


def plot(studies: dict, out_dir: Path) -> list[Path]:
    """PNG figures like the paper's Figs. 15-19 into out_dir."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    speeds = studies["speeds"]
    cmap = plt.get_cmap("viridis")

    def scatter(ax, eigs_by_speed, labels):
        for i, eigs in enumerate(eigs_by_speed):
            e = np.asarray(eigs)
            ax.scatter(e[:, 0], e[:, 1], color=cmap(i / max(1, len(eigs_by_speed) - 1)), label=labels[i], s=25)
        ax.axvline(0, color="k", lw=0.5)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("Re(lambda+)")
        ax.set_ylabel("Im(lambda+)")

    fig, axs = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, key in zip(axs, ("longitudinal", "lateral")):
        scatter(ax, studies["fig15"][key], [f"{v:g} m/s" for v in speeds])
        ax.set_title(f"Fig. 15: {key} eigenvalues vs ascent speed")
    axs[0].legend(fontsize=8)
    fig.tight_layout()
    paths.append(out_dir / "fig15_eigenvalues.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, axs = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, key in zip(axs, ("longitudinal", "lateral")):
        for name, vals in studies["fig16"][key].items():
            ax.plot(speeds, vals, "o-", label=name)
        ax.set_xlabel("ascent speed (m/s)")
        ax.set_title(f"Fig. 16: {key} derivatives (Eq. 8)")
        ax.legend(fontsize=7, ncol=3)
    fig.tight_layout()
    paths.append(out_dir / "fig16_derivatives.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    for key, name in (("longitudinal", "fig17"), ("lateral", "fig18")):
        runs = studies["fig17_18"]
        fig, axs = plt.subplots(1, len(runs), figsize=(3.6 * len(runs), 3.6), squeeze=False)
        for ax, run in zip(axs[0], runs):
            scatter(ax, run[key], [f"{v:.1f}" for v in run["speeds"]])
            ax.set_title(f"derivatives at {run['frozen_at']:g} m/s", fontsize=9)
        fig.suptitle(f"{name}: {key} eigenvalues, w_e+ swept 0-2 m/s, derivatives frozen")
        fig.tight_layout()
        paths.append(out_dir / f"{name}_we_sweep_{key}.png")
        fig.savefig(paths[-1], dpi=100)
        plt.close(fig)

    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    scatter(ax, studies["fig19"]["lateral"], [f"Nr from {v:g} m/s" for v in studies["fig19"]["speeds"]])
    ax.set_title("Fig. 19: lateral eigenvalues, hover derivatives, N_r+ varied")
    ax.legend(fontsize=8)
    fig.tight_layout()
    paths.append(out_dir / "fig19_nr_sweep.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)
    return paths


def write(reports: list[dict], out_dir: Path) -> dict:
    """Write stability_reports.json, stability_studies.json and the PNGs; return the studies."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    studies = summarize(reports)
    (out_dir / "stability_reports.json").write_text(json.dumps(reports, indent=1))
    (out_dir / "stability_studies.json").write_text(json.dumps(studies, indent=1))
    plot(studies, out_dir)
    return studies
