"""Stability at the five ascent speeds and the paper's studies (Figs. 15-19) into results/stability/
(also part of `hawksim reproduce`).

    python scripts/stability_studies.py --out results/stability
"""

import argparse
import json
from pathlib import Path

from hawksim.reproduce import stability_all


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="results/stability")
    a = ap.parse_args()
    print(json.dumps(stability_all(Path(a.out))))


if __name__ == "__main__":
    main()
