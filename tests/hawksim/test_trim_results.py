"""The trim-results writers: the power fit, the tables and the shipped-trim-table layout, on synthetic rows."""

import numpy as np
import pytest

from hawksim.insect.kinematics import PARAM_NAMES, TABLE3_DEG, TABLE3_SPEEDS
from hawksim.paper.trims import PAPER_POWER_FIT_W, figures, power_fit, table3_markdown, table4_markdown, trim_table

FIT_RTOL = 1e-12
"""Relative: least-squares line through five exact points vs its coefficients: round-off of a 2 x 2 solve;
measured 4.8e-16."""


def test_power_fit_recovers_a_line():
    v = np.array(TABLE3_SPEEDS)
    a, b = power_fit(v, PAPER_POWER_FIT_W[0] + PAPER_POWER_FIT_W[1] * v)
    assert (a, b) == pytest.approx(PAPER_POWER_FIT_W, rel=FIT_RTOL)


def _synthetic_results():
    rows = []
    for i, v in enumerate(TABLE3_SPEEDS):
        k = {p: TABLE3_DEG[p][i] for p in PARAM_NAMES}
        loads = {"L_plus": 1.0, "D_plus": 0.0, "M_plus": 0.0, "P_plus": 0.9 + 0.2 * v, "power_W": 0.07 + 0.02 * v}
        t = np.linspace(0, 1, 41)[:-1]
        rows.append({"speed": v, "surrogate": {"kinematics": k, "chi": 60 - k["beta"], "ann": loads},
                     "uvlm_at_optimum": loads,
                     "balanced": {"kinematics": k, "chi": 60 - k["beta"], "uvlm": loads, "converged": True,
                                  "evaluations": 3, "wall_time_s": 1.0, "P_plus_change": 0.0,
                                  "series": {"t_over_T": t.tolist(), "lift_N": np.sin(2 * np.pi * t).tolist(),
                                             "drag_N": np.cos(2 * np.pi * t).tolist(),
                                             "power_W": (0.07 + 0.02 * v + 0 * t).tolist()}}})
    fit = power_fit(TABLE3_SPEEDS, [r["balanced"]["uvlm"]["power_W"] for r in rows])
    return {"rows": rows, "seed": 0, "power_fit_W": {"uvlm_balanced": {"a": fit[0], "b": fit[1]},
                                                      "paper": dict(zip("ab", PAPER_POWER_FIT_W))}}


def test_tables_figures_and_trim_table_layout(tmp_path):
    res = _synthetic_results()
    t3 = table3_markdown(res)
    assert t3.count("paper Table 3") == 5 and "| 2 | UVLM-balanced | 31.0 | 2.9 |" in t3
    t4 = table4_markdown(res)
    assert "| 1.5 | 1.000 (1.000) |" in t4 and "1.21" in t4  # the paper's P+ at 1.5 m/s beside ours
    paths = figures(res, tmp_path)
    assert [p.name for p in paths] == ["fig09_kinematics.png", "fig11_forces.png", "fig13_power.png",
                                       "fig14_energy.png"]
    assert all(p.stat().st_size > 10_000 for p in paths)
    from test_figures import assert_published

    for p in paths:
        assert_published(p)
    table = trim_table(res, "hawksim reproduce --out results")
    # the layout hawksim.trim.tables reads
    path = tmp_path / "trim_table.json"
    import json

    path.write_text(json.dumps(table))
    rows = sorted(json.loads(path.read_text())["rows"], key=lambda r: r["speed"])
    assert [r["speed"] for r in rows] == list(TABLE3_SPEEDS)
    assert rows[2]["kinematics"]["f"] == TABLE3_DEG["f"][2]
