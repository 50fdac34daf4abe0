"""512-bit vectors for hawksim's numba kernels on CPUs that run them at full speed (process-wide).

LLVM, and so numba, vectorises for 256-bit registers on every AVX-512 CPU by default (the tuning flag
``prefer-256-bit``), because the first AVX-512 server CPUs (Skylake-SP, Cascade Lake) lowered their clock when
512-bit instructions ran. On the CPUs in :data:`WIDE_VECTOR_CPUS` they do not, and the UVLM's Biot-Savart kernels,
whose corner loop is bound by the latency of its 1/sqrt refinement, run 1.2-1.35x faster with 512-bit vectors
(measured on an Emerald Rapids KVM guest, 2 cores: docs/uvlm.md, "Speed").

numba reads its code-generation target once per process (``NUMBA_CPU_FEATURES``, when its CPU target is first
used), so this cannot be chosen per function: :func:`use_wide_vectors` sets the variable for the whole process and
its child processes (dask workers) and must run before numba is imported. The ``hawksim`` command and the
benchmark scripts call it first thing; a library user who wants the same calls it before importing ``aero``.
Results differ from 256-bit code only in the rounding of reassociated sums (~1e-15 relative per kernel call,
~1e-12 on a 220-step UVLM run's mean lift).
"""

from __future__ import annotations

import os
import sys

WIDE_VECTOR_CPUS = frozenset({"icelake-server", "sapphirerapids", "emeraldrapids", "graniterapids",
                              "graniterapids-d", "diamondrapids", "znver4", "znver5"})
"""LLVM host CPU names (``llvmlite.binding.get_host_cpu_name()``) whose 512-bit vector instructions run without a
clock penalty (Intel Ice Lake-SP and later Xeons: Intel 64 and IA-32 Architectures Optimization Reference Manual,
vol. 1, ch. "Intel AVX-512"; AMD Zen 4 and 5, which split 512-bit operations into two 256-bit halves at no
frequency cost)."""

OPT_OUT = "HAWKSIM_VECTOR_WIDTH"
"""Environment variable: set to 256 to keep numba's default vector width."""


def wide_vector_features(cpu_name: str, features: str) -> str | None:
    """The ``NUMBA_CPU_FEATURES`` value for 512-bit vectors on a CPU (LLVM name, flattened LLVM feature string
    such as ``"+avx512f,+fma,..."``), or None when the CPU is not in :data:`WIDE_VECTOR_CPUS` or lacks AVX-512F."""
    if cpu_name not in WIDE_VECTOR_CPUS or "+avx512f" not in features.split(","):
        return None
    return features + ",-prefer-256-bit"


def use_wide_vectors(environ=None) -> bool:
    """Let numba vectorise for 512-bit registers in this process when the host CPU runs them at full speed.

    Does nothing (returns False) when numba is already imported (its target is then fixed), when the user set
    ``NUMBA_CPU_FEATURES`` or ``HAWKSIM_VECTOR_WIDTH=256``, or on other CPUs. environ: the environment to set
    (default ``os.environ``). Returns whether 512-bit vectors were chosen."""
    env = os.environ if environ is None else environ
    if "numba" in sys.modules or "NUMBA_CPU_FEATURES" in env or env.get(OPT_OUT, "").strip() == "256":
        return False
    import llvmlite.binding as llb

    value = wide_vector_features(llb.get_host_cpu_name(), llb.get_host_cpu_features().flatten())
    if value is None:
        return False
    env["NUMBA_CPU_FEATURES"] = value
    return True


def vector_bits() -> int:
    """The vector width [bits] numba compiles this process's kernels for (512 when :func:`use_wide_vectors`
    chose it or the user's ``NUMBA_CPU_FEATURES`` asks for it, else 256)."""
    return 512 if "-prefer-256-bit" in os.environ.get("NUMBA_CPU_FEATURES", "").split(",") else 256
