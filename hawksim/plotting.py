"""One figure style for everything hawksim draws (the paper's figures, the surrogate's validation, the free-flight
validation): fonts, 300 dpi PNG + vector PDF side by side, panel letters, titles and captions.

Bottom layer (tests/test_layers.py), so any subpackage may use it; matplotlib is imported lazily (the CLI stays fast
and the numerical code never needs it). Usage::

    with plotting.style():
        plt = plotting.pyplot()
        fig, axes = plt.subplots(1, 2, figsize=(plotting.WIDE, 3.4))
        ...
        plotting.panel_letters(axes, ("longitudinal", "lateral"))
        plotting.save(fig, out_dir / "fig15_eigenvalues.png", title=plotting.title(15, "..."), caption="...")

Titles read ``Fig. N: <what>`` with the paper's figure cited in the caption (:func:`title`, :func:`cite`);
eigenvalues are written with :data:`LAMBDA`; everything a figure leaves out (a speed, a mode) is said in its caption.
"""

from __future__ import annotations

import textwrap
from contextlib import contextmanager
from pathlib import Path

DPI = 300
"""Raster resolution of every PNG."""
FORMATS = ("png", "pdf")
"""Written side by side by :func:`save`: the PNG for viewing, the PDF (vector) for print."""
WIDE, NARROW = 10.0, 5.0
"""Figure widths [in]: a full page and a single column."""
PAPER = "Nguyen et al. (2020)"
LAMBDA = r"\lambda^+"
"""Mathtext of the nondimensional eigenvalue (t+ = t/T), without the dollars."""
RE_LAMBDA, IM_LAMBDA = rf"Re ${LAMBDA}$ (per wingbeat)", rf"Im ${LAMBDA}$ (per wingbeat)"

RC = {"font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "legend.fontsize": 7.5, "xtick.labelsize": 8,
      "ytick.labelsize": 8, "figure.titlesize": 10.5, "lines.linewidth": 1.3, "lines.markersize": 4,
      "legend.framealpha": 0.85, "figure.constrained_layout.use": True,
      "savefig.dpi": DPI, "pdf.fonttype": 42, "mathtext.fontset": "dejavusans"}
CAPTION_FONTSIZE = 7.5


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


@contextmanager
def style():
    """The style's rcParams for the figures made (and saved) inside the block."""
    plt = pyplot()
    with plt.rc_context(RC):
        yield


def title(n: int | str | None, what: str) -> str:
    """``Fig. n: what`` (or ``what`` alone for a figure with no paper counterpart)."""
    return f"Fig. {n}: {what}" if n is not None else what


def cite(n: int | str) -> str:
    """The caption's first sentence pointing at the paper's figure."""
    return f"Cf. {PAPER}, Fig. {n}."


def panel_letters(axes, labels=None, start: int = 0) -> None:
    """Left titles "(a)", "(b)", ... (optionally "(a) label") on the axes in reading order."""
    import numpy as np

    axes = list(np.ravel(axes))
    labels = list(labels) if labels is not None else [""] * len(axes)
    for i, (ax, lab) in enumerate(zip(axes, labels)):
        ax.set_title(f"({chr(97 + start + i)})" + (f" {lab}" if lab else ""), loc="left", fontsize=RC["axes.titlesize"])


def min_span(ax, span: float, axis: str = "y") -> None:
    """Widen the axis limits about their centre to at least ``span`` (so a constant does not look like a curve)."""
    lo, hi = ax.get_ylim() if axis == "y" else ax.get_xlim()
    if hi - lo < span:
        c = 0.5 * (lo + hi)
        lo, hi = c - 0.5 * span, c + 0.5 * span
        (ax.set_ylim if axis == "y" else ax.set_xlim)(lo, hi)


def wrap(text: str, width: int) -> str:
    """``text`` broken into lines of at most about ``width`` characters, never inside $mathtext$ (matplotlib
    parses math line by line, so a formula split over two lines would print its source) nor at hyphens."""
    parts = text.split("$")
    glued = "$".join(p.replace(" ", "\x00") if i % 2 else p for i, p in enumerate(parts))
    lines = textwrap.wrap(glued, width, break_on_hyphens=False, break_long_words=False)
    return "\n".join(lines).replace("\x00", " ")


def save(fig, path: str | Path, *, title: str | None = None, caption: str | None = None) -> Path:
    """Write ``fig`` as PNG (:data:`DPI`) and PDF beside it (same stem), with the title on top and the caption
    (wrapped to the figure's width) below; close it and return the PNG's path. The output is deterministic (no
    timestamps in the metadata)."""
    plt = pyplot()
    path = Path(path).with_suffix(".png")
    path.parent.mkdir(parents=True, exist_ok=True)
    if title:
        fig.suptitle(title, fontsize=RC["figure.titlesize"])
    if caption:
        width = max(40, int(fig.get_figwidth() * 72 / (0.52 * CAPTION_FONTSIZE)))
        from matplotlib.transforms import offset_copy

        fig.text(0.005, 0.0, wrap(caption, width), ha="left", va="top", fontsize=CAPTION_FONTSIZE,
                 transform=offset_copy(fig.transFigure, fig=fig, y=-4, units="points"))
    meta = {"png": {"Software": "hawksim"}, "pdf": {"Creator": "hawksim", "Producer": None, "CreationDate": None}}
    import io

    from hawksim.atomic import write_bytes

    try:
        for ext in FORMATS:  # each file all or nothing (a full disk: OSError naming it)
            buf = io.BytesIO()
            fig.savefig(buf, format=ext, dpi=DPI, bbox_inches="tight", pad_inches=0.06, metadata=meta[ext])
            write_bytes(path.with_suffix(f".{ext}"), buf.getvalue(), "figure")
    finally:
        plt.close(fig)
    return path
