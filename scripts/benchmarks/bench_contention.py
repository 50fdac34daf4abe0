"""Benchmark: the UVLM reference case with 1 and 2 numba threads, on an idle machine and with one core busy.

Prints ONE JSON object. The reference case is bench_uvlm.py's (two flapping wings, 8 x 16 panels each by mirror
symmetry, 3 wingbeats at 25 Hz, ``--steps`` steps, free wake), run in a fresh process per measurement (compile or
cache load excluded: each worker first runs 4 steps). A competitor (a Python busy loop, ``os.sched_setaffinity``
pinned to the last CPU this process may use) occupies one core for the ``busy`` runs; the workers are not pinned.
Settings (``--setting NAME:VAR=VALUE,...``, default: ``1 thread`` NUMBA_NUM_THREADS=1 and ``2 threads``
NUMBA_NUM_THREADS=2) and the two load conditions are interleaved, ``--repeats`` rounds, so that the machine's
drift (it is shared) reaches every setting alike; each figure comes with the load average when it started.
Each run also reports a SHA-256 of its force history, so runs of one setting can be checked bit for bit.

    python -m scripts.benchmarks.bench_contention --repeats 3 [--steps 220] [--out FILE]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

DEFAULT_SETTINGS = ("1 thread:NUMBA_NUM_THREADS=1", "2 threads:NUMBA_NUM_THREADS=2")


def _loadavg() -> list[float] | None:
    try:
        return [float(v) for v in open("/proc/loadavg").read().split()[:3]]
    except OSError:
        return None


def worker(steps: int) -> None:
    """Run the reference case in this process; print wall time [s], threading layer, threads and force hash."""
    from scripts.benchmarks.bench_uvlm import run_case  # noqa: I001  (imports aero, which sets numba's environment first)

    import numba

    run_case(steps=4, cycles=4 / 220 * 3)
    t0 = time.perf_counter()
    res = run_case(steps)
    wall = time.perf_counter() - t0
    print(json.dumps({"wall_s": wall, "layer": numba.threading_layer(), "threads": numba.get_num_threads(),
                      "force_sha256": hashlib.sha256(res.force.tobytes()).hexdigest()[:16]}))


def start_competitor() -> tuple[subprocess.Popen, int]:
    """A busy loop pinned to the last CPU this process may run on; returns (process, cpu)."""
    cpu = max(os.sched_getaffinity(0))
    code = f"import os\nos.sched_setaffinity(0, {{{cpu}}})\nwhile True:\n    pass\n"
    return subprocess.Popen([sys.executable, "-c", code]), cpu


def parse_setting(text: str) -> tuple[str, dict]:
    name, _, assignments = text.partition(":")
    env = {}
    for item in filter(None, assignments.split(",")):
        key, _, value = item.partition("=")
        env[key.strip()] = value.strip()
    return name.strip(), env


def measure(steps: int, env: dict) -> dict:
    load = _loadavg()
    proc = subprocess.run([sys.executable, "-m", "scripts.benchmarks.bench_contention", "--worker", "--steps",
                           str(steps)], cwd=REPO, env={**os.environ, **env}, capture_output=True, text=True, check=True)
    return {**json.loads(proc.stdout.strip().splitlines()[-1]), "loadavg": load}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=220)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--setting", action="append", help="NAME:VAR=VALUE,... (repeatable; default 1 and 2 threads)")
    ap.add_argument("--conditions", default="idle,busy", help="comma list of idle, busy (default both)")
    ap.add_argument("--out", help="also write the JSON here")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args.steps)
        return
    settings = [parse_setting(s) for s in (args.setting or DEFAULT_SETTINGS)]
    conditions = [c.strip() for c in args.conditions.split(",") if c.strip()]
    runs: dict[str, dict[str, list]] = {c: {name: [] for name, _ in settings} for c in conditions}
    start = _loadavg()
    cpu = None
    for _ in range(args.repeats):
        for cond in conditions:
            comp = None
            if cond == "busy":
                comp, cpu = start_competitor()
                time.sleep(0.5)
            try:
                for name, env in settings:
                    runs[cond][name].append(measure(args.steps, env))
            finally:
                if comp is not None:
                    comp.kill()
                    comp.wait()
    summary = {}
    for cond in conditions:
        summary[cond] = {}
        for name, _ in settings:
            walls = [r["wall_s"] for r in runs[cond][name]]
            summary[cond][name] = {"wall_s": [round(w, 2) for w in walls],
                                   "median_s": round(statistics.median(walls), 2),
                                   "loadavg_1min": [r["loadavg"][0] if r["loadavg"] else None
                                                    for r in runs[cond][name]],
                                   "layer": runs[cond][name][0]["layer"],
                                   "threads": runs[cond][name][0]["threads"],
                                   "bit_identical_runs": len({r["force_sha256"] for r in runs[cond][name]}) == 1,
                                   "force_sha256": runs[cond][name][0]["force_sha256"]}
        base = summary[cond][settings[0][0]]["median_s"]
        for name, _ in settings[1:]:
            summary[cond][name][f"ratio_to_{settings[0][0].replace(' ', '_')}"] = round(
                summary[cond][name]["median_s"] / base, 3)
    out = {"command": " ".join(["python", "-m", "scripts.benchmarks.bench_contention", *sys.argv[1:]]),
           "case": f"bench_uvlm reference case, {args.steps} steps", "repeats": args.repeats,
           "settings": {name: env for name, env in settings}, "competitor_cpu": cpu,
           "affinity": sorted(os.sched_getaffinity(0)), "results": summary, "loadavg_start": start}
    from hawksim.jsonout import emit

    emit(out, args.out, host=True)


if __name__ == "__main__":
    main()
