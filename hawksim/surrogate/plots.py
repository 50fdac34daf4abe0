"""Validation figures of the surrogates (like Nguyen et al. 2020, Fig. 5): network vs UVLM on held-out samples,
one panel per output, with RMSE and R^2; PNG (300 dpi) and PDF beside it (:mod:`hawksim.plotting`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from hawksim.backends.network import OUTPUTS

LABELS = {"L_plus": "$L^+$", "D_plus": "$D^+$", "M_plus": "$M^+$", "P_plus": "$P^+$"}


def _panel(ax, a: np.ndarray, b: np.ndarray, name: str, rmse: float, r2: float, xlabel: bool, ylabel: bool):
    lo, hi = float(min(a.min(), b.min())), float(max(a.max(), b.max()))
    pad = 0.04 * (hi - lo or 1.0)
    ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], "k-", lw=0.7, zorder=1)
    ax.plot(a, b, "o", ms=3, mfc="none", color="C0", zorder=2)
    ax.set_xlim(lo - pad, hi + pad)
    ax.set_ylim(lo - pad, hi + pad)
    ax.set_aspect("equal")
    ax.text(0.97, 0.04, f"RMSE {rmse:.3g}\n$R^2$ = {r2:.4f}", transform=ax.transAxes, ha="right", va="bottom",
            fontsize=7)
    if xlabel:
        ax.set_xlabel(f"UVLM {LABELS[name]} (\u2013)")
    if ylabel:
        ax.set_ylabel(f"ANN {LABELS[name]} (\u2013)")


def scatter_figure(y_uvlm: np.ndarray, y_ann: np.ndarray, path: str | Path, title: str,
                   caption: str | None = None) -> Path:
    """Scatter of ANN vs UVLM, (n, 4) each, one panel per output; returns the PNG's path (the PDF beside it)."""
    from hawksim import plotting
    from hawksim.surrogate.train import scores

    sc = scores(y_uvlm, y_ann)
    with plotting.style():
        plt = plotting.pyplot()
        fig, axes = plt.subplots(1, 4, figsize=(plotting.WIDE, 3.0))
        for k, (ax, name) in enumerate(zip(axes, OUTPUTS)):
            _panel(ax, y_uvlm[:, k], y_ann[:, k], name, sc.rmse[name], sc.r2[name], True, True)
        plotting.panel_letters(axes, [LABELS[n] for n in OUTPUTS])
        return plotting.save(fig, path, title=title, caption=caption or (
            f"{plotting.cite(5)} Cycle-averaged nondimensional loads predicted by the network against the UVLM's "
            f"labels, {len(y_uvlm)} held-out cases; the line is y = x."))


def grid_figure(panels, path: str | Path, caption: str | None = None) -> Path:
    """Speeds x outputs grid of ANN vs UVLM; ``panels``: [(speed, y_uvlm (n, 4), y_ann (n, 4))]. Returns the
    PNG's path (the PDF beside it)."""
    from hawksim import plotting
    from hawksim.surrogate.train import scores

    n = sorted({len(y) for _, y, _ in panels})
    with plotting.style():
        plt = plotting.pyplot()
        fig, axes = plt.subplots(len(panels), 4, figsize=(plotting.WIDE * 0.8, 2.05 * len(panels) + 0.3),
                                 squeeze=False)
        for i, (_, y, p) in enumerate(panels):
            s = scores(y, p)
            for k, name in enumerate(OUTPUTS):
                _panel(axes[i, k], y[:, k], p[:, k], name, s.rmse[name], s.r2[name], True, True)
        plotting.panel_letters(axes, [f"V = {v:g} m/s, {LABELS[name]}" for v, _, _ in panels for name in OUTPUTS])
        return plotting.save(
            fig, path, title=plotting.title(5, "per-speed surrogates against the UVLM on held-out cases"),
            caption=caption or (
                f"{plotting.cite(5)} Rows: the shipped per-speed networks; columns: the cycle-averaged "
                f"nondimensional outputs. {'/'.join(map(str, n))} held-out cases per speed drawn at random "
                f"(seed 0) from each network's test split (never seen in training); labels are the UVLM's "
                f"wingbeat-3 averages; the line is y = x. Scores on all test cases and those of the speed-input "
                f"network are in validation.json."))


def validation_figure(result, path: str | Path, n: int = 50, seed: int = 0) -> Path:
    """Fig. 5-like scatter on ``n`` random held-out samples of a TrainResult."""
    from hawksim import plotting

    sur = result.surrogate
    rng = np.random.default_rng(seed)
    idx = rng.choice(result.test_x.shape[0], size=min(n, result.test_x.shape[0]), replace=False)
    x = result.test_x[idx]
    pred = sur.predict(x[:, :7], x[:, 7] if sur.inputs.speed is None else None)
    where = "all speeds" if sur.inputs.speed is None else f"V = {sur.inputs.speed:g} m/s"
    return scatter_figure(result.test_y[idx], pred, path,
                          plotting.title(5, f"surrogate against the UVLM, {len(idx)} held-out cases, {where}"))
