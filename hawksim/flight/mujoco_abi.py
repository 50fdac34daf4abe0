"""How compiled code reaches MuJoCo from Python: the byte offsets of mjData's fields, the addresses of libmujoco's
functions, LLVM intrinsics to use an integer address as a pointer or to call through it, and a trampoline that
turns a numba function of (m, d, params) into the ``mjcb_control`` of this process (:mod:`hawksim.flight.native`
builds its callback from these).

Offsets: every field of ``mjData`` after ``buffer`` is a pointer (the wheel's ``include/mujoco/mjdata.h``), so a
field's offset is ``buffer``'s plus 8 per field before it; ``buffer`` follows ``time`` and ``energy[2]``, and
``time`` is found by a sentinel in a probe MjData. Every offset used is checked against the address numpy shows
for that field; anything unexpected (another layout, no header, no library) gives None, and the caller keeps its
Python path.
"""

from __future__ import annotations

import ctypes
import glob
import os
import re
from dataclasses import dataclass
from functools import lru_cache

import mujoco
import numpy as np
from llvmlite import ir
from numba import types
from numba.core.extending import intrinsic


@dataclass(frozen=True)
class Layout:
    """Byte offsets of the mjData fields the callback uses, and the addresses of the libmujoco functions."""

    time: int
    qpos: int
    qvel: int
    qfrc_smooth: int
    qfrc_applied: int
    xfrc_applied: int
    xpos: int
    xipos: int
    xmat: int
    cvel: int
    fwd_actuation: int
    fwd_acceleration: int
    full_m: int


def _library() -> ctypes.CDLL | None:
    here = os.path.dirname(mujoco.__file__)
    found = sorted(glob.glob(os.path.join(here, "libmujoco.so*")) + glob.glob(os.path.join(here, "libmujoco*.dylib")))
    return ctypes.CDLL(found[0]) if found else None


def _pointer_fields() -> list[str] | None:
    """Names of mjData's pointer fields after ``buffer`` in declaration order, up to the first field that is not a
    pointer, from the wheel's header."""
    path = os.path.join(os.path.dirname(mujoco.__file__), "include", "mujoco", "mjdata.h")
    try:
        text = open(path).read()
    except OSError:
        return None
    body = re.search(r"struct mjData_ \{(.*?)\n\}", text, re.S)
    if body is None or "void*   buffer;" not in body.group(1):
        return None
    tail = body.group(1).split("void*   buffer;", 1)[1]
    names = []
    for line in tail.splitlines():
        line = line.split("//")[0].strip()
        if not line:
            continue
        m = re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*\s*\*\s*([A-Za-z_][A-Za-z0-9_]*)\s*;", line)
        if m is None:
            break  # the first non-pointer field (``signature``): the offsets of those before it are known
        names.append(m.group(1))
    return names


_SCAN_WORDS = 400_000 // 8
"""How far into mjData :func:`layout` looks for 'time' (mujoco 4.0: at 160 648 bytes, after the solver statistics)."""


@lru_cache(maxsize=1)
def layout() -> Layout | None:
    """The mjData offsets (checked on a probe MjData) and function addresses, or None where they cannot be had."""
    lib, names = _library(), _pointer_fields()
    if lib is None or names is None:
        return None
    m = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body><freejoint/><geom size='.1' mass='1'/></body></worldbody></mujoco>")
    d = mujoco.MjData(m)
    base = d._address
    d.time = 1234.5625  # a sentinel to find 'time', which sits 3 words before 'buffer' (time, energy[2], buffer)
    # read forward in 512-byte blocks and stop at the sentinel: 'time' lies ~2 kB before the struct's end (the
    # pointer fields follow it), so no block reaches past the allocation
    t_off, block = None, 64
    for k in range(_SCAN_WORDS // block):
        words = np.frombuffer((ctypes.c_char * (8 * block)).from_address(base + 8 * block * k), dtype=np.float64)
        hit = np.nonzero(words == 1234.5625)[0]
        if len(hit):
            t_off = 8 * (block * k + int(hit[0]))
            break
    if t_off is None:
        return None
    buf_off = t_off + 24

    def ptr_at(off: int) -> int:
        return int(np.frombuffer((ctypes.c_char * 8).from_address(base + off), dtype=np.int64)[0])

    offs = {k: buf_off + 8 * (1 + i) for i, k in enumerate(names)}  # names[0] is 'arena', right after 'buffer'
    checks = {"qpos": d.qpos, "qvel": d.qvel, "qfrc_smooth": d.qfrc_smooth, "qfrc_applied": d.qfrc_applied,
              "xfrc_applied": d.xfrc_applied, "xpos": d.xpos, "xipos": d.xipos, "cvel": d.cvel}
    for k, arr in checks.items():
        if k not in offs or ptr_at(offs[k]) != arr.ctypes.data:
            return None
    if ptr_at(buf_off) != d.qpos.ctypes.data:
        return None
    fns = []
    for name in ("mj_fwdActuation", "mj_fwdAcceleration", "mj_fullM"):
        try:
            fns.append(ctypes.cast(getattr(lib, name), ctypes.c_void_p).value)
        except AttributeError:
            return None
    if "xmat" not in offs or ptr_at(offs["xmat"]) != d.xmat.ctypes.data:
        return None
    return Layout(time=t_off, qpos=offs["qpos"], qvel=offs["qvel"], qfrc_smooth=offs["qfrc_smooth"],
                  qfrc_applied=offs["qfrc_applied"], xfrc_applied=offs["xfrc_applied"], xpos=offs["xpos"],
                  xipos=offs["xipos"], xmat=offs["xmat"], cvel=offs["cvel"], fwd_actuation=fns[0],
                  fwd_acceleration=fns[1], full_m=fns[2])


# ---- LLVM helpers: an integer address as a pointer, calls through a function address ---------------------------
@intrinsic
def voidptr(typingctx, addr):
    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], ir.IntType(8).as_pointer())
    return types.voidptr(types.intp), codegen


