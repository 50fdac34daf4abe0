"""The backend registry (:mod:`hawksim.backends.registry`): a backend is one descriptor, registered once.

A toy backend (a constant force through the body's centre of mass) is registered here, in the test itself, and
flown through the public flight functions by its name; the descriptor's update interval, capabilities and memory
protocol are what the flight loop uses. The built-in descriptors keep the numbers the string tables held."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hawksim.backends import make_backend
from hawksim.backends.base import FlightState, WingLoads
from hawksim.backends.memory import PREVIOUS_CALL
from hawksim.backends.registry import (BackendDescriptor, descriptor, descriptor_of, names, no, register,
                                       unregister)
from hawksim.frames import cross
from hawksim.insect.model import load_model
from hawksim.trim.tables import shipped_trim

G = 9.81


class ConstantLift:
    """A constant upward force ``lift`` [N] (world z) through the body's centre of mass, half on each wing (the
    moment about each hinge cancels its arm, so the total moment about the centre of mass is zero). With
    ``remember`` it keeps a previous-call memory and counts its primes."""

    name = "toy-lift"

    def __init__(self, lift: float):
        self.lift = float(lift)
        self.primed: list[float] = []

    def reset(self, state: FlightState) -> None:
        pass

    def prime(self, previous: FlightState) -> None:
        self.primed.append(previous.t)

    def loads(self, state: FlightState) -> WingLoads:
        f = np.tile([0.0, 0.0, self.lift / 2], (2, 1))
        m = -cross(state.wing_origin - state.body_pos, f)
        return WingLoads(force=f, moment=m, power=0.0)


def _toy(lift: float, **kw) -> BackendDescriptor:
    return BackendDescriptor(name="toy-lift", summary="a constant lift through the centre of mass",
                             factory=lambda **_: ConstantLift(lift), **kw)


@pytest.fixture
def toy():
    """Registers the toy under "toy-lift" (the caller's descriptor) and removes it afterwards."""
    made = []

    def reg(desc):
        made.append(register(desc))
        return desc

    yield reg
    unregister("toy-lift")


def _total_mass(model) -> float:
    return float(np.sum(model.body_mass))


def test_a_registered_toy_backend_flies_by_name_at_its_update_interval(toy):
    """Registered with 50 calls per wingbeat, the toy is a name like the built-ins; flown 3 beats open loop from the
    trim's start, its lift changes the body's vertical speed against the vacuum's by lift / m_total x t (the
    momentum of the whole system: dP/dt = F - m g wherever F acts), within 1 %."""
    from hawksim.flight.fly import fly

    model = load_model()
    m = _total_mass(model)
    lift = 0.5 * m * G
    toy(_toy(lift, calls_per_beat=50))
    assert "toy-lift" in names() and descriptor("toy-lift").update_interval(200) == 4
    trim = shipped_trim(1.0, "quasi-steady")
    res = {}
    for name in ("toy-lift", "none"):
        r = fly(trim, make_backend(name, kinematics=trim.kinematics), 3, model=model, periodic_start=False)
        res[name] = r
    assert res["toy-lift"].aero_every == 4 and res["none"].aero_every == 1
    t = res["toy-lift"].t
    dv = res["toy-lift"].body_v[:, 2] - res["none"].body_v[:, 2]
    T = trim.kinematics.period
    for k in range(1, 4):  # at each phase-0 strobe the wings are on the same pose and rates in both flights
        i = int(np.argmin(np.abs(t - k * T)))
        assert dv[i] == pytest.approx(lift / m * t[i], rel=1e-2)


def test_the_toy_on_the_command_line(toy, capsys):
    """`hawksim fly --aero toy-lift` accepts the registered name (the parser's choices are the registry's), starts
    from the trim (the toy has no periodic orbit: its descriptor's reason is printed) and reports the toy."""
    from hawksim.cli import main

    m = _total_mass(load_model())
    toy(_toy(m * G, orbits=no("a constant force has no periodic orbit of its own"), orbits_on_demand=False,
             control=no("toy")))
    assert main(["fly", "--aero", "toy-lift", "--speed", "1", "--cycles", "2", "--control", "none", "--json",
                 "--no-progress"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert out["aero"] == "toy-lift" and len(out["beats"]) == 2
    assert "a constant force has no periodic orbit of its own" in cap.err
    # lift = weight from a start at 1 m/s up: the mean vertical speed stays near 1 m/s (the vacuum's loses g T)
    assert out["beats"][-1]["mean_vertical_speed"] == pytest.approx(1.0, abs=0.05)
    assert main(["fly", "--aero", "toy-lift", "--speed", "1", "--cycles", "2", "--control", "lqr",
                 "--no-progress"]) == 2
    assert "--aero quasi-steady, uvlm or surrogate" in capsys.readouterr().err


def test_hover_refused_where_the_descriptor_says_so(toy):
    from hawksim.flight.fly import fly

    toy(_toy(0.0, hover=no("the toy stalls without a free stream")))
    trim = shipped_trim(0.0, "quasi-steady")
    with pytest.raises(ValueError, match="aero='toy-lift': the toy stalls without a free stream"):
        fly(trim, make_backend("toy-lift"), 1, periodic_start=False)


def test_previous_call_memory_is_primed_once_by_the_loop(toy):
    """A backend of previous-call memory gets one prime, at t = -h (h: one update interval) before a flight that
    starts from a state (the orbit start); a memoryless one is never primed."""
    from hawksim.flight.fly import fly

    trim = shipped_trim(1.0, "quasi-steady")
    x0 = np.zeros(9)
    x0[2], x0[7] = -1.0, trim.kinematics.chi
    for memory, expect in ((PREVIOUS_CALL, 1), ("none", 0)):
        unregister("toy-lift")
        toy(_toy(0.0, memory=memory, calls_per_beat=100))
        b = make_backend("toy-lift")
        fly(trim, b, 1, start_state=(x0, trim.kinematics.chi))
        assert len(b.primed) == expect
        if expect:
            assert b.primed[0] == pytest.approx(-2 * trim.kinematics.period / 200)


def test_registry_refusals():
    with pytest.raises(ValueError, match="unknown aero 'nope'; choose quasi-steady, uvlm, surrogate, surrogate-mean"):
        descriptor("nope")
    with pytest.raises(ValueError, match="already registered"):
        register(descriptor("uvlm"))
    with pytest.raises(ValueError, match="memory must be one of"):
        BackendDescriptor(name="x", summary="", factory=lambda **_: None, memory="goldfish")
    with pytest.raises(ValueError, match="a periodic orbit is not available for aero='surrogate-mean'"):
        from hawksim.flight.orbit import make_orbit_backend

        make_orbit_backend("surrogate-mean")


def test_builtin_descriptors_hold_the_former_tables():
    """The numbers the string-keyed tables held, now each backend's descriptor's."""
    from hawksim.backends.resolution import FLY_UVLM

    qs, uv, su, sm = (descriptor(n) for n in ("quasi-steady", "uvlm", "surrogate", "surrogate-mean"))
    assert names() == ("quasi-steady", "uvlm", "surrogate", "surrogate-mean")
    assert names(having="half_stroke") == ("quasi-steady", "surrogate")
    assert names(having="orbits") == ("quasi-steady", "uvlm", "surrogate")
    n = 200 // FLY_UVLM.steps_per_cycle
    assert [d.update_interval(200) for d in (qs, uv, su, sm)] == [1, n, n, 1]
    assert (qs.fd.orbit, uv.fd.orbit, su.fd.orbit) == (1e-6, 1e-3, 1e-4)
    assert (qs.fd.monodromy, uv.fd.monodromy, su.fd.monodromy) == (1e-5, 1e-3, 1e-4)
    assert (qs.fd.control, uv.fd.control, su.fd.control) == (1e-5, 1e-3, 1e-3)
    assert (qs.warm_beats, uv.warm_beats, su.warm_beats) == (0, 2, 0)
    r = np.array([5e-4, 0, 0, 0, 0, 0])  # normalized u periodicity 5e-4 at U = 1 m/s: 0.5 mm/s
    assert uv.orbit_tolerance.met(r, 1.0, 0.04) and not qs.orbit_tolerance.met(r, 1.0, 0.04)
    assert su.orbit_tolerance.met(r * 2e-3, 1.0, 0.04) and not qs.orbit_tolerance.met(r * 2e-3, 1.0, 0.04)
    assert "phase 0.5" in uv.half_stroke.why_not and not sm.orbits and su.history and not qs.history
    assert descriptor_of(make_backend("quasi-steady")) is qs
    assert descriptor_of(object()).update_interval(200) == 1  # an unregistered object: every step, no memory
