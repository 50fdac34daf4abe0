"""`python -m hawksim` and the `hawksim` console script (:func:`run`)."""

import os
import sys


def run() -> int:
    """The hawksim command: :func:`hawksim.cli.main`, and a Ctrl-C before it has its own handler (while the CLI's
    modules are imported, ~0.5 s) also exits with status 130 and one line."""
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
