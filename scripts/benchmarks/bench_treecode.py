"""Benchmark of the free wake's treecode (aero.treecode, ``UVLMConfig(wake_summation="tree")``) against the direct
sum, and the lattice kernel against this CPU's FMA roofline (issue 23, items 1 and 5); prints ONE JSON object.

Sections (``--sections``, default all):

* ``accuracy``: cycle averages of the last beat with the wake-on-wake sum by the tree (forced, at each
  ``--thetas``) against the direct sum: the reference case of bench_uvlm.py (L = F_z, D = F_x, M = M_y, P) and
  `hawksim aero`'s held-body evaluation at the default resolution, Table 3's kinematics, hover and 2 m/s
  (L+, D+, M+, P+); relative differences, whether within ``BOUND``, wall times.
* ``crossover``: one wake-on-wake evaluation (the UVLM's convection call: mirror images on, convection cores),
  direct (``aero.lattice.lattice_velocity``) and tree (``aero.treecode.lattice_tree``), best of 3, on
  (a) the wakes of a held-body UVLM flight at the fly lattice (6 x 12 rings, 40 steps per beat, 1 m/s, Table 3,
  no truncation) after 1, 2, 3, 5, 7 and 10 beats, and (b) unstretched wake-like lattices (rows of 12 rings,
  1 mm apart, the geometry of bench_uvlm.py's lattice kernel case) of 50 to 3200 rows; wake segments (edges with
  circulation), the tree's maximum velocity error relative to the largest velocity, time ratio.
* ``fly``: `hawksim fly --aero uvlm --speed 1 --cycles N --wake-cycles 10` (default N = 20) with the wake-on-wake
  sum "direct", "tree" and "auto" (the fly backend's default), and "direct" with the opt-in mixed precision
  (``--wake-precision mixed``), one after the other in this process, and the default 3-beat wake beside them:
  loop wall time and wingbeats per wall second (issue 23's target: >= 1 with the 10-beat wake), and the last
  beat's mean vertical speed (auto that keeps the direct sum gives its bits; mixed differs from direct by it).
* ``roofline``: peak FMA throughput of this CPU on all cores with 256- and 512-bit vectors (a C microbenchmark of
  12 independent FMA chains per thread, compiled here with the system C compiler; null without one), the lattice
  kernel's rate (bench_uvlm.py's case; the 512-bit figure in a child process with HAWKSIM_VECTOR_WIDTH=512, which
  checks that numba did compile for 512 bits: before 2026-12-03 bench_uvlm imported numba before aero, so that
  child ran the 256-bit code),
  its FP lane-operations per edge-target pair (:data:`LANE_OPS_PER_PAIR`, counted from its source), and the
  kernel's fraction of the roofline = achieved lane-ops/s / (FMA instructions/s x lanes)
  (``fraction_of_fma_roofline``: right where every FP operation needs the FMA ports, as on Intel Xeons), and
  against the larger of that and the peak of FMAs and additions interleaved (``fp_peak``,
  ``fraction_of_fp_roofline``, roofline.roofline_fractions: on AMD Zen 5, whose additions have pipes of their own,
  the 256-bit kernel ran
  1.06-1.09x the FMA-only peak on 2026-12-04). The 512-bit child checks that numba did compile for the width asked
  for (aero.vector_bits reads it off the compiled code; before 2026-12-04 it read the setting, and on Zen 5, whose
  default is 512-bit, the "256-bit" figures were the 512-bit code's).

Every section records /proc/loadavg before and after; the JSON has the host and date (hawksim.jsonout).

    python -m scripts.benchmarks.bench_treecode [--sections accuracy crossover fly roofline] [--cycles 20]
        [--thetas 0.4] [--out FILE]
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

from scripts.benchmarks.bench_uvlm import lattice_kernel_rate, reference_wing  # noqa: I001  (imports aero first)
from scripts.benchmarks.roofline import pair_ceiling, roofline_fractions  # noqa: E402

import aero.uvlm as uvlm_module  # noqa: E402
from aero.lattice import lattice_velocity, ring_lattice  # noqa: E402
from aero.lattice_lanes import lane_config  # noqa: E402
from aero.treecode import TreeParams, lattice_tree  # noqa: E402
from aero.uvlm import UVLMConfig, run_prescribed  # noqa: E402
from aero.uvlm_kinematics import two_wing_motion  # noqa: E402
from aero.vector_width import vector_bits  # noqa: E402
from hawksim.jsonout import emit  # noqa: E402

BOUND = 1e-4
"""Issue 23's bound on the cycle averages (relative to the direct sum's)."""

CORNER_LANE_OPS = {"rsqrt14": 17, "float32": 22}
"""FP lane-operations per corner of the lattice kernel (aero.lattice_lanes), an FMA counted as one, by its 1/sqrt
route: 3 differences, 3 for r^2, max, 1/sqrt, 3 multiplies for r/|r|, where 1/sqrt is the vrsqrt14pd estimate and
its fourth-order step (1 + 2 for e, 3 for the polynomial, 1 FMA: 7) or the float32 detour (conversion, estimate,
its Newton step (4), conversion back, the third-order step (5): 12)."""

CORNERS_PER_EDGE = 10217 / 19816
"""Corners per edge of bench_uvlm.py's lattice (601 x 17 corners, 19 816 edges): per-corner operations count this
much per edge-target pair."""

LANE_OPS_PER_PAIR = 25 + CORNER_LANE_OPS[lane_config()[1]] * CORNERS_PER_EDGE
"""FP lane-operations per edge-target pair of the lattice kernel (aero.lattice_lanes, its 1/sqrt route in this
process): per edge 6 for the cross product (3 multiplies, 3 fused multiply-subtracts), 9 for K (6 differences, a
multiply and 2 FMAs), 5 for the denominator, 1 division, 1 multiply by gamma and 3 FMAs into the sums: 25; per
corner :data:`CORNER_LANE_OPS`; with bench_uvlm.py's lattice (601 x 17 = 10 217 corners for 19 816 edges) ~33.8
with the estimate, ~36.3 without (the corner-block kernel's count before 2026-12-04)."""

CORNER_FMA_PORT_OPS = {"rsqrt14": 12, "float32": 15}
"""Multiplies and FMAs (the operations an FMA pipe must issue) per corner of the lattice kernel, by its 1/sqrt route:
3 for r^2, 3 multiplies for r/|r|, and the 1/sqrt's step: 6 for vrsqrt14pd's fourth-order step (2 for e, 4 for
the polynomial and its FMA into y), 9 for the float32 detour (its Newton step and the third-order step). Read off
the compiled code (:func:`kernel_op_counts`) on AMD Zen 4, 2026-12-06, at 8 and 4 lanes: the corner loop with both
edges has 44 of them with the estimate (16 vmulpd, 27 vfmadd/vfmsub, 1 vfnmadd), 12 + 2 x 16. The roofline section
uses the counts read off this process's code; these are the fallback."""

EDGE_FMA_PORT_OPS = 16
"""Multiplies and FMAs per edge of the lattice kernel: 6 for the cross product, 3 for K's dot product, 3 for
|r1 x r2|^2, 1 multiply by gamma, 3 FMAs into the sums (K's 6 differences, the core's addition and the division
issue elsewhere)."""

FMA_PORT_OPS_PER_PAIR = EDGE_FMA_PORT_OPS + CORNER_FMA_PORT_OPS[lane_config()[1]] * CORNERS_PER_EDGE
"""Multiplies and FMAs per edge-target pair (bench_uvlm.py's lattice, as :data:`LANE_OPS_PER_PAIR`): ~22.2 with the
estimate. Divides the FMA-only peak in roofline.pair_ceiling, where additions have pipes of their own."""

def kernel_op_counts() -> dict | None:
    """Vector FP operations per edge and per corner in this process's compiled lattice kernel, read off its machine
    code (the lanes kernel of :func:`aero.lattice_lanes.chunks_kernel` at :func:`lane_config`, compiled uncached so
    that numba shows its assembly): its corner loop with both edges is the basic block with the most vector FP
    instructions, the loop with the spanwise edge alone the next (the first ``stride`` corners; with 4 lanes each
    loop comes twice, once per half of the GROUP of 8 targets), so per edge = their difference and per corner = the
    second less one edge. ``fma_port``: multiplies and FMAs (:data:`EDGE_FMA_PORT_OPS`, :data:`CORNER_FMA_PORT_OPS`
    count them from the source); ``fp``: every vector FP instruction (the division and 1/sqrt estimate included;
    the float32 route's conversions not). Per vector of lanes, i.e. per lane-operation. None where the code does
    not have that shape (per-corner counts not positive)."""
    import re

    from aero.lattice_lanes import chunks_kernel

    kernel = chunks_kernel(lane_config())
    T, v = np.zeros((3, 16)), np.zeros(20)
    kernel(T, 16, v, v, v, 5, v, v + 1.0, v, v + 1.0, np.zeros((16, 3)), np.zeros(1, np.int64), 1)
    asm = next(iter(kernel.inspect_asm().values()))
    fp = re.compile(r"^v(add|sub|mul|div|max|min|sqrt|rsqrt14|fmadd|fmsub|fnmadd|fnmsub)\w*p[sd]$")
    fma = re.compile(r"^v(mul|fmadd|fmsub|fnmadd|fnmsub)\w*p[sd]$")
    blocks, cur = [], {"fp": 0, "fma_port": 0}
    for line in asm.splitlines():
        s = line.strip()
        if s.endswith(":") and not s.startswith("#"):
            blocks.append(cur)
            cur = {"fp": 0, "fma_port": 0}
            continue
        op = s.split(None, 1)
        if len(op) == 2 and ("mm" in op[1]) and fp.match(op[0]):
            cur["fp"] += 1
            cur["fma_port"] += bool(fma.match(op[0]))
    blocks.append(cur)
    # with fewer lanes than GROUP the loops come once per lane vector: take the two largest distinct blocks
    distinct = {b["fp"]: b for b in blocks}
    two, one = [distinct[k] for k in sorted(distinct, reverse=True)[:2]]
    edge = {k: two[k] - one[k] for k in two}
    corner = {k: one[k] - edge[k] for k in one}
    if min(corner.values()) <= 0 or min(edge.values()) <= 0:
        return None
    return {"per_edge": edge, "per_corner": corner}


FMA_C = r"""
#include <immintrin.h>
#include <stdint.h>
#define CHAINS(T, FMA, SET) \
    T a = SET(0.999999), b = SET(1e-9); \
    T x0 = SET(1.0), x1 = SET(1.1), x2 = SET(1.2), x3 = SET(1.3), x4 = SET(1.4), x5 = SET(1.5), \
      x6 = SET(1.6), x7 = SET(1.7), x8 = SET(1.8), x9 = SET(1.9), x10 = SET(2.0), x11 = SET(2.1); \
    for (int64_t i = 0; i < n; i++) { \
        x0 = FMA(x0, a, b); x1 = FMA(x1, a, b); x2 = FMA(x2, a, b); x3 = FMA(x3, a, b); \
        x4 = FMA(x4, a, b); x5 = FMA(x5, a, b); x6 = FMA(x6, a, b); x7 = FMA(x7, a, b); \
        x8 = FMA(x8, a, b); x9 = FMA(x9, a, b); x10 = FMA(x10, a, b); x11 = FMA(x11, a, b); }
double fma256(int64_t n) {
    CHAINS(__m256d, _mm256_fmadd_pd, _mm256_set1_pd)
    __m256d s = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(x0, x1), _mm256_add_pd(x2, x3)),
                              _mm256_add_pd(_mm256_add_pd(x4, x5), _mm256_add_pd(x6, x7)));
    s = _mm256_add_pd(s, _mm256_add_pd(_mm256_add_pd(x8, x9), _mm256_add_pd(x10, x11)));
    double o[4]; _mm256_storeu_pd(o, s); return o[0] + o[1] + o[2] + o[3];
}
double fma512(int64_t n) {
    CHAINS(__m512d, _mm512_fmadd_pd, _mm512_set1_pd)
    __m512d s = _mm512_add_pd(_mm512_add_pd(_mm512_add_pd(x0, x1), _mm512_add_pd(x2, x3)),
                              _mm512_add_pd(_mm512_add_pd(x4, x5), _mm512_add_pd(x6, x7)));
    s = _mm512_add_pd(s, _mm512_add_pd(_mm512_add_pd(x8, x9), _mm512_add_pd(x10, x11)));
    return _mm512_reduce_add_pd(s);
}
#define MIX(T, FMA, ADD, SET) \
    T a = SET(0.999999), b = SET(1e-9); \
    T x0 = SET(1.0), x1 = SET(1.1), x2 = SET(1.2), x3 = SET(1.3), x4 = SET(1.4), x5 = SET(1.5), \
      x6 = SET(1.6), x7 = SET(1.7), x8 = SET(1.8), x9 = SET(1.9); \
    T y0 = SET(2.0), y1 = SET(2.1), y2 = SET(2.2), y3 = SET(2.3), y4 = SET(2.4), y5 = SET(2.5), \
      y6 = SET(2.6), y7 = SET(2.7); \
    for (int64_t i = 0; i < n; i++) { \
        x0 = FMA(x0, a, b); y0 = ADD(y0, b); x1 = FMA(x1, a, b); y1 = ADD(y1, b); \
        x2 = FMA(x2, a, b); y2 = ADD(y2, b); x3 = FMA(x3, a, b); y3 = ADD(y3, b); \
        x4 = FMA(x4, a, b); y4 = ADD(y4, b); x5 = FMA(x5, a, b); y5 = ADD(y5, b); \
        x6 = FMA(x6, a, b); y6 = ADD(y6, b); x7 = FMA(x7, a, b); y7 = ADD(y7, b); \
        x8 = FMA(x8, a, b); x9 = FMA(x9, a, b); } \
    T s = ADD(ADD(ADD(x0, x1), ADD(x2, x3)), ADD(ADD(x4, x5), ADD(x6, x7))); \
    s = ADD(s, ADD(ADD(x8, x9), ADD(ADD(y0, y1), ADD(y2, y3)))); \
    s = ADD(s, ADD(ADD(y4, y5), ADD(y6, y7)));
double mix256(int64_t n) {
    MIX(__m256d, _mm256_fmadd_pd, _mm256_add_pd, _mm256_set1_pd)
    double o[4]; _mm256_storeu_pd(o, s); return o[0] + o[1] + o[2] + o[3];
}
double mix512(int64_t n) {
    MIX(__m512d, _mm512_fmadd_pd, _mm512_add_pd, _mm512_set1_pd)
    return _mm512_reduce_add_pd(s);
}
"""
"""fma256 / fma512: 12 independent FMA chains (more than FMA latency x FMA ports), so the loop runs at the FMA
ports' throughput. mix256 / mix512: 10 FMA chains and 8 addition chains interleaved (18 instructions per
iteration), the throughput of every FP pipe together: above the FMA peak where additions have pipes of their own
(AMD Zen: 2 FMA and 2 FADD pipes), equal to it where they share the FMA ports."""

MIX_PER_ITER = 18
"""Vector instructions per loop iteration of mix256 / mix512 (10 FMAs, 8 additions)."""


def loadavg():
    try:
        return [float(x) for x in open("/proc/loadavg").read().split()[:3]]
    except OSError:
        return None


def numba_threads() -> int:
    import numba

    return numba.get_num_threads()


# ---- accuracy ------------------------------------------------------------------------------------------------
def _reference(config: UVLMConfig, steps: int = 220) -> dict:
    t = np.linspace(0.0, 3 / 25.0 * steps / 220, steps)  # 220 steps per 3 beats, as bench_uvlm.py
    R, o, v, w = two_wing_motion(t, freq=25.0)
    plane = (np.zeros(3), np.array([0.0, 1.0, 0.0]))
    res = run_prescribed([reference_wing()], config, t, R[:, :1], o[:, :1], v[:, :1], w[:, :1], mirror_plane=plane)
    last = slice(steps - steps // 3, steps)
    f, m = 2 * res.force[last, 0], res.moment[last, 0]
    return {"L": float(f[:, 2].mean()), "D": float(f[:, 0].mean()), "M": float(2 * m[:, 1].mean()),
            "P": float(2 * res.power[last].mean())}


def _held(config: UVLMConfig, speed: float) -> dict:
    from hawksim.backends.held import held_flight
    from hawksim.backends.resolution import DEFAULT
    from hawksim.backends.uvlm import UVLMBackend
    from hawksim.insect.kinematics import table3_kinematics

    backend = UVLMBackend(n_chord=DEFAULT.n_chord, n_span=DEFAULT.n_span, config=config)
    a = held_flight(table3_kinematics(speed), speed, backend, cycles=DEFAULT.cycles,
                    average_cycles=DEFAULT.average_cycles, steps_per_cycle=DEFAULT.steps_per_cycle).averages
    return {"L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus}


def accuracy_cases(variants: dict, key: str) -> dict:
    """The cycle averages of the three accuracy cases (the reference case; the held body at hover and 2 m/s) by the
    direct sum and by each variant: ``variants[label](case, base)`` returns ``case`` run with the variant, ``base``
    the case's UVLMConfig arguments. Per case: the direct values and, under ``key``, per label the values, relative
    differences, whether within :data:`BOUND`, wall times."""
    from hawksim.insect.morphology import RHO_AIR

    cases = {"reference": (_reference, {}), "hover": (lambda c: _held(c, 0.0), {"rho": RHO_AIR}),
             "2 m/s": (lambda c: _held(c, 2.0), {"rho": RHO_AIR})}
    out = {}
    for name, (case, base) in cases.items():
        t0 = time.perf_counter()
        ref = case(UVLMConfig(**base))
        entry = {"direct": ref, "direct_wall_s": round(time.perf_counter() - t0, 2), key: {}}
        for label, run in variants.items():
            t0 = time.perf_counter()
            val = run(case, base)
            rel = {k: abs(val[k] - ref[k]) / abs(ref[k]) for k in ref}
            entry[key][label] = {"values": val, "relative": rel, "max_relative": max(rel.values()),
                                 "within_bound": max(rel.values()) <= BOUND,
                                 "wall_s": round(time.perf_counter() - t0, 2)}
        out[name] = entry
    return out


def accuracy(thetas) -> dict:
    return accuracy_cases({str(th): (lambda case, base, th=th: case(UVLMConfig(**base, wake_summation="tree",
                                                                                tree_theta=th)))
                           for th in thetas}, "tree")


# ---- crossover -----------------------------------------------------------------------------------------------
def best_time(fn, reps=3):
    fn()
    best = np.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _compare(lats, pts, mirror, params) -> dict:
    """One convection call's wake-on-wake sum, direct and by the tree, on the same targets (with images)."""
    allp = with_images(pts, mirror)
    ref = lattice_velocity(allp, lats)
    tree = lattice_tree(allp, lats, params)
    td = best_time(lambda: lattice_velocity(allp, lats))
    tt = best_time(lambda: lattice_tree(allp, lats, params))
    segs = sum(int(np.count_nonzero(lat.span_gamma)) + int(np.count_nonzero(lat.chord_gamma)) for lat in lats)
    return {"wake_segments": segs, "targets": int(allp.shape[0]), "direct_s": round(td, 5), "tree_s": round(tt, 5),
            "direct_over_tree": round(td / tt, 3),
            "max_error_rel": float(np.linalg.norm(tree - ref, axis=1).max() / np.linalg.norm(ref, axis=1).max())}


def crossover_cases() -> list[tuple[str, int, list, np.ndarray, tuple]]:
    """The crossover's cases: (kind, size, wake lattices, targets (n, 3) [m], mirror (point, normal)). Kind
    "uvlm_wakes_1ms": the free wake of a held 1 m/s flight (Table 3 kinematics, 6 x 12 rings, 40 steps a beat)
    after size = 1, 2, 3, 5, 7 and 10 beats, its corners the targets, as one convection call sees them; kind
    "unstretched_lattices": a wake-like lattice of size rows x 12 rings with a small random jitter (seed 0)."""
    from hawksim.backends.held import held_flight
    from hawksim.backends.uvlm import UVLMBackend
    from hawksim.insect.kinematics import table3_kinematics
    from hawksim.insect.morphology import RHO_AIR

    snaps = {}
    beats = (1, 2, 3, 5, 7, 10)

    class Snap(UVLMBackend):
        def loads(self, state):
            r = super().loads(state)
            k = self.solver.step_count
            if k % 40 == 0 and k // 40 in beats:
                s = self.solver
                rcv = s.config.convection_core_chords * s.chord
                snaps[k // 40] = (s._wake_lattices(r_attached=rcv),
                                  np.concatenate([w.vertices[1:].reshape(-1, 3) for w in s.wakes]),
                                  (state.body_pos.copy(), state.body_R[:, 1].copy()))
            return r

    held_flight(table3_kinematics(1.0), 1.0, Snap(n_chord=6, n_span=12, config=UVLMConfig(rho=RHO_AIR)), cycles=10,
                average_cycles=1, steps_per_cycle=40)
    cases = [("uvlm_wakes_1ms", b, *snaps[b]) for b in beats]
    rng = np.random.default_rng(0)
    for rows in (50, 100, 200, 400, 800, 1600, 3200):
        G = np.zeros((rows + 1, 13, 3))
        G[..., 0] = -1e-3 * np.arange(rows + 1)[:, None]
        G[..., 1] = 4e-3 * np.arange(13)[None, :]
        G += 2e-4 * rng.normal(size=G.shape)
        lat = ring_lattice(G, 1e-3 * rng.normal(size=(rows, 12)), 1e-8, 1e-8)
        cases.append(("unstretched_lattices", rows, [lat], G[1:].reshape(-1, 3),
                      (np.zeros(3), np.array([0.0, 1.0, 0.0]))))
    return cases


def with_images(pts: np.ndarray, mirror) -> np.ndarray:
    """The targets and their mirror images (2n, 3), as the solver passes them to one wake-on-wake call."""
    p0, nrm = mirror
    return np.concatenate([pts, pts - 2.0 * ((pts - p0) @ nrm)[:, None] * nrm])


def crossover(theta: float) -> dict:
    params = TreeParams(theta=theta)
    out = {"theta": theta, "threads": numba_threads(), "uvlm_wakes_1ms": [], "unstretched_lattices": []}
    for kind, size, lats, pts, mirror in crossover_cases():
        key = "beats" if kind == "uvlm_wakes_1ms" else "rows"
        out[kind].append({key: size, "load": loadavg(), **_compare(lats, pts, mirror, params)})
    return out


# ---- fly -----------------------------------------------------------------------------------------------------
def fly(cycles: int) -> dict:
    from hawksim.cli.fly import fly_named

    fly_named(1.0, 1, "uvlm", wake_cycles=10, wake_summation="tree")  # warm-up: numba cache, model
    out = {"speed_m_s": 1.0, "cycles": cycles, "threads": numba_threads(), "vector_bits": vector_bits(), "runs": {}}
    settings = (("wake_10_direct", 10, "direct", "float64"), ("wake_10_tree", 10, "tree", "float64"),
                ("wake_10_auto", 10, "auto", "float64"), ("wake_10_mixed", 10, "direct", "mixed"),
                ("wake_3_default", 3, "auto", "float64"))
    for name, wake, summation, precision in settings:
        load = loadavg()
        r = fly_named(1.0, cycles, "uvlm", wake_cycles=wake, wake_summation=summation, wake_precision=precision)
        beats = r.summary()["beats"]
        out["runs"][name] = {"wake_cycles": wake, "wake_summation": summation, "wake_precision": precision,
                             "loop_wall_s": round(r.wall_time_s, 2),
                             "wingbeats_per_s": round(cycles / r.wall_time_s, 3), "load_before": load,
                             "load_after": loadavg(), "mean_vertical_speed_last_beat": beats[-1]["mean_vertical_speed"]}
    runs = out["runs"]
    direct, tree = runs["wake_10_direct"]["loop_wall_s"], runs["wake_10_tree"]["loop_wall_s"]
    out["tree_speedup_10_beat_wake"] = round(direct / tree, 3)
    out["mixed_speedup_10_beat_wake"] = round(direct / runs["wake_10_mixed"]["loop_wall_s"], 3)
    w = [runs[k]["mean_vertical_speed_last_beat"] for k in ("wake_10_mixed", "wake_10_direct")]
    out["mixed_last_beat_vertical_speed_difference_m_s"] = abs(w[0] - w[1])
    out["target_wingbeats_per_s"] = 1.0
    return out


# ---- roofline ------------------------------------------------------------------------------------------------
def _fma_peak(lib, name: str, lanes: int, threads: int, n: int = 5_000_000, tries: int = 15, per_iter: int = 12
              ) -> dict:
    fn = getattr(lib, name)
    fn.restype = ctypes.c_double
    fn.argtypes = [ctypes.c_int64]
    fn(1000)
    best = np.inf
    for _ in range(tries):  # ctypes releases the GIL: one chain set per thread, all at once
        ts = [threading.Thread(target=fn, args=(n,)) for _ in range(threads)]
        t0 = time.perf_counter()
        for t in ts:
            t.start()
        for t in ts:
            t.join()
        best = min(best, time.perf_counter() - t0)
    instr = per_iter * n * threads / best
    return {"instructions_g_s": round(instr / 1e9, 3), "lane_ops_g_s": round(instr * lanes / 1e9, 2)}


def kernel_rates() -> dict:
    """The lattice kernel's rate [G edge-target pairs/s] on all threads and on one (best of 5 each)."""
    import numba

    n = numba.get_num_threads()
    out = {"all": lattice_kernel_rate()}
    numba.set_num_threads(1)
    try:
        out["one"] = lattice_kernel_rate()
    finally:
        numba.set_num_threads(n)
    return out


def roofline() -> dict:
    """Peak FMA throughput (one thread, all threads) at 256 and 512 bits, the lattice kernel's rates with numba
    compiling for 256- and 512-bit vectors, and the kernel's fraction of the roofline per thread count (the
    one-thread figures are the robust ones on a shared machine: other processes take cores from both runs)."""
    threads = numba_threads()
    counts = kernel_op_counts()
    fma_ops = FMA_PORT_OPS_PER_PAIR if counts is None else (
        counts["per_edge"]["fma_port"] + counts["per_corner"]["fma_port"] * CORNERS_PER_EDGE)
    out = {"threads": threads, "lane_ops_per_pair": round(LANE_OPS_PER_PAIR, 2),
           "fma_port_ops_per_pair": round(fma_ops, 2), "compiled_op_counts": counts, "load_before": loadavg()}
    cc = shutil.which("cc") or shutil.which("gcc")
    peaks, fp_peaks = {}, {}
    if cc:
        with tempfile.TemporaryDirectory() as d:
            src, so = os.path.join(d, "fma.c"), os.path.join(d, "fma.so")
            open(src, "w").write(FMA_C)
            subprocess.run([cc, "-O2", "-mavx2", "-mfma", "-mavx512f", "-mavx512vl", "-shared", "-fPIC", src,
                            "-o", so],
                           check=True, capture_output=True)
            lib = ctypes.CDLL(so)
            for bits, lanes in (("256", 4), ("512", 8)):
                peaks[bits] = {"one": _fma_peak(lib, f"fma{bits}", lanes, 1),
                               "all": _fma_peak(lib, f"fma{bits}", lanes, threads)}
                fp_peaks[bits] = {k: _fma_peak(lib, f"mix{bits}", lanes, t, per_iter=MIX_PER_ITER)
                                  for k, t in (("one", 1), ("all", threads))}

    out["peak"] = peaks or None
    out["fp_peak"] = fp_peaks or None
    rates = {str(vector_bits()): kernel_rates()}
    other = "512" if vector_bits() == 256 else "256"
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    code = ("import json; from scripts.benchmarks.bench_treecode import kernel_rates, vector_bits; "
            "print(json.dumps({'bits': vector_bits(), **kernel_rates()}))")
    env = dict(os.environ, HAWKSIM_VECTOR_WIDTH=other)
    env.pop("NUMBA_CPU_FEATURES", None)
    proc = subprocess.run([sys.executable, "-c", code], cwd=repo, env=env, capture_output=True, text=True,
                          check=True)
    child = json.loads(proc.stdout.strip().splitlines()[-1])
    if child.pop("bits") != int(other):  # numba imported before aero, or a host without AVX-512F
        raise SystemExit(f"bench_treecode: the {other}-bit child process compiled for another vector width")
    rates[other] = child
    out["lattice_kernel_g_pairs_s"] = {b: {k: round(v, 3) for k, v in r.items()} for b, r in rates.items()}
    out["achieved_lane_ops_g_s"] = {b: {k: round(v * LANE_OPS_PER_PAIR, 2) for k, v in r.items()}
                                    for b, r in rates.items()}
    if peaks:
        out["fraction_of_fma_roofline"] = {
            b: {k: round(rates[b][k] * LANE_OPS_PER_PAIR / peaks[b][k]["lane_ops_g_s"], 3) for k in ("one", "all")}
            for b in ("256", "512")}
        out["fraction_of_fp_roofline"] = roofline_fractions(out)
        out["pair_ceiling_g_pairs_s"] = {b: {k: round(pair_ceiling(out, b, k), 3) for k in ("one", "all")}
                                         for b in ("256", "512")}
    out["load_after"] = loadavg()
    return out


SECTIONS = {"accuracy": None, "crossover": None, "fly": None, "roofline": None}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sections", nargs="+", choices=list(SECTIONS), default=list(SECTIONS))
    ap.add_argument("--cycles", type=int, default=20)
    ap.add_argument("--thetas", type=float, nargs="+", default=[TreeParams.theta])
    ap.add_argument("--out")
    args = ap.parse_args()
    out = {"command": " ".join(["python", *sys.argv]), "bound": BOUND, "tree_params": TreeParams().__dict__,
           "tree_min_segments": uvlm_module.TREE_MIN_SEGMENTS, "vector_bits": vector_bits(),
           "numba_threads": numba_threads(), "loadavg_start": loadavg()}
    for name in args.sections:
        t0 = time.perf_counter()
        if name == "accuracy":
            out[name] = accuracy(args.thetas)
        elif name == "crossover":
            out[name] = crossover(args.thetas[0])
        elif name == "fly":
            out[name] = fly(args.cycles)
        else:
            out[name] = roofline()
        out[name]["section_wall_s"] = round(time.perf_counter() - t0, 1)
        print(json.dumps({name: "done", "load": loadavg()}), file=sys.stderr, flush=True)
    out["loadavg_end"] = loadavg()
    emit(out, args.out, host=True)


if __name__ == "__main__":
    main()
