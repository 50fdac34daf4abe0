"""hawksim.vector_width: when 512-bit vectors are chosen, and that the choice reaches numba in a new process."""

import json
import os
import subprocess
import sys

from hawksim.vector_width import WIDE_VECTOR_CPUS, use_wide_vectors, vector_bits, wide_vector_features

FEATURES = "+64bit,+avx2,+avx512f,+fma"


def test_wide_vectors_only_on_listed_cpus_with_avx512():
    assert wide_vector_features("emeraldrapids", FEATURES) == FEATURES + ",-prefer-256-bit"
    assert wide_vector_features("znver4", FEATURES) == FEATURES + ",-prefer-256-bit"
    assert wide_vector_features("skylake-avx512", FEATURES) is None  # clocks down on 512-bit instructions
    assert wide_vector_features("emeraldrapids", "+64bit,+avx2,-avx512f,+fma") is None
    assert "cascadelake" not in WIDE_VECTOR_CPUS


def test_nothing_changes_once_numba_is_imported():
    import numba  # noqa: F401  (the test process has compiled kernels already)

    env = {}
    assert use_wide_vectors(env) is False and env == {}


def test_user_settings_win():
    code = ("import os; from hawksim.vector_width import use_wide_vectors as u; e = dict(os.environ); "
            "print(u(e), e.get('NUMBA_CPU_FEATURES'))")
    for extra, expect in (({"NUMBA_CPU_FEATURES": "+avx2"}, "False +avx2"), ({"HAWKSIM_VECTOR_WIDTH": "256"},
                                                                             "False None")):
        env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_FEATURES", "HAWKSIM_VECTOR_WIDTH")}
        env.update(extra)
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        assert out.stdout.strip() == expect


def test_choice_reaches_numba_in_a_new_process():
    """In a fresh process, use_wide_vectors() decides from the host CPU, and numba's target follows it."""
    code = ("import json, llvmlite.binding as b; from hawksim.vector_width import use_wide_vectors, vector_bits; "
            "w = use_wide_vectors(); from numba.core import config; "
            "print(json.dumps([w, vector_bits(), config.CPU_FEATURES, b.get_host_cpu_name(), "
            "b.get_host_cpu_features().flatten()]))")
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_FEATURES", "HAWKSIM_VECTOR_WIDTH")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    chosen, bits, numba_features, cpu, features = json.loads(out.stdout)
    expected = wide_vector_features(cpu, features)
    assert chosen is (expected is not None)
    assert numba_features == expected
    assert bits == (512 if chosen else 256)
    assert vector_bits() in (256, 512)
