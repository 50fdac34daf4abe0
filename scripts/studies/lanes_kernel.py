"""The targets-in-lanes lattice kernel's configurations, timed against the corner-block kernel side by side (issue 23).

The corner-block kernel (:func:`aero.biot_savart.lattice_chunks`, shipped until 2026-12-04) puts a block's
corners in the vector lanes: per target, a corner pass stores r = p - corner and r/|r| for 192 corners, and the
edge pass reads corners k and k + 1 (k + stride for chordwise edges): with 512-bit vectors every second-corner load
straddles two cache lines. :mod:`aero.lattice_lanes` (shipped since) puts 8 targets in the lanes and makes ONE pass
over all corners (its module docstring). This study runs every (lanes, 1/sqrt route) configuration the host
supports (:func:`aero.lattice_lanes.supported_configs`), named ``lanes<L>_<route>``: L = 8 lanes of <8 x double>
(zmm) or 4 of <4 x double> (ymm; the shipped choice at 256 bits), route ``f32`` (float32 1/sqrt and the
third-order float64 step of :func:`aero.biot_savart.rsqrt`, portable) or ``rsqrt14`` (AVX-512's vrsqrt14pd and
one fourth-order step; AVX-512F, and AVX512VL for 4 lanes). ``base`` is the corner-block kernel. ``_x2``: two lane
vectors of targets per pass over the corners (16 targets a group at 8 lanes), two independent chains for the
out-of-order core, with the shipped 1/sqrt route (added 2026-12-06; on AMD Zen 4, whose FMA pipes bind, 0.97-1.03x
at 8 lanes and 1.04-1.08x at 4: docs/performance.md, "AMD Zen 4").

Rates in G edge-target pairs/s, one thread, on bench_uvlm.py's lattice (600 rows x ns rings, 4000 targets) for
ns = 16 (stride 17, the reference case's) and ns = 8 (stride 9, the flight wake's), best of 5, twice
interleaved, and for ns = 8 also on 2 threads (:func:`aero.biot_savart`'s chunked scheduling, ``ns8_two_threads``);
the 256-bit figures from a child process with HAWKSIM_VECTOR_WIDTH=256. Prints ONE JSON object.

    python -m scripts.studies.lanes_kernel [--widths 512 256] [--out FILE]
"""

from __future__ import annotations

import aero  # noqa: F401, I001  (before numba: importing aero applies HAWKSIM_VECTOR_WIDTH)

import time

import numpy as np

from aero.biot_savart import lattice_chunks
from aero.lattice import stacked_lattices
from aero.lattice_lanes import chunks_kernel, config_group, lane_config, supported_configs, transpose_targets
from aero.scheduling import run_chunked

from scripts.benchmarks.bench_uvlm import kernel_lattice  # noqa: E402
from scripts.studies.kernel_variants import width_study_main  # noqa: E402

def rates(ns: int, rounds=2, reps=5, threads=1) -> dict:
    lat, p = kernel_lattice(600, ns, 4000)
    p = np.ascontiguousarray(p)
    (stride, arrays), = stacked_lattices([lat]).items()
    vx, vy, vz, sg, sr, cg, cr = (np.ascontiguousarray(a) for a in arrays)
    counter = np.zeros(1, np.int64)
    pairs = (sg.size + cg.size) * p.shape[0]
    nt = p.shape[0]

    def base(o):
        if threads > 1:
            run_chunked(lattice_chunks, (p, vx, vy, vz, stride, sg, sr, cg, cr, o), nt, pairs, threads)
            return
        counter[0] = 0
        lattice_chunks(p, vx, vy, vz, stride, sg, sr, cg, cr, o, counter, 1)

    variants = {"base": base}
    configs = [(*c, 1) for c in supported_configs()]
    # two lane vectors per pass over the corners, the shipped 1/sqrt route where this host runs it at that lane count
    configs += [(lanes, lane_config()[1] if (lanes, lane_config()[1]) in supported_configs() else "float32", 2)
                for lanes in (8, 4)]
    for lanes, inverse_sqrt, interleave in configs:
        name = f"lanes{lanes}_{'f32' if inverse_sqrt == 'float32' else inverse_sqrt}" + (
            f"_x{interleave}" if interleave > 1 else "")
        cfg = (lanes, inverse_sqrt, interleave)
        k, group = chunks_kernel(cfg), config_group(cfg)
        T = transpose_targets(p, group)

        def run(o, k=k, T=T, group=group):
            if threads > 1:
                run_chunked(k, (T, nt, vx, vy, vz, stride, sg, sr, cg, cr, o), T.shape[1] // group, pairs, threads)
                return
            counter[0] = 0
            k(T, nt, vx, vy, vz, stride, sg, sr, cg, cr, o, counter, 1)
        variants[name] = run
    outs = {}
    for name, f in variants.items():
        outs[name] = np.zeros((nt, 3))
        f(outs[name])
    got = {name: [] for name in variants}
    for _ in range(rounds):
        for name, f in variants.items():
            best = np.inf
            for _ in range(reps):
                o = np.zeros((nt, 3))
                t0 = time.perf_counter()
                f(o)
                best = min(best, time.perf_counter() - t0)
            got[name].append(round(pairs / best / 1e9, 3))
    scale = np.abs(outs["base"]).max()
    return {"stride": stride, "g_pairs_s": got,
            "best_ratio_to_base": {k: round(max(v) / max(got["base"]), 3) for k, v in got.items()},
            "max_rel_difference_to_base": {k: float(np.abs(v - outs["base"]).max() / scale) for k, v in outs.items()}}


def main():
    def child():
        return {"ns16": rates(16), "ns8": rates(8), "ns8_two_threads": rates(8, threads=2)}

    width_study_main(__file__, __doc__, child, ["512", "256"], {"NUMBA_NUM_THREADS": "1"})


if __name__ == "__main__":
    main()
