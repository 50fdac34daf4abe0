"""Benchmark `hawksim fly --speed 1 --cycles 20 --aero quasi-steady` against real time (issue 2), and the UVLM's
wingbeats per wall second (`--aero uvlm --cycles 6`; issue 19's target: >= 1 at the default resolution).

Prints one JSON object: the simulated flight time, the flight loop's wall time (best of --repeat, in process,
after a warm-up that compiles/loads the numba kernels), the whole command's wall time (subprocess, including
Python start-up and imports), and the real-time factors (simulated time / wall time; >= 1 is real time).

    python scripts/benchmarks/bench_fly.py [--speed 1] [--cycles 20] [--aero quasi-steady] [--repeat 3]

``time_split_s`` says where the flight loop's time goes (one more flight under cProfile, whose overhead inflates the
Python parts: read it as proportions): MuJoCo's steps with the native computed-torque callback, a Python callback
(0 unless the native one is unavailable), the backend's loads, the rest of ``Simulator.advance`` (state read-out,
the held loads) and what ``fly`` does outside it (issue 21's target for `--aero surrogate`: >= 10x real time over
20 wingbeats). ``loop_wall_python_callback_s``: the same flights with the Python callback and one Python step per
step (the loop before the native callback), interleaved with the native ones; ``floors_s`` / ``realtime_ceilings``:
MuJoCo's RK4 steps alone, with and without the native computed torque, no aerodynamics, no Python per step.
"""

import argparse
import contextlib
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
    ap.add_argument("--steps-per-cycle", type=int, default=None,
                    help="RK4 steps per wingbeat (default the flight's 200, from the shipped orbit; another count "
                         "starts from the held-body trim with a calibration beat, as `hawksim fly` does)")
    a = ap.parse_args()
    spc = {} if a.steps_per_cycle is None else {"steps_per_cycle": a.steps_per_cycle}

    from hawksim.cli.fly import fly_named

    fly_named(a.speed, 1, a.aero, **spc)  # warm-up: numba cache, model generation
    with python_callback():
        fly_named(a.speed, 1, a.aero, **spc)
    loop, loop_py = [], []
    for _ in range(a.repeat):  # interleaved: the native callback (default) and the Python one, same sitting
        t0 = time.perf_counter()
        r = fly_named(a.speed, a.cycles, a.aero, **spc)
        loop.append((r.wall_time_s, time.perf_counter() - t0))
        with python_callback():
            loop_py.append(fly_named(a.speed, a.cycles, a.aero, **spc).wall_time_s)
    sim_time = a.cycles * r.kinematics.period  # the flown trim (the model's own)
    cmd = [sys.executable, "-m", "hawksim.cli", "fly", "--speed", str(a.speed), "--cycles", str(a.cycles),
           "--aero", a.aero, "--json", "--no-progress"] + (
        [] if a.steps_per_cycle is None else ["--steps-per-cycle", str(a.steps_per_cycle)])
    wall_cmd = []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        wall_cmd.append(time.perf_counter() - t0)
    split = _time_split(a, spc)
    floors = _floors(r.kinematics, r.steps_per_cycle, a.cycles, a.repeat)
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
        "loop_wall_python_callback_s": min(loop_py),
        "native_callback_speedup": min(loop_py) / best_loop,
        "floors_s": floors,
        "realtime_ceilings": {k: sim_time / v for k, v in floors.items()},
        "steps_per_s": a.cycles * r.steps_per_cycle / best_loop,
        "wingbeats_per_s_loop": a.cycles / best_loop,
        "wingbeats_per_s_fly_call": a.cycles / best_fly,
        "target_wingbeats_per_s": 1.0 if a.aero == "uvlm" else None,  # issue 19, item 8
        "target_realtime_factor": 10.0 if a.aero == "surrogate" else None,  # issue 21, item 5
        "time_split_s": split,
        "start": r.trim_source,
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "processor": platform.machine()},
    }))


@contextlib.contextmanager
def python_callback():
    """Within the block every Simulator solves the computed torque in the Python callback (the baseline)."""
    from hawksim.flight.simulator import Simulator

    init = Simulator.__init__

    def python_init(self, *args, **kw):
        init(self, *args, **dict(kw, native=False))

    Simulator.__init__ = python_init
    try:
        yield
    finally:
        Simulator.__init__ = init


def _floors(kin, steps_per_cycle: int, cycles: int, repeat: int) -> dict:
    """What the flight's steps cost without any Python per step and without aerodynamics, same model and time
    step: MuJoCo's RK4 alone (``mj_step(m, d, nstep)``, no callback: the wings flail) and with the native
    computed-torque callback (the wings on Eq. 1): the real-time factors no flight loop of this model at this
    resolution can pass on this machine (issue 21's 10x: ceilings below it make it unreachable here). The flight
    switches MuJoCo's stage timers off (:attr:`hawksim.flight.mujoco_abi.Trampoline.no_timer`), and so do these
    floors; ``rk4_alone_mujoco_default_timer`` keeps the mujoco package's default clock."""
    import mujoco

    from hawksim.backends.base import NoAero
    from hawksim.flight.simulator import Simulator, control_callback
    from hawksim.insect.model import load_model

    sim = Simulator(load_model(), kin, NoAero(), steps_per_cycle=steps_per_cycle)
    m, d, steps = sim.m, sim.d, cycles * steps_per_cycle
    out = {}
    native = sim.native_control.callback if sim.native_control else None
    no_timer = sim.native_control.no_timer if sim.native_control else None
    for name, cb, timer in (("rk4_alone_mujoco_default_timer", None, None), ("rk4_alone", None, no_timer),
                            ("rk4_native_computed_torque", native, no_timer)):
        if name != "rk4_alone_mujoco_default_timer" and (native is None):
            continue
        best = float("inf")
        for _ in range(repeat):
            sim.reset()
            if cb is not None:
                sim.native_control.install()
            with control_callback(cb, timer):
                t0 = time.perf_counter()
                mujoco.mj_step(m, d, nstep=steps)
                best = min(best, time.perf_counter() - t0)
        out[name] = best
    return out


def _time_split(a, spc: dict) -> dict:
    import cProfile
    import pstats

    from hawksim.cli.fly import fly_named

    prof = cProfile.Profile()
    prof.enable()
    fly_named(a.speed, a.cycles, a.aero, **spc)
    prof.disable()
    st = pstats.Stats(prof).stats  # {(file, line, name): (cc, nc, tottime, cumtime, callers)}

    def cum(name, file_part=""):
        return sum(v[3] for k, v in st.items() if k[2] == name and file_part in k[0])

    advance, mj_step = cum("advance", "simulator.py"), cum("<built-in method mujoco._functions.mj_step>")
    control = cum("_control", "simulator.py")  # the Python callback (0 with the native one)
    loads = sum(v[3] for k, v in st.items() if k[2] == "loads" and "backends" in k[0])
    fly_total = cum("fly", "flight/fly.py")
    return {"fly_total": fly_total, "mujoco_step_with_native_callback": mj_step - control,
            "python_computed_torque_callback": control, "backend_loads": loads,
            "simulator_advance_rest": advance - mj_step - loads, "fly_outside_advance": fly_total - advance}


if __name__ == "__main__":
    main()
