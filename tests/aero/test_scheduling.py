"""aero.scheduling: the kernels' chunks taken on demand give the same bits for any chunking and thread count, and
concurrent Python threads may call the kernels."""

import hashlib
import json
import os
import subprocess
import sys

import numba
import numpy as np
import pytest

from aero import scheduling
from aero.biot_savart import lattice_chunks, _ring_chunks, _segment_chunks, pack, ring_influence
from aero.lattice import _fill, ring_lattice
from aero.lattice_lanes import _lanes_chunks, transpose_targets


def _wake_like(rows=40, ns=8, seed=0):
    rng = np.random.default_rng(seed)
    G = np.zeros((rows + 1, ns + 1, 3))
    G[..., 0] = -1e-3 * np.arange(rows + 1)[:, None]
    G[..., 1] = 3e-3 * np.arange(ns + 1)[None, :]
    G += 2e-4 * rng.normal(size=G.shape)
    lat = ring_lattice(G, 1e-3 * rng.normal(size=(rows, ns)), 1e-8, 1e-8)
    p = np.stack([-0.04 * rng.random(300), 0.024 * rng.random(300), 0.003 * rng.normal(size=300)], axis=1)
    return lat, p


def _lattice_args(lat, p):
    stride = lat.G.shape[1]
    arrays = np.empty((7, lat.G.shape[0] * stride))
    _fill(lat.G, lat.span_gamma, lat.span_rc2, lat.chord_gamma, lat.chord_rc2, 0, *arrays)
    vx, vy, vz, sg, sr, cg, cr = arrays
    return (p, vx, vy, vz, stride, sg, sr, cg, cr, np.zeros((p.shape[0], 3)))


def _tasks(kernel, args, nchunk, ntask):
    """Run ntask tasks of kernel one after the other over nchunk chunks (as the threads would, in any order)."""
    counter = np.zeros(1, dtype=np.int64)
    for _ in range(ntask):
        kernel(*args, counter, nchunk)
    return counter[0]


def test_any_chunking_and_task_count_gives_the_same_bits():
    """Every chunk is taken exactly once (a chunk done twice would double its targets, one skipped would leave
    zeros) and a target's arithmetic does not depend on its chunk: bit-identical outputs, for the four kernels,
    run as sequential tasks and on real threads."""
    lat, p = _wake_like()
    rng = np.random.default_rng(2)
    corners = rng.normal(size=(30, 4, 3)) * 1e-2
    normals = rng.normal(size=p.shape)
    a = rng.normal(size=(50, 3)) * 1e-2
    seg = pack(a, a + 1e-3 * rng.normal(size=a.shape), rng.normal(size=50), 1e-6)
    cases = [(lattice_chunks, lambda: _lattice_args(lat, p), -1),
             (_lanes_chunks, lambda: (transpose_targets(p), p.shape[0], *_lattice_args(lat, p)[1:]), -1),
             (_ring_chunks, lambda: (p, normals, corners, 1e-6, np.zeros((p.shape[0], 30))), -1),
             (_segment_chunks, lambda: (p, *seg, np.zeros((p.shape[0], 3))), -1)]
    for kernel, make, out_index in cases:
        args = make()
        _tasks(kernel, args, 1, 1)
        ref = args[out_index]
        assert np.abs(ref).max() > 0
        for nchunk, ntask in ((3, 1), (7, 2), (64, 5), (300, 2), (1000, 3)):
            args = make()
            claimed = _tasks(kernel, args, nchunk, ntask)
            assert claimed == nchunk + ntask  # each chunk once, and one look past the end per task
            assert np.array_equal(args[out_index], ref), (kernel, nchunk, ntask)
        for threads in (2, 3):
            args = make()
            old = scheduling.MIN_PARALLEL_WORK
            scheduling.MIN_PARALLEL_WORK = 0
            try:
                scheduling.run_chunked(kernel, args, p.shape[0], 1.0, threads=threads)
            finally:
                scheduling.MIN_PARALLEL_WORK = old
            assert np.array_equal(args[out_index], ref), (kernel, threads)


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


PROBE = """
import json, threading
import numpy as np
import aero
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
print(json.dumps({"same": all(same), "calls": len(same)}))
"""


def test_concurrent_python_threads_may_call_the_kernels():
    """Three Python threads calling the lattice kernel at once (2 kernel threads each) get the serial answer
    (in a fresh process; numba's workqueue threading layer would abort the process here)."""
    env = {**os.environ, "NUMBA_NUM_THREADS": "2"}
    proc = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert json.loads(proc.stdout.strip().splitlines()[-1]) == {"same": True, "calls": 60}


def test_small_calls_stay_on_the_calling_thread():
    """Below MIN_PARALLEL_WORK no pool thread is used (a 4 x 3 influence matrix)."""
    scheduling._forget_pool()
    A = np.empty((4, 3))
    rng = np.random.default_rng(3)
    ring_influence(rng.normal(size=(4, 3)), rng.normal(size=(4, 3)), rng.normal(size=(3, 4, 3)), 1e-6, A)
    assert scheduling._pool is None and np.all(np.isfinite(A))


MIXED_RTOL = 2e-6
"""Mixed-precision lattice kernel (float32 pair evaluations, float64 sums) against float64, per velocity
component, relative to the largest velocity of the case: float32 rounding (6e-8 relative) of the distances,
unit vectors and edge terms, summed over the lattice's ~700 edges with partial cancellation. Measured on this
test's 40 x 8 lattice: 2.3e-7."""


def test_mixed_precision_kernel_is_close_to_float64_and_deterministic():
    """precision="mixed": within float32 rounding of the float64 kernel, and bit-identical for any thread count
    and chunking (the determinism within a precision setting that issue 23 asks for)."""
    from aero.biot_savart import _lattice_chunks_mixed
    from aero.lattice_lanes import lattice_induced_velocity

    lat, p = _wake_like(seed=4)
    args = _lattice_args(lat, p)
    ref64 = np.zeros((p.shape[0], 3))
    lattice_induced_velocity(*args[:-1], ref64, threads=1)
    mixed = np.zeros((p.shape[0], 3))
    lattice_induced_velocity(*args[:-1], mixed, threads=1, precision="mixed")
    assert not np.array_equal(mixed, ref64)
    assert np.abs(mixed - ref64).max() <= MIXED_RTOL * np.abs(ref64).max()
    f32 = tuple(a.astype(np.float32) for a in args[5:9])
    for nchunk, ntask in ((1, 1), (7, 2), (300, 3)):
        out = np.zeros((p.shape[0], 3))
        _tasks(_lattice_chunks_mixed, (*args[:5], *f32, out), nchunk, ntask)
        assert np.array_equal(out, mixed), (nchunk, ntask)


def test_wake_precision_is_checked():
    from aero.uvlm import UVLMConfig

    assert UVLMConfig().wake_precision == "float64"
    with pytest.raises(ValueError, match="wake_precision"):
        UVLMConfig(wake_precision="float16")
