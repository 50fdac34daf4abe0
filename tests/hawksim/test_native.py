"""The native computed-torque callback (hawksim.flight.native) against the Python callback it replaces.

Reference: the Python callback ``Simulator._control`` (the method of hawksim/flight/simulator.py's docstring, whose
momentum conservation and prescribed-motion tracking are tested in test_simulation.py). The native one is the same
arithmetic in a numba cfunc, so the two flights must agree bit for bit, for the Eq. 1 motion (mode 0) and for the
controlled plant's per-wing blend between beats (mode 1).
"""

from dataclasses import replace

import numpy as np
import pytest

from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.control.plant import ControlledSimulator
from hawksim.flight.mujoco_abi import layout
from hawksim.flight.native import C_NET_ADDR
from hawksim.flight.simulator import Simulator
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.model import load_model

pytestmark = pytest.mark.skipif(layout() is None, reason="the native callback is unavailable for this mujoco")

FIELDS = ("qpos", "qvel", "qacc", "qfrc_applied", "xfrc_applied")


def _run(sim, steps):
    out = []
    for _ in range(steps):
        r = sim.step()
        out.append((r.joint_power, *(getattr(sim.d, f).copy() for f in FIELDS)))
    return out


def _same(a, b):
    assert len(a) == len(b)
    for ra, rb in zip(a, b):
        assert ra[0] == rb[0]
        for x, y in zip(ra[1:], rb[1:]):
            np.testing.assert_array_equal(x, y)


def test_eq1_motion_bit_identical_to_python_callback():
    kin = table3_kinematics(1.0)
    runs = []
    for native in (False, True):
        sim = Simulator(load_model(), kin, QuasiSteadyBackend(), steps_per_cycle=100, native=native)
        assert (sim._native is not None) == native
        sim.reset(velocity=(0.0, 0.0, 1.0))
        runs.append(_run(sim, 150))
    _same(*runs)


def test_blended_beats_bit_identical_to_python_callback():
    """Mode 1: a beat that blends both wings to other (and different) kinematics, then a half-stroke segment."""
    kin = table3_kinematics(1.0)
    left = replace(kin, phi_a=kin.phi_a * 0.97, alpha0=kin.alpha0 + 0.02, f=kin.f * 1.01)
    right = replace(kin, phi_a=kin.phi_a * 1.02, phi0=kin.phi0 - 0.03, f=kin.f * 1.01)
    runs = []
    for native in (False, True):
        sim = ControlledSimulator(load_model(), kin, QuasiSteadyBackend(), steps_per_cycle=80, native=native)
        assert (sim._native is not None) == native
        sim.reset(velocity=(0.0, 0.0, 1.0))
        rec = _run(sim, 80)
        sim.begin_beat(left, right)
        rec += _run(sim, 80)
        sim.begin_beat(right, left, phase=np.pi, span=0.5)
        rec += _run(sim, 40)
        runs.append(rec)
    _same(*runs)


def test_a_subclass_with_its_own_motion_keeps_the_python_callback():
    class Other(Simulator):
        def desired(self, t):
            return super().desired(t)

    kin = table3_kinematics(1.0)
    assert Other(load_model(), kin, QuasiSteadyBackend(), steps_per_cycle=40)._native is None


def _advance_vs_step(backend, steps=150, chunks=(37, 63, 50)):
    from hawksim.flight.simulator import StepBatch, aero_every_for

    kin = table3_kinematics(1.0)
    every = aero_every_for(backend, 100)
    runs = []
    for batched in (False, True):
        sim = Simulator(load_model(), kin, backend, steps_per_cycle=100, aero_every=every)
        sim.reset(velocity=(0.0, 0.0, 1.0))
        if batched:
            parts = [sim.advance(k) for k in chunks]  # chunks that cut the backend's update intervals
        else:
            parts = [StepBatch.of([sim.step() for _ in range(steps)], 0, 0)]
        cat = {name: np.concatenate([getattr(p, name) for p in parts]) for name in BATCH_FIELDS}
        runs.append((cat, sim.d.qpos.copy(), sim.d.qvel.copy()))
    return runs


BATCH_FIELDS = ("t", "body_pos", "body_R", "body_v", "body_omega", "wing_R", "wing_origin", "force", "moment",
                "power_aero", "power_joint")


def test_advance_is_the_steps_it_replaces():
    """Simulator.advance (the steps between backend updates in one mj_step(nstep), loads applied and the state
    recorded by the native callback) against the same steps one by one (Simulator.step): the same floats, with a
    backend updated every step (quasi-steady) and one held over several (the per-step surrogate, its network
    evaluated in Python)."""
    from hawksim.backends.step_surrogate import StepSurrogateBackend

    python_net = StepSurrogateBackend(table3_kinematics(1.0))
    python_net.native = lambda every: None  # the network stays in Python: loads held, applied by the callback
    for backend in (QuasiSteadyBackend(), python_net):
        (a, qa, va), (b, qb, vb) = _advance_vs_step(backend)
        np.testing.assert_array_equal(qa, qb)
        np.testing.assert_array_equal(va, vb)
        for name in BATCH_FIELDS:
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)


