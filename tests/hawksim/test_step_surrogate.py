"""The per-step surrogate (`--aero surrogate`): its file format, its inference, the mirror symmetry it relies on,
and its held-out accuracy against the UVLM on committed flights."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hawksim.backends.base import FlightState
from hawksim.backends.step_network import (
    MIRROR_F,
    MIRROR_M,
    OUTPUTS,
    StepNetwork,
    StepNetworkFileError,
    input_names,
    load,
    mirror_inputs,
    shipped_path,
)
from hawksim.backends.step_surrogate import StepSurrogateBackend
from hawksim.frames import rot_x, rot_y, rot_z
from hawksim.insect.kinematics import table3_kinematics

ROOT = Path(__file__).resolve().parents[2]
FLIGHTS = ROOT / "data" / "uvlm_flights_0.3.0.sqlite"

FOLD_RTOL = 1e-4
"""Relative (to the largest output): the folded float32 network against the float64 reference. float32 carries 24
bits (6e-8); three hidden layers of 128 sums of products accumulate ~sqrt(128) * 6e-8 * (sum of |terms|) per
layer, and the standardisation spans y_std ~ the outputs' size: measured 3e-6; 1e-4 leaves 30x."""


def _random_net(lags=(), hidden=(16, 16), seed=0, age_beats=0.0) -> StepNetwork:
    rng = np.random.default_rng(seed)
    n_in = len(input_names(lags, age_beats))
    sizes = [n_in, *hidden, len(OUTPUTS)]
    weights = tuple((rng.normal(0, 1 / math.sqrt(a), (b, a)).astype(np.float32), rng.normal(0, 0.1, b).astype(
        np.float32)) for a, b in zip(sizes[:-1], sizes[1:]))
    return StepNetwork(weights, rng.normal(0, 1, n_in), rng.uniform(0.5, 2, n_in), rng.normal(0, 1e-3, 6),
                       rng.uniform(1e-3, 1e-2, 6), lags=lags, meta={"test": True}, age_beats=age_beats)


def _inputs(net, n=7, seed=1):
    return np.random.default_rng(seed).normal(net.x_mean, net.x_std, (n, net.n_in))


# ---------------------------------------------------------------------------------------------- the file


def test_round_trip_and_folded_inference(tmp_path):
    net = _random_net(lags=(0.5,))
    p = net.save(tmp_path / "n.safetensors")
    back = load(p)
    assert back.lags == (0.5,) and back.meta == {"test": True}
    x = _inputs(net)
    ref = net.predict(x)
    assert np.array_equal(back.predict(x), ref)
    b = StepSurrogateBackend(table3_kinematics(1.0), back)
    y = b.evaluate(x.astype(np.float32))
    assert np.abs(y - ref).max() <= FOLD_RTOL * np.abs(ref).max()


def test_missing_and_foreign_files_are_refused(tmp_path):
    with pytest.raises(StepNetworkFileError, match="does not exist"):
        load(tmp_path / "nope.safetensors")
    junk = tmp_path / "junk.safetensors"
    junk.write_bytes(b"not a safetensors file at all")
    with pytest.raises(StepNetworkFileError, match="not a safetensors"):
        load(junk)
    from hawksim.backends.network import shipped_path as mean_path

    if mean_path(None).is_file():  # the cycle-mean network: another format, named
        with pytest.raises(StepNetworkFileError, match="surrogate-mean"):
            load(mean_path(None))


def _save_raw(path, tensors, md):
    from safetensors.numpy import save_file

    save_file({k: np.ascontiguousarray(v, np.float32) for k, v in tensors.items()}, str(path), metadata=md)


def _raw(net):
    t = {f"{p}{k}": a for k, (W, b) in enumerate(net.weights) for p, a in (("W", W), ("b", b))}
    t.update(x_mean=net.x_mean, x_std=net.x_std, y_mean=net.y_mean, y_std=net.y_std)
    md = {"format": "hawksim-step-surrogate-1", "inputs": json.dumps({"names": list(input_names(()))
                                                                     , "lags": []}),
          "outputs": json.dumps(list(OUTPUTS)), "meta": "{}"}
    return t, md


