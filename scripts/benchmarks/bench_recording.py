"""Benchmark: what a Rerun recording adds to a flight (issue 52: the UVLM's ``--rrd`` should add at most ~20 %).

Prints ONE JSON object. For each beat count in --cycles, ``--runs`` pairs of whole commands run alternately in the
same sitting, ``hawksim fly --aero AERO --speed 1 --cycles N --control none --json`` without and with ``--rrd`` (to
a temporary file), each timed as a whole process (start-up and imports included) and by its own ``wall_time_s``;
the ratio with / without of the medians, the load average before and after, the date. The baseline is the same
command without the recording, in the same sitting (docs/performance.md's rule: ratios, not absolute times).

    python scripts/benchmarks/bench_recording.py --cycles 2 10 --runs 3 [--aero uvlm]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone


def _run(argv: list[str]) -> tuple[float, float]:
    """(process wall time [s], the command's own wall_time_s [s])."""
    t0 = time.perf_counter()
    proc = subprocess.run(argv, capture_output=True, text=True, check=True)
    return time.perf_counter() - t0, float(json.loads(proc.stdout)["wall_time_s"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, nargs="+", default=[2, 10])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--aero", default="uvlm")
    a = ap.parse_args()
    load0 = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.cycles:
            base = [sys.executable, "-m", "hawksim", "fly", "--aero", a.aero, "--speed", "1", "--cycles", str(n),
                    "--control", "none", "--json"]
            plain, rec = [], []
            for i in range(a.runs):
                plain.append(_run(base))
                rec.append(_run(base + ["--rrd", os.path.join(tmp, f"r{n}_{i}.rrd")]))
            p_proc = statistics.median(t for t, _ in plain)
            r_proc = statistics.median(t for t, _ in rec)
            rows.append({"cycles": n, "process_s": {"without": p_proc, "with_rrd": r_proc},
                         "wall_time_s": {"without": statistics.median(w for _, w in plain),
                                         "with_rrd": statistics.median(w for _, w in rec)},
                         "ratio_process": r_proc / p_proc,
                         "ratio_wall_time_s": statistics.median(w for _, w in rec)
                         / statistics.median(w for _, w in plain),
                         "runs": a.runs})
            print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    print(json.dumps({"benchmark": "recording overhead", "aero": a.aero, "command": "python " + " ".join(sys.argv),
                      "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
                      "loadavg_before": load0, "loadavg_after": os.getloadavg(), "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
