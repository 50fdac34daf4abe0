"""`hawksim warmup`: compile the numba kernels for this CPU once, ahead of the first real command.

numba compiles each kernel the first time it runs in an install and keeps the machine code in the per-user cache
(:mod:`aero.numba_cache`); later processes load it in well under a second. The first ``hawksim aero`` after
``pip install`` would otherwise spend ~5-10 s compiling (docs/uvlm.md, "Speed"). ``hawksim warmup`` runs a
coarse held-body UVLM evaluation, a quasi-steady one, one open-loop quasi-steady wingbeat and one with the per-step
surrogate, which between them use every kernel of ``hawksim aero`` and ``hawksim fly`` with the argument types
those commands pass, but for the UVLM flight's opt-in wake sums: the treecode (which ``--wake-cycles 5`` and up may
plan, ``aero.uvlm``'s ``wake_summation="auto"``) and ``--wake-precision mixed`` compile on their first use, with the
notice below (the treecode's compilation takes seconds). Warming them here too took half of this command's time
(docs/performance.md) for options few flights use, so it does not.
The README's install command runs it. Any command that does have to compile says so first, in one line on stderr
when stderr is a terminal and progress is on (:func:`install_compile_notice`).
"""

from __future__ import annotations

import os
import sys
import time

from hawksim.cli.reproduce_report import render_warmup

NOTICE = ("hawksim: compiling the numba kernels for this CPU (once per install, ~5-10 s; cached in {cache}; "
          "`hawksim warmup` does this ahead)")
"""The one line a command prints on stderr before it compiles its first kernel."""

PREFIXES = ("aero", "hawksim")
"""Modules whose kernels count (a user's own numba code is not announced)."""


def _ours(dispatcher, prefixes) -> bool:
    module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def compile_counter(prefixes=PREFIXES, notice=None):
    """A numba event listener (registered for ``"numba:compile"``) that counts the compilations of kernels from
    ``prefixes`` (loading one from the cache is not a compilation) and calls ``notice()`` before the first.
    Returns the listener; ``listener.count`` is the number of kernels compiled so far."""
    from numba.core import event

    class Counter(event.Listener):
        count = 0

        def on_start(self, ev):
            if _ours(ev.data.get("dispatcher"), prefixes):
                if self.count == 0 and notice is not None:
                    notice()
                self.count += 1

        def on_end(self, ev):
            pass

    listener = Counter()
    event.register("numba:compile", listener)
    return listener


_NOTICE_LISTENER = None


def install_compile_notice(stream=None):
    """Print :data:`NOTICE` on ``stream`` (default stderr) once, before this process compiles its first hawksim
    kernel, where the stream is a terminal (like the progress bars: a script or test that reads stderr sees only
    the contract's lines). Installed once per process; returns the listener, or None off a terminal."""
    global _NOTICE_LISTENER
    stream = sys.stderr if stream is None else stream
    if _NOTICE_LISTENER is None and stream.isatty():
        cache = os.environ.get("NUMBA_CACHE_DIR", "numba's default cache")
        _NOTICE_LISTENER = compile_counter(notice=lambda: print(NOTICE.format(cache=cache), file=stream,
                                                                flush=True))
    return _NOTICE_LISTENER


def cmd_warmup(args) -> dict:
    from hawksim.backends.held import run
    from hawksim.backends.resolution import MIN_STEPS_PER_CYCLE, Resolution
    from hawksim.cli.fly import fly_named
    from hawksim.insect.kinematics import table3_kinematics

    counter = compile_counter()
    kin = table3_kinematics(0.0)
    stages = {}
    t_all = time.perf_counter()
    for aero in ("uvlm", "quasi-steady"):
        t0 = time.perf_counter()
        run(kin, 0.0, Resolution(aero=aero, n_chord=2, n_span=3, steps_per_cycle=MIN_STEPS_PER_CYCLE, cycles=1))
        stages[f"aero_{aero.replace('-', '_')}_s"] = round(time.perf_counter() - t0, 3)
    t0 = time.perf_counter()
    fly_named(1.0, 1, "quasi-steady", steps_per_cycle=MIN_STEPS_PER_CYCLE)
    stages["fly_quasi_steady_s"] = round(time.perf_counter() - t0, 3)
    t0 = time.perf_counter()  # the per-step surrogate's kernels (the network, its record of calls) in the flight loop
    fly_named(1.0, 1, "surrogate")
    stages["fly_surrogate_s"] = round(time.perf_counter() - t0, 3)
    return {"compiled": counter.count, "cache_dir": os.environ.get("NUMBA_CACHE_DIR"), "stages": stages,
            "wall_time_s": round(time.perf_counter() - t_all, 3)}


def register(sub) -> None:
    p = sub.add_parser("warmup", help="compile the numba kernels for this CPU once (after an install)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_warmup, human=render_warmup)