NETWORK_REL_TOL = 1e-5
"""The per-step surrogate evaluated in the callback (float32 sums in another order than numpy's sgemm) against the
numpy evaluation: the loads agree to float32 round-off (measured 2-3e-7 relative to the peak force over a beat)."""
FLOAT32_EVAL_TOL = 3e-5
"""A float32 evaluation of the shipped network against the same weights in float64, relative to the peak output
(measured 6-7e-6: sums of 192 products and the last layer's cancellation)."""


def test_advance_with_the_network_in_the_callback_matches_the_python_network():
    from hawksim.backends.step_surrogate import StepSurrogateBackend

    (a, qa, va), (b, qb, vb) = _advance_vs_step(StepSurrogateBackend(table3_kinematics(1.0)))
    peak = np.abs(a["force"]).max()
    assert np.abs(a["force"] - b["force"]).max() <= NETWORK_REL_TOL * peak
    assert np.abs(a["moment"] - b["moment"]).max() <= NETWORK_REL_TOL * np.abs(a["moment"]).max()
    np.testing.assert_allclose(qb, qa, rtol=0, atol=1e-7)  # 1.5 beats: positions [m], angles [rad] (measured 4e-9)
    np.testing.assert_array_equal(a["t"], b["t"])


HISTORY_QUAT_TOL = 5e-7
"""The body's attitude quaternion after the random history network's 2.5 beats (test below), callback against
Python: the loads differ by float32 round-off (2.8e-6 of their peak, within NETWORK_REL_TOL), integrated over a flight
in which this network spins the body at up to 65 rad/s. Measured 1.5e-7 on hawksim 0.3.0's sourced hawkmoth and
1.4e-8 on hawksim 0.2's (loads apart by 1.8e-6 there; the previous bound, 1e-7, for position and attitude alike): this
flight of the new morphology amplifies the same round-off ten times more (which of its changes does was not
isolated); the callback is not less exact (the positions agree to 4e-10, the wing joints exactly)."""


def test_history_network_in_the_callback_matches_the_python_network():
    """A network with history lags (T/2 and T) evaluated in the callback, which reads and writes its backend's record
    of calls (StepSurrogateBackend.history, lagged_states), against the same network evaluated in Python at each
    update (Simulator.step): 2.5 beats, so both lags read recorded states; float32 round-off apart."""
    import math

    from hawksim.backends.step_network import OUTPUTS, StepNetwork, input_names
    from hawksim.backends.step_surrogate import StepSurrogateBackend

    rng = np.random.default_rng(4)
    lags = (0.5, 1.0)
    n_in = len(input_names(lags))
    sizes = [n_in, 16, 16, len(OUTPUTS)]
    weights = tuple((rng.normal(0, 1 / math.sqrt(a), (b, a)).astype(np.float32),
                     rng.normal(0, 0.1, b).astype(np.float32)) for a, b in zip(sizes[:-1], sizes[1:]))
    x_std = np.concatenate([np.ones(9), np.full(n_in - 9, 0.3)])  # the state inputs matter at flight scale
    net = StepNetwork(weights, np.zeros(n_in), x_std, np.zeros(6), np.full(6, 2e-3), lags=lags, meta={"test": True})
    backend = StepSurrogateBackend(table3_kinematics(1.0), net)
    assert backend.native(5) is not None
    (a, qa, va), (b, qb, vb) = _advance_vs_step(backend, steps=250, chunks=(37, 63, 50, 100))
    late = a["t"] >= a["t"][0] + 1.2 / table3_kinematics(1.0).f  # both lags inside the flight
    assert late.sum() > 50
    assert np.abs(a["force"] - b["force"]).max() <= NETWORK_REL_TOL * np.abs(a["force"]).max()
    assert np.abs(a["moment"] - b["moment"]).max() <= NETWORK_REL_TOL * np.abs(a["moment"]).max()
    np.testing.assert_allclose(qb[:3], qa[:3], rtol=0, atol=1e-7)  # position [m] (measured 4e-10)
    np.testing.assert_allclose(qb[7:], qa[7:], rtol=0, atol=1e-7)  # the wing joints [rad] (measured 0)
    np.testing.assert_allclose(qb[3:7], qa[3:7], rtol=0, atol=HISTORY_QUAT_TOL)
    # the lagged inputs act: the same network with its history inputs zeroed gives other loads
    flat = StepNetwork(tuple((W.copy(), c.copy()) for W, c in weights), np.zeros(n_in), x_std, np.zeros(6),
                       np.full(6, 2e-3), lags=lags, meta={"test": True})
    flat.weights[0][0][:, 15:] = 0.0
    (c, _, _), _ = _advance_vs_step(StepSurrogateBackend(table3_kinematics(1.0), flat), steps=250,
                                    chunks=(37, 63, 50, 100))
    assert np.abs(c["force"][late] - a["force"][late]).max() > 100 * NETWORK_REL_TOL * np.abs(a["force"]).max()


