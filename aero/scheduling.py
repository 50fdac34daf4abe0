"""How the Biot-Savart kernels share the cores: nogil numba kernels on a small thread pool, chunks taken on demand.

The kernels of :mod:`aero.biot_savart` are compiled without numba's ``parallel=True``. numba's threading layers
split a ``prange`` statically, one equal part per thread, so a thread that shares its core with another process
finishes last while the others wait; and GNU OpenMP (the layer a pip install of numba gets without TBB) keeps its
workers spinning after each parallel region, where they take a core from the main thread's serial numpy work
between the 4-5 short regions of a UVLM step. On this shared 2-core machine the UVLM reference case took
1.6-2.5x as long with 2 numba threads as with 1 that way (ratio of medians 1.8x; 1.7x with a busy-loop
competitor on one core); with the scheme below, 0.63-0.79x with the competitor (docs/uvlm.md, "Speed";
``scripts/benchmarks/bench_contention.py``). ``parallel=True`` also more than doubled the lattice kernel's
compile time (7.2 s against 3.3 s), which a user meets on the first run after an install.

Instead, :func:`run_chunked` splits a kernel's targets into chunks and runs the kernel as one task per thread:
on the calling thread and on the threads of a pool (:class:`concurrent.futures.ThreadPoolExecutor`, the kernels
release the GIL), each task taking the next chunk from a shared counter (:func:`aero.biot_savart.claim`, an
atomic fetch-and-add) until none is left, so a thread on a free core takes more chunks. Idle pool threads sleep.
Which task computes a target does not change its arithmetic: results are bit-identical for any thread count
and chunking (``tests/aero/test_scheduling.py``), and to the former ``parallel=True`` kernels. Concurrent calls
from several Python threads are safe (each call has its own counter).

The thread count is numba's (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``), so the settings that limit numba
(dask workers: :data:`hawksim.cluster.ONE_THREAD`) limit these kernels too.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np

CHUNKS_PER_THREAD = 16
"""Chunks per thread: enough that a thread slowed by another process on its core leaves the chunks it cannot
reach to the others (a chunk costs one more pass over the source's blocks). Tuned: 4 and 16 ran alike within the
run-to-run spread on the shared machine (scripts/benchmarks/bench_scheduling.py, docs/uvlm.md, "Speed")."""

MIN_PARALLEL_WORK = 100_000
"""Smallest kernel call [target-source pair evaluations] that is split over threads; smaller ones run on the
calling thread alone. Tuned: a pool hand-off measured 30 us (~1e4 pair evaluations on one core), so a split
call of 1e5 pairs (~0.3 ms) saves more than it costs; 0 and 1e5 ran alike within the spread
(scripts/benchmarks/bench_scheduling.py)."""

_pool: ThreadPoolExecutor | None = None
_pool_workers = 0
_pool_lock = threading.Lock()


def thread_count() -> int:
    """Threads a kernel call may use: numba's current setting (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``)."""
    return numba.get_num_threads()


def _workers(n: int) -> ThreadPoolExecutor:
    """The pool, with at least n threads."""
    global _pool, _pool_workers
    with _pool_lock:
        if _pool is None or _pool_workers < n:
            old = _pool
            _pool, _pool_workers = ThreadPoolExecutor(max_workers=n, thread_name_prefix="aero-kernel"), n
            if old is not None:
                old.shutdown(wait=False)
        return _pool


def _forget_pool() -> None:
    """In a forked child: the parent's pool threads do not exist there."""
    global _pool, _pool_workers, _pool_lock
    _pool, _pool_workers, _pool_lock = None, 0, threading.Lock()


os.register_at_fork(after_in_child=_forget_pool)


def run_chunked(kernel, args: tuple, n_items: int, work: float, threads: int | None = None) -> None:
    """Run ``kernel(*args, counter, nchunk)`` as one task per thread over ``n_items`` items in chunks.

    kernel: a nogil numba function whose tasks take chunk numbers q = claim(counter) until q >= nchunk and
    process items [q n / nchunk, (q + 1) n / nchunk). work: the call's size [pair evaluations]; below
    :data:`MIN_PARALLEL_WORK` the calling thread runs one chunk. threads: default :func:`thread_count`.
    """
    if n_items <= 0:
        return
    threads = thread_count() if threads is None else threads
    if work < MIN_PARALLEL_WORK:
        threads = 1
    counter = np.zeros(1, dtype=np.int64)
    if threads <= 1:
        kernel(*args, counter, 1)
        return
    nchunk = min(n_items, CHUNKS_PER_THREAD * threads)
    tasks = min(threads, nchunk)
    futures = [_workers(tasks - 1).submit(kernel, *args, counter, nchunk) for _ in range(tasks - 1)]
    try:
        kernel(*args, counter, nchunk)
    finally:
        for f in futures:
            f.result()
