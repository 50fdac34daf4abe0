"""Benchmark of aero.scheduling's two tuned constants, in one process, settings interleaved; prints ONE JSON object.

* handoff_us: the cost of splitting one kernel call over 2 threads (the pool hand-off), measured as the time of
  a call too small to matter (8 targets x one 2 x 2 lattice) with 2 threads minus with 1, per call [us], calls
  back to back; handoff_after_gap_us: the same with ``GAP_S`` of numpy work between the calls (not timed), as
  between a UVLM step's kernel calls, where the pool's idle thread has gone to sleep (median over the calls);
* reference case (bench_uvlm.py's: 8 x 16 panels, ``--steps`` steps, free wake) and ``hawksim aero``'s solve
  (Table 3 hover, default resolution) under each setting of CHUNKS_PER_THREAD and MIN_PARALLEL_WORK given,
  ``--repeats`` rounds, with the load average at each run. All with numba's thread count (NUMBA_NUM_THREADS).

    python -m scripts.benchmarks.bench_scheduling [--chunks 4,16] [--min-work 0,100000] [--repeats 2]
        [--handoff-only]
"""

from __future__ import annotations

import argparse
import hashlib
import statistics
import sys
import time

import numpy as np

from scripts.benchmarks.bench_uvlm import run_case  # noqa: I001  (imports aero first)

from aero import scheduling  # noqa: E402
from aero.lattice import lattice_velocity, ring_lattice  # noqa: E402
from hawksim.backends.held import run  # noqa: E402
from hawksim.backends.resolution import DEFAULT  # noqa: E402
from hawksim.insect.kinematics import table3_kinematics  # noqa: E402
from hawksim.jsonout import emit  # noqa: E402


def _loadavg():
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except OSError:
        return None


GAP_S = 2e-4
"""Numpy work between two timed calls in handoff_us(gap=True) [s]: the order of the Python work between a UVLM
step's kernel calls at the default lattice (~0.1-0.5 ms)."""


def _gap(seconds: float) -> None:
    t_end = time.perf_counter() + seconds
    x = np.ones(4096)
    while time.perf_counter() < t_end:
        x = x * 1.0000001


def handoff_us(calls: int = 2000, gap: bool = False) -> float:
    rng = np.random.default_rng(0)
    lat = ring_lattice(rng.normal(size=(3, 3, 3)), rng.normal(size=(2, 2)), 1e-6, 1e-6)
    p = rng.normal(size=(8, 3))
    old = scheduling.MIN_PARALLEL_WORK
    scheduling.MIN_PARALLEL_WORK = 0
    best = {}
    try:
        for _ in range(3):
            for threads in (1, 2):
                numba_threads = scheduling.thread_count
                scheduling.thread_count = lambda t=threads: t
                try:
                    lattice_velocity(p, [lat])
                    if gap:
                        times = []
                        for _ in range(calls // 4):
                            _gap(GAP_S)
                            t0 = time.perf_counter()
                            lattice_velocity(p, [lat])
                            times.append(time.perf_counter() - t0)
                        per_call = statistics.median(times)
                    else:
                        t0 = time.perf_counter()
                        for _ in range(calls):
                            lattice_velocity(p, [lat])
                        per_call = (time.perf_counter() - t0) / calls
                    best[threads] = min(best.get(threads, np.inf), per_call)
                finally:
                    scheduling.thread_count = numba_threads
    finally:
        scheduling.MIN_PARALLEL_WORK = old
    return (best[2] - best[1]) * 1e6


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--chunks", default="4,16", help="CHUNKS_PER_THREAD values (comma list)")
    ap.add_argument("--min-work", default="0,100000", help="MIN_PARALLEL_WORK values (comma list)")
    ap.add_argument("--steps", type=int, default=220)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--handoff-only", action="store_true", help="only the two hand-off figures")
    ap.add_argument("--out")
    args = ap.parse_args()
    settings = [(int(c), int(w)) for c in args.chunks.split(",") for w in args.min_work.split(",")]
    out = {"command": " ".join(["python", *sys.argv]), "threads": scheduling.thread_count(), "loadavg_1min_before":
           _loadavg(), "handoff_us": round(handoff_us(), 1), "handoff_after_gap_us": round(handoff_us(gap=True), 1),
           "gap_s": GAP_S, "settings": {}}
    if args.handoff_only:
        out["loadavg_1min_after"] = _loadavg()
        emit(out, args.out, host=True)
        return
    run_case(steps=4, cycles=4 / 220 * 3)
    run(table3_kinematics(0.0), 0.0, DEFAULT)
    rows = {s: {"reference_s": [], "aero_s": [], "loadavg": [], "hash": set()} for s in settings}
    for _ in range(args.repeats):
        for s in settings:
            scheduling.CHUNKS_PER_THREAD, scheduling.MIN_PARALLEL_WORK = s
            rows[s]["loadavg"].append(_loadavg())
            t0 = time.perf_counter()
            res = run_case(args.steps)
            rows[s]["reference_s"].append(round(time.perf_counter() - t0, 2))
            rows[s]["hash"].add(hashlib.sha256(res.force.tobytes()).hexdigest()[:16])
            rows[s]["aero_s"].append(round(run(table3_kinematics(0.0), 0.0, DEFAULT).wall_time_s, 3))
    for (c, w), r in rows.items():
        out["settings"][f"chunks={c},min_work={w}"] = {
            "reference_s": r["reference_s"], "reference_median_s": statistics.median(r["reference_s"]),
            "aero_s": r["aero_s"], "aero_median_s": statistics.median(r["aero_s"]), "loadavg_1min": r["loadavg"],
            "force_sha256": sorted(r["hash"])}
    emit(out, args.out, host=True)


if __name__ == "__main__":
    main()
