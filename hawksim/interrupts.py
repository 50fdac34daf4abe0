"""Ctrl-C and SIGTERM for the `hawksim` command: exit 130 with one line, at any moment (docs/conventions.md, "The
CLI contract"; issue 18).

A Python signal handler runs in the main thread at the next bytecode boundary, wherever that is. Raising
KeyboardInterrupt there is how a program normally stops, but at three kinds of place Python loses it or turns it
into something else (each measured on a fresh install, ``scripts/studies/interrupt_cold_trial.py``):

* inside an extension module's import: numpy's ``multiarray`` imports ``datetime`` from C, the KeyboardInterrupt
  becomes ``ImportError: PyCapsule_Import could not import module "datetime"``, and numpy wraps it in its
  20-line "IMPORTANT: PLEASE READ THIS" ImportError (exit 1);
* inside a weakref callback or ``__del__`` (importlib's module-lock callback during any import): Python prints
  "Exception ignored in ..." and carries on, so the command ran to the end (exit 0) or stalled;
* inside ``sys.unraisablehook`` itself: dropped the same way.

So the handler (:func:`install`) works in two phases:

1. **Starting** (from :func:`install` until :func:`begin_work`: the CLI's imports and its argument parsing): nothing
   has been written and no child process started, so a signal prints ``hawksim: interrupted`` and leaves at once
   (:func:`leave`), whatever the main thread was doing.
2. **Working** (the subcommand runs; it may hold a data set open, a Dask cluster, a recording): the handler raises
   KeyboardInterrupt, so that the command cleans up (rolls back, closes the cluster, writes the recording of the
   steps flown) -- except while an import is under way on the main thread or the unraisable hook runs, where it
   leaves the interrupt pending and a helper thread signals the main thread again every
   :data:`REDELIVERY_DELAY_S` until the handler runs at a safe point. A KeyboardInterrupt that Python dropped (a
   weakref callback) reaches :func:`_unraisable` and is made pending the same way.

Before :func:`install` runs, the interpreter's own defaults apply: a signal then (the interpreter's start and
``site``: 24-131 ms after the exec on a fresh install, 0.24-0.47 s with every module compiled from source, measured
at a load average of 6-9, results/cli/interrupt_cold/) kills the process (SIGTERM: a shell shows 143) or makes
Python print a traceback of ``site`` ("Fatal Python error: init_import_site", SIGINT); nothing of hawksim has run
then, so nothing is written. No program can move that moment.
"""

from __future__ import annotations

import os
import signal
import sys
import threading

REDELIVERY_DELAY_S = 0.01
"""Seconds between the re-deliveries of a pending interrupt (one in an import, or one Python dropped)."""

LINE = "hawksim: interrupted"
"""The one line of an interrupt (stderr)."""

_state = {"installed": False, "working": False, "pending": False, "thread": None, "before_leaving": None}


def install() -> None:
    """Make SIGINT and SIGTERM interrupts of the command (phase 1, "starting"; see the module docstring) and hand
    dropped KeyboardInterrupts back (``sys.unraisablehook``). A SIGINT the command was started with ignored stays
    ignored, as Python leaves it (a shell starts background jobs so: a Ctrl-C at the terminal is not theirs)."""
    if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, _handler)
    signal.signal(signal.SIGTERM, _handler)
    sys.unraisablehook = _unraisable
    _state["installed"] = True


def begin_work() -> None:
    """Phase 2, "working": from here an interrupt raises KeyboardInterrupt (at a safe point) so that the command
    cleans up. The CLI calls it before the subcommand runs; a subcommand that writes nothing for a while (train,
    until its network) calls it itself before its first write. A no-op where :func:`install` did not run (the CLI
    called in-process, by tests)."""
    _state["working"] = _state["installed"]


def set_before_leaving(fn) -> None:
    """Call ``fn()`` (errors ignored) before :func:`leave` prints its line: the CLI closes its progress bars, so
    that on a terminal the line starts a line of its own."""
    _state["before_leaving"] = fn


def _in_import_or_hook(frame) -> bool:
    """Whether the main thread is inside an import (a frame of importlib's bootstrap on its stack: the module's
    own code, an extension's initialisation that calls back into Python, importlib's module-lock callbacks) or
    inside :func:`_unraisable`."""
    while frame is not None:
        code = frame.f_code
        if code.co_filename.startswith("<frozen importlib._bootstrap") or code is _unraisable.__code__:
            return True
        frame = frame.f_back
    return False