def test_wake_age_network_in_the_callback_matches_the_python_network():
    """A network with the wake-age input (issue 49) evaluated in the callback, which reads its backend's launch time
    by address, against the same network in Python: 2.5 beats from a launch (the age ramps from 0 and saturates at
    2), float32 round-off apart; the input acts (a developed wake from the start gives other loads early, the same
    loads once the age saturates)."""
    import math

    from hawksim.backends.step_network import OUTPUTS, StepNetwork, input_names
    from hawksim.backends.step_surrogate import StepSurrogateBackend

    rng = np.random.default_rng(5)
    lags = (0.5,)
    n_in = len(input_names(lags, 2.0))
    sizes = [n_in, 16, 16, len(OUTPUTS)]
    weights = tuple((rng.normal(0, 1 / math.sqrt(a), (b, a)).astype(np.float32),
                     rng.normal(0, 0.1, b).astype(np.float32)) for a, b in zip(sizes[:-1], sizes[1:]))
    x_std = np.concatenate([np.ones(9), np.full(n_in - 10, 0.3), [0.5]])
    net = StepNetwork(weights, np.zeros(n_in), x_std, np.zeros(6), np.full(6, 2e-3), lags=lags, age_beats=2.0)
    backend = StepSurrogateBackend(table3_kinematics(1.0), net)
    assert backend.native(5).age_beats == 2.0
    steps, chunks = 250, (37, 63, 50, 100)
    (a, qa, _), (b, qb, _) = _advance_vs_step(backend, steps=steps, chunks=chunks)
    assert np.abs(a["force"] - b["force"]).max() <= NETWORK_REL_TOL * np.abs(a["force"]).max()
    assert np.abs(a["moment"] - b["moment"]).max() <= NETWORK_REL_TOL * np.abs(a["moment"]).max()
    np.testing.assert_allclose(qb, qa, rtol=0, atol=1e-7)
    grown = StepSurrogateBackend(table3_kinematics(1.0), net)
    grown.set_developed_wake(True)
    (c, _, _), (d, _, _) = _advance_vs_step(grown, steps=steps, chunks=chunks)
    assert np.abs(c["force"] - d["force"]).max() <= NETWORK_REL_TOL * np.abs(c["force"]).max()
    early = a["t"] < 0.5 / table3_kinematics(1.0).f
    assert np.abs(c["force"][early] - a["force"][early]).max() > 100 * NETWORK_REL_TOL * np.abs(a["force"]).max()
    # a copied simulator (hawksim.control.derivatives.Snapshot) reads its own backend's launch time
    import copy

    from hawksim.flight.native import C_LAUNCH_ADDR

    sim = Simulator(load_model(), table3_kinematics(1.0), backend, steps_per_cycle=100, aero_every=5)
    sim.reset(velocity=(0.0, 0.0, 1.0))
    sim.advance(10)
    twin = copy.deepcopy(sim)
    assert twin._native.ctx[C_LAUNCH_ADDR] == twin.backend.launch.ctypes.data != sim._native.ctx[C_LAUNCH_ADDR]


def test_a_copied_simulator_flies_on_with_its_own_network_and_record():
    """copy.deepcopy of a simulator on the native callback (hawksim.control.derivatives.Snapshot branches from
    copies): the copy's ctx points at its own network buffer and history record, and both continue bit for bit."""
    import copy

    from hawksim.backends.step_surrogate import StepSurrogateBackend

    kin = table3_kinematics(1.0)
    sim = Simulator(load_model(), kin, StepSurrogateBackend(kin), steps_per_cycle=200, aero_every=5)
    sim.reset(velocity=(0.0, 0.0, 1.0))
    sim.advance(130)
    twin = copy.deepcopy(sim)
    assert twin._native._tramp is sim._native._tramp and twin.backend is not sim.backend
    a, b = sim.advance(200), twin.advance(200)
    np.testing.assert_array_equal(a.force, b.force)
    np.testing.assert_array_equal(sim.d.qpos, twin.d.qpos)
    assert twin._native.ctx[C_NET_ADDR] == twin._net.buffer.ctypes.data != sim._native.ctx[C_NET_ADDR]


