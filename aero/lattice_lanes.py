"""The lattice kernel: Biot-Savart velocities of a ring lattice's edges at many targets, targets in the vector lanes.

:func:`lattice_induced_velocity` evaluates the Scully-core segment formula of :mod:`aero.biot_savart` for the edges
of a flattened lattice (wing or wake), whose corners each edge shares with its neighbours. Per target, the unit
vector r/|r| is formed once per corner, and per edge, since r0 = r1 - r2,

    v = Gamma / (4 pi) * (r1 x r2) * K / (|r1 x r2|^2 + |r0|^2 r_c^2),   K = (r1 - r2) . (r1/|r1| - r2/|r2|),

which needs no square root per edge and keeps the plain formula's precision for short edges; one division per edge
is left (the core denominator).

How it is laid out (issue 23; ``scripts/studies/lanes_kernel.py`` measured the design, docs/performance.md "A
targets-in-lanes lattice kernel"): a group of :data:`GROUP` = 8 targets sits in the lanes of vectors of
:func:`lane_config` lanes (8 doubles with 512-bit vectors, else 4), and the kernel makes one pass over all corners
per group. At corner k it forms r and r/|r| for the group, adds the spanwise edge k-1 -> k from the previous
corner (held in registers) and the chordwise edge k-stride -> k from a ring buffer of stride + 1 corners (cache
line aligned), and keeps the group's sums in registers. The corner-block kernel it replaces
(:func:`aero.biot_savart.lattice_chunks`, corners in the lanes) stored r and r/|r| of 192 corners per target to
scratch and read corners k + 1 and k + stride back from it, so that with 512-bit vectors every second load
straddled two cache lines; this one has no such loads, no corner scratch pass and no remainder loops. The vector
code is written in LLVM IR (through a numba ``@intrinsic``, as :func:`aero.biot_savart.claim` is), because numba
does not vectorise a loop over corners with the targets in the lanes.

1/|r|: on AVX-512 hosts from the hardware estimate ``vrsqrt14pd`` (relative error < 2^-14) and one fourth-order
Householder step y (1 + e/2 + 3 e^2/8 + 5 e^3/16), e = 1 - s y^2 (error ~ (35/128) (2 d)^4 for an estimate's
error d: below float64 rounding); elsewhere from float32 1/sqrt (the hardware estimate and one Newton step under
fastmath) and the third-order step of :func:`aero.biot_savart.rsqrt`. Both are checked to <= 4 ulp over
1e-36..1e36 (tests/aero/test_lattice_lanes.py). The estimate route was 1.24-1.30x the float32 route at 512 bits
(the float32 conversions cost issue slots on the FMA pipes, which bind here).

Rounding: the same formula and division as the corner-block kernel, but each target's sum runs in corner order
(spanwise and chordwise edges interleaved), so the last bits differ from it (largest velocity difference ~5e-15 of
the largest velocity). A target's sum does not depend on which group, chunk or thread computes it: results are
bit-identical for any thread count, and for a target wherever it sits among the others.
"""

from __future__ import annotations

import functools
from types import FunctionType

import llvmlite.binding as llb
import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import cgutils, config, types
from numba.extending import intrinsic

from aero.biot_savart import (FOUR_PI, PRECISIONS, RSQRT_MIN, TINY, _lattice_chunks_mixed, aligned_buffer,
                              claim)
from aero.scheduling import run_chunked

GROUP = 8
"""Targets per group: the kernel's unit of work (one pass over the corners). A multiple of every lane count."""

INVERSE_SQRTS = ("rsqrt14", "float32")
"""The two routes to 1/|r| (see the module docstring): AVX-512's estimate, or float32 1/sqrt."""

_F64 = ir.DoubleType()
_F32 = ir.FloatType()
_I64 = ir.IntType(64)
_I32 = ir.IntType(32)
_I8 = ir.IntType(8)
_FAST = ("fast",)


