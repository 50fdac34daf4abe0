"""Environment variables the hawksim command reads through its libraries, checked before those libraries are
imported (issue 53, defect 10): numba reads ``NUMBA_NUM_THREADS`` when it is imported, and a bad value was a
28-line traceback (``0``) or a warning with a traceback and a silent fallback (``abc``). A bad value is a user
mistake: one line naming the variable, exit status 2. Imports nothing heavy (this runs before numba is imported)."""

from __future__ import annotations

import os

MAX_NUMBA_THREADS = 1024
"""Largest NUMBA_NUM_THREADS: each is an OS thread of numba's pool, all started at the first parallel kernel; 1024 is
far above any machine hawksim runs on (2 to 64 cores), and a value beyond it is a typo, not a request."""


class EnvironmentVariableError(ValueError):
    """An environment variable with a value hawksim's libraries cannot use: a bad input (exit status 2)."""


def _positive_int(name: str, text: str, maximum: int) -> None:
    try:
        v = int(text)
    except ValueError:
        raise EnvironmentVariableError(f"environment variable {name}={text!r} is not an integer (unset it or give "
                                       f"the number of threads, 1 to {maximum})") from None
    if not 1 <= v <= maximum:
        raise EnvironmentVariableError(f"environment variable {name}={text!r} must be an integer from 1 to {maximum}")


def check_environment(environ=None) -> None:
    """Raise :class:`EnvironmentVariableError` (one line naming the variable) for a bad value of a variable read
    by hawksim's libraries; an unset or empty variable is their default."""
    env = os.environ if environ is None else environ
    text = env.get("NUMBA_NUM_THREADS", "").strip()
    if text:
        _positive_int("NUMBA_NUM_THREADS", text, MAX_NUMBA_THREADS)
