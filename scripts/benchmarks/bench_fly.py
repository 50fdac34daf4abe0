"""Benchmark `hawksim fly --speed 1 --cycles 20 --aero quasi-steady` against real time (issue 2), and the UVLM's
wingbeats per wall second (`--aero uvlm --cycles 6`; issue 19's target: >= 1 at the default resolution).

Prints one JSON object: the simulated flight time, the flight loop's wall time (best of --repeat, in process,
after a warm-up that compiles/loads the numba kernels), the whole command's wall time (subprocess, including
Python start-up and imports), and the real-time factors (simulated time / wall time; >= 1 is real time).

    python scripts/benchmarks/bench_fly.py [--speed 1] [--cycles 20] [--aero quasi-steady] [--repeat 3]
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import time

from hawksim.jsonout import host_info


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--cycles", type=int, default=20)
    ap.add_argument("--aero", default="quasi-steady")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()

    from hawksim.cli.fly import fly_named

    fly_named(a.speed, 1, a.aero)  # warm-up: numba cache, model generation
    loop = []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        r = fly_named(a.speed, a.cycles, a.aero)
        loop.append((r.wall_time_s, time.perf_counter() - t0))
    sim_time = a.cycles * r.kinematics.period  # the flown trim (the model's own)
    cmd = [sys.executable, "-m", "hawksim.cli", "fly", "--speed", str(a.speed), "--cycles", str(a.cycles),
           "--aero", a.aero, "--json", "--no-progress"]
    wall_cmd = []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        wall_cmd.append(time.perf_counter() - t0)
    best_loop = min(x[0] for x in loop)
    best_fly = min(x[1] for x in loop)
    print(json.dumps({
        "host": host_info(),
        "benchmark": "hawksim fly",
        "speed": a.speed, "cycles": a.cycles, "aero": a.aero, "steps": a.cycles * r.steps_per_cycle,
        "simulated_time_s": sim_time,
        "loop_wall_s": best_loop,
        "fly_call_wall_s": best_fly,
        "command_wall_s": min(wall_cmd),
        "realtime_factor_loop": sim_time / best_loop,
        "realtime_factor_fly_call": sim_time / best_fly,
        "realtime_factor_command": sim_time / min(wall_cmd),
        "steps_per_s": a.cycles * r.steps_per_cycle / best_loop,
        "wingbeats_per_s_loop": a.cycles / best_loop,
        "wingbeats_per_s_fly_call": a.cycles / best_fly,
        "target_wingbeats_per_s": 1.0 if a.aero == "uvlm" else None,  # issue 19, item 8
        "start": r.trim_source,
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "processor": platform.machine()},
    }))


if __name__ == "__main__":
    main()
