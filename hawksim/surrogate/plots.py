"""Validation figure of a trained surrogate (like Nguyen et al. 2020, Fig. 5): network vs UVLM on held-out
samples, one panel per output, with RMSE and R^2."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from hawksim.backends.network import OUTPUTS

LABELS = {"L_plus": "$L^+$", "D_plus": "$D^+$", "M_plus": "$M^+$", "P_plus": "$P^+$"}


def scatter_figure(y_uvlm: np.ndarray, y_ann: np.ndarray, path: str | Path, title: str) -> Path:
    """Scatter of ANN vs UVLM, (n, 4) each, to a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hawksim.surrogate.train import scores

    sc = scores(y_uvlm, y_ann)
    fig, axes = plt.subplots(1, 4, figsize=(13, 3.4))
    for k, (ax, name) in enumerate(zip(axes, OUTPUTS)):
        a, b = y_uvlm[:, k], y_ann[:, k]
        lo, hi = float(min(a.min(), b.min())), float(max(a.max(), b.max()))
        ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
        ax.plot(a, b, "o", ms=3.5, mfc="none", color="C0")
        ax.set_xlabel(f"UVLM {LABELS[name]}")
        ax.set_ylabel(f"ANN {LABELS[name]}")
        ax.set_title(f"RMSE {sc.rmse[name]:.3g}, $R^2$ {sc.r2[name]:.4f}", fontsize=9)
        ax.set_aspect("equal", adjustable="datalim")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def validation_figure(result, path: str | Path, n: int = 50, seed: int = 0) -> Path:
    """Fig. 5-like scatter on ``n`` random held-out samples of a TrainResult."""
    sur = result.surrogate
    rng = np.random.default_rng(seed)
    idx = rng.choice(result.test_x.shape[0], size=min(n, result.test_x.shape[0]), replace=False)
    x = result.test_x[idx]
    pred = sur.predict(x[:, :7], x[:, 7] if sur.inputs.speed is None else None)
    where = "all speeds" if sur.inputs.speed is None else f"V = {sur.inputs.speed:g} m/s"
    return scatter_figure(result.test_y[idx], pred, path, f"surrogate vs UVLM, {len(idx)} held-out cases, {where}")
