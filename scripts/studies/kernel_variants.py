"""What bounds the lattice kernel? Two rewrites of its edge loop timed against it, side by side (issue 23).

The lattice kernel (:func:`aero.biot_savart.lattice_chunks`) evaluates, per target and edge, K = (r1 - r2) .
(r1/|r1| - r2/|r2|) and c = r1 x r2 from the target's corner vectors. Variants, each in the kernel's own structure
(blocks of :data:`aero.biot_savart.LATTICE_BLOCK` corners, the corner pass :func:`aero.biot_savart.corner_vectors`
unchanged, one thread):

* ``base``: the shipped kernel;
* ``edge_vector``: r1 - r2 is the edge's own vector d (target-independent), precomputed per edge, and c = d x r1:
  three lane-operations fewer per edge (36.3 -> 33.3 per pair); the same velocities to round-off (not the same
  bits, so the shipped results would move: the free wake at hover amplifies round-off, docs/surrogate.md);
* ``no_division``: ``edge_vector`` with the division by the denominator replaced by a multiplication, a
  diagnostic (wrong velocities): how much of the time the divider takes.
* ``corners_only``, ``edges_only``: the shipped kernel's two passes apart, diagnostics (wrong velocities): the
  corner pass alone for every block and target (no edge sums), and the edge sums alone (the corner pass run once
  per block, for the first target, then the edge sums of every target over those same scratch arrays); their
  times add up to about the kernel's, and ``split`` gives each pass's FP lane-operations per second (22 per
  corner, 25 per edge: bench_treecode.LANE_OPS_PER_PAIR's count), to set against the FMA peak at that width.
* ``edges_shifted``, ``edges_aligned``: diagnostics (wrong velocities) of whether the edge sums' loads bound them:
  ``edges_only`` over 64-byte aligned scratch, the second corners read from the first corners' arrays shifted (as
  in the kernel: at 512 bits each such load straddles two cache lines) or from aligned copies made once per block.

The variants repeat the kernel's block loop on purpose (a measurement of alternatives, not a second kernel).

Rates in G edge-target pairs/s on bench_uvlm.py's lattice (601 x 17 corners, 4000 targets), best of 5, twice
interleaved; with ``--widths 256 512`` the 512-bit figures come from a child process with HAWKSIM_VECTOR_WIDTH=512
(the vector width is fixed per process). Prints ONE JSON object.

    python -m scripts.studies.kernel_variants [--widths 256 512] [--out FILE]
"""

from __future__ import annotations

import aero  # noqa: F401, I001  (before numba: importing aero applies HAWKSIM_VECTOR_WIDTH)

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
from numba import njit

from aero.biot_savart import (FOUR_PI, LATTICE_BLOCK, TINY, edge_sum, lattice_chunks, aligned_scratch,
                               corner_vectors)
from aero.lattice import stacked_lattices
from aero.vector_width import vector_bits

from scripts.benchmarks.bench_uvlm import kernel_lattice  # noqa: E402


@njit(inline="always")
def _block(b, nc, stride):
    """Block b's first corner, corners used (with the next row's), spanwise and chordwise edges, as in
    :func:`aero.biot_savart.lattice_chunks`."""
    c0 = b * LATTICE_BLOCK
    c1 = min(c0 + LATTICE_BLOCK, nc)
    return c0, min(c1 + stride, nc) - c0, min(c1, nc - 1) - c0, min(c1, nc - stride) - c0


@njit(inline="always")
def _scratch(stride):
    """A target's corner vectors r and unit vectors e for one block, as in :func:`aero.biot_savart.lattice_chunks`."""
    size = LATTICE_BLOCK + stride + 1
    return np.empty(size), np.empty(size), np.empty(size), np.empty(size), np.empty(size), np.empty(size)


