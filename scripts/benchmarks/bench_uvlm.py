"""Benchmark of the extended UVLM (aero.uvlm); prints ONE JSON object.

* kernel_geval_s: Biot-Savart segment-point evaluations per second (float64, all cores) of the per-segment
  kernel (aero.biot_savart.induced_velocity), 20k random segments x 4k points.
* lattice_kernel_geval_s: the same for the lattice kernel the UVLM uses (aero.lattice_lanes.lattice_induced_velocity:
  corners shared by the edges, targets in the vector lanes), on a wake-like lattice of 600 x 16 rings (19 816 edges) x
  4k points; evaluations counted per real edge.
* reference case: two flapping wings (8 x 16 panels each, mirror images), 3 wingbeats at 25 Hz, 220 steps,
  free wake, no truncation, core growth and leading-edge suction on; wall time excluding compilation.
* reference_case_pairs, reference_case_kernel_calls: the edge-target pairs the reference case evaluates in the
  lattice kernel and the kernel's calls (:func:`reference_pairs`, one extra run); reference_case_kernel_share:
  pairs / lattice_kernel_geval_s / the case's wall time, the share of the run the kernel would take at the
  benchmark's rate (an estimate: the case's calls are smaller than the benchmark's; by cProfile on 2026-12-04
  the kernel ran at 0.92 x the benchmark's rate there and took 2.73 s of the profiled 3.23 s run at 512 bits).
* compile_s: first-call time of a tiny run (numba compilation or cache load).
* sqrt_g_s, div_g_s: this machine's float64 square-root and division throughput (G/s, all cores, vectorised
  numba loops), and kernel_bound_geval_s = 1 / (2 / sqrt_g_s + 1 / div_g_s): the per-segment kernel's
  ceiling, since each of its evaluations needs two square roots and one division (measured, so the kernel's rate
  can be compared with what the machine allows on the day: the rates here vary by up to 2x between days). The
  lattice kernel needs one division per evaluation and no square root: its ceiling is div_g_s.
* ptera_wall_s / speedup: when --ptera-json FILE (output of scripts/benchmarks/bench_pterasoftware.py) is given.
* aero_command_s, aero_wall_time_s: `hawksim aero` at the default resolution (Table 3's hover kinematics, a
  fresh process): the whole command's wall time and the solve time it reports (``wall_time_s``, which includes
  numba's one-time start in that process, ~0.35 s here); aero_warm_s: the same solve in this process, numba
  already started (best of 2).
* targets: the speed targets of the UVLM issue, for reading the numbers above against.
* vector_bits: the vector width numba compiled for (256 by default; HAWKSIM_VECTOR_WIDTH=512 in the environment
  asks for 512-bit vectors on AVX-512 hosts: aero.vector_width).
"""

import argparse
import json
import os
import subprocess
import sys
import time

import aero  # noqa: F401, I001  (before numba: importing aero applies HAWKSIM_VECTOR_WIDTH, which numba reads once)
import numpy as np
from numba import njit, prange

from aero.biot_savart import induced_velocity, pack
from aero.lattice import lattice_velocity, ring_lattice
from aero.mesh import wing_mesh
from aero.uvlm import UVLMConfig, run_prescribed
from aero.uvlm_kinematics import two_wing_motion
from aero.vector_width import vector_bits
from hawksim.backends.held import run
from hawksim.backends.resolution import DEFAULT
from hawksim.insect.kinematics import TABLE3_DEG, table3_kinematics
from hawksim.jsonout import host_info

TARGETS = {"lattice_kernel_geval_s": 1.5, "reference_case_s": 6.0, "aero_wall_time_s": 1.0,
           "speedup_vs_ptera": 25.0}
"""Issue 3's speed targets (G evaluations/s, s, s, ratio)."""


def reference_wing(nc=8, ns=16):
    y = np.linspace(0, 0.05, ns + 1)
    c = 0.02 * np.sqrt(np.clip(1 - (y / 0.05) ** 2, 0, 1)) + 0.004
    return wing_mesh(y, 0.25 * c, -0.75 * c, nc)


def run_case(steps, cycles=3.0, freq=25.0):
    t = np.linspace(0.0, cycles / freq, steps)
    R, o, v, w = two_wing_motion(t, freq=freq)
    plane = (np.zeros(3), np.array([0.0, 1.0, 0.0]))
    return run_prescribed([reference_wing()], UVLMConfig(), t, R[:, :1], o[:, :1], v[:, :1],
                          w[:, :1], mirror_plane=plane)


def reference_pairs(steps: int = 220) -> dict:
    """Edge-target pairs the reference case evaluates in the lattice kernel (every call of
    ``aero.uvlm.lattice_velocity`` in one run: the wake at the collocation points, the loads' edge midpoints and
    the wake's own corners, mirror images included): targets x lattice edges summed over the calls, counted by
    wrapping that function for one extra run (the sizes alone set it, so the count is exact and the same every
    run). Divided by the lattice kernel's measured rate it is the time the kernel alone needs; the rest of a run
    is the influence matrix, the solve and the step's numpy work."""
    import aero.uvlm as uvlm_module

    plain = uvlm_module.lattice_velocity
    count = {"calls": 0, "pairs": 0}

    def counted(targets, lattices, precision="float64"):
        count["calls"] += 1
        count["pairs"] += np.asarray(targets).reshape(-1, 3).shape[0] * sum(
            lat.span_gamma.size + lat.chord_gamma.size for lat in lattices)
        return plain(targets, lattices, precision)

    uvlm_module.lattice_velocity = counted
    try:
        run_case(steps)
    finally:
        uvlm_module.lattice_velocity = plain
    return count