@pytest.mark.parametrize("break_it, message", [
    (lambda t, md: t.update(W0=np.zeros((16, 5))), "layer 0 has W"),
    (lambda t, md: t.update(W2=np.zeros((5, 16)), b2=np.zeros(5)), "layer 2 has W"),
    (lambda t, md: t.update(x_std=np.zeros(15)), "non-positive"),
    (lambda t, md: t.update(b1=np.full(16, np.nan)), "non-finite"),
    (lambda t, md: t.pop("y_std"), "holds tensors"),
    (lambda t, md: md.update(outputs=json.dumps(["L_plus"])), "predicts"),
    (lambda t, md: md.update(inputs=json.dumps({"names": ["f"], "lags": []})), "has inputs"),
    (lambda t, md: md.update(format="hawksim-surrogate-1"), "not a hawksim-step-surrogate-1"),
])
def test_wrong_shapes_and_metadata_give_a_clear_error(tmp_path, break_it, message):
    t, md = _raw(_random_net())
    break_it(t, md)
    p = tmp_path / "bad.safetensors"
    _save_raw(p, t, md)
    with pytest.raises(StepNetworkFileError, match=message):
        load(p)


# ---------------------------------------------------------------------------------------------- the backend


def _state(seed=0):
    rng = np.random.default_rng(seed)
    R = rot_z(0.2) @ rot_y(-1.0) @ rot_x(0.1)
    wR = np.stack([rot_z(0.5) @ rot_x(0.3), rot_z(-0.5) @ rot_x(-0.3)])
    return FlightState(t=0.0123, dt=1e-4, body_pos=np.zeros(3), body_R=R, body_v=rng.normal(0, 0.5, 3),
                       body_omega=rng.normal(0, 5, 3), wing_R=wR, wing_origin=rng.normal(0, 1e-3, (2, 3)),
                       wing_v=rng.normal(0, 0.1, (2, 3)), wing_omega=rng.normal(0, 100, (2, 3)))


LOADS_RTOL = 1e-4
"""The backend's world loads against the float64 network turned by hand: the float32 fold (FOLD_RTOL)."""


def test_backend_applies_both_wings_by_mirror_symmetry_and_its_power_identity():
    net = _random_net()
    kin = table3_kinematics(1.0)
    b = StepSurrogateBackend(kin, net)
    st = _state()
    ld = b.loads(st)
    R = st.body_R
    ph = 2 * math.pi * kin.f * st.t
    x = np.concatenate([kin.as_array(), [math.sin(ph), math.cos(ph)], R.T @ st.body_v, R.T @ st.body_omega])[None]
    yl, yr = net.predict(x)[0], net.predict(mirror_inputs(x))[0]
    F = np.stack([st.wing_R[0] @ yl[:3], st.wing_R[1] @ (MIRROR_F * yr[:3])])
    M = np.stack([st.wing_R[0] @ yl[3:], st.wing_R[1] @ (MIRROR_M * yr[3:])])
    assert np.abs(ld.force - F).max() <= LOADS_RTOL * np.abs(F).max()
    assert np.abs(ld.moment - M).max() <= LOADS_RTOL * np.abs(M).max()
    p = -sum(float((st.wing_omega[k] - st.body_omega) @ ld.moment[k]) for k in range(2))
    assert ld.power == pytest.approx(p, rel=1e-12)


def test_history_lags_interpolate_the_backends_own_record():
    """With a lag of half a beat, the lagged inputs at t are the state the backend saw T/2 earlier."""
    net = _random_net(lags=(0.5,))
    kin = table3_kinematics(1.0)
    b = StepSurrogateBackend(kin, net)
    st0 = _state(0)
    b.reset(st0)
    T = 1.0 / kin.f
    seen = []
    for i in range(41):
        st = FlightState(**{**st0.__dict__, "t": i * T / 40, "body_v": st0.body_v + 0.01 * i})
        b.loads(st)
        seen.append(st.body_R.T @ st.body_v)
    assert np.allclose(b._x[0, 15:18], seen[20], atol=1e-6)


