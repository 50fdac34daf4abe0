"""The augmented-state Floquet analysis of a history network (hawksim.stability.history_floquet)."""

import numpy as np
import pytest

from hawksim.backends.step_network import StepNetwork, load, shipped_path
from hawksim.backends.step_surrogate import lagged_states, new_history

MULTIPLIER_TOL = 2e-3
"""Relative: two central-difference monodromies (step 1e-4 normalized, float32 loads) of the same dynamics; the
shipped surrogate's Floquet fits agree to ~1e-4 between steps (docs/free_flight.md)."""


N_MEMORYLESS_INPUTS = 15
"""The memoryless inputs: the seven kinematic parameters, sin and cos of the phase, the body-axes velocity and angular
velocity; a history network's lagged states follow them (hawksim.backends.step_surrogate)."""


def _silenced(net: StepNetwork) -> tuple[StepNetwork, StepNetwork]:
    """(silent, memoryless) from the history network ``net``: the first with the history inputs' first-layer
    weights zeroed (the same lags, so the map's state still carries the record, which now feeds nothing), the
    second with those inputs removed. Both give the same loads.

    A network with the wake-age input (the regenerated hawksim 0.3.0 network: ``age_beats`` 2, its last input,
    hawksim.backends.step_network.AGE_INPUT) has it folded into the first layer's bias at its saturated value (a
    developed wake, as on an orbit with a record) and removed: a memoryless network has no record, so its flights
    would be launches from no wake (the age counting from 0) while the silent one's, seeded with the orbit's record,
    are not; with the age folded in both see the developed wake."""
    assert net.lags, "the shipped per-step network has history inputs"
    (W0, b0), rest = net.weights[0], net.weights[1:]
    n = N_MEMORYLESS_INPUTS
    n_hist = n + 6 * len(net.lags)
    x_mean, x_std = np.asarray(net.x_mean, float), np.asarray(net.x_std, float)
    if net.age_beats > 0:  # the age input, last, at its saturated value (standardised as the network does)
        age = (net.age_beats - x_mean[n_hist]) / x_std[n_hist]
        b0 = (b0.astype(np.float64) + W0[:, n_hist].astype(np.float64) * age).astype(b0.dtype)
    W0 = np.ascontiguousarray(W0[:, :n_hist])
    W0s = W0.copy()
    W0s[:, n:] = 0.0
    silent = StepNetwork(((W0s, b0), *rest), x_mean[:n_hist], x_std[:n_hist], net.y_mean, net.y_std,
                         lags=net.lags, meta={"test": "silent history"})
    plain = StepNetwork(((np.ascontiguousarray(W0[:, :n]), b0), *rest), x_mean[:n], x_std[:n], net.y_mean,
                        net.y_std, lags=(), meta={"test": "history inputs removed"})
    return silent, plain


@pytest.fixture(scope="module")
def silenced():
    """The silent and memoryless versions of the shipped network, and the memoryless one's 1 m/s orbit (solved here
    with it installed as the shipped network; ~1 s)."""
    from hawksim.backends import step_surrogate
    from hawksim.flight.orbit import periodic_orbit

    silent, plain = _silenced(load(shipped_path()))
    key = str(shipped_path())
    saved = step_surrogate._CACHE.get(key)
    step_surrogate._CACHE[key] = plain
    try:
        orbit = periodic_orbit(1.0, "surrogate")
    finally:
        if saved is None:
            step_surrogate._CACHE.pop(key, None)
        else:
            step_surrogate._CACHE[key] = saved
    assert orbit.converged and orbit.record is None
    return silent, plain, orbit


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
def test_silent_history_gives_the_memoryless_multipliers(silenced, monkeypatch):
    """With history inputs that do not act, the augmented map is block-triangular (the record feeds nothing), so
    its body modes are the memoryless network's multipliers (its 1 m/s orbit's own monodromy) and every other
    multiplier is 0: checks the augmented state's assembly (body rows and columns, their scaling, the split into
    longitudinal and lateral blocks)."""
    from hawksim.backends import step_surrogate
    from hawksim.stability.floquet import monodromy
    from hawksim.stability.history_floquet import history_monodromy

    silent, plain, orbit = silenced
    monkeypatch.setitem(step_surrogate._CACHE, str(shipped_path()), plain)
    ref = monodromy(orbit)
    hf = history_monodromy(orbit, network=silent)
    assert hf.records == 40 and hf.coupling < 1e-6
    for got, want in ((hf.multipliers_long, ref.multipliers_long), (hf.multipliers_lat, ref.multipliers_lat)):
        np.testing.assert_allclose(np.sort_complex(got[:4]), np.sort_complex(want), rtol=MULTIPLIER_TOL,
                                   atol=MULTIPLIER_TOL)
        assert np.abs(got[4:]).max() < 1e-6
    assert hf.residual < 1e-5  # the memoryless orbit is periodic in the augmented state too


