"""Dask clients for the UVLM's embarrassingly parallel work (data sets, stability derivatives).

``dask_client(scheduler, workers)`` yields a client of a running scheduler (e.g. dask-jobqueue on SLURM) or of a
LocalCluster of single-threaded worker processes. Each worker runs numba, OpenMP, MKL and OpenBLAS on one thread:
the UVLM's small problems scale poorly over threads, so one process per core is faster than one process with a
thread per core (the measurement, made before the kernels moved to aero.scheduling's thread pool and not
repeated since: docs/performance.md).
"""

from __future__ import annotations

import logging
import os
import signal
import threading
from contextlib import contextmanager

ONE_THREAD = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
"""Environment of the workers."""


SCHEDULER_TIMEOUT_S = 5.0
"""Seconds to wait for a Dask scheduler given by address before giving up (dask's default is 30 s)."""

INTERRUPTED_CLOSE_S = 0.5
"""Seconds the client and the cluster each get to close after a Ctrl-C (their workers already killed); then the
interrupt goes on regardless. Closing a LocalCluster took 2.5-10 s on two loaded cores (load 9-12)."""


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None):
    """A dask.distributed Client (closed, with its LocalCluster, on exit). ConnectionError (one line, naming the
    address) when a scheduler does not answer within :data:`SCHEDULER_TIMEOUT_S`.

    Ctrl-C (SIGINT to the terminal's process group) at any moment, the LocalCluster's start-up included, raises
    KeyboardInterrupt in this process only, within a fraction of a second: the worker processes are born with SIGINT
    blocked (:func:`_start_local_cluster`), so none prints a traceback, and on the interrupt they are killed (they
    hold nothing: results reach the caller only through this process) before the cluster is closed.

    A scheduler lost mid-run (a future cancelled, "scheduler-connection-lost", or its connection closed) is a
    ConnectionError of one line (:func:`lost_cluster_line`), the environment's failure (exit status 1)."""
    from concurrent.futures import CancelledError

    from dask.distributed import Client
    from distributed.comm.core import CommClosedError

    if scheduler:
        try:
            client, cluster = Client(scheduler, timeout=SCHEDULER_TIMEOUT_S), None
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(f"--scheduler {scheduler}: no Dask scheduler answered within "
                                  f"{SCHEDULER_TIMEOUT_S:g} s ({type(exc).__name__})") from None
    else:
        import multiprocessing

        others = {p.pid for p in multiprocessing.active_children()}  # not ours to kill on a Ctrl-C
        cluster = _start_local_cluster(workers or os.cpu_count() or 1, others)
        try:
            client = Client(cluster)
        except KeyboardInterrupt:
            _abandon_local_workers(others)
            cluster.close()
            raise
    interrupted = lost = False
    try:
        yield client
    except KeyboardInterrupt:
        interrupted = True
        if cluster is not None:
            _abandon_local_workers(others)
        else:
            _quiet()
        raise
    except (CancelledError, CommClosedError) as exc:  # the scheduler went away mid-run (issue 53, defect 2)
        lost = True
        _quiet()
        raise ConnectionError(lost_cluster_line(scheduler, exc)) from None
    finally:
        timeout = INTERRUPTED_CLOSE_S if interrupted or lost else None
        for close in (client.close, cluster.close if cluster is not None else None):
            try:
                if close is not None:
                    close(timeout=timeout)
            except Exception:  # after a Ctrl-C (or a lost scheduler) that is what the caller is told
                if not (interrupted or lost):
                    raise


def lost_cluster_line(scheduler: str | None, exc: BaseException) -> str:
    """The one line of a run whose Dask scheduler (or LocalCluster) was lost mid-run: what happened, and that the
    rows committed before are kept, so the same command on a working cluster continues the file (each result is
    committed as it arrives; a lost one is recomputed)."""
    where = f"the Dask scheduler {scheduler}" if scheduler else "the local Dask cluster"
    reason = getattr(exc, "reason", None) or type(exc).__name__
    return (f"{where} was lost mid-run ({reason}): every result committed before is kept; rerun the same command "
            "on a working cluster to continue")


def _start_local_cluster(workers: int, others: set):
    """A LocalCluster of ``workers`` single-threaded processes whose SIGINT is blocked from birth (``others``: the
    pids of multiprocessing children that are not the cluster's, spared on a Ctrl-C).

    A signal mask is inherited by threads from the thread that creates them and by processes across fork and exec,
    so the cluster is built in a thread started with SIGINT blocked: dask's event-loop thread, the threads that
    spawn the workers and the workers inherit the mask, while this (the main) thread keeps SIGINT and takes every
    Ctrl-C, also during the ~3 s start-up (an ignored SIGINT, inherited the same way, lost those). multiprocessing's
    resource tracker unblocks SIGINT in the thread that first starts it, so it is started here first. The workers'
    environment (:data:`ONE_THREAD`) is set in this process while they start: they inherit it from their first
    instruction on (LocalCluster's env= alone reached them too late)."""
    import multiprocessing.resource_tracker

    from dask.distributed import LocalCluster

    multiprocessing.resource_tracker.ensure_running()
    box: dict = {}

    def start():
        try:
            # CRITICAL: a worker's heartbeat error under load is not the CLI's one line (the CLI reports failures)
            box["cluster"] = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                          dashboard_address=":0", silence_logs=logging.CRITICAL, death_timeout=10,
                                          env=ONE_THREAD)
        except BaseException as exc:  # handed to the main thread
            box["error"] = exc

    saved = {k: os.environ.get(k) for k in ONE_THREAD}
    os.environ.update(ONE_THREAD)
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            thread = threading.Thread(target=start, name="hawksim LocalCluster start", daemon=True)
            thread.start()
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)
        try:
            while thread.is_alive():
                thread.join(0.05)
        except KeyboardInterrupt:
            _abandon_local_workers(others)
            raise
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    if "error" in box:
        raise box["error"]
    return box["cluster"]


QUIET_AFTER_INTERRUPT = ("distributed", "asyncio")
"""Loggers silenced after a Ctrl-C: a cluster losing its workers logs errors, and the tasks of an interrupted
``client.gather`` end with AllExit, which asyncio reports as "Task exception was never retrieved" with a traceback
each (12 for `hawksim stability`)."""


def _quiet() -> None:
    for name in QUIET_AFTER_INTERRUPT:
        logging.getLogger(name).setLevel(logging.CRITICAL)


def _abandon_local_workers(others: set) -> None:
    """After a Ctrl-C: silence the logs (:data:`QUIET_AFTER_INTERRUPT`) and kill the cluster's worker processes
    (the multiprocessing children but ``others``; SIGKILL: their work is lost anyway), so that closing the cluster
    does not wait for them."""
    import multiprocessing

    _quiet()
    for p in multiprocessing.active_children():
        if p.pid not in others:
            p.kill()