def _target_features() -> list[str]:
    """The CPU features numba compiles for (``NUMBA_CPU_FEATURES`` if set, else the host's), as LLVM flags."""
    features = config.CPU_FEATURES if config.CPU_FEATURES is not None else llb.get_host_cpu_features().flatten()
    return features.split(",")


@functools.cache
def lane_config() -> tuple[int, str]:
    """(lanes, inverse_sqrt) the kernel is compiled for in this process: 8 lanes when numba compiles 512-bit
    vectors (:func:`aero.vector_width.vector_bits`), else 4 (so that at the 256-bit preference of Intel's AVX-512
    CPUs no zmm register is used); ``"rsqrt14"`` with AVX-512F (and AVX512VL for 4 lanes), else ``"float32"``.
    A function of the CPU name and features numba compiles for, which key numba's cache, so a cached kernel
    always matches it."""
    from aero.vector_width import vector_bits

    feats = _target_features()
    lanes = 8 if vector_bits() >= 512 else 4
    avx512 = "+avx512f" in feats and (lanes == 8 or "+avx512vl" in feats)
    return lanes, "rsqrt14" if avx512 else "float32"


def config_group(config_) -> int:
    """Targets per group of a kernel configuration (lanes, inverse_sqrt[, interleave]): :data:`GROUP`, or more where
    ``interleave`` lane vectors of ``lanes`` targets each share a pass over the corners."""
    lanes, interleave = config_[0], (config_[2] if len(config_) > 2 else 1)
    return max(GROUP, lanes * interleave)


def group_intrinsic(config_=None):
    """The numba intrinsic ``group_velocity(T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U)`` (njit code
    only): U[c * G + j] = the c-th velocity component (times 4 pi) at target T[:, i0 + j] (j < G) of all
    edges, G = :func:`config_group` (:data:`GROUP` by default). T (3, npad) float64 targets, i0 a multiple of G;
    ring an aligned scratch of (stride + 1) * 6 * G float64, U of 3 * G. config_: (lanes, inverse_sqrt) or (lanes,
    inverse_sqrt, interleave), default :func:`lane_config` (read when a kernel is compiled); the studies pass
    others. ``interleave`` lane vectors share one pass over the corners (independent chains for the out-of-order
    core; each target's sum is the same, bit for bit)."""

    @intrinsic
    def group_velocity(typingctx, T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U):
        sig = types.void(T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U)

        def codegen(context, builder, signature, args):
            cfg = lane_config() if config_ is None else config_
            lanes, inverse_sqrt = cfg[:2]
            interleave = cfg[2] if len(cfg) > 2 else 1
            _emit_group(context, builder, signature, args, lanes, inverse_sqrt, interleave, config_group(cfg))
            return context.get_dummy_value()

        return sig, codegen

    return group_velocity


