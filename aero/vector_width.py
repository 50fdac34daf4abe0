"""Opt-in 512-bit vectors for the numba kernels (process-wide): ``HAWKSIM_VECTOR_WIDTH=512``.

LLVM, and so numba, vectorises for 256-bit registers on every AVX-512 CPU by default (the tuning flag
``prefer-256-bit``), because the first AVX-512 server CPUs (Skylake-SP, Cascade Lake) lower their clock while
512-bit instructions run. Later CPUs (Intel Ice Lake-SP and newer Xeons, AMD Zen 4 and 5) do not, and there the
lattice Biot-Savart kernel, whose corner loop is bound by the latency of its 1/sqrt refinement, runs 1.2-1.35x
faster with 512-bit vectors (measured on an Emerald Rapids KVM guest with 2 cores: docs/uvlm.md, "Speed").

numba fixes its code-generation target once per process (``NUMBA_CPU_FEATURES``, read when numba is imported), so
the width cannot be chosen per function. It is therefore opt-in: with ``HAWKSIM_VECTOR_WIDTH=512`` in the
environment, importing :mod:`aero` (before numba) sets ``NUMBA_CPU_FEATURES`` to the host's features with 512-bit
vectors preferred, for this process and its children (dask workers). Results differ from the default 256-bit
code only in the rounding of reassociated sums (~1e-15 relative per kernel call, ~1e-12 on a 220-step UVLM run's
mean lift), so a data set is bit-reproducible only with the same setting.
"""

from __future__ import annotations

import os
import sys

ENV = "HAWKSIM_VECTOR_WIDTH"
"""Environment variable: 512 asks for 512-bit vectors; unset or 256 keeps numba's default."""


def wide_vector_features(features: str) -> str | None:
    """``NUMBA_CPU_FEATURES`` for 512-bit vectors given the host's flattened LLVM feature string (such as
    ``"+avx512f,+fma,..."``), or None when the host lacks AVX-512F."""
    if "+avx512f" not in features.split(","):
        return None
    return features + ",-prefer-256-bit"


def apply_vector_width(environ=None, strict: bool = False) -> bool:
    """Set ``NUMBA_CPU_FEATURES`` for 512-bit vectors when ``HAWKSIM_VECTOR_WIDTH=512`` asks for them.

    Does nothing (returns False) without that request, when numba is already imported (its target is then
    fixed), when the user set ``NUMBA_CPU_FEATURES`` already, or on a host without AVX-512F. environ: the
    environment to read and set (default ``os.environ``). Returns whether 512-bit vectors were set. A value other
    than 256 or 512 is ignored, or with strict=True raises ValueError (the ``hawksim`` command reports it)."""
    env = os.environ if environ is None else environ
    want = env.get(ENV, "").strip()
    if want not in ("", "256", "512"):
        if strict:
            raise ValueError(f"{ENV} must be 256 or 512, got {want!r}")
        return False
    if want != "512" or "numba" in sys.modules or "NUMBA_CPU_FEATURES" in env:
        return False
    import llvmlite.binding as llb

    value = wide_vector_features(llb.get_host_cpu_features().flatten())
    if value is None:
        return False
    env["NUMBA_CPU_FEATURES"] = value
    return True


def vector_bits() -> int:
    """The vector width [bits] numba compiles for in this process: 512 when ``NUMBA_CPU_FEATURES`` turns off the
    256-bit preference, else 256."""
    return 512 if "-prefer-256-bit" in os.environ.get("NUMBA_CPU_FEATURES", "").split(",") else 256
