"""Choose the size of the reference surrogate's correction network on the reference data set's own test split.

For each ``--hidden`` H, `hawksim train --all-speeds --base shipped --hidden H` on ``--data`` (the same command as
the shipped reference network but for --out), and its held-out scores (the 10 % test split of the reference data
set, never seen in training or early stopping); the H with the lowest RMSE of L+ plus P+ is the one to ship. The
held-out kinematics of scripts/studies/surrogate_vs_reference.py (seed 22) play no part in the choice.

    OMP_NUM_THREADS=1 python scripts/studies/reference_correction_size.py --data data/uvlm_reference_0.1.sqlite \\
        --hidden 10 20 40 80 --out results/surrogate/reference_correction_size.json
"""

from __future__ import annotations

import argparse
import datetime
import json
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

from hawksim.jsonout import emit


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default="data/uvlm_reference_0.1.sqlite")
    ap.add_argument("--hidden", type=int, nargs="+", default=[10, 20, 40, 80])
    ap.add_argument("--out")
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for h in a.hidden:
            cmd = [sys.executable, "-m", "hawksim.cli", "train", "--data", a.data, "--out",
                   str(Path(tmp) / f"h{h}.safetensors"), "--seed", "0", "--hidden", str(h), "--max-iter", "300",
                   "--time-limit", "900", "--all-speeds", "--base", "shipped", "--no-progress", "--json"]
            done = subprocess.run(cmd, check=True, capture_output=True, text=True)
            r = json.loads(done.stdout.strip().splitlines()[-1])
            rows.append({"correction_hidden": h, "rmse": r["rmse"], "r2": r["r2"], "iterations": r["iterations"],
                         "stopped_by": r["stopped_by"], "n_test": r["n_test"], "wall_time_s": r["wall_time_s"]})
            print(f"H={h}: test RMSE L+ {r['rmse']['L_plus']:.4f} P+ {r['rmse']['P_plus']:.4f}", file=sys.stderr)
    best = min(rows, key=lambda r: r["rmse"]["L_plus"] + r["rmse"]["P_plus"])
    load = Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else None
    emit({"command": shlex.join(["python", "scripts/studies/reference_correction_size.py", *sys.argv[1:]]),
          "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"), "loadavg": load,
          "data": a.data, "candidates": rows, "chosen_hidden": best["correction_hidden"]}, a.out)


if __name__ == "__main__":
    main()
