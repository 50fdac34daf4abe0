"""A targets-in-lanes lattice kernel, timed against the shipped one side by side (issue 23; a study, not shipped).

The shipped lattice kernel (:func:`aero.biot_savart._lattice_chunks`) puts a block's corners in the vector lanes:
per target, a corner pass stores r = p - corner and r/|r| for 192 corners, and the edge pass reads corners k and
k + 1 (k + stride for chordwise edges): with 512-bit vectors every second-corner load straddles two cache lines.
This variant puts 8 targets in the lanes (one <8 x double> vector per coordinate, written in LLVM IR through a numba
``@intrinsic``, as :func:`aero.biot_savart.claim` is) and makes ONE pass over all corners: at corner k it forms r
and r/|r| for the 8 targets, adds the spanwise edge k-1 -> k from the previous corner (held in registers) and the
chordwise edge k-stride -> k from a ring buffer of stride + 1 corners (6 aligned 64-byte vectors each), and keeps
the 8 targets' sums in registers. No straddling loads, no scratch pass per block, no per-block corner overlap,
no remainder loops. The same formula and the same division per edge; the sums per target run in corner order
(so the last bits differ from the shipped kernel's: max velocity difference ~4-5e-15 of the largest velocity).

Two ways to 1/|r|: ``lanes_f32``: float32 1/sqrt (vrsqrtps and a Newton step under fastmath) and the shipped
third-order float64 step (:func:`aero.biot_savart.rsqrt`), portable; ``lanes_rsqrt14``: AVX-512's vrsqrt14pd
(relative error < 2^-14) and one fourth-order step y (1 + e/2 + 3e^2/8 + 5e^3/16), e = 1 - s y^2 (error
~0.27 e^4 < 1e-16), AVX-512F hosts only.

Rates in G edge-target pairs/s, one thread, on bench_uvlm.py's lattice (600 rows x ns rings, 4000 targets) for
ns = 16 (stride 17, the reference case's) and ns = 8 (stride 9, the flight wake's), best of 5, twice
interleaved, and for ns = 8 also on 2 threads (:func:`aero.biot_savart`'s chunked scheduling, ``ns8_two_threads``);
the 256-bit figures from a child process with HAWKSIM_VECTOR_WIDTH=256. Prints ONE JSON object.

    python scripts/studies/lanes_kernel.py [--widths 512 256] [--out FILE]
"""

from __future__ import annotations

import aero  # noqa: F401, I001  (before numba: importing aero applies HAWKSIM_VECTOR_WIDTH)

import os
import sys
import time

import llvmlite.binding as llb
import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import cgutils, types
from numba.extending import intrinsic

from aero.biot_savart import FOUR_PI, RSQRT_MIN, TINY, _lattice_chunks, aligned_scratch, claim
from aero.lattice import stacked_lattices
from aero.scheduling import run_chunked

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
from bench_uvlm import kernel_lattice  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from kernel_variants import width_study_main  # noqa: E402

LANES = 8
F64 = ir.DoubleType()
F32 = ir.FloatType()
I64 = ir.IntType(64)
I32 = ir.IntType(32)
V = ir.VectorType(F64, LANES)
VF = ir.VectorType(F32, LANES)
FAST = ("fast",)


def _vec(c):
    return ir.Constant(V, [c] * LANES)