def _make(divide: bool):
    @njit(fastmath=True, error_model="numpy", inline="always")
    def edge_sum(m, x1, y1, z1, e1, f1, g1, e2, f2, g2, dx, dy, dz, gamma, rr, ux, uy, uz):
        for k in range(m):
            ax, ay, az = x1[k], y1[k], z1[k]
            px, py, pz = dx[k], dy[k], dz[k]
            cx = py * az - pz * ay
            cy = pz * ax - px * az
            cz = px * ay - py * ax
            K = px * (e1[k] - e2[k]) + py * (f1[k] - f2[k]) + pz * (g1[k] - g2[k])
            den = cx * cx + cy * cy + cz * cz + rr[k] + TINY
            f = gamma[k] * K / den if divide else gamma[k] * K * den
            ux += f * cx
            uy += f * cy
            uz += f * cz
        return ux, uy, uz

    @njit(nogil=True, fastmath=True, error_model="numpy")
    def kernel(targets, vx, vy, vz, stride, sdx, sdy, sdz, cdx, cdy, cdz, sg_all, sr_all, cg_all, cr_all, out):
        n, nc = targets.shape[0], vx.shape[0]
        nb = (nc + LATTICE_BLOCK - 1) // LATTICE_BLOCK
        scale = 1.0 / FOUR_PI
        rx, ry, rz, ex, ey, ez = _scratch(stride)
        for b in range(nb):
            c0, m, ms, mc = _block(b, nc, stride)
            bx, by, bz = vx[c0:c0 + m], vy[c0:c0 + m], vz[c0:c0 + m]
            sg, sr, cg, cr = sg_all[c0:], sr_all[c0:], cg_all[c0:], cr_all[c0:]
            a1, a2, a3, b1, b2, b3 = sdx[c0:], sdy[c0:], sdz[c0:], cdx[c0:], cdy[c0:], cdz[c0:]
            for i in range(n):
                corner_vectors(targets[i, 0], targets[i, 1], targets[i, 2], bx, by, bz, m, rx, ry, rz, ex, ey, ez)
                ux, uy, uz = edge_sum(ms, rx, ry, rz, ex, ey, ez, ex[1:], ey[1:], ez[1:], a1, a2, a3, sg, sr,
                                      0.0, 0.0, 0.0)
                if mc > 0:
                    ux, uy, uz = edge_sum(mc, rx, ry, rz, ex, ey, ez, ex[stride:], ey[stride:], ez[stride:],
                                          b1, b2, b3, cg, cr, ux, uy, uz)
                out[i, 0] += ux * scale
                out[i, 1] += uy * scale
                out[i, 2] += uz * scale

    return kernel


def _make_split(corners: bool, edges: bool):
    """The shipped kernel's block loop with only its corner pass (corners) or, after one corner pass per block,
    only its edge sums (edges) per target."""
    @njit(nogil=True, fastmath=True, error_model="numpy")
    def kernel(targets, vx, vy, vz, stride, sg_all, sr_all, cg_all, cr_all, out):
        n, nc = targets.shape[0], vx.shape[0]
        nb = (nc + LATTICE_BLOCK - 1) // LATTICE_BLOCK
        rx, ry, rz, ex, ey, ez = _scratch(stride)
        for b in range(nb):
            c0, m, ms, mc = _block(b, nc, stride)
            bx, by, bz = vx[c0:c0 + m], vy[c0:c0 + m], vz[c0:c0 + m]
            sg, sr, cg, cr = sg_all[c0:], sr_all[c0:], cg_all[c0:], cr_all[c0:]
            if not corners:
                corner_vectors(targets[0, 0], targets[0, 1], targets[0, 2], bx, by, bz, m, rx, ry, rz, ex, ey, ez)
            for i in range(n):
                if corners:
                    corner_vectors(targets[i, 0], targets[i, 1], targets[i, 2], bx, by, bz, m, rx, ry, rz, ex, ey,
                                   ez)
                    out[i, 0] += ex[m - 1] + ey[0]  # keeps the pass's results alive
                if edges:
                    ux, uy, uz = edge_sum(ms, rx, ry, rz, ex, ey, ez, rx[1:], ry[1:], rz[1:], ex[1:], ey[1:],
                                           ez[1:], sg, sr, 0.0, 0.0, 0.0)
                    if mc > 0:
                        ux, uy, uz = edge_sum(mc, rx, ry, rz, ex, ey, ez, rx[stride:], ry[stride:], rz[stride:],
                                               ex[stride:], ey[stride:], ez[stride:], cg, cr, ux, uy, uz)
                    out[i, 0] += ux
                    out[i, 1] += uy
                    out[i, 2] += uz

    return kernel