class _Lanes:
    """IR building blocks on vectors of ``lanes`` float64 (fast-math flags: LLVM may fuse multiply-adds)."""

    def __init__(self, builder, lanes: int, inverse_sqrt: str):
        if lanes not in (4, 8) or inverse_sqrt not in INVERSE_SQRTS:
            raise ValueError(f"unsupported lane configuration {(lanes, inverse_sqrt)}")
        self.b, self.lanes, self.inverse_sqrt = builder, lanes, inverse_sqrt
        self.V = ir.VectorType(_F64, lanes)
        self.VF = ir.VectorType(_F32, lanes)
        mod = builder.module
        self.maxnum = cgutils.get_or_insert_function(mod, ir.FunctionType(self.V, [self.V, self.V]),
                                                     f"llvm.maxnum.v{lanes}f64")
        if inverse_sqrt == "rsqrt14":
            self.rsqrt14 = cgutils.get_or_insert_function(mod, ir.FunctionType(self.V, [self.V, self.V, _I8]),
                                                          f"llvm.x86.avx512.rsqrt14.pd.{64 * lanes}")
        else:
            self.sqrt32 = cgutils.get_or_insert_function(mod, ir.FunctionType(self.VF, [self.VF]),
                                                         f"llvm.sqrt.v{lanes}f32")

    def vec(self, c):
        return ir.Constant(self.V, [c] * self.lanes)

    def load(self, ptr, align):
        return self.b.load(self.b.bitcast(ptr, self.V.as_pointer()), align=align, typ=self.V)

    def store(self, v, ptr, align):
        self.b.store(v, self.b.bitcast(ptr, self.V.as_pointer()), align=align)

    def splat(self, s):
        v = self.b.insert_element(ir.Constant(self.V, ir.Undefined), s, ir.Constant(_I32, 0))
        return self.b.shuffle_vector(v, ir.Constant(self.V, ir.Undefined),
                                     ir.Constant(ir.VectorType(_I32, self.lanes), [0] * self.lanes))

    def add(self, a, b):
        return self.b.fadd(a, b, flags=_FAST)

    def sub(self, a, b):
        return self.b.fsub(a, b, flags=_FAST)

    def mul(self, a, b):
        return self.b.fmul(a, b, flags=_FAST)

    def div(self, a, b):
        return self.b.fdiv(a, b, flags=_FAST)

    def inv_sqrt(self, s):
        """1/sqrt(max(s, RSQRT_MIN)) by the configured route (module docstring)."""
        s = self.b.call(self.maxnum, [s, self.vec(RSQRT_MIN)])
        add, sub, mul, vec = self.add, self.sub, self.mul, self.vec
        if self.inverse_sqrt == "rsqrt14":
            y = self.b.call(self.rsqrt14, [s, vec(0.0), ir.Constant(_I8, -1)])
            e = sub(vec(1.0), mul(mul(s, y), y))
            return add(y, mul(y, mul(e, add(vec(0.5), mul(e, add(vec(0.375), mul(vec(0.3125), e)))))))
        y32 = self.b.fdiv(ir.Constant(self.VF, [1.0] * self.lanes),
                          self.b.call(self.sqrt32, [self.b.fptrunc(s, self.VF)], fastmath=_FAST), flags=_FAST)
        y = self.b.fpext(y32, self.V)
        e = sub(vec(1.0), mul(mul(s, y), y))
        return add(y, mul(mul(y, e), add(vec(0.5), mul(vec(0.375), e))))


def _data(context, builder, aryty, ary):
    """The float64 data pointer of an array argument."""
    return builder.bitcast(context.make_array(aryty)(context, builder, ary).data, _F64.as_pointer())


def inverse_sqrt_intrinsic(config_=None):
    """The numba intrinsic ``inverse_sqrt(s, out)`` (njit code only): out[:m] = the kernel's 1/sqrt(max(s,
    RSQRT_MIN)) for contiguous float64 s, out of m a multiple of the lane count. For tests of the two routes;
    config_ as in :func:`group_intrinsic`."""

    @intrinsic
    def inverse_sqrt(typingctx, s, out):
        def codegen(context, builder, signature, args):
            L = _Lanes(builder, *(lane_config() if config_ is None else config_))
            m = builder.extract_value(context.make_array(signature.args[0])(context, builder, args[0]).shape, 0)
            src, dst = (_data(context, builder, t, a) for t, a in zip(signature.args, args))
            step = ir.Constant(_I64, L.lanes)
            with cgutils.for_range_slice(builder, ir.Constant(_I64, 0), m, step, inc=True) as (k, _):
                x = L.load(builder.gep(src, [k], inbounds=True, source_etype=_F64), 8)
                L.store(L.inv_sqrt(x), builder.gep(dst, [k], inbounds=True, source_etype=_F64), 8)
            return context.get_dummy_value()

        return types.void(s, out), codegen

    return inverse_sqrt


