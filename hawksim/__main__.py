"""`python -m hawksim` and the `hawksim` console script (:func:`run`)."""

import os
import signal
import sys


REDELIVERY_DELAY_S = 0.01
"""Seconds after a dropped KeyboardInterrupt that it is delivered again (:func:`redeliver_dropped_interrupts`)."""


def _terminate(signum, frame):
    raise KeyboardInterrupt


def redeliver_dropped_interrupts(unraisable) -> None:
    """``sys.unraisablehook``: a KeyboardInterrupt that Python had to drop is delivered again (at the main thread's
    next check), so a Ctrl-C or SIGTERM is never lost; other unraisable exceptions go to the default hook.

    A signal handler raises in whatever frame is running; inside a weakref callback or ``__del__`` (importlib's
    module-lock callback ``_get_module_lock.<locals>.cb`` during an import, measured in the issue-18 trial) Python
    prints "Exception ignored in ..." and carries on: `hawksim trim` then ran to the end (exit 0, 72 s after the
    Ctrl-C) and `hawksim dataset`, its start-up stalled, failed with a traceback 10 s later."""
    if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
        import threading

        # not from here: a handler run inside this hook would be dropped too ("Exception ignored in
        # sys.unraisablehook"); 10 ms later the main thread is past it (were it in another such callback, the
        # interrupt would come back here). A real SIGINT to the main thread, so that a blocking call there returns.
        main = threading.main_thread().ident
        timer = threading.Timer(REDELIVERY_DELAY_S, signal.pthread_kill, args=(main, signal.SIGINT))
        timer.daemon = True
        timer.start()
        return
    sys.__unraisablehook__(unraisable)


def run() -> int:
    """The hawksim command: :func:`hawksim.cli.main`. SIGTERM (a batch system's stop, ``kill``) is an interrupt like
    Ctrl-C: the command cleans up as for a Ctrl-C (a data set keeps its committed rows, a recording holds the steps
    flown, a Dask cluster is shut down quietly) and exits with status 130 and one line. A Ctrl-C before the CLI has
    its own handler (while its modules are imported, ~0.5 s) also exits 130 with one line."""
    signal.signal(signal.SIGTERM, _terminate)
    sys.unraisablehook = redeliver_dropped_interrupts
    # After an interrupt the CLI leaves at once (_leave_now); multiprocessing's resource tracker (a process of its
    # own, started with this interpreter's -W options) then removes the Dask workers' semaphores, as is its job, and
    # would warn of them on stderr as leaked.
    sys.warnoptions.append("ignore:resource_tracker:UserWarning")
    # The CLI never renders: without this, importing mujoco imports glfw, which starts a Python subprocess to read
    # glfw's version, and a Ctrl-C that reached that subprocess printed its traceback. (A user's own setting stays.)
    os.environ.setdefault("MUJOCO_GL", "disable")
    try:
        from hawksim.cli import main

        code = main()
    except KeyboardInterrupt:
        print("hawksim: interrupted", file=sys.stderr)
        code = 130
    if code == 130:
        _leave_now(code)
    return code


def _leave_now(code: int) -> None:
    """After an interrupt: flush and leave at once (os._exit), skipping the interpreter's shutdown. A Dask cluster
    interrupted in its start-up keeps a thread that goes on starting workers, and distributed's atexit handlers then
    waited for it, 10-23 s in the issue-18 trial, while a worker started after the Ctrl-C printed a traceback;
    leaving at once ends the workers too (each exits when its parent's pipe closes). What hawksim writes is
    complete by then: samples committed, recordings and networks fsync'ed and renamed."""
    if "multiprocessing" in sys.modules:  # the CLI's only such children are its Dask workers: one may have been
        for child in sys.modules["multiprocessing"].active_children():  # started after the interrupt killed the
            child.kill()  # others
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


if __name__ == "__main__":
    sys.exit(run())