def make_kernel(rsqrt14: bool):
    """The targets-in-lanes kernel, (lanes_chunks(T, n, vx, vy, vz, stride, sg, sr, cg, cr, out, counter,
    nchunk)): 1/|r| from AVX-512's 14-bit estimate and a fourth-order step (rsqrt14) or, portable, from float32
    1/sqrt and a third-order step (the shipped :func:`aero.biot_savart.rsqrt`)."""

    @intrinsic
    def group_velocity(typingctx, T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U):
        """U[3*8] = the velocity sums (times 4 pi) at targets T[:, i0:i0+8] of all edges."""
        sig = types.void(T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U)

        def codegen(context, builder, signature, args):
            aty = signature.args
            arrs = {}
            for idx, name in ((0, "T"), (2, "vx"), (3, "vy"), (4, "vz"), (6, "sg"), (7, "sr"), (8, "cg"), (9, "cr"),
                              (10, "ring"), (11, "U")):
                arrs[name] = context.make_array(aty[idx])(context, builder, args[idx])
            i0v, stridev = args[1], args[5]
            nc = builder.extract_value(arrs["vx"].shape, 0)
            npad = builder.extract_value(arrs["T"].shape, 1)
            dptr = {k: builder.bitcast(a.data, F64.as_pointer()) for k, a in arrs.items()}
            vp = V.as_pointer()

            def elt(name, k):
                return builder.gep(dptr[name], [k], inbounds=True, source_etype=F64)

            def vload(ptr, align):
                return builder.load(builder.bitcast(ptr, vp), align=align, typ=V)

            def vstore(v, ptr, align):
                builder.store(v, builder.bitcast(ptr, vp), align=align)

            zero_mask = ir.Constant(ir.VectorType(I32, LANES), [0] * LANES)

            def splat(s):
                v = builder.insert_element(ir.Constant(V, ir.Undefined), s, ir.Constant(I32, 0))
                return builder.shuffle_vector(v, ir.Constant(V, ir.Undefined), zero_mask)

            def fadd(a, b):
                return builder.fadd(a, b, flags=FAST)

            def fsub(a, b):
                return builder.fsub(a, b, flags=FAST)

            def fmul(a, b):
                return builder.fmul(a, b, flags=FAST)

            p = [vload(builder.gep(dptr["T"], [builder.add(builder.mul(ir.Constant(I64, c), npad), i0v)], inbounds=True,
                                   source_etype=F64), 8) for c in range(3)]
            mod = builder.module
            sqrt32 = cgutils.get_or_insert_function(mod, ir.FunctionType(VF, [VF]), "llvm.sqrt.v8f32")
            maxnum = cgutils.get_or_insert_function(mod, ir.FunctionType(V, [V, V]), "llvm.maxnum.v8f64")
            one32 = ir.Constant(VF, [1.0] * LANES)

            def corner(k):
                r = [fsub(p[c], splat(builder.load(elt(n, k)))) for c, n in enumerate(("vx", "vy", "vz"))]
                s = fadd(fadd(fmul(r[0], r[0]), fmul(r[1], r[1])), fmul(r[2], r[2]))
                s = builder.call(maxnum, [s, _vec(RSQRT_MIN)])
                if rsqrt14:
                    rsq = cgutils.get_or_insert_function(mod, ir.FunctionType(V, [V, V, ir.IntType(8)]),
                                                         "llvm.x86.avx512.rsqrt14.pd.512")
                    y = builder.call(rsq, [s, _vec(0.0), ir.Constant(ir.IntType(8), -1)])
                    e = fsub(_vec(1.0), fmul(fmul(s, y), y))
                    poly = fmul(e, fadd(_vec(0.5), fmul(e, fadd(_vec(0.375), fmul(_vec(0.3125), e)))))
                    inv = fadd(y, fmul(y, poly))
                else:
                    y32 = builder.fdiv(one32, builder.call(sqrt32, [builder.fptrunc(s, VF)], fastmath=FAST), flags=FAST)
                    y = builder.fpext(y32, V)
                    e = fsub(_vec(1.0), fmul(fmul(s, y), y))
                    inv = fadd(y, fmul(fmul(y, e), fadd(_vec(0.5), fmul(_vec(0.375), e))))
                return r, [fmul(rc, inv) for rc in r]

            def edge(a, ea, b, eb, g, rr, u):
                cx = fsub(fmul(a[1], b[2]), fmul(a[2], b[1]))
                cy = fsub(fmul(a[2], b[0]), fmul(a[0], b[2]))
                cz = fsub(fmul(a[0], b[1]), fmul(a[1], b[0]))
                K = fadd(fadd(fmul(fsub(a[0], b[0]), fsub(ea[0], eb[0])), fmul(fsub(a[1], b[1]), fsub(ea[1], eb[1]))),
                         fmul(fsub(a[2], b[2]), fsub(ea[2], eb[2])))
                den = fadd(fadd(fadd(fmul(cx, cx), fmul(cy, cy)), fmul(cz, cz)), fadd(splat(rr), _vec(TINY)))
                f = builder.fdiv(fmul(splat(g), K), den, flags=FAST)
                return [fadd(u[0], fmul(f, cx)), fadd(u[1], fmul(f, cy)), fadd(u[2], fmul(f, cz))]

            def slot_ptr(slot, c):
                off = builder.add(builder.mul(slot, ir.Constant(I64, 6 * LANES)), ir.Constant(I64, c * LANES))
                return builder.gep(dptr["ring"], [off], inbounds=True, source_etype=F64)

            def store_corner(slot, r, e):
                for c in range(3):
                    vstore(r[c], slot_ptr(slot, c), 64)
                    vstore(e[c], slot_ptr(slot, 3 + c), 64)

            def load_corner(slot):
                return [vload(slot_ptr(slot, c), 64) for c in range(3)], [vload(slot_ptr(slot, 3 + c), 64)
                                                                          for c in range(3)]

            # state carried across iterations (promoted to registers by mem2reg)
            st_r = [cgutils.alloca_once(builder, V) for _ in range(6)]
            st_u = [cgutils.alloca_once(builder, V) for _ in range(3)]
            st_slot = cgutils.alloca_once(builder, I64)
            st_pslot = cgutils.alloca_once(builder, I64)
            for a in st_u:
                builder.store(_vec(0.0), a)
            zero64 = ir.Constant(I64, 0)
            one64 = ir.Constant(I64, 1)
            S = builder.add(stridev, one64)
            with builder.if_then(builder.icmp_signed(">", nc, zero64)):
                r, e = corner(zero64)
                for a, v in zip(st_r, r + e):
                    builder.store(v, a)
                store_corner(zero64, r, e)
                builder.store(zero64, st_slot)
                builder.store(zero64, st_pslot)
                k_mid = builder.select(builder.icmp_signed("<", stridev, nc), stridev, nc)

                def phase(k, chord):
                    r, e = corner(k)
                    a = [builder.load(x) for x in st_r]
                    u = [builder.load(x) for x in st_u]
                    km1 = builder.sub(k, one64)
                    u = edge(a[:3], a[3:], r, e, builder.load(elt("sg", km1)), builder.load(elt("sr", km1)), u)
                    slot = builder.load(st_slot)
                    nxt = builder.add(slot, one64)
                    nxt = builder.select(builder.icmp_signed("==", nxt, S), zero64, nxt)
                    if chord:
                        ps = builder.load(st_pslot)
                        pr, pe = load_corner(ps)
                        pn = builder.add(ps, one64)
                        builder.store(builder.select(builder.icmp_signed("==", pn, S), zero64, pn), st_pslot)
                        ks = builder.sub(k, stridev)
                        u = edge(pr, pe, r, e, builder.load(elt("cg", ks)), builder.load(elt("cr", ks)), u)
                    store_corner(nxt, r, e)
                    builder.store(nxt, st_slot)
                    for x, v in zip(st_r, r + e):
                        builder.store(v, x)
                    for x, v in zip(st_u, u):
                        builder.store(v, x)

                with cgutils.for_range_slice(builder, one64, k_mid, one64, inc=True) as (k, _):
                    phase(k, False)
                with cgutils.for_range_slice(builder, k_mid, nc, one64, inc=True) as (k, _):
                    phase(k, True)
            for c in range(3):
                vstore(builder.load(st_u[c]), builder.gep(dptr["U"], [ir.Constant(I64, c * LANES)], inbounds=True,
                                                          source_etype=F64), 64)
            return context.get_dummy_value()

        return sig, codegen


    @njit(nogil=True, fastmath=True, error_model="numpy")
    def lanes_chunks(T, n, vx, vy, vz, stride, sg, sr, cg, cr, out, counter, nchunk):
        ng = T.shape[1] // LANES
        ring = aligned_scratch((stride + 1) * 6 * LANES)[0]
        U = aligned_scratch(3 * LANES)[0]
        scale = 1.0 / FOUR_PI
        q = claim(counter)
        while q < nchunk:
            for g in range(q * ng // nchunk, (q + 1) * ng // nchunk):
                i0 = g * LANES
                group_velocity(T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U)
                for j in range(LANES):
                    i = i0 + j
                    if i < n:
                        out[i, 0] += U[j] * scale
                        out[i, 1] += U[LANES + j] * scale
                        out[i, 2] += U[2 * LANES + j] * scale
            q = claim(counter)


    return lanes_chunks


def transpose_targets(p):
    """Targets (n, 3) as (3, n rounded up to LANES), padded with copies of the last target."""
    n = p.shape[0]
    npad = (n + LANES - 1) // LANES * LANES
    T = np.empty((3, npad))
    T[:, :n] = p.T
    T[:, n:] = p[-1][:, None]
    return T


def rates(ns: int, rounds=2, reps=5, threads=1) -> dict:
    lat, p = kernel_lattice(600, ns, 4000)
    p = np.ascontiguousarray(p)
    (stride, arrays), = stacked_lattices([lat]).items()
    vx, vy, vz, sg, sr, cg, cr = (np.ascontiguousarray(a) for a in arrays)
    counter = np.zeros(1, np.int64)
    pairs = (sg.size + cg.size) * p.shape[0]
    T = transpose_targets(p)
    nt = p.shape[0]

    def base(o):
        if threads > 1:
            run_chunked(_lattice_chunks, (p, vx, vy, vz, stride, sg, sr, cg, cr, o), nt, pairs, threads)
            return
        counter[0] = 0
        _lattice_chunks(p, vx, vy, vz, stride, sg, sr, cg, cr, o, counter, 1)

    variants = {"base": base}
    flags = llb.get_host_cpu_features().flatten().split(",")
    for name, r14 in (("lanes_f32", False), ("lanes_rsqrt14", True)):
        if r14 and "+avx512f" not in flags:
            continue
        k = make_kernel(r14)

        def run(o, k=k):
            if threads > 1:
                run_chunked(k, (T, nt, vx, vy, vz, stride, sg, sr, cg, cr, o), T.shape[1] // LANES, pairs, threads)
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