def _emit_group(context, builder, signature, args, lanes: int, inverse_sqrt: str, interleave: int = 1,
                group: int = GROUP) -> None:
    """The IR of one group_velocity call: group // lanes lane vectors of targets, ``interleave`` of them per pass
    over the corners."""
    nvec = group // lanes
    if group % lanes or nvec % interleave:
        raise ValueError(f"a group of {group} targets is not {interleave}-interleaved vectors of {lanes} lanes")
    L = _Lanes(builder, lanes, inverse_sqrt)
    vec, splat, add, sub, mul = L.vec, L.splat, L.add, L.sub, L.mul
    vload, vstore = L.load, L.store
    V = L.V
    aty = signature.args
    names = {0: "T", 2: "vx", 3: "vy", 4: "vz", 6: "sg", 7: "sr", 8: "cg", 9: "cr", 10: "ring", 11: "U"}
    dptr = {name: _data(context, builder, aty[idx], args[idx]) for idx, name in names.items()}
    i0v, stridev = args[1], args[5]
    nc = builder.extract_value(context.make_array(aty[2])(context, builder, args[2]).shape, 0)
    npad = builder.extract_value(context.make_array(aty[0])(context, builder, args[0]).shape, 1)
    H = range(interleave)

    def at(name, k):
        return builder.gep(dptr[name], [k], inbounds=True, source_etype=_F64)

    def slot_ptr(slot, c, j):
        off = builder.add(builder.mul(slot, ir.Constant(_I64, 6 * lanes * interleave)),
                          ir.Constant(_I64, (c * interleave + j) * lanes))
        return builder.gep(dptr["ring"], [off], inbounds=True, source_etype=_F64)

    def edge(a, ea, b, eb, g, rr, u):
        """u + the edge a -> b's term: corners' distance vectors a, b and unit vectors ea, eb."""
        cx = sub(mul(a[1], b[2]), mul(a[2], b[1]))
        cy = sub(mul(a[2], b[0]), mul(a[0], b[2]))
        cz = sub(mul(a[0], b[1]), mul(a[1], b[0]))
        K = add(add(mul(sub(a[0], b[0]), sub(ea[0], eb[0])), mul(sub(a[1], b[1]), sub(ea[1], eb[1]))),
                mul(sub(a[2], b[2]), sub(ea[2], eb[2])))
        den = add(add(add(mul(cx, cx), mul(cy, cy)), mul(cz, cz)), add(splat(rr), vec(TINY)))
        f = L.div(mul(splat(g), K), den)
        return [add(u[0], mul(f, cx)), add(u[1], mul(f, cy)), add(u[2], mul(f, cz))]

    zero = ir.Constant(_I64, 0)
    one = ir.Constant(_I64, 1)
    slots = builder.add(stridev, one)
    # state carried across corners, per interleaved vector, in allocas that LLVM promotes to registers
    st_prev = [[cgutils.alloca_once(builder, V) for _ in range(6)] for _ in H]
    st_u = [[cgutils.alloca_once(builder, V) for _ in range(3)] for _ in H]
    st_slot = cgutils.alloca_once(builder, _I64)
    st_partner = cgutils.alloca_once(builder, _I64)
    for h0 in range(0, nvec, interleave):
        p = []
        for j in H:
            first = builder.add(i0v, ir.Constant(_I64, (h0 + j) * lanes))
            p.append([vload(builder.gep(dptr["T"], [builder.add(builder.mul(ir.Constant(_I64, c), npad), first)],
                                        inbounds=True, source_etype=_F64), 8) for c in range(3)])

        def corner(k, p=p):
            cs = [splat(builder.load(at(n, k))) for n in ("vx", "vy", "vz")]
            out = []
            for j in H:
                r = [sub(p[j][c], cs[c]) for c in range(3)]
                inv = L.inv_sqrt(add(add(mul(r[0], r[0]), mul(r[1], r[1])), mul(r[2], r[2])))
                out.append((r, [mul(rc, inv) for rc in r]))
            return out

        def keep(slot, re_):
            for j, (r, e) in zip(H, re_):
                for c in range(3):
                    vstore(r[c], slot_ptr(slot, c, j), 8 * lanes)
                    vstore(e[c], slot_ptr(slot, 3 + c, j), 8 * lanes)
                for x, v in zip(st_prev[j], r + e):
                    builder.store(v, x)

        def step(k, chord):
            """Corner k: its spanwise edge from k - 1 and, if chord, its chordwise edge from k - stride."""
            re_ = corner(k)
            km1 = builder.sub(k, one)
            g_s, rr_s = builder.load(at("sg", km1)), builder.load(at("sr", km1))
            us = []
            for j, (r, e) in zip(H, re_):
                prev = [builder.load(x) for x in st_prev[j]]
                u = [builder.load(x) for x in st_u[j]]
                us.append(edge(prev[:3], prev[3:], r, e, g_s, rr_s, u))
            nxt = builder.add(builder.load(st_slot), one)
            nxt = builder.select(builder.icmp_signed("==", nxt, slots), zero, nxt)
            if chord:
                ps = builder.load(st_partner)
                ks = builder.sub(k, stridev)
                g_c, rr_c = builder.load(at("cg", ks)), builder.load(at("cr", ks))
                for j, (r, e) in zip(H, re_):
                    pr = [vload(slot_ptr(ps, c, j), 8 * lanes) for c in range(3)]
                    pe = [vload(slot_ptr(ps, 3 + c, j), 8 * lanes) for c in range(3)]
                    us[j] = edge(pr, pe, r, e, g_c, rr_c, us[j])
                pn = builder.add(ps, one)
                builder.store(builder.select(builder.icmp_signed("==", pn, slots), zero, pn), st_partner)
            keep(nxt, re_)
            builder.store(nxt, st_slot)
            for j in H:
                for x, v in zip(st_u[j], us[j]):
                    builder.store(v, x)

        for j in H:
            for x in st_u[j]:
                builder.store(vec(0.0), x)
        with builder.if_then(builder.icmp_signed(">", nc, zero)):
            keep(zero, corner(zero))
            builder.store(zero, st_slot)
            builder.store(zero, st_partner)
            k_mid = builder.select(builder.icmp_signed("<", stridev, nc), stridev, nc)
            with cgutils.for_range_slice(builder, one, k_mid, one, inc=True) as (k, _):
                step(k, False)
            with cgutils.for_range_slice(builder, k_mid, nc, one, inc=True) as (k, _):
                step(k, True)
        for j in H:
            for c in range(3):
                vstore(builder.load(st_u[j][c]),
                       builder.gep(dptr["U"], [ir.Constant(_I64, c * group + (h0 + j) * lanes)], inbounds=True,
                                   source_etype=_F64), 8 * lanes)


