"""Does a regenerated data set reproduce a shipped one? Labels of the same (speed, seed, idx) compared.

For every speed: the samples both files hold, how many rows agree bit for bit (kinematics, the four labels and the
status), how many differ in status, and per label (L+, D+, M+, P+) the median and largest |new - old|, with the
sample of the largest. Round-off level medians with a few large differences are the free wake's amplification of
summation-order changes between code versions (largest at hover: docs/uvlm.md, "Hover is not periodic"); a
difference in kinematics means the two files did not draw the same samples. Prints ONE JSON object.

    python scripts/studies/dataset_reproduction.py NEW.sqlite OLD.sqlite [--out FILE]
"""

from __future__ import annotations

import argparse
import shlex
import sqlite3
import sys
from pathlib import Path

import numpy as np

from hawksim.backends.averages import OUTPUTS
from hawksim.jsonout import emit

KINEMATICS = ("f", "beta", "phi0", "theta0", "alpha0", "phi_a", "alpha_a")


def rows(path: str) -> dict:
    cols = ", ".join(("speed", "seed", "idx", *KINEMATICS, *OUTPUTS, "status"))
    with sqlite3.connect(f"file:{path}?mode=ro", uri=True) as db:
        return {r[:3]: r[3:] for r in db.execute(f"SELECT {cols} FROM samples")}


def compare(new: dict, old: dict) -> dict:
    nk = len(KINEMATICS)
    out = {}
    for v in sorted({k[0] for k in new} | {k[0] for k in old}):
        keys = sorted(k for k in set(new) & set(old) if k[0] == v)
        entry = {"new": sum(k[0] == v for k in new), "old": sum(k[0] == v for k in old), "common": len(keys),
                 "identical_rows": sum(new[k] == old[k] for k in keys),
                 "kinematics_differ": sum(new[k][:nk] != old[k][:nk] for k in keys),
                 "status_differ": sum(new[k][-1] != old[k][-1] for k in keys), "labels": {}}
        both = [k for k in keys if None not in new[k][nk:nk + 4] and None not in old[k][nk:nk + 4]]
        if both:
            d = np.abs(np.array([new[k][nk:nk + 4] for k in both]) - np.array([old[k][nk:nk + 4] for k in both]))
            for j, name in enumerate(OUTPUTS):
                worst = int(np.argmax(d[:, j]))
                entry["labels"][name] = {"median_abs": float(np.median(d[:, j])), "max_abs": float(d[worst, j]),
                                         "max_at": {"seed": both[worst][1], "idx": both[worst][2]}}
        out[f"{v:g}"] = entry
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("new")
    ap.add_argument("old")
    ap.add_argument("--out")
    a = ap.parse_args()
    for p in (a.new, a.old):
        if not Path(p).is_file():
            sys.exit(f"error: {p}: no such data set")
    emit({"command": shlex.join(["python", "scripts/studies/dataset_reproduction.py", *sys.argv[1:]]),
          "new": a.new, "old": a.old, "per_speed": compare(rows(a.new), rows(a.old))}, a.out, host=True)


if __name__ == "__main__":
    main()
