"""`hawksim warmup` and the compile notice (issue 23, item 4: no cold start for users)."""

import io
import json
import os
import subprocess
import sys

import pytest
from numba import njit
from numba.core import event

from hawksim.cli.warmup import compile_counter

TABLE3_HOVER = "f=26.5,beta=1.5,phi0=-5.5,theta0=15.8,alpha0=0.7,phi_a=60.0,alpha_a=66.9"


def test_compile_counter_announces_once_and_counts_only_the_given_modules():
    calls = []
    ours = compile_counter(prefixes=(__name__,), notice=lambda: calls.append(1))
    theirs = compile_counter(prefixes=("not_this_module",), notice=lambda: calls.append(2))
    try:
        @njit
        def f(x):
            return x + 1

        f(1)
        f(1.5)  # a second specialisation: compiled, counted, not announced again
        f(2)  # already compiled
        assert ours.count == 2 and theirs.count == 0 and calls == [1]
    finally:
        event.unregister("numba:compile", ours)
        event.unregister("numba:compile", theirs)


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_compile_notice_only_on_a_terminal(monkeypatch):
    """Off a terminal (a script, a test, CI reading stderr) no notice is installed; on one, the first compile of
    a hawksim kernel prints the notice, once."""
    from types import SimpleNamespace

    from hawksim.cli import warmup

    monkeypatch.setattr(warmup, "_NOTICE_LISTENER", None)
    assert warmup.install_compile_notice(io.StringIO()) is None
    term = _Terminal()
    listener = warmup.install_compile_notice(term)
    try:
        assert listener is not None and warmup.install_compile_notice(term) is listener
        kernel = SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=SimpleNamespace(__module__="aero.x"))})
        other = SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=SimpleNamespace(__module__="aerox"))})
        listener.on_start(other)
        assert term.getvalue() == ""
        listener.on_start(kernel)
        listener.on_start(kernel)
        assert term.getvalue().count("\n") == 1 and term.getvalue().startswith("hawksim: compiling")
        assert listener.count == 2
    finally:
        event.unregister("numba:compile", listener)


@pytest.mark.slow
def test_warmup_compiles_then_aero_starts_warm(tmp_path):
    """In an empty numba cache: `hawksim warmup` compiles; then `hawksim aero` and a second warmup compile
    nothing (the notice goes to terminals only, so none is printed here)."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    cli = [sys.executable, "-m", "hawksim"]
    first = subprocess.run(cli + ["warmup", "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert first.returncode == 0, first.stderr[-2000:]
    assert json.loads(first.stdout)["compiled"] > 0
    assert "compiling" not in first.stderr
    aero = subprocess.run(cli + ["aero", "--speed", "0", "--kinematics", TABLE3_HOVER, "--cycles", "1",
                                 "--no-progress", "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert aero.returncode == 0, aero.stderr[-2000:]
    assert "compiling" not in aero.stderr
    again = subprocess.run(cli + ["warmup", "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert json.loads(again.stdout)["compiled"] == 0 and "compiling" not in again.stderr