@intrinsic
def address(typingctx, ptr):
    def codegen(context, builder, signature, args):
        return builder.ptrtoint(args[0], ir.IntType(64))
    return types.intp(types.voidptr), codegen


@intrinsic
def call_md(typingctx, fn, m, d):
    """Call void f(const mjModel*, mjData*) at address fn."""
    def codegen(context, builder, signature, args):
        p8 = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [p8, p8])
        f = builder.inttoptr(args[0], fnty.as_pointer())
        builder.call(f, [args[1], args[2]])
        return context.get_dummy_value()
    return types.void(types.intp, types.voidptr, types.voidptr), codegen


@intrinsic
def call_mdx(typingctx, fn, m, d, x):
    """Call void f(const mjModel*, const mjData*, mjtNum* x) at address fn (``mj_fullM``)."""
    def codegen(context, builder, signature, args):
        p8 = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [p8, p8, p8])
        f = builder.inttoptr(args[0], fnty.as_pointer())
        builder.call(f, [args[1], args[2], args[3]])
        return context.get_dummy_value()
    return types.void(types.intp, types.voidptr, types.voidptr, types.voidptr), codegen


class Trampoline:
    """The mjcb_control of this process: ``void f(m, d)`` calling ``_control_impl(m, d, params)`` with this
    process's params array, as a two-instruction LLVM function compiled by llvmlite (milliseconds; the numba
    body above comes from numba's cache)."""

    def __init__(self, impl_address: int, params: np.ndarray):
        import llvmlite.binding as llvm

        llvm.initialize_native_target()
        llvm.initialize_native_asmprinter()
        p8 = ir.IntType(8).as_pointer()
        mod = ir.Module(name="hawksim_native_trampoline")
        mod.triple = llvm.get_process_triple()
        fn = ir.Function(mod, ir.FunctionType(ir.VoidType(), [p8, p8]), name="hawksim_mjcb_control")
        b = ir.IRBuilder(fn.append_basic_block())
        implty = ir.FunctionType(ir.VoidType(), [p8, p8, p8])
        impl = b.inttoptr(ir.Constant(ir.IntType(64), impl_address), implty.as_pointer())
        prm = b.inttoptr(ir.Constant(ir.IntType(64), params.ctypes.data), p8)
        b.call(impl, [fn.args[0], fn.args[1], prm])
        b.ret_void()
        clock = ir.Function(mod, ir.FunctionType(ir.DoubleType(), []), name="hawksim_mjcb_time")
        ir.IRBuilder(clock.append_basic_block()).ret(ir.Constant(ir.DoubleType(), 0.0))
        target = llvm.Target.from_default_triple().create_target_machine()
        module = llvm.parse_assembly(str(mod))
        module.verify()
        self._engine = llvm.create_mcjit_compiler(module, target)
        self._engine.finalize_object()
        self.params = params  # kept alive with the engine
        addr = self._engine.get_function_address("hawksim_mjcb_control")
        self.callback = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)(addr)
        self.no_timer = ctypes.CFUNCTYPE(ctypes.c_double)(self._engine.get_function_address("hawksim_mjcb_time"))
        """An ``mjcb_time`` that returns 0: MuJoCo's stage timers (``mjData.timer``, which nothing here reads) cost
        nothing. The mujoco package's own default clock, a call into its bindings and ``clock_gettime`` per timer,
        took about a quarter of an RK4 step of the hawkmoth without aerodynamics (docs/performance.md)."""