@pytest.mark.skipif(not shipped_path().is_file(), reason="the shipped per-step network is not in this checkout")
def test_half_stroke_maps_branch_from_the_orbit_flight_and_its_record(silenced, monkeypatch):
    """An orbit with backend memory has its half-stroke maps taken on copies of the orbit's flight at phase 0 and
    0.5 (hawksim.control.derivatives.Snapshot). With history inputs that do not act they are the settable path's
    maps of the memoryless network: launched one beat earlier (a warm-up beat, the record held), and with the
    orbit's record in the state (the augmented maps: their body block is the settable path's, and the record's
    columns are zero, for it feeds nothing). The same dynamics, differenced from another start (the wings'
    tracking error and the time differ by round-off)."""
    from dataclasses import replace

    from hawksim.backends import step_surrogate
    from hawksim.control.halfstroke import linearize_half_stroke
    from hawksim.flight.orbit import fly_orbit

    silent, plain, orbit = silenced
    key = str(shipped_path())
    monkeypatch.setitem(step_surrogate._CACHE, key, plain)
    ref = linearize_half_stroke(orbit)
    monkeypatch.setitem(step_surrogate._CACHE, key, silent)
    got = linearize_half_stroke(replace(orbit, warm_beats=1))
    assert got.records == 0
    np.testing.assert_allclose(got.x_half, ref.x_half, rtol=0, atol=1e-5)
    for a, b in zip(got.A + got.B0 + got.B1, ref.A + ref.B0 + ref.B1):
        assert np.abs(a - b).max() < MULTIPLIER_TOL
    rec = fly_orbit(orbit, 1).record  # the periodic beat's own calls: the orbit in the augmented state
    aug = linearize_half_stroke(replace(orbit, record=rec, record_dt=orbit.kinematics.period / 40))
    assert aug.records == 40 and aug.A[0].shape == (11 + 240, 11 + 240)
    np.testing.assert_allclose(aug.x_half, ref.x_half, rtol=0, atol=1e-5)
    for a, b in zip(aug.A + aug.B0 + aug.B1, ref.A + ref.B0 + ref.B1):
        assert np.abs(a[:11, :b.shape[1]] - b).max() < MULTIPLIER_TOL  # the body rows and columns
    for a in aug.A:
        assert np.abs(a[:11, 11:]).max() < 1e-9  # the record feeds nothing


@pytest.mark.skipif(not shipped_path().is_file(), reason="the shipped per-step network is not in this checkout")
def test_an_orbit_with_a_record_starts_its_flights_with_it():
    """The shipped 1 m/s orbit carries its record of calls (40 x 6), and a flight from it starts with that record
    (Orbit.seed -> StepSurrogateBackend.reset): the ring holds exactly those rows before the first step, as calls
    at t0 - 40 dt ... t0 - dt; one beat later the record repeats to RECORD_TOL (normalized; measured 6.8e-7)."""
    from hawksim.backends.step_surrogate import HISTORY_ROW, StepSurrogateBackend, history_rows, record_scale
    from hawksim.flight.orbit import RECORD_TOL, fly_orbit, shipped_orbit

    orbit = shipped_orbit(1.0, "surrogate")
    assert orbit.record is not None and orbit.record.shape == (40, 6) and orbit.warm_beats == 0
    assert orbit.record_change <= RECORD_TOL
    backend = StepSurrogateBackend(orbit.kinematics)
    orbit.seed(backend)

    class _State:
        t = 0.0

    backend.reset(_State())
    np.testing.assert_array_equal(history_rows(backend.history, 40), orbit.record)
    times = backend.history[3:3 + 40 * HISTORY_ROW:HISTORY_ROW]
    np.testing.assert_allclose(times, -orbit.record_dt * np.arange(40, 0, -1), rtol=0, atol=1e-15)
    after = fly_orbit(orbit, 1).record
    assert np.abs((after - orbit.record) / record_scale(orbit.kinematics)).max() <= RECORD_TOL