def _handler(signum, frame) -> None:
    if not _state["working"]:
        leave(130, LINE)
    if _in_import_or_hook(frame):
        _defer()
        return
    _state["pending"] = False
    raise KeyboardInterrupt


def _unraisable(unraisable) -> None:
    """``sys.unraisablehook``: a KeyboardInterrupt that Python had to drop is made pending again (delivered by
    :func:`_defer`'s thread); other unraisable exceptions go to the default hook."""
    if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
        _defer()
        return
    sys.__unraisablehook__(unraisable)


def _defer() -> None:
    """Keep the interrupt pending and make sure the thread that re-delivers it runs: one thread, started at the
    first deferral and running until the process ends (so that no deferral can find it just ending), which
    signals the main thread while an interrupt is pending."""
    _state["pending"] = True
    if _state["thread"] is None:
        t = threading.Thread(target=_redeliver, args=(threading.main_thread().ident,), name="hawksim interrupt",
                             daemon=True)
        _state["thread"] = t
        t.start()


def _redeliver(main_ident: int) -> None:
    # a real signal to the main thread (not _thread.interrupt_main), so that a blocking call there returns; SIGTERM,
    # whose handler is always ours (SIGINT may be ignored: install)
    tick = threading.Event()
    while True:
        tick.wait(REDELIVERY_DELAY_S)
        if _state["pending"]:
            signal.pthread_kill(main_ident, signal.SIGTERM)


def leave(code: int, line: str | None = None) -> None:
    """Print ``line`` (stderr), end this process's child processes and exit with ``code`` at once (os._exit),
    skipping the interpreter's shutdown.

    After an interrupt: a Dask cluster interrupted in its start-up keeps a thread that goes on starting workers,
    and distributed's atexit handlers then waited for it (10-23 s in the issue-18 trial) while a worker started
    after the Ctrl-C printed a traceback. The children are found by their parent pid, not only by
    ``multiprocessing.active_children()``, which lists a worker only once its start has returned: one still being
    spawned (its interpreter starting, its start-up data in the pipe) would otherwise outlive this process and fail
    with a traceback. multiprocessing's resource tracker is spared: it removes the workers' semaphores once this
    process is gone, and then exits. What hawksim writes is complete by then: samples committed, recordings and
    networks fsync'ed and renamed. A further Ctrl-C from here on is ignored (this is the main thread: the handler and
    the CLI's end call it)."""
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_IGN)
    _state["pending"] = False
    if _state["before_leaving"] is not None:
        try:
            _state["before_leaving"]()
        except Exception:
            pass
    if line is not None:
        try:
            sys.stderr.flush()
            os.write(2, (line + "\n").encode())
        except OSError:
            pass
    try:
        sys.stdout.flush()
    except (OSError, ValueError):
        pass
    _end_children()
    os._exit(code)


def _never(*args, **kwargs):
    """In place of fork and exec while the process leaves: the thread that calls it waits for the exit."""
    threading.Event().wait()


def _end_children() -> None:
    """Stop new child processes (fork and ``_posixsubprocess.fork_exec``, behind subprocess and multiprocessing's
    spawn, now wait for the exit: a Dask nanny restarts a worker killed here at once, and the restarted worker, its
    start-up data cut off by the exit, printed a traceback in a clean-clone CI run), then SIGKILL every child but
    multiprocessing's resource tracker until a look finds none (20 ms apart, at most 0.5 s: a spawn already past
    the gate when it closed shows up)."""
    import _posixsubprocess

    _posixsubprocess.fork_exec = _never
    os.fork = _never
    spare = set()
    tracker = sys.modules.get("multiprocessing.resource_tracker")
    if tracker is not None and getattr(tracker._resource_tracker, "_pid", None):
        spare.add(tracker._resource_tracker._pid)
    for _ in range(25):
        left = _children() - spare
        if not left:
            break
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        threading.Event().wait(0.02)


def _children() -> set[int]:
    """Pids of this process's children (Linux: /proc; elsewhere multiprocessing's list)."""
    me = os.getpid()
    try:
        entries = os.listdir("/proc")
    except OSError:
        mp = sys.modules.get("multiprocessing")
        return {p.pid for p in mp.active_children()} if mp is not None else set()
    found = set()
    for name in entries:
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat", "rb") as fh:
                stat = fh.read()
            fields = stat[stat.rindex(b")") + 2:].split()
            if int(fields[1]) == me and fields[0] != b"Z":  # a killed child stays a zombie until the exit
                found.add(int(name))
        except (OSError, ValueError, IndexError):
            continue
    return found