# ------------------------------------------------------------------------------- the wake's age (issue 49)


def test_the_wake_age_counts_beats_from_the_launch_and_saturates():
    """The age input along a flight: min(f t, 2) from a launch at the reset (t = 0); saturated from the start for
    a flight seeded with a record (an orbit's continuation) or declared to have a developed wake; a launch again when
    declared so despite the seed."""
    kin = table3_kinematics(1.0)
    T = 1.0 / kin.f
    st0 = FlightState(**{**_state(0).__dict__, "t": 0.0})

    def ages(b):
        b.reset(st0)
        out = []
        for k in range(13):
            b.loads(FlightState(**{**st0.__dict__, "t": k * T / 4}))
            assert b._x[0, -1] == b._x[1, -1]  # both wings
            out.append(float(b._x[0, -1]))
        return np.array(out)

    net = _random_net(lags=(0.5,), age_beats=2.0)
    assert net.n_in == 9 + 6 + 6 + 1 and input_names((0.5,), 2.0)[-1] == "wake_age_beats"
    b = StepSurrogateBackend(kin, net)
    np.testing.assert_allclose(ages(b), np.minimum(np.arange(13) / 4, 2.0), rtol=1e-6, atol=1e-6)
    assert ages(b)[8:].tolist() == [2.0] * 5
    b.seed(np.zeros((20, 6)), T / 40)
    assert ages(b).tolist() == [2.0] * 13
    b.set_developed_wake(False)
    np.testing.assert_allclose(ages(b), np.minimum(np.arange(13) / 4, 2.0), rtol=1e-6, atol=1e-6)
    c = StepSurrogateBackend(kin, net)
    c.set_developed_wake(True)
    assert ages(c).tolist() == [2.0] * 13
    # the input acts: another age, other loads
    b.set_developed_wake(None)
    b.reset(st0)
    late = b.loads(FlightState(**{**st0.__dict__, "t": 0.3 * T}))
    c.reset(st0)
    assert np.abs(c.loads(FlightState(**{**st0.__dict__, "t": 0.3 * T})).force - late.force).max() > 1e-6


def _synthetic_flight(symmetric=True, beats=4):
    from hawksim.surrogate.flights import COLUMNS, StoredFlight

    kin = table3_kinematics(1.0)
    n = 40 * beats
    rng = np.random.default_rng(3)
    rows = rng.normal(0, 1, (n, len(COLUMNS)))
    rows[:, 0] = np.arange(n) / (40 * kin.f)
    return StoredFlight(0, 0, 1.0, kin.as_array(), symmetric, rows, None, "ok")


def test_training_rows_keep_the_warm_up_only_with_the_age_input():
    """Without the age input the rows of the first WARM_BEATS beats (t < 2 T) are left out of the training; with
    it every row is kept, its last input the age min(f t, 2) and its other inputs those without it."""
    from hawksim.surrogate.flights import WARM_BEATS
    from hawksim.surrogate.step_train import rows_of

    fl = _synthetic_flight()
    f = fl.kinematics[0]
    plain, aged = rows_of([fl], (0.5, 1.0)), rows_of([fl], (0.5, 1.0), float(WARM_BEATS))
    assert WARM_BEATS == 2 and plain.x.shape == (80, 27) and aged.x.shape == (160, 28)
    np.testing.assert_array_equal(aged.x[80:, :27], plain.x)
    np.testing.assert_array_equal(aged.y[80:], plain.y)
    np.testing.assert_allclose(aged.x[:, -1], np.minimum(f * fl.rows[:, 0], 2.0), rtol=1e-12)
    assert aged.x[0, -1] == 0.0 and aged.x[79, -1] < 2.0 and np.all(aged.x[80:, -1] == 2.0)
    lateral = rows_of([_synthetic_flight(symmetric=False)], (0.5, 1.0), 2.0)
    assert lateral.x.shape == (320, 28)
    np.testing.assert_array_equal(lateral.x[160:, -1], lateral.x[:160, -1])  # the mirrored wing: the same age


