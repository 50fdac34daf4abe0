"""How the numba kernels share the cores: the threading layer, a dynamic work queue, one launch at a time.

**Threading layer.** numba picks TBB, else OpenMP, else its own ``workqueue`` layer. With GNU OpenMP (what a pip
install of numba gets without TBB) the worker threads spin for a while after each parallel region (libgomp's
default ``GOMP_SPINCOUNT``), and a UVLM step launches 4-5 short regions between stretches of serial numpy work: a
spinning worker takes a core from the main thread whenever the cores are shared. On this 2-core machine, with a
busy-loop competitor on one core, the reference case of ``scripts/benchmarks/bench_contention.py`` took 3.7x as
long with 2 threads as with 1 under GNU OpenMP, and 0.4-0.6x with workqueue or with OpenMP told not to spin
(``OMP_WAIT_POLICY=passive``) (2026-12-02; the figures and their commands are in docs/uvlm.md, "Speed").
Importing :mod:`aero` therefore sets ``NUMBA_THREADING_LAYER=workqueue`` unless the user set it: its threads
sleep on condition variables between regions, it is fork-safe, and, unlike ``OMP_WAIT_POLICY``, it touches no
other library's OpenMP runtime (torch's).

**Dynamic work queue.** workqueue (like OpenMP's default schedule) splits a ``prange`` statically, one equal part
per thread, so a thread that shares its core with another process finishes last and the others wait for it. The
lattice kernel instead starts one task per thread, each of which takes the next chunk of targets from a shared
counter (:func:`aero.biot_savart.claim`, an atomic fetch-and-add) until none is left: a thread on a free core
takes more chunks.
Which thread computes a target does not change its arithmetic, so results are bit-identical for any thread
count and chunking (tested: ``tests/aero/test_scheduling.py``).

**One launch at a time.** workqueue cannot run two parallel regions at once (numba aborts the process if two
Python threads launch kernels concurrently), so every parallel kernel launch in :mod:`aero` holds
:data:`KERNEL_LOCK`; concurrent callers then take turns.
"""

from __future__ import annotations

import os
import sys
import threading

ENV = "NUMBA_THREADING_LAYER"
DEFAULT_LAYER = "workqueue"
"""The layer set when the user has not chosen one (see the module docstring for the measurement)."""

KERNEL_LOCK = threading.RLock()
"""Held around every parallel numba kernel launch in :mod:`aero` (workqueue is not re-entrant across threads)."""


def apply_threading_layer(environ=None) -> str:
    """Set ``NUMBA_THREADING_LAYER`` to :data:`DEFAULT_LAYER` unless set; returns the value in force. Before
    numba's first parallel launch (which reads it), also when numba is already imported."""
    env = os.environ if environ is None else environ
    env.setdefault(ENV, DEFAULT_LAYER)
    if environ is None and "numba" in sys.modules:
        from numba.core import config

        config.THREADING_LAYER = env[ENV]
    return env[ENV]