def _make_edges(aligned: bool):
    """The edge sums alone (as ``edges_only``) over scratch the caller allocates 64-byte aligned
    (:func:`aero.biot_savart.aligned_scratch`, a tuple of six arrays for each of sc, s2, c2): with
    aligned=False the second corners are the first corners' arrays shifted by 1 (spanwise) and by the stride
    (chordwise), as in the shipped kernel, so that every 512-bit load of them straddles two cache lines; with
    aligned=True they are copies, made once per block, in arrays of their own (64-byte aligned)."""
    @njit(nogil=True, fastmath=True, error_model="numpy")
    def kernel(targets, vx, vy, vz, stride, sg_all, sr_all, cg_all, cr_all, out, sc, s2, c2):
        n, nc = targets.shape[0], vx.shape[0]
        nb = (nc + LATTICE_BLOCK - 1) // LATTICE_BLOCK
        rx, ry, rz, ex, ey, ez = sc
        for b in range(nb):
            c0, m, ms, mc = _block(b, nc, stride)
            bx, by, bz = vx[c0:c0 + m], vy[c0:c0 + m], vz[c0:c0 + m]
            sg, sr, cg, cr = sg_all[c0:], sr_all[c0:], cg_all[c0:], cr_all[c0:]
            corner_vectors(targets[0, 0], targets[0, 1], targets[0, 2], bx, by, bz, m, rx, ry, rz, ex, ey, ez)
            if aligned:
                for j in range(6):
                    s2[j][:ms] = sc[j][1:ms + 1]
                    c2[j][:max(mc, 0)] = sc[j][stride:stride + max(mc, 0)]
                span, chord = s2, c2
            else:
                span = (rx[1:], ry[1:], rz[1:], ex[1:], ey[1:], ez[1:])
                chord = (rx[stride:], ry[stride:], rz[stride:], ex[stride:], ey[stride:], ez[stride:])
            for i in range(n):
                ux, uy, uz = edge_sum(ms, rx, ry, rz, ex, ey, ez, span[0], span[1], span[2], span[3], span[4],
                                       span[5], sg, sr, 0.0, 0.0, 0.0)
                if mc > 0:
                    ux, uy, uz = edge_sum(mc, rx, ry, rz, ex, ey, ez, chord[0], chord[1], chord[2], chord[3],
                                           chord[4], chord[5], cg, cr, ux, uy, uz)
                out[i, 0] += ux
                out[i, 1] += uy
                out[i, 2] += uz

    return kernel