def test_a_network_without_the_age_input_loads_writes_and_predicts_as_before(tmp_path):
    """A file without ``age_beats`` (every file before the age input) loads with none, predicts as the network it
    was written from, and is written back with the same input metadata; one with it round-trips (the shipped one
    since hawksim 0.3.0: the regeneration's `step_network` stage trained it with ``--wake-age``, age_beats 2,
    results/regeneration/commands.log; hawksim 0.2's shipped network, which had none, left the tree with it); a file
    whose names and age disagree is refused."""
    from safetensors import safe_open

    if shipped_path().is_file():
        net = load(shipped_path())
        assert net.age_beats == 2.0 and net.n_in == 28 and "--wake-age" in net.meta["command"]
        with safe_open(str(shipped_path()), framework="numpy") as fh:
            before = json.loads(fh.metadata()["inputs"])
        with safe_open(str(net.save(tmp_path / "again.safetensors")), framework="numpy") as fh:
            assert json.loads(fh.metadata()["inputs"]) == before and before["age_beats"] == 2.0
    old = _random_net(lags=(0.5, 1.0))  # the layout of hawksim 0.2's shipped network: 27 inputs, no age
    with safe_open(str(old.save(tmp_path / "old.safetensors")), framework="numpy") as fh:
        assert "age_beats" not in json.loads(fh.metadata()["inputs"])
    back = load(tmp_path / "old.safetensors")
    assert back.age_beats == 0.0 and back.n_in == 27
    np.testing.assert_array_equal(back.predict(_inputs(old)), old.predict(_inputs(old)))
    aged = _random_net(lags=(0.5,), age_beats=2.0)
    back = load(aged.save(tmp_path / "aged.safetensors"))
    assert back.age_beats == 2.0 and back.n_in == 22
    x = _inputs(aged)
    np.testing.assert_array_equal(back.predict(x), aged.predict(x))
    plain = StepNetwork(aged.weights, aged.x_mean, aged.x_std, aged.y_mean, aged.y_std, lags=(0.5, 1.0))
    with pytest.raises(ValueError, match="inputs must have shape"):
        plain.predict(x)  # a network is one or the other: the age input is not silently dropped
    with safe_open(str(tmp_path / "aged.safetensors"), framework="numpy") as fh:
        md, arrays = fh.metadata(), {k: fh.get_tensor(k) for k in fh.keys()}
    inputs = json.loads(md["inputs"])
    del inputs["age_beats"]
    from safetensors.numpy import save_file

    save_file(arrays, str(tmp_path / "bad.safetensors"), metadata={**md, "inputs": json.dumps(inputs)})
    with pytest.raises(StepNetworkFileError, match="wake_age_beats"):
        load(tmp_path / "bad.safetensors")


# ------------------------------------------------------------------------------------ accuracy vs the UVLM


def _shipped():
    return load(shipped_path())


@pytest.mark.skipif(not (FLIGHTS.is_file() and shipped_path().is_file()),
                    reason="the flights data set or the shipped per-step network is not in this checkout")
def test_uvlm_right_wing_is_the_mirror_image_of_the_left_in_symmetric_flights():
    """The exact symmetry the network's use for the right wing rests on (MIRROR_F, MIRROR_M)."""
    from hawksim.surrogate.flights import COLUMNS, read_flights

    c = {n: i for i, n in enumerate(COLUMNS)}
    fl = next(f for f in read_flights(FLIGHTS) if f.symmetric)
    r = fl.rows
    for a, b, m in (("FL", "FR", MIRROR_F), ("ML", "MR", MIRROR_M)):
        L = r[:, [c[a + k] for k in "xyz"]]
        R = r[:, [c[b + k] for k in "xyz"]]
        assert np.abs(R - m * L).max() <= 1e-6 * np.abs(L).max()


CI_FLIGHTS = 105
"""Held-out flights scored in CI: all 105 test flights of the shipped network (15 % of its 700; hawksim 0.3.0's
data set: 21 181 rows; ~3 s)."""

R2_TARGET = 0.98
"""Issue 21's per-step target on held-out flights, here for the six components of each wing's force and moment in
BODY axes (in wing axes the in-plane force Fy is ~2 % of the normal force and its R^2 is 0.94: docs/surrogate.md;
hawksim 0.3.0's network, measured: 0.987-0.997, the least Fy; docs/results.md's 0.914 is the side force's in wing
axes)."""

