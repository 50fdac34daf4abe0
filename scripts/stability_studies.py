"""Stability at the five ascent speeds and the paper's studies (Figs. 15-19) into results/stability/
(also part of `hawksim reproduce`).

    python scripts/stability_studies.py --out results/stability
    python scripts/stability_studies.py --table3 --out results/stability_table3   (at the paper's Table 3 kinematics)
"""

import argparse
import json
from pathlib import Path

from hawksim.paper.reproduce import stability_all


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="results/stability")
    ap.add_argument("--table3", action="store_true", help="at the paper's Table 3 kinematics, not the default trims")
    a = ap.parse_args()
    print(json.dumps(stability_all(Path(a.out), table3=a.table3)))


if __name__ == "__main__":
    main()
