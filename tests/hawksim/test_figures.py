"""The figure style (hawksim.plotting): every figure written as a 300 dpi PNG with a vector PDF beside it, by the
trim, stability-study and surrogate plotters alike."""

import json
from pathlib import Path

import numpy as np
import pytest

from hawksim import plotting

ROOT = Path(__file__).resolve().parents[2]

DPI_ATOL = 0.5
"""dots per inch: the PNG stores pixels per metre as an integer, so 300 dpi reads back as 299.9994."""

STUDIES = ("fig15_eigenvalues", "fig16_derivatives", "fig17_we_sweep_longitudinal", "fig18_we_sweep_lateral",
           "fig19_nr_sweep")


def assert_published(png: Path) -> None:
    """PNG at 300 dpi and a PDF of the same stem beside it."""
    from PIL import Image

    assert png.suffix == ".png" and png.is_file()
    with Image.open(png) as im:
        assert im.format == "PNG"
        assert im.info["dpi"] == pytest.approx((plotting.DPI, plotting.DPI), abs=DPI_ATOL)
    pdf = png.with_suffix(".pdf")
    assert pdf.is_file() and pdf.read_bytes()[:5] == b"%PDF-"


def test_save_writes_png_and_pdf_at_300_dpi_deterministically(tmp_path):
    out = []
    for name in ("one", "two"):
        with plotting.style():
            fig, axes = plotting.pyplot().subplots(1, 2, figsize=(4, 2))
            for ax in axes:
                ax.plot([0, 1], [0, 1])
            plotting.panel_letters(axes, ("x", "y"))
            assert [ax.get_title(loc="left") for ax in axes] == ["(a) x", "(b) y"]
            out.append(plotting.save(fig, tmp_path / f"{name}.png", title=plotting.title(1, "t"), caption="c " * 80))
    for p in out:
        assert_published(p)
    assert out[0].read_bytes() == out[1].read_bytes()  # no timestamps
    assert out[0].with_suffix(".pdf").read_bytes() == out[1].with_suffix(".pdf").read_bytes()


def test_min_span_widens_a_flat_axis():
    with plotting.style():
        fig, ax = plotting.pyplot().subplots()
        ax.plot([0, 1], [25.0, 25.0])
        plotting.min_span(ax, 20.0)
        lo, hi = ax.get_ylim()
        plotting.pyplot().close(fig)
    assert hi - lo == pytest.approx(20.0) and 0.5 * (lo + hi) == pytest.approx(25.0)


def test_stability_figures_from_the_stored_studies(tmp_path):
    from hawksim.paper.studies import plot

    studies = json.loads((ROOT / "results" / "stability" / "stability_studies.json").read_text())
    paths = plot(studies, tmp_path, "test trims")
    assert [p.name for p in paths] == [f"{s}.png" for s in STUDIES]
    for p in paths:
        assert_published(p)


def test_surrogate_figures(tmp_path):
    from hawksim.surrogate.plots import grid_figure, scatter_figure

    rng = np.random.default_rng(0)
    y = rng.normal(size=(50, 4))
    p = grid_figure([(0.0, y, y + 0.01 * rng.normal(size=y.shape)), (1.0, y, y)], tmp_path / "validation.png")
    assert_published(p)
    assert_published(scatter_figure(y, y, tmp_path / "scatter.png", plotting.title(5, "t")))


def test_caption_wrap_keeps_mathtext_on_one_line():
    text = "forces by $\\frac{1}{2}\\rho U^2 S_t$ and " * 6 + "minimum-power"
    lines = plotting.wrap(text, 30).splitlines()
    assert len(lines) > 3 and all(line.count("$") % 2 == 0 for line in lines)
    assert lines[-1].endswith("minimum-power")