CYCLE_MEAN_TARGET = 0.02
"""Issue 21's target for |network - UVLM| of L+, D+, M+, P+ (absolute), on the mean over held-out wingbeats (hawksim
0.3.0's network with the wake-age input on data/uvlm_flights_0.3.0.sqlite, measured: 0.0150, 0.0142, 0.0142, 0.0096,
docs/results.md; hawksim 0.2's history network: 0.0167, 0.0130, 0.0189, 0.0064; the memoryless one before it had M+
0.0245, docs/surrogate.md)."""


@pytest.mark.skipif(not (FLIGHTS.is_file() and shipped_path().is_file()),
                    reason="the flights data set or the shipped per-step network is not in this checkout")
def test_shipped_network_meets_the_targets_on_held_out_flights():
    from hawksim.surrogate.flights import read_flights
    from hawksim.surrogate.step_train import _flights_sha256, score

    net = _shipped()
    # trained on the data set's first n_flights flights (all 700 of seed 0 for hawksim 0.3.0's network); a set that
    # grew since (the resumable generation appends) is hashed over that prefix
    prefix = net.meta.get("max_flights") or net.meta["n_flights"]
    assert net.meta["data_sha256"] == _flights_sha256(FLIGHTS, prefix), "the shipped network was trained on other data"
    test = set(net.meta["test_flights"][:CI_FLIGHTS])
    assert not test & set(net.meta["val_flights"])
    flights = [f for f in read_flights(FLIGHTS) if f.idx in test]
    sc = score(net, flights)
    for k, v in sc["r2_body"].items():
        assert v >= R2_TARGET, (k, sc["r2_body"])
    err = sc["cycle_mean_abs_error"]
    for k in ("L_plus", "D_plus", "M_plus", "P_plus"):
        assert err[k] <= CYCLE_MEAN_TARGET, (k, err)


# ------------------------------------------------------------------------------------------------ the data


def test_flight_data_set_resumes_without_duplicates_and_is_seeded(tmp_path):
    """`hawksim dataset --kind flights`'s machinery: flight i is a pure function of (seed, i); a second run with a
    larger n computes only the missing flights; the flock refuses a second writer (tested for samples in
    test_dataset.py, the same code)."""
    from hawksim.surrogate.flights import generate_flights, read_flights, sample_flight

    a, b = sample_flight(3, 5), sample_flight(3, 5)
    assert a == b and sample_flight(3, 6) != a and sample_flight(4, 5) != a
    assert not sample_flight(0, 3).symmetric and sample_flight(0, 0).symmetric
    p = tmp_path / "f.sqlite"
    r1 = generate_flights(p, 1, seed=3, workers=1, beats=1)
    r2 = generate_flights(p, 2, seed=3, workers=1, beats=1)
    assert (r1.new, r1.flights, r2.new, r2.flights) == (1, 1, 1, 2)
    fl = read_flights(p)
    assert [f.idx for f in fl] == [0, 1]
    assert fl[0].rows.shape == (40, len(__import__("hawksim.surrogate.flights", fromlist=["x"]).COLUMNS))



def test_flight_families_draw_apart_and_a_file_holds_one(tmp_path):
    """The wide family (hawksim.surrogate.flights.FAMILIES) draws from its own stream, every flight lateral, with
    kinematics spread 6x the orbit family's; a file of one family refuses flights of another (one line naming
    both)."""
    from hawksim.insect.kinematics import bounds_si
    from hawksim.surrogate.dataset import DatasetError
    from hawksim.surrogate.flights import FAMILIES, generate_flights, orbit_at, sample_flight

    assert sample_flight(0, 5, "wide") == sample_flight(0, 5, "wide") != sample_flight(0, 5)
    lo, hi = bounds_si()
    dev = {f: max(np.abs((sample_flight(0, i, f).kinematics.as_array() - orbit_at(sample_flight(0, i, f).speed)[0]
                          .as_array()) / (hi - lo)).max() for i in range(40)) for f in ("orbit", "wide")}
    assert dev["orbit"] <= FAMILIES["orbit"].kin_spread + 1e-12 < 0.1 < dev["wide"] <= FAMILIES["wide"].kin_spread
    assert not any(sample_flight(0, i, "wide").symmetric for i in range(8))
    p = tmp_path / "w.sqlite"
    assert generate_flights(p, 1, seed=0, workers=1, beats=1, family="wide").flights == 1
    with pytest.raises(DatasetError, match="'wide' flights, not 'orbit'"):
        generate_flights(p, 2, seed=0, workers=1, beats=1)


