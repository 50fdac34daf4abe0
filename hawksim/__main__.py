"""`python -m hawksim` and the `hawksim` console script (:func:`run`)."""

import os
import signal
import sys


def _terminate(signum, frame):
    raise KeyboardInterrupt


def run() -> int:
    """The hawksim command: :func:`hawksim.cli.main`. SIGTERM (a batch system's stop, ``kill``) is an interrupt like
    Ctrl-C: the command cleans up as for a Ctrl-C (a data set keeps its committed rows, a recording holds the steps
    flown, a Dask cluster is shut down quietly) and exits with status 130 and one line. A Ctrl-C before the CLI has
    its own handler (while its modules are imported, ~0.5 s) also exits 130 with one line."""
    signal.signal(signal.SIGTERM, _terminate)
    # The CLI never renders: without this, importing mujoco imports glfw, which starts a Python subprocess to read
    # glfw's version, and a Ctrl-C that reached that subprocess printed its traceback. (A user's own setting stays.)
    os.environ.setdefault("MUJOCO_GL", "disable")
    try:
        from hawksim.cli import main

        return main()
    except KeyboardInterrupt:
        print("hawksim: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(run())
