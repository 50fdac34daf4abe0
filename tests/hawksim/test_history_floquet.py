"""The augmented-state Floquet analysis of a history network (hawksim.stability.history_floquet)."""

import numpy as np
import pytest

from hawksim.backends.step_network import StepNetwork, load, shipped_path
from hawksim.backends.step_surrogate import lagged_states, new_history
from hawksim.flight.orbit import shipped_orbit

MULTIPLIER_TOL = 2e-3
"""Relative: two central-difference monodromies (step 1e-4 normalized, float32 loads) of the same dynamics; the
shipped surrogate's Floquet fits agree to ~1e-4 between steps (docs/free_flight.md)."""


def _with_silent_history(net: StepNetwork, lags=(0.5, 1.0)) -> StepNetwork:
    """``net`` with history inputs for ``lags`` whose first-layer weights are zero: the same loads, but the map's
    state now carries the record."""
    (W0, b0), rest = net.weights[0], net.weights[1:]
    extra = 6 * len(lags)
    W0x = np.concatenate([W0, np.zeros((W0.shape[0], extra), np.float32)], axis=1)
    return StepNetwork(((W0x, b0), *rest), np.concatenate([net.x_mean, np.zeros(extra)]),
                       np.concatenate([net.x_std, np.ones(extra)]), net.y_mean, net.y_std, lags=lags,
                       meta={"test": "silent history"})


def test_ring_record_interpolates_like_np_interp():
    """lagged_states against np.interp over the same calls (and the first call's state before them)."""
    rng = np.random.default_rng(0)
    h = new_history((1.0,))
    ts = np.cumsum(rng.uniform(0.5, 1.5, 60)) * 1e-3
    S = rng.normal(size=(60, 6))
    out = np.zeros((2, 6))
    lags = np.array([0.5, 1.0])
    period = 0.02
    for i, (t, s) in enumerate(zip(ts, S)):
        lagged_states(h, t, s, lags, period, out)
        for k, lag in enumerate(lags):
            ref = [np.interp(t - lag * period, ts[:i + 1], S[:i + 1, j]) for j in range(6)]
            np.testing.assert_allclose(out[k], ref, rtol=0, atol=1e-12)


def test_ring_record_wraps_around():
    """A ring of 8 rows over 50 calls (it wraps 6 times): the lag still reads the right rows (np.interp over the
    calls it keeps)."""
    from hawksim.backends.step_surrogate import HISTORY_ROW

    h = np.zeros(3 + HISTORY_ROW * 8)
    h[0] = 8
    ts = np.arange(50) * 1e-3
    S = np.random.default_rng(1).normal(size=(50, 6))
    out = np.zeros((1, 6))
    for i in range(50):
        lagged_states(h, ts[i], S[i], np.array([0.25]), 0.0185, out)  # 4.6 calls back
        lo = max(0, i - 7)
        ref = [np.interp(ts[i] - 0.25 * 0.0185, ts[lo:i + 1], S[lo:i + 1, j]) for j in range(6)]
        np.testing.assert_allclose(out[0], ref, rtol=0, atol=1e-12)


@pytest.mark.skipif(not shipped_path().is_file(), reason="the shipped per-step network is not in this checkout")
def test_silent_history_gives_the_memoryless_multipliers():
    """With history inputs that do not act, the augmented map is block-triangular (the record feeds nothing), so
    its body modes are the memoryless network's multipliers (the shipped 1 m/s orbit's own monodromy) and every
    other multiplier is 0: checks the augmented state's assembly (body rows and columns, their scaling, the split
    into longitudinal and lateral blocks)."""
    from hawksim.stability.floquet import monodromy
    from hawksim.stability.history_floquet import history_monodromy

    orbit = shipped_orbit(1.0, "surrogate")
    assert orbit is not None and orbit.warm_beats == 0
    ref = monodromy(orbit)
    hf = history_monodromy(orbit, network=_with_silent_history(load(shipped_path())))
    assert hf.records == 40 and hf.coupling < 1e-6
    for got, want in ((hf.multipliers_long, ref.multipliers_long), (hf.multipliers_lat, ref.multipliers_lat)):
        np.testing.assert_allclose(np.sort_complex(got[:4]), np.sort_complex(want), rtol=MULTIPLIER_TOL,
                                   atol=MULTIPLIER_TOL)
        assert np.abs(got[4:]).max() < 1e-6
    assert hf.residual < 1e-5  # the memoryless orbit is periodic in the augmented state too


@pytest.mark.skipif(not shipped_path().is_file(), reason="the shipped per-step network is not in this checkout")
def test_half_stroke_maps_branch_from_the_orbit_flight_and_its_record(monkeypatch):
    """An orbit with a warm-up beat (a history network's) has its half-stroke maps taken on copies of the orbit's
    flight at phase 0 and 0.5, record included (hawksim.control.derivatives.Snapshot). With history inputs that do
    not act and the shipped 1 m/s orbit launched one beat earlier, they are the settable path's maps: the same
    dynamics, differenced from another start (the wings' tracking error and the time differ by round-off)."""
    from dataclasses import replace

    from hawksim.backends import step_surrogate
    from hawksim.control.halfstroke import linearize_half_stroke

    orbit = shipped_orbit(1.0, "surrogate")
    ref = linearize_half_stroke(orbit)
    monkeypatch.setitem(step_surrogate._CACHE, str(shipped_path()), _with_silent_history(load(shipped_path())))
    got = linearize_half_stroke(replace(orbit, warm_beats=1))
    np.testing.assert_allclose(got.x_half, ref.x_half, rtol=0, atol=1e-5)
    for a, b in zip(got.A + got.B0 + got.B1, ref.A + ref.B0 + ref.B1):
        assert np.abs(a - b).max() < MULTIPLIER_TOL