def test_skipping_the_idle_pipeline_stages_changes_nothing():
    """hawksim.flight.simulator.idle_stages: the hawkmoth's visual-only geoms cannot collide and it has no
    constraints, so skipping collision detection and the constraint stage gives the same floats."""
    from hawksim.flight.simulator import idle_stages

    kin = table3_kinematics(1.0)
    assert idle_stages(load_model()) != 0
    runs = []
    for skip in (True, False):
        sim = Simulator(load_model(), kin, QuasiSteadyBackend(), steps_per_cycle=100)
        if not skip:
            sim.m.opt.disableflags = 0
        sim.reset(velocity=(0.0, 0.0, 1.0))
        runs.append(_run(sim, 100))
    _same(*runs)


def test_controlled_surrogate_in_the_callback_matches_the_python_network(monkeypatch):
    """The controlled plant's per-step surrogate (per-wing blended kinematics and phase, hawksim.control.surrogate)
    evaluated in the callback against the same network in Python: a gust makes the controller change both wings'
    kinematics every beat, so every beat blends."""
    from hawksim.control import surrogate as cs
    from hawksim.control.closed_loop import fly_closed_loop
    from hawksim.control.command import parse_gust

    runs = []
    for native in (True, False):
        if not native:
            monkeypatch.setattr(cs.ControlledStepSurrogate, "native", lambda self, every: None)
        runs.append(fly_closed_loop(1.0, 4, aero="surrogate", gusts=[parse_gust("0,0.2,0@1:2")], record=True))
    a, b = (r.result for r in runs)
    assert max(abs(x["roll_deg"]) for x in runs[0].beats) > 0.1  # the gust acted (and the commands with it)
    assert np.abs(a.force - b.force).max() <= NETWORK_REL_TOL * np.abs(b.force).max()
    np.testing.assert_allclose(a.body_pos, b.body_pos, rtol=0, atol=1e-6)


def test_tanh32_is_within_one_float32_ulp_of_tanh():
    """hawksim.flight.network_kernel.tanh32, the network's vectorisable tanh: within 1 float32 ulp of the exact
    tanh (float64 reference) on [-12, 12] (measured 0.75 ulp), odd, and 1 beyond the clamp."""
    from numba import njit

    from hawksim.flight.network_kernel import tanh32

    @njit
    def many(v):
        out = np.empty_like(v)
        for i in range(v.size):
            out[i] = tanh32(v[i])
        return out

    v = np.linspace(-12.0, 12.0, 400_001).astype(np.float32)
    got = many(v)
    ref = np.tanh(v.astype(np.float64))
    ulp = np.spacing(np.abs(ref).astype(np.float32)).astype(np.float64)
    assert np.max(np.abs(got - ref) / np.maximum(ulp, np.spacing(np.float32(1e-30)))) <= 1.0
    np.testing.assert_array_equal(many(-v), -got)
    assert many(np.array([30.0, -30.0], np.float32)).tolist() == [1.0, -1.0]


def test_compiled_network_matches_the_numpy_evaluation():
    """mlp (output-major weights, vectorised float32 sums, tanh32) and StepSurrogateBackend.evaluate (numpy
    sgemm, np.tanh) on random inputs around the 1 m/s trim, each against the same weights evaluated in float64:
    float32 round-off only (both measured 6-7e-6 of the peak on 2026-12-02 with numpy 2.4.6; their difference
    reaches 1e-5, so each is held to the exact evaluation, not to the other)."""
    from hawksim.backends.step_surrogate import StepSurrogateBackend
    from hawksim.flight.network_kernel import mlp

    be = StepSurrogateBackend(table3_kinematics(1.0))
    nn = be.native(5)
    buf = nn.buffer[1:].view(np.float32)[:int(nn.buffer[0])]
    last = len(be.blocks) - 1

    def exact(x):
        h = x[None].astype(np.float64)
        for k, (WT, b) in enumerate(be.blocks):
            h = np.matmul(h, WT.astype(np.float64)) + b
            h = np.tanh(h) if k < last else h
        return h.sum(0) + be.layers[-1][1]

    rng = np.random.default_rng(3)
    for _ in range(20):
        x = be._x.copy()
        x[:, 7:] = rng.normal(scale=0.3, size=(2, nn.n_in - 7)).astype(np.float32)
        ref = exact(x)
        peak = np.abs(ref).max()
        assert np.abs(mlp(x, buf, nn.members, nn.n_in, nn.hidden, nn.layers) - ref).max() <= FLOAT32_EVAL_TOL * peak
        assert np.abs(be.evaluate(x) - ref).max() <= FLOAT32_EVAL_TOL * peak
