"""The vector width of the numba kernels (process-wide): ``HAWKSIM_VECTOR_WIDTH=256`` or ``512``.

LLVM, and so numba, picks the width of the vectors it compiles loops for by the host CPU's tuning. On the first
AVX-512 server CPUs (Intel Skylake-SP, Cascade Lake) and the Xeons after them it prefers 256-bit registers (the
tuning flag ``prefer-256-bit``), because those CPUs lower their clock while 512-bit instructions run; on AMD Zen 5
(``znver5``) and Zen 4 (``znver4``; both seen on this project's hosts, docs/performance.md) it uses 512-bit registers
already by default (the compiled kernels hold zmm registers). The default width therefore depends on the host.
The default float64 UVLM gives the same bits at both widths: its lattice kernel (:mod:`aero.lattice_lanes`) puts
targets in the lanes, so a target's arithmetic does not depend on the lane count (tests/aero/test_vector_width.py);
a CPU without AVX-512 takes another route to 1/|r| there, with other last bits. Kernels whose loops numba
vectorises over sources still differ in the last bits between widths: the treecode's near field and the
mixed-precision wake (~1e-15 relative per call; the corner-block kernel moved a 220-step UVLM run's mean lift by
~1e-12).

On an Intel Xeon the 512-bit code ran the UVLM 1.19-1.28x faster (an Emerald Rapids KVM guest with 2 cores:
docs/uvlm.md, "Speed"). numba fixes its code-generation target once per process (``NUMBA_CPU_FEATURES``, read
when numba is imported), so the width cannot be chosen per function. With ``HAWKSIM_VECTOR_WIDTH`` in the
environment, importing :mod:`aero` (before numba) sets ``NUMBA_CPU_FEATURES`` to the host's features with the
256-bit preference turned on (256) or off (512), for this process and its children (dask workers); on a host
without AVX-512F both give the 256-bit code. Unset, numba's own choice stands. A data set made with the treecode or
mixed precision is bit-reproducible only with the same width on the same kind of CPU; :func:`vector_bits` says which
width a process compiles for.
"""

from __future__ import annotations

import functools
import os
import sys

ENV = "HAWKSIM_VECTOR_WIDTH"
"""Environment variable: 256 or 512 asks for that vector width; unset keeps numba's (the host's) default."""

WIDTHS = ("256", "512")


def vector_features(features: str, bits: int = 512) -> str | None:
    """``NUMBA_CPU_FEATURES`` for ``bits``-bit vectors (256 or 512) given the host's flattened LLVM feature string
    (such as ``"+avx512f,+fma,..."``), or None when the host lacks AVX-512F (its code is 256-bit either way)."""
    if "+avx512f" not in features.split(","):
        return None
    return features + (",-prefer-256-bit" if bits == 512 else ",+prefer-256-bit")


def apply_vector_width(environ=None, strict: bool = False) -> bool:
    """Set ``NUMBA_CPU_FEATURES`` for the vector width ``HAWKSIM_VECTOR_WIDTH`` asks for.

    Does nothing (returns False) without that request, when numba is already imported (its target is then
    fixed), when the user set ``NUMBA_CPU_FEATURES`` already, or on a host without AVX-512F. environ: the
    environment to read and set (default ``os.environ``). Returns whether the features were set. A value other
    than 256 or 512 is ignored, or with strict=True raises ValueError (the ``hawksim`` command reports it)."""
    env = os.environ if environ is None else environ
    want = env.get(ENV, "").strip()
    if want not in ("", *WIDTHS):
        if strict:
            raise ValueError(f"{ENV} must be 256 or 512, got {want!r}")
        return False
    if not want or "numba" in sys.modules or "NUMBA_CPU_FEATURES" in env:
        return False
    import llvmlite.binding as llb

    value = vector_features(llb.get_host_cpu_features().flatten(), int(want))
    if value is None:
        return False
    env["NUMBA_CPU_FEATURES"] = value
    return True


@functools.cache
def vector_bits() -> int:
    """The vector width [bits] numba compiles loops for in this process, read off compiled code: a small loop
    compiled here (~0.1 s, once per process) and the widest registers in its machine code (512 for zmm, 256 for
    ymm, else 128). Unlike ``NUMBA_CPU_FEATURES`` this also tells the host's default width."""
    import numpy as np
    from numba import njit

    @njit(fastmath=True, error_model="numpy")
    def axpy(a, x, y):
        for i in range(x.shape[0]):
            y[i] += a * x[i]

    x = np.ones(64)
    axpy(2.0, x, x.copy())
    asm = axpy.inspect_asm(axpy.signatures[0])
    return 512 if "zmm" in asm else 256 if "ymm" in asm else 128