group_velocity = group_intrinsic()
"""The shipped group kernel (:func:`lane_config`)."""


@njit(nogil=True, fastmath=True, error_model="numpy", cache=True)
def _lanes_chunks(T, n, vx, vy, vz, stride, sg, sr, cg, cr, out, counter, nchunk):
    """One task of :func:`lattice_induced_velocity`: chunks q = claim(counter) < nchunk of the target groups.
    T (3, npad) the targets transposed and padded (:func:`transpose_targets`), n the number of real ones."""
    ng = T.shape[1] // GROUP
    if ng == 0 or vx.shape[0] == 0:
        return
    ring = aligned_buffer((stride + 1) * 6 * GROUP)
    U = aligned_buffer(3 * GROUP)
    scale = 1.0 / FOUR_PI
    q = claim(counter)
    while q < nchunk:
        for g in range(q * ng // nchunk, (q + 1) * ng // nchunk):
            i0 = g * GROUP
            group_velocity(T, i0, vx, vy, vz, stride, sg, sr, cg, cr, ring, U)
            for j in range(min(GROUP, n - i0)):
                out[i0 + j, 0] += U[j] * scale
                out[i0 + j, 1] += U[GROUP + j] * scale
                out[i0 + j, 2] += U[2 * GROUP + j] * scale
        q = claim(counter)


def chunks_kernel(config_):
    """:func:`_lanes_chunks` compiled for another (lanes, inverse_sqrt[, interleave]) than :func:`lane_config` (not
    cached; for tests and studies): the same code with its group kernel from :func:`group_intrinsic` (config_) and
    groups of :func:`config_group` (config_) targets (pad the targets to it: :func:`transpose_targets`)."""
    py = _lanes_chunks.py_func
    code = FunctionType(py.__code__, dict(py.__globals__, group_velocity=group_intrinsic(config_),
                                          GROUP=config_group(config_)), py.__name__)
    return njit(nogil=True, fastmath=True, error_model="numpy")(code)


def supported_configs() -> list[tuple[int, str]]:
    """The (lanes, inverse_sqrt) configurations this host can run: both lane counts with float32 1/sqrt, and with
    the estimate where AVX-512F (8 lanes) and AVX512VL (4 lanes) are there."""
    feats = _target_features()
    out = [(8, "float32"), (4, "float32")]
    if "+avx512f" in feats:
        out.append((8, "rsqrt14"))
        if "+avx512vl" in feats:
            out.append((4, "rsqrt14"))
    return out


def transpose_targets(targets: np.ndarray, group: int = GROUP) -> np.ndarray:
    """Targets (n, 3) as (3, n rounded up to ``group``), padded with copies of the last target (n >= 1)."""
    n = targets.shape[0]
    T = np.empty((3, -(-n // group) * group))
    T[:, :n] = targets.T
    T[:, n:] = targets[-1][:, None]
    return T


def lattice_induced_velocity(targets, vx, vy, vz, stride, span_gamma, span_rr, chord_gamma, chord_rr, out,
                             threads=None, precision="float64"):
    """out[i] += velocity (3,) at targets[i] (n, 3) induced by the edges of a flattened lattice [m/s].

    Corners (nc,) each of vx, vy, vz [m], row-major with ``stride`` corners per row; the edge from corner c to
    c + 1 has circulation span_gamma[c] and rr = |r0|^2 r_c^2 span_rr[c], the edge from c to c + stride
    chord_gamma[c], chord_rr[c]. Edges that do not exist (from the last corner of a row, from the last row) must
    have gamma 0 and rr > 0: they then add exactly zero, so lattices with the same stride can be stacked.
    All arrays contiguous float64. threads: default numba's thread count (:func:`aero.scheduling.run_chunked`;
    the result is the same, bit for bit, for any thread count). precision: one of
    :data:`aero.biot_savart.PRECISIONS`: "float64" runs this module's kernel, "mixed" the corner-block kernel
    with float32 pair evaluations (:func:`aero.biot_savart._lattice_chunks_mixed`; slower than "float64" since
    this kernel, see docs/uvlm.md).
    """
    if precision not in PRECISIONS:
        raise ValueError(f"precision must be one of {PRECISIONS}, got {precision!r}")
    n = targets.shape[0]
    if n == 0 or vx.shape[0] == 0:
        return
    pairs = n * vx.shape[0]
    if precision == "mixed":
        f32 = (a.astype(np.float32) for a in (span_gamma, span_rr, chord_gamma, chord_rr))
        run_chunked(_lattice_chunks_mixed, (targets, vx, vy, vz, stride, *f32, out), n, pairs, threads)
        return
    T = transpose_targets(targets)
    run_chunked(_lanes_chunks, (T, n, vx, vy, vz, stride, span_gamma, span_rr, chord_gamma, chord_rr, out),
                T.shape[1] // GROUP, pairs, threads)
