"""Regenerate the paper's figures from the JSON already in results/ (no UVLM run): Figs. 9, 11, 13, 14 from
results/trim/trim_results.json, Figs. 15-19 from results/stability*/stability_studies.json (with the reports beside
them for what the derivatives were linearised about) and the surrogate's Fig. 5 grid from the shipped networks on
their held-out cases of the data set (``--data``; network predictions only, the labels are the stored UVLM ones).
Each figure is written as PNG (300 dpi) and PDF beside it (hawksim.plotting). Prints ONE JSON object: the PNGs.

    python scripts/figures.py [--results results] [--data data/uvlm_training_0.3.sqlite] [--only trim stability]
"""

import argparse
import json
from pathlib import Path

from hawksim.jsonout import emit

PARTS = ("trim", "stability", "stability_table3", "surrogate")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--results", default="results", type=Path)
    ap.add_argument("--data", default="data/uvlm_training_0.3.sqlite")
    ap.add_argument("--only", nargs="+", choices=PARTS, default=PARTS)
    a = ap.parse_args()
    out = {}
    if "trim" in a.only:
        from hawksim.paper.trims import figures

        d = a.results / "trim"
        out["trim"] = [str(p) for p in figures(json.loads((d / "trim_results.json").read_text()), d)]
    for part in ("stability", "stability_table3"):
        if part in a.only:
            from hawksim.paper.studies import plot, trims_label

            d = a.results / part
            reports = json.loads((d / "stability_reports.json").read_text())
            out[part] = [str(p) for p in plot(json.loads((d / "stability_studies.json").read_text()), d,
                                              trims_label(reports))]
    if "surrogate" in a.only:
        import numpy as np

        from hawksim.surrogate.plots import grid_figure
        from hawksim.surrogate.train import shipped_held_out

        panels = []
        for v, sur, t, te in shipped_held_out(a.data):  # the same 50 cases as scripts/studies/surrogate_validation.py
            pick = np.random.default_rng(0).choice(len(te), size=min(50, len(te)), replace=False)
            panels.append((v, t.y[te][pick], sur.predict(t.x[te], v)[pick]))
        out["surrogate"] = [str(grid_figure(panels, a.results / "surrogate" / "validation.png"))]
    emit(out)


if __name__ == "__main__":
    main()
