"""aero.scheduling: the lattice kernel's dynamic work queue gives the same bits for any chunking and thread count,
the threading layer defaults to workqueue, and concurrent Python threads take turns instead of aborting numba."""

import hashlib
import json
import os
import subprocess
import sys

import numba
import numpy as np

from aero.biot_savart import lattice_induced_velocity
from aero.lattice import _fill, lattice_velocity, ring_lattice
from aero.scheduling import DEFAULT_LAYER, ENV, apply_threading_layer


def _wake_like(rows=40, ns=8, seed=0):
    rng = np.random.default_rng(seed)
    G = np.zeros((rows + 1, ns + 1, 3))
    G[..., 0] = -1e-3 * np.arange(rows + 1)[:, None]
    G[..., 1] = 3e-3 * np.arange(ns + 1)[None, :]
    G += 2e-4 * rng.normal(size=G.shape)
    lat = ring_lattice(G, 1e-3 * rng.normal(size=(rows, ns)), 1e-8, 1e-8)
    p = np.stack([-0.04 * rng.random(300), 0.024 * rng.random(300), 0.003 * rng.normal(size=300)], axis=1)
    return lat, p


def _kernel(lat, p, nchunk, ntask):
    stride = lat.G.shape[1]
    arrays = np.empty((7, lat.G.shape[0] * stride))
    _fill(lat.G, lat.span_gamma, lat.span_rc2, lat.chord_gamma, lat.chord_rc2, 0, *arrays)
    out = np.zeros((p.shape[0], 3))
    vx, vy, vz, sg, sr, cg, cr = arrays
    lattice_induced_velocity(p, vx, vy, vz, stride, sg, sr, cg, cr, out, nchunk, ntask)
    return out


def test_any_chunking_and_task_count_gives_the_same_bits():
    """Every chunk is taken exactly once (a chunk done twice would double its targets, one skipped would leave
    zeros) and a target's arithmetic does not depend on its chunk or task: bit-identical outputs."""
    lat, p = _wake_like()
    ref = _kernel(lat, p, 1, 1)
    assert np.abs(ref).max() > 0
    for nchunk, ntask in ((3, 1), (7, 2), (64, 2), (64, 5), (300, 2), (1000, 3)):
        out = _kernel(lat, p, nchunk, ntask)
        assert np.array_equal(out, ref), (nchunk, ntask)


def test_thread_count_does_not_change_a_uvlm_run():
    """A short free-wake UVLM run with 1 and with 2 numba threads: the same force history, bit for bit."""
    from aero.mesh import wing_mesh
    from aero.uvlm import UVLMConfig, run_prescribed
    from aero.uvlm_kinematics import two_wing_motion

    y = np.linspace(0, 0.05, 9)
    c = 0.02 * np.sqrt(np.clip(1 - (y / 0.05) ** 2, 0, 1)) + 0.004
    mesh = wing_mesh(y, 0.25 * c, -0.75 * c, 4)
    t = np.linspace(0.0, 0.6 / 25.0, 30)
    R, o, v, w = two_wing_motion(t, freq=25.0)
    plane = (np.zeros(3), np.array([0.0, 1.0, 0.0]))
    before = numba.get_num_threads()
    runs = []
    try:
        for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
            numba.set_num_threads(threads)
            res = run_prescribed([mesh], UVLMConfig(), t, R[:, :1], o[:, :1], v[:, :1], w[:, :1], mirror_plane=plane)
            runs.append(hashlib.sha256(res.force.tobytes() + res.gamma.tobytes()).hexdigest())
    finally:
        numba.set_num_threads(before)
    assert runs[0] == runs[1]


def test_threading_layer_default_and_user_choice():
    env = {}
    assert apply_threading_layer(env) == DEFAULT_LAYER and env[ENV] == "workqueue"
    env = {ENV: "omp"}
    assert apply_threading_layer(env) == "omp" and env[ENV] == "omp"


PROBE = """
import json, sys, threading
import numpy as np
import aero
import numba
from aero.lattice import lattice_velocity, ring_lattice
rng = np.random.default_rng(0)
G = rng.normal(size=(41, 9, 3)) * 1e-2
lat = ring_lattice(G, rng.normal(size=(40, 8)), 1e-6, 1e-6)
p = rng.normal(size=(2000, 3)) * 1e-2
ref = lattice_velocity(p, [lat])
same = []
def work():
    for _ in range(20):
        same.append(bool(np.array_equal(lattice_velocity(p, [lat]), ref)))
threads = [threading.Thread(target=work) for _ in range(3)]
for t in threads:
    t.start()
for t in threads:
    t.join()
print(json.dumps({"layer": numba.threading_layer(), "same": all(same), "calls": len(same)}))
"""


def test_concurrent_python_threads_take_turns_under_the_default_layer():
    """numba's workqueue layer aborts the process when two threads launch parallel kernels at once; aero's
    kernel lock makes them take turns (in a fresh process, where the default layer is chosen)."""
    env = {k: v for k, v in os.environ.items() if k != ENV}
    env["NUMBA_NUM_THREADS"] = "2"
    proc = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out == {"layer": "workqueue", "same": True, "calls": 60}


def test_lattice_velocity_uses_the_queue_with_more_chunks_than_threads():
    """lattice_velocity (the UVLM's entry point) equals the kernel run as one chunk on one task, bit for bit."""
    lat, p = _wake_like(seed=1)
    assert np.array_equal(lattice_velocity(p, [lat]), _kernel(lat, p, 1, 1))