def rates(rows=600, ns=16, nt=4000, reps=5, rounds=2) -> dict:
    """Rates [G pairs/s] of the three variants in this process (its vector width) and the edge_vector variant's
    largest velocity difference from base, relative to the largest velocity."""
    lat, p = kernel_lattice(rows, ns, nt)
    p = np.ascontiguousarray(p)
    (stride, arrays), = stacked_lattices([lat]).items()
    vx, vy, vz, sg, sr, cg, cr = (np.ascontiguousarray(a) for a in arrays)

    def diff(v, s):
        d = np.zeros_like(v)
        d[:-s] = v[s:] - v[:-s]
        return d

    d = [diff(v, 1) for v in (vx, vy, vz)] + [diff(v, stride) for v in (vx, vy, vz)]
    counter = np.zeros(1, np.int64)
    with_div, without_div = _make(True), _make(False)
    corners_only, edges_only = _make_split(True, False), _make_split(False, True)
    edges_shifted, edges_aligned = _make_edges(False), _make_edges(True)
    size = LATTICE_BLOCK + stride + 1
    sc, s2, c2 = aligned_scratch(size), aligned_scratch(size), aligned_scratch(size)

    def base(out):
        counter[0] = 0
        lattice_chunks(p, vx, vy, vz, stride, sg, sr, cg, cr, out, counter, 1)

    variants = {"base": base,
                "edge_vector": lambda out: with_div(p, vx, vy, vz, stride, *d, sg, sr, cg, cr, out),
                "no_division": lambda out: without_div(p, vx, vy, vz, stride, *d, sg, sr, cg, cr, out),
                "corners_only": lambda out: corners_only(p, vx, vy, vz, stride, sg, sr, cg, cr, out),
                "edges_only": lambda out: edges_only(p, vx, vy, vz, stride, sg, sr, cg, cr, out),
                "edges_shifted": lambda out: edges_shifted(p, vx, vy, vz, stride, sg, sr, cg, cr, out, sc, s2, c2),
                "edges_aligned": lambda out: edges_aligned(p, vx, vy, vz, stride, sg, sr, cg, cr, out, sc, s2, c2)}
    outs = {}
    for name, f in variants.items():
        outs[name] = np.zeros((nt, 3))
        f(outs[name])
    pairs = (sg.size + cg.size) * nt
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
    rel = float(np.abs(outs["edge_vector"] - outs["base"]).max() / np.abs(outs["base"]).max())
    edges, corners = sg.size + cg.size, vx.size
    ns_pair = {k: 1.0 / max(v) for k, v in got.items()}  # ns per pair, best round
    split = {"corner_pass_ns_per_pair": round(ns_pair["corners_only"], 4),
             "edge_pass_ns_per_pair": round(ns_pair["edges_only"], 4),
             "sum_over_kernel": round((ns_pair["corners_only"] + ns_pair["edges_only"]) / ns_pair["base"], 3),
             "corner_pass_g_lane_ops_s": round(22 * corners / edges / ns_pair["corners_only"], 2),
             "edge_pass_g_lane_ops_s": round(25 / ns_pair["edges_only"], 2)}
    return {"g_pairs_s": got, "best_ratio_to_base": {k: round(max(v) / max(got["base"]), 3) for k, v in got.items()},
            "edge_vector_max_rel_difference": rel, "split": split}


def width_study_main(script: str, doc: str, child, default_widths, child_env=None) -> None:
    """The command line of a per-width kernel study (this one, lanes_kernel.py): each width in --widths runs in a child
    process of ``script`` (``python -m scripts.studies.<name>`` in the repository root) with HAWKSIM_VECTOR_WIDTH set
    (and ``child_env``), which prints {"bits": ..., **child()}; the parent checks the width and emits ONE JSON
    object (host, dates, load) to stdout or --out."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--widths", nargs="+", default=default_widths, choices=["256", "512"])
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--out")
    a = ap.parse_args()
    if a.child:
        print(json.dumps({"bits": vector_bits(), **child()}))
        return
    from hawksim.jsonout import emit, host_info

    module = "scripts.studies." + os.path.splitext(os.path.basename(script))[0]  # the child: python -m module
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(script))))
    began = host_info()
    out = {}
    for w in a.widths:
        env = dict(os.environ, HAWKSIM_VECTOR_WIDTH=w, **(child_env or {}))
        env.pop("NUMBA_CPU_FEATURES", None)
        proc = subprocess.run([sys.executable, "-m", module, "--child"], cwd=repo, env=env, capture_output=True,
                              text=True, check=True)
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        if r.pop("bits") != int(w):
            sys.exit(f"error: the {w}-bit child compiled for another width (no AVX-512F here?)")
        out[w] = r
    command = " ".join(["python", "-m", module, *sys.argv[1:]])
    emit({"command": command, "began": began["date"], "ended": host_info()["date"], "host": began,
          "loadavg_after": host_info()["loadavg"], "threads": 1, "widths": out}, a.out)


def main():
    width_study_main(__file__, __doc__, rates, ["256", "512"])


if __name__ == "__main__":
    main()
