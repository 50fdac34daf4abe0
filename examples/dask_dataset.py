"""A Dask data set on a local cluster: three held-body UVLM samples at a 1 m/s ascent, at the surrogate's training
resolution (4 x 8 vortex rings per wing, 30 steps per wingbeat, 3 wingbeats), computed by a Dask LocalCluster of
2 single-threaded worker processes, then read back with the standard library's sqlite3.

Shows: ``hawksim dataset`` (run here as ``python -m hawksim``; ``--scheduler ADDRESS`` sends the same work to a
running Dask scheduler, e.g. dask-jobqueue on a cluster) and its resumable SQLite file (dataset.sqlite): a rerun
computes only the missing samples. Each row holds the seven kinematic parameters (SI: f [Hz], angles [rad]) drawn
within Table 2's bounds and the UVLM's cycle averages L+, D+, M+, P+ (of the weight W, W cbar and P0), and a
status: a run whose loads blew up at this coarse resolution (about 2 % of the training samples,
docs/surrogate.md) is stored as 'diverged', one whose cycle averages are not yet periodic as 'unsettled'; both
are left out of training. Here sample 0 is a diverged one.
"""

import json
import sqlite3
import subprocess
import sys

import numpy as np

cmd = [sys.executable, "-m", "hawksim", "dataset", "--speed", "1", "--samples", "3", "--workers", "2",
       "--resolution", "training", "--out", "dataset.sqlite", "--no-progress", "--json"]
run = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
print(f"{run['new']} new samples ({run['samples']} in the file) in {run['wall_time_s']:.1f} s on 2 workers")

with sqlite3.connect("dataset.sqlite") as db:
    rows = db.execute("SELECT idx, f, phi_a, L_plus, P_plus, status FROM samples ORDER BY idx").fetchall()
for idx, f, phi_a, L, P, status in rows:
    print(f"  sample {idx}: f {f:.2f} Hz, phi_a {np.rad2deg(phi_a):.1f} deg -> L+ {L:.3f}, P+ {P:.3f} ({status})")

again = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
print(f"rerun: {again['new']} new samples (the file is resumable)")
