"""aero.vector_width: the vector width asked for reaches numba in a new process, and vector_bits reads it off the
compiled code."""

import json
import os
import subprocess
import sys

import pytest

from aero.vector_width import apply_vector_width, vector_bits, vector_features

FEATURES = "+64bit,+avx2,+avx512f,+fma"
CLEAN = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CPU_FEATURES", "HAWKSIM_VECTOR_WIDTH")}
PROBE = ("import json, llvmlite.binding as b, aero; from aero.vector_width import vector_bits; "
         "from numba.core import config; "
         "print(json.dumps([vector_bits(), config.CPU_FEATURES, b.get_host_cpu_features().flatten()]))")


def _probe(**extra):
    out = subprocess.run([sys.executable, "-c", PROBE], env={**CLEAN, **extra}, capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout)


def test_features_need_avx512():
    assert vector_features(FEATURES, 512) == FEATURES + ",-prefer-256-bit"
    assert vector_features(FEATURES, 256) == FEATURES + ",+prefer-256-bit"
    assert vector_features("+64bit,+avx2,-avx512f,+fma", 512) is None


def test_default_is_numbas_own_choice():
    bits, numba_features, _ = _probe()
    assert numba_features is None and bits in (256, 512)  # 256 on Intel Xeons, 512 on AMD Zen 5 (module doc)


@pytest.mark.parametrize("width", [256, 512])
def test_the_width_asked_for_reaches_numba_in_a_new_process(width):
    bits, numba_features, host = _probe(HAWKSIM_VECTOR_WIDTH=str(width))
    expected = vector_features(host, width)
    assert numba_features == expected
    assert bits == (width if expected else 256)  # read off the compiled code, not off the setting


def test_user_features_win_and_bad_values_are_refused():
    env = {"HAWKSIM_VECTOR_WIDTH": "512", "NUMBA_CPU_FEATURES": "+avx2"}
    assert apply_vector_width(env) is False and env["NUMBA_CPU_FEATURES"] == "+avx2"
    assert apply_vector_width({"HAWKSIM_VECTOR_WIDTH": "1024"}) is False  # importing aero ignores it
    with pytest.raises(ValueError, match="HAWKSIM_VECTOR_WIDTH"):
        apply_vector_width({"HAWKSIM_VECTOR_WIDTH": "1024"}, strict=True)


def test_the_command_refuses_a_bad_width():
    out = subprocess.run([sys.executable, "-m", "hawksim.cli", "aero", "--speed", "0", "--kinematics",
                          "f=26.1,beta=4.3,phi0=9.4,theta0=-2.8,alpha0=-0.4,phi_a=58.4,alpha_a=48.8", "--json"],
                         env={**CLEAN, "HAWKSIM_VECTOR_WIDTH": "1024"}, capture_output=True, text=True)
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.strip() == "hawksim: HAWKSIM_VECTOR_WIDTH must be 256 or 512, got '1024'"


def test_nothing_changes_once_numba_is_imported():
    import numba  # noqa: F401  (this test process has compiled kernels already)

    env = {"HAWKSIM_VECTOR_WIDTH": "512"}
    assert apply_vector_width(env) is False and "NUMBA_CPU_FEATURES" not in env
    assert vector_bits() in (256, 512)


UVLM_PROBE = """
import hashlib, json
import numpy as np
import aero
from aero.mesh import wing_mesh
from aero.uvlm import UVLMConfig, run_prescribed
from aero.uvlm_kinematics import two_wing_motion
from aero.vector_width import vector_bits
y = np.linspace(0, 0.05, 9)
c = 0.02 * np.sqrt(np.clip(1 - (y / 0.05) ** 2, 0, 1)) + 0.004
t = np.linspace(0.0, 0.6 / 25.0, 30)
R, o, v, w = two_wing_motion(t, freq=25.0)
res = run_prescribed([wing_mesh(y, 0.25 * c, -0.75 * c, 4)], UVLMConfig(), t, R[:, :1], o[:, :1], v[:, :1],
                     w[:, :1], mirror_plane=(np.zeros(3), np.array([0.0, 1.0, 0.0])))
print(json.dumps([vector_bits(), hashlib.sha256(res.force.tobytes() + res.gamma.tobytes()).hexdigest()]))
"""


def test_a_uvlm_run_does_not_depend_on_the_vector_width():
    """Since the lattice kernel puts targets, not corners, in the vector lanes (aero.lattice_lanes), each target's
    arithmetic is the same at 256 and 512 bits: a short free-wake UVLM run (the default float64 direct sum) gives
    the same forces and circulations, bit for bit, at both widths. (The corner-block kernel's sums over corners
    were reassociated by the width: ~1e-12 of a mean lift apart.)"""
    runs = {}
    for width in (256, 512):
        out = subprocess.run([sys.executable, "-c", UVLM_PROBE], env={**CLEAN, "HAWKSIM_VECTOR_WIDTH": str(width)},
                             capture_output=True, text=True, check=True)
        runs[width] = json.loads(out.stdout)
    if runs[512][0] != 512:
        pytest.skip("this host has no AVX-512F: both widths are the 256-bit code")
    assert runs[256][0] == 256
    assert runs[256][1] == runs[512][1]
