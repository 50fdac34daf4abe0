"""The JSON summary of a `scripts/benchmarks/time_datasets.sh` log: per resolution and speed the samples, the
wall time and the load average at its start; the totals; the first start and the last end, as one line of JSON.

    python scripts/benchmarks/time_datasets_summary.py OUT/run.log
"""

import json
import sys
from datetime import datetime


def main(path):
    rows, start = [], None
    lines = open(path).read().splitlines()
    for line in lines:
        if " start " in line:
            stamp, _, res, v, n, *_ = line.split()
            load = line.split("load ")[1].split()[:3]
            start = {"resolution": res, "speed": float(v[2:]), "samples": int(n[2:]), "started": stamp,
                     "loadavg_at_start": [float(x) for x in load]}
        elif line.startswith("{") and start is not None:
            d = json.loads(line)
            rows.append({**start, "new": d["new"], "diverged_new": d["diverged_new"],
                         "unsettled_new": d["unsettled_new"], "wall_time_s": d["wall_time_s"]})
            start = None
    end = next(line.split()[0] for line in reversed(lines) if " done " in line)
    t0 = datetime.fromisoformat(rows[0]["started"].replace("Z", "+00:00"))
    t1 = datetime.fromisoformat(end.replace("Z", "+00:00"))
    totals = {}
    for r in rows:
        t = totals.setdefault(r["resolution"], {"samples": 0, "wall_time_s": 0.0})
        t["samples"] += r["new"]
        t["wall_time_s"] += r["wall_time_s"]
    print(json.dumps({"log": path, "rows": rows, "totals": totals, "first_start": rows[0]["started"], "end": end,
                      "elapsed_min": round((t1 - t0).total_seconds() / 60, 2), "target_min": 120.0}))


if __name__ == "__main__":
    main(sys.argv[1])
