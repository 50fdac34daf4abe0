"""How much the cycle-mean labels moved between two data sets of the same kinematics (issue 49: the reference labels
of hawksim 0.2's UVLM and hawkmoth against those of issue 48's UVLM and the sourced hawkmoth).

Pairs the samples of two `hawksim dataset` files by (speed, seed, idx) (the same seed gives the same kinematics),
keeps the pairs whose status is 'ok' in both and whose kinematics agree to 1e-9, and reports per speed the count and
the mean, standard deviation and mean |.| of the change of L+, D+, M+ and P+ (new - old). Prints ONE JSON object.

    python -m scripts.studies.label_shift --old data/uvlm_reference_0.1.sqlite \
        --new data/uvlm_reference_0.3.0.sqlite --out results/label_shift_reference.json
"""

from __future__ import annotations

import argparse
import sqlite3
import sys

import numpy as np

from hawksim.insect.kinematics import PARAM_NAMES
from hawksim.jsonout import emit

OUTPUTS = ("L_plus", "D_plus", "M_plus", "P_plus")
KIN_ATOL = 1e-9
"""The paired samples' kinematics must agree to this (SI): the same draw."""


def rows(path: str) -> dict:
    """{(speed, seed, idx): (kinematics (7,), outputs (4,))} of the 'ok' samples of a data set (read only)."""
    conn = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    cols = ", ".join((*PARAM_NAMES, *OUTPUTS))
    out = {(s, e, i): (np.array(r[:7], float), np.array(r[7:], float))
           for s, e, i, *r in conn.execute(f"SELECT speed, seed, idx, {cols} FROM samples WHERE status = 'ok'")}
    conn.close()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", required=True)
    ap.add_argument("--out")
    a = ap.parse_args()
    old, new = rows(a.old), rows(a.new)
    keys = sorted(k for k in old.keys() & new.keys() if np.allclose(old[k][0], new[k][0], rtol=0, atol=KIN_ATOL))
    by_speed = {}
    for v in sorted({k[0] for k in keys}):
        d = np.array([new[k][1] - old[k][1] for k in keys if k[0] == v])
        base = np.array([old[k][1] for k in keys if k[0] == v])
        by_speed[f"{v:g}"] = {"pairs": len(d), **{o: {"mean_change": float(d[:, j].mean()),
                                                     "std_change": float(d[:, j].std()),
                                                     "mean_abs_change": float(np.abs(d[:, j]).mean()),
                                                     "old_mean": float(base[:, j].mean())}
                                                 for j, o in enumerate(OUTPUTS)}}
    emit({"command": "python -m scripts.studies.label_shift " + " ".join(sys.argv[1:]), "old": a.old,
          "new": a.new, "by_speed": by_speed}, a.out)


if __name__ == "__main__":
    main()