def test_extra_flights_leave_the_main_split_as_it_is(tmp_path):
    """`hawksim train --kind step --extra-data`: each file is split on its own with the seed, so the main file's
    held-out flights are those it has alone (comparable scores) and the extra file's are scored apart."""
    from hawksim.surrogate.flights import copy_flights
    from hawksim.surrogate.step_train import TrainConfig, fit

    if not FLIGHTS.is_file():
        pytest.skip("the flights data set is not in this checkout")
    a, b = tmp_path / "a.sqlite", tmp_path / "b.sqlite"
    copy_flights(FLIGHTS, a, [(0, i) for i in range(8)])
    copy_flights(FLIGHTS, b, [(0, i) for i in range(8, 14)])
    cfg = TrainConfig(hidden=(8,), epochs=1, max_seconds=30.0)
    alone, _ = fit(a, cfg)
    both, _ = fit(a, cfg, extra=(b,))
    assert both.meta["test_flights"] == alone.meta["test_flights"]
    assert both.meta["val_flights"] == alone.meta["val_flights"]
    assert both.meta["n_train_rows"] > alone.meta["n_train_rows"]
    (ex,) = both.meta["extra"]
    assert set(ex["test_flights"]) <= set(range(8, 14)) and ex["test"]["n_flights"] == len(ex["test_flights"])

def test_train_with_the_wake_age_writes_a_network_that_records_it(tmp_path, capsys):
    """`hawksim train --kind step --wake-age`: the network file records the age input (saturating at WARM_BEATS)
    and it trained on the warm-up rows too (more rows than without, on the same flights); --wake-age without
    --kind step is refused."""
    from hawksim.cli import main
    from hawksim.surrogate.flights import WARM_BEATS, copy_flights

    if not FLIGHTS.is_file():
        pytest.skip("the flights data set is not in this checkout")
    a = tmp_path / "a.sqlite"
    copy_flights(FLIGHTS, a, [(0, i) for i in range(6)])
    nets = {}
    for age in (False, True):
        out = tmp_path / f"n{int(age)}.safetensors"
        argv = ["train", "--kind", "step", "--data", str(a), "--out", str(out), "--layers", "8", "--lags", "0.5",
                "--max-iter", "1", "--no-progress", "--json"] + (["--wake-age"] if age else [])
        assert main(argv) == 0
        nets[age] = load(out)
    capsys.readouterr()
    assert nets[False].age_beats == 0.0 and nets[True].age_beats == float(WARM_BEATS)
    assert nets[True].n_in == nets[False].n_in + 1 and "--wake-age" in nets[True].meta["command"]
    assert nets[True].meta["n_train_rows"] > nets[False].meta["n_train_rows"]
    assert main(["train", "--data", str(a), "--out", str(tmp_path / "m.safetensors"), "--wake-age"]) != 0
    assert "--wake-age needs --kind step" in capsys.readouterr().err


def test_an_ensemble_folds_exactly_into_one_network():
    from hawksim.surrogate.step_train import fold_ensemble

    nets = [_random_net(hidden=(8, 8, 8), seed=s) for s in range(3)]
    x = _inputs(nets[0])
    ref = np.mean([StepNetwork(n.weights, nets[0].x_mean, nets[0].x_std, nets[0].y_mean, nets[0].y_std).predict(x)
                   for n in nets], axis=0)
    folded = StepNetwork(fold_ensemble([n.weights for n in nets]), nets[0].x_mean, nets[0].x_std, nets[0].y_mean,
                         nets[0].y_std)
    assert np.allclose(folded.predict(x), ref, rtol=1e-5, atol=1e-9)


