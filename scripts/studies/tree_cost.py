"""Calibrate the treecode's cost model (``aero.treecode.NEAR_COST``, ``FAR_COST``) against the direct sum (issue 23).

``wake_summation="auto"`` asks the tree's plan (:func:`aero.treecode.lattice_tree_velocity`, ``plan=True``) whether
it beats the direct sum: the tree when NEAR_COST x near + FAR_COST x far < TREE_MARGIN x the direct sum's pairs,
with near the near-field edge-target pairs and far the cluster-target evaluations (:func:`aero.treecode.tree_work`)
and both costs in direct-sum pairs. Those costs are ratios to the lattice kernel's time per pair, so they move when
the kernel does. This study times, on bench_treecode.py's crossover cases (a held 1 m/s flight's free wake after
1-10 beats; unstretched wake-like lattices of 50-3200 rows), one wake-on-wake call by the direct sum and by the tree
(theta 0.2, best of 3), counts the tree's work, fits (NEAR_COST, FAR_COST) by least squares on the relative error of
the predicted tree time, and says for each case whether the plan, with the shipped and with the fitted costs, picks
the faster sum. The fit ignores the tree's build time (both trees are rebuilt every call), which the fit's
residuals show on small cases. Prints ONE JSON object.

    python -m scripts.studies.tree_cost [--out FILE]
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path

import numpy as np


from scripts.benchmarks.bench_treecode import loadavg, numba_threads, best_time, crossover_cases, with_images  # noqa: E402

from aero.lattice import lattice_velocity, stacked_lattices  # noqa: E402
from aero.treecode import FAR_COST, NEAR_COST, TREE_MARGIN, TreeParams, lattice_tree, tree_work  # noqa: E402
from aero.vector_width import vector_bits  # noqa: E402
from hawksim.jsonout import emit  # noqa: E402

THETA = 0.2
"""The treecode's error parameter in the UVLM (``UVLMConfig.tree_theta``'s default; docs/performance.md)."""


def measure(kind: str, size: int, lats, pts, mirror, params: TreeParams) -> dict:
    """One case: times of the direct sum and of the tree [s], the direct sum's pairs and the tree's work."""
    allp = with_images(pts, mirror)
    near = far = pairs = 0.0
    for stride, arrays in stacked_lattices(lats).items():
        n_near, n_far = tree_work(allp, *arrays[:3], stride, *arrays[3:], params=params)
        near, far, pairs = near + n_near, far + n_far, pairs + 2.0 * allp.shape[0] * arrays[0].shape[0]
    return {"kind": kind, "size": size, "load": loadavg(), "targets": int(allp.shape[0]), "direct_pairs": pairs,
            "near_pairs": near, "far_evaluations": far,
            "direct_s": best_time(lambda: lattice_velocity(allp, lats)),
            "tree_s": best_time(lambda: lattice_tree(allp, lats, params))}


def fit(cases: list[dict]) -> tuple[float, float]:
    """(near, far) cost in direct-sum pairs minimising sum over cases of (predicted / measured tree time - 1)^2."""
    a = np.array([[c["near_pairs"], c["far_evaluations"]] for c in cases])
    t_pair = np.array([c["direct_s"] / c["direct_pairs"] for c in cases])
    t_tree = np.array([c["tree_s"] for c in cases])
    sol, *_ = np.linalg.lstsq(a * (t_pair / t_tree)[:, None], np.ones(len(cases)), rcond=None)
    return float(sol[0]), float(sol[1])


def decisions(cases: list[dict], near_cost: float, far_cost: float) -> list[dict]:
    """Per case: whether the plan with these costs takes the tree, and whether the tree was the faster."""
    out = []
    for c in cases:
        planned = (near_cost * c["near_pairs"] + far_cost * c["far_evaluations"]) / c["direct_pairs"]
        out.append({"kind": c["kind"], "size": c["size"], "planned_tree_over_direct": round(planned, 3),
                    "measured_tree_over_direct": round(c["tree_s"] / c["direct_s"], 3),
                    "plan_takes_tree": bool(planned < TREE_MARGIN), "tree_faster": bool(c["tree_s"] < c["direct_s"])})
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, help="also write the JSON here")
    args = ap.parse_args()
    began = time.strftime("%Y-%m-%dT%H:%M:%S+00:00", time.gmtime())
    params = TreeParams(theta=THETA)
    cases = [measure(*case, params) for case in crossover_cases()]
    near_cost, far_cost = fit(cases)
    shipped = decisions(cases, NEAR_COST, FAR_COST)
    fitted = decisions(cases, near_cost, far_cost)
    emit({"command": "python -m scripts.studies.tree_cost " + shlex.join(sys.argv[1:]), "began": began,
          "ended": time.strftime("%Y-%m-%dT%H:%M:%S+00:00", time.gmtime()), "threads": numba_threads(),
          "vector_bits": vector_bits(), "theta": THETA, "tree_margin": TREE_MARGIN,
          "shipped_costs": {"near": NEAR_COST, "far": FAR_COST},
          "fitted_costs": {"near": round(near_cost, 3), "far": round(far_cost, 3)},
          "wrong_decisions": {"shipped": sum(d["plan_takes_tree"] != d["tree_faster"] for d in shipped),
                              "fitted": sum(d["plan_takes_tree"] != d["tree_faster"] for d in fitted)},
          "cases": cases, "decisions_shipped": shipped, "decisions_fitted": fitted}, args.out, host=True)


if __name__ == "__main__":
    main()
