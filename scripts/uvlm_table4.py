"""Table 3's kinematics evaluated by our UVLM at the five ascent speeds, next to the paper's Table 4.
Prints one JSON object and writes it to --out (also part of `hawksim reproduce`).

    python scripts/uvlm_table4.py --out results/uvlm_table4.json
"""

import argparse

from hawksim.jsonout import emit
from hawksim.paper.reproduce import table4_comparison


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out")
    ap.add_argument("--cycles", type=int, default=4)
    a = ap.parse_args()
    out = table4_comparison(a.cycles)
    emit(out, a.out)


if __name__ == "__main__":
    main()
