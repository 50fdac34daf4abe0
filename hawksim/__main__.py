"""`python -m hawksim` and the `hawksim` console script (:func:`run`)."""

import os
import sys

from hawksim import interrupts


def run() -> int:
    """The hawksim command: :func:`hawksim.cli.main`. SIGTERM (a batch system's stop, ``kill``) is an interrupt like
    Ctrl-C, at any moment (:mod:`hawksim.interrupts`): while the CLI starts (its imports, ~0.5 s) the command leaves
    at once; once the subcommand runs it cleans up (a data set keeps its committed rows, a recording holds the steps
    flown, a Dask cluster is shut down quietly). Either way it exits with status 130 and one line."""
    interrupts.install()
    # After an interrupt the CLI leaves at once (interrupts.leave); multiprocessing's resource tracker (a process of
    # its own, started with this interpreter's -W options) then removes the Dask workers' semaphores, as is its job,
    # and would warn of them on stderr as leaked.
    sys.warnoptions.append("ignore:resource_tracker:UserWarning")
    # The CLI never renders: without this, importing mujoco imports glfw, which starts a Python subprocess to read
    # glfw's version, and a Ctrl-C that reached that subprocess printed its traceback. (A user's own setting stays.)
    os.environ.setdefault("MUJOCO_GL", "disable")
    from hawksim.environment import EnvironmentVariableError, check_environment

    try:  # before numba is imported (hawksim.cli imports it), which reads NUMBA_NUM_THREADS
        check_environment()
    except EnvironmentVariableError as exc:
        print(f"hawksim: {exc}", file=sys.stderr)
        return 2
    try:
        from hawksim.cli import main

        code = main()
    except KeyboardInterrupt:  # raised outside main's own handling (its failure path)
        code = 130
        print(interrupts.LINE, file=sys.stderr)
    if code == 130:
        interrupts.leave(code)
    return code


if __name__ == "__main__":
    sys.exit(run())
