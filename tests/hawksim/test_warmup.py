"""`hawksim warmup` and the compile notice (issue 23, item 4: no cold start for users)."""

import json
import os
import subprocess
import sys

import pytest
from numba import njit
from numba.core import event

from hawksim.cli.warmup import NOTICE, compile_counter

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


@pytest.mark.slow
def test_warmup_compiles_then_aero_starts_warm(tmp_path):
    """In an empty numba cache: `hawksim warmup` compiles (and says so in one line); then `hawksim aero` and a
    second warmup compile nothing and print no notice."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    cli = [sys.executable, "-m", "hawksim"]
    first = subprocess.run(cli + ["warmup", "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert first.returncode == 0, first.stderr[-2000:]
    assert json.loads(first.stdout)["compiled"] > 0
    assert NOTICE.split("(")[0] in first.stderr
    aero = subprocess.run(cli + ["aero", "--speed", "0", "--kinematics", TABLE3_HOVER, "--cycles", "1",
                                 "--no-progress", "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert aero.returncode == 0, aero.stderr[-2000:]
    assert "compiling" not in aero.stderr
    again = subprocess.run(cli + ["warmup", "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert json.loads(again.stdout)["compiled"] == 0 and "compiling" not in again.stderr
