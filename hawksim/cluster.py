"""Dask clients for the UVLM's embarrassingly parallel work (data sets, stability derivatives).

``dask_client(scheduler, workers)`` yields a client of a running scheduler (e.g. dask-jobqueue on SLURM) or of a
LocalCluster of single-threaded worker processes. Each worker runs numba, OpenMP, MKL and OpenBLAS on one thread:
the UVLM's small problems scale poorly over threads, so one process per core is faster than one process with a
thread per core (measured for the data set: 0.65 s per sample against 1.9 s when the workers kept 2 numba
threads).
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


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None):
    """A dask.distributed Client (closed, with its LocalCluster, on exit). ConnectionError (one line, naming the
    address) when a scheduler does not answer within :data:`SCHEDULER_TIMEOUT_S`."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            client, cluster = Client(scheduler, timeout=SCHEDULER_TIMEOUT_S), None
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(f"--scheduler {scheduler}: no Dask scheduler answered within "
                                  f"{SCHEDULER_TIMEOUT_S:g} s ({type(exc).__name__})") from None
    else:
        # Set in this process too while the workers start: they inherit it from their first instruction on
        # (LocalCluster's env= alone reached them too late).
        saved = {k: os.environ.get(k) for k in ONE_THREAD}
        os.environ.update(ONE_THREAD)
        # the workers inherit an ignored SIGINT (Python keeps it ignored), so a Ctrl-C reaches this process only:
        # it closes the cluster below instead of every worker printing a KeyboardInterrupt traceback. (A Ctrl-C in the
        # ~3 s the workers take to start is ignored too; blocking SIGINT instead did not reach dask's spawning thread.)
        main = threading.current_thread() is threading.main_thread()
        sigint = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
        try:
            cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", silence_logs=40, death_timeout=10, env=ONE_THREAD)
        finally:
            if sigint is not None:
                signal.signal(signal.SIGINT, sigint)
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        client = Client(cluster)
    try:
        yield client
    except KeyboardInterrupt:
        logging.getLogger("distributed").setLevel(logging.CRITICAL)  # a quiet shutdown after Ctrl-C
        raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