def kernel_rate(ns=20000, nt=4000, reps=5):
    rng = np.random.default_rng(0)
    a = rng.normal(size=(ns, 3))
    seg = pack(a, a + 0.1 * rng.normal(size=(ns, 3)), rng.normal(size=ns), 1e-4)
    p = rng.normal(size=(nt, 3))
    out = np.empty((nt, 3))
    induced_velocity(p[:8], *seg, out[:8])
    best = np.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        induced_velocity(p, *seg, out)
        best = min(best, time.perf_counter() - t0)
    return ns * nt / best / 1e9


def kernel_lattice(rows=600, ns=16, nt=4000):
    """The lattice-kernel benchmark's case (seed 0): a wake-like lattice of rows x ns rings (a stretched, jittered
    sheet, 1 mm x 3 mm rings) and nt targets around it: (Lattice, targets (nt, 3))."""
    rng = np.random.default_rng(0)
    G = np.zeros((rows + 1, ns + 1, 3))
    G[..., 0] = -1e-3 * np.arange(rows + 1)[:, None]
    G[..., 1] = 3e-3 * np.arange(ns + 1)[None, :]
    G += 2e-4 * rng.normal(size=G.shape)
    lat = ring_lattice(G, 1e-3 * rng.normal(size=(rows, ns)), 1e-8, 1e-8)
    p = np.stack([-0.6 * rng.random(nt), 0.05 * rng.random(nt), 0.01 * rng.normal(size=nt)], axis=1)
    return lat, p


def lattice_kernel_rate(rows=600, ns=16, nt=4000, reps=5):
    lat, p = kernel_lattice(rows, ns, nt)
    lattice_velocity(p[:8], [lat])
    best = np.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        lattice_velocity(p, [lat])
        best = min(best, time.perf_counter() - t0)
    return (lat.span_gamma.size + lat.chord_gamma.size) * nt / best / 1e9


def _unit_kernel(op: str):
    """A vectorised loop over both cores doing one float64 `op` ("sqrt" or "div") per element."""
    use_sqrt = op == "sqrt"

    @njit(parallel=True, fastmath=True, error_model="numpy")
    def kernel(x, reps):
        out = np.zeros(reps)
        for r in prange(reps):
            s = 0.0
            for k in range(x.shape[0]):
                s += np.sqrt(x[k] + r) if use_sqrt else 1.0 / (x[k] + r)
            out[r] = s
        return out.sum()

    return kernel


def unit_rate(fn, n=2048, reps=20000, tries=5):
    """Throughput of fn's operation [G/s] over all cores (best of tries)."""
    x = np.random.default_rng(0).random(n) + 1.0
    fn(x, 2)
    best = np.inf
    for _ in range(tries):
        t0 = time.perf_counter()
        fn(x, reps)
        best = min(best, time.perf_counter() - t0)
    return n * reps / best / 1e9


def aero_timings() -> dict:
    """`hawksim aero` at the default resolution with Table 3's hover kinematics: a fresh command, then the same
    solve in this process (warm)."""
    kin = ",".join(f"{k}={v[0]}" for k, v in TABLE3_DEG.items())
    argv = ["aero", "--speed", "0", "--kinematics", kin, "--json", "--no-progress"]
    code = "import sys; from hawksim.cli import main; sys.exit(main(sys.argv[1:]))"
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, check=True)
    command = time.perf_counter() - t0
    warm = min(run(table3_kinematics(0.0), 0.0, DEFAULT).wall_time_s for _ in range(2))
    return {"aero_command_s": round(command, 2), "aero_wall_time_s": round(json.loads(proc.stdout)["wall_time_s"], 3),
            "aero_warm_s": round(warm, 3)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ptera-json", help="JSON file written by scripts/benchmarks/bench_pterasoftware.py")
    ap.add_argument("--steps", type=int, default=220)
    args = ap.parse_args()
    t0 = time.perf_counter()
    run_case(steps=4, cycles=4 / 220 * 3)
    compile_s = time.perf_counter() - t0
    rate = kernel_rate()
    lattice_rate = lattice_kernel_rate()
    sqrt_rate, div_rate = unit_rate(_unit_kernel("sqrt")), unit_rate(_unit_kernel("div"))
    t0 = time.perf_counter()
    res = run_case(args.steps)
    wall = time.perf_counter() - t0
    n = args.steps // 3
    out = {"kernel_geval_s": round(rate, 3), "lattice_kernel_geval_s": round(lattice_rate, 3),
           "reference_case_s": round(wall, 2), "steps": args.steps,
           "sqrt_g_s": round(sqrt_rate, 3), "div_g_s": round(div_rate, 3),
           "kernel_bound_geval_s": round(1.0 / (2.0 / sqrt_rate + 1.0 / div_rate), 3),
           "panels_per_wing": "8x16", "compile_s": round(compile_s, 2), "cpus": os.cpu_count(),
           "vector_bits": vector_bits(),
           "mean_lift_last_cycle_N": float(2 * res.force[-n:, 0, 2].mean()),
           "mean_power_last_cycle_W": float(2 * res.power[-n:].mean())}
    pairs = reference_pairs(args.steps)
    out.update({"reference_case_pairs": pairs["pairs"], "reference_case_kernel_calls": pairs["calls"],
                "reference_case_kernel_share": round(pairs["pairs"] / (lattice_rate * 1e9) / wall, 3)})
    out.update(aero_timings())
    if args.ptera_json:
        with open(args.ptera_json) as f:
            p = json.load(f)
        out["ptera_wall_s"] = p.get("ptera_wall_s")
        if out["ptera_wall_s"]:
            out["speedup_vs_ptera"] = round(out["ptera_wall_s"] / wall, 1)
    out["targets"] = TARGETS
    out["host"] = host_info()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