@pytest.mark.skipif(not shipped_path().is_file(), reason="the shipped per-step network is not in this checkout")
def test_fly_with_the_surrogate_starts_on_its_orbit_and_holds():
    """`hawksim fly --aero surrogate` from the shipped surrogate orbit at 1 m/s, which starts with the orbit's record
    of calls: the mean vertical speed stays within 0.01 m/s of V for 3 beats (the orbit's largest multiplier is
    ~1.42 per beat, so an orbit error of 1e-3 m/s grows to ~3e-3 m/s in 3 beats: 0.01 leaves 3x)."""
    from hawksim.cli.fly import fly_named
    from hawksim.flight.orbit import shipped_orbit

    o = shipped_orbit(1.0, "surrogate")
    assert o is not None and o.converged, "no shipped surrogate orbit for this network"
    r = fly_named(1.0, o.warm_beats + 3, "surrogate")
    assert r.aero == "surrogate"
    beats = r.beats()
    for b in beats[o.warm_beats:]:
        assert b["mean_vertical_speed"] == pytest.approx(1.0, abs=0.01)


def test_a_folded_ensemble_is_evaluated_block_by_block_with_the_same_result():
    from hawksim.backends.step_surrogate import ensemble_blocks
    from hawksim.surrogate.step_train import fold_ensemble

    nets = [_random_net(hidden=(8, 8, 8), seed=s) for s in range(3)]
    net = StepNetwork(fold_ensemble([n.weights for n in nets]), nets[0].x_mean, nets[0].x_std, nets[0].y_mean,
                      nets[0].y_std)
    b = StepSurrogateBackend(table3_kinematics(1.0), net)
    assert b.blocks is not None and b.blocks[1][0].shape == (3, 8, 8)
    assert ensemble_blocks(_random_net(hidden=(8, 8, 8)).folded()) is None
    x = _inputs(net).astype(np.float32)
    ref = net.predict(x)
    assert np.abs(b.evaluate(x) - ref).max() <= FOLD_RTOL * np.abs(ref).max()


def test_twin_flights_share_the_body_state_but_not_the_wake():
    """scripts/studies/step_surrogate_memory.py's twins (hawksim.surrogate.flights.evaluate_flight's history
    options): flight 54 of seed 7 (hover, 0.027 m/s) and its twin kicked one beat earlier too, written to the same
    body state at the kick. The defaults are untouched (kick_log changes nothing); the twins leave the kick in one
    state (float32 rows); their UVLM M+ over the next beat differs by what the wake remembers (measured +0.062 at 4
    beats, results/surrogate/step_memory.json), which a memoryless network cannot see. The cycle means are the
    study's (:func:`hawksim.surrogate.step_train.flight_cycle_means` of the stored flights)."""
    from hawksim.surrogate.flights import StoredFlight, evaluate_flight, sample_flight
    from hawksim.surrogate.step_train import UPDATES_PER_BEAT, flight_cycle_means

    spec = sample_flight(7, 54)
    plain = evaluate_flight(7, 54, beats=3)
    log: list = []
    a = evaluate_flight(7, 54, beats=3, kick_log=log)
    np.testing.assert_array_equal(plain.rows, a.rows)
    pert = np.asarray(spec.perturbation)
    b = evaluate_flight(7, 54, beats=3, history_kick=pert, state_at_kick=log[0] + pert)
    k = 2 * UPDATES_PER_BEAT  # the row of the kick's step (rows every update, the kick at t = 2 T)
    np.testing.assert_allclose(b.rows[k, 1:7], a.rows[k, 1:7], rtol=1e-4, atol=1e-6)  # one step after the kick
    assert np.abs(b.rows[UPDATES_PER_BEAT + 5, 1:4] - a.rows[UPDATES_PER_BEAT + 5, 1:4]).max() > 1e-3  # history
    ua, ub = (flight_cycle_means(StoredFlight.from_sample(s)) for s in (a, b))
    assert abs((ua - ub)[0, 2]) == pytest.approx(0.062, abs=0.02)
