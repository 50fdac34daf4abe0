"""One operating point and one linear model (issue 50, item 3): find_operating_point -> linearize -> LinearModel ->
LQR, the one registry of shipped points keyed by insect, backend, speed and MJCF, and the caches that never give one
insect another's point or gains."""

import dataclasses
import json

import numpy as np
import pytest

import hawksim
from hawksim.control.derivatives import XI_NAMES
from hawksim.control.derivatives import linearize as linearize_beat
from hawksim.control.lqr import lqr_gain, periodic_lqr_gain
from hawksim.control.plant import INPUTS
from hawksim.flight.orbit import Orbit, periodic_orbit, shipped_orbit
from hawksim.flight.points import find_operating_point
from hawksim.trim.registry import point_key, shipped_point, shipped_table
from hawksim.insect.insect import DEFAULT_INSECT, Insect
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.model import load_model
from hawksim.insect.morphology import HAWKMOTH
from hawksim.stability.floquet import floquet_analysis, monodromy
from hawksim.stability.linear_model import LinearModel
from hawksim.trim.point import OperatingPoint, Trim

HEAVY = Insect(dataclasses.replace(HAWKMOTH, total_mass=1.2 * HAWKMOTH.total_mass, name="heavier"))


@pytest.fixture(scope="module")
def orbit():
    return periodic_orbit(1.0)


def test_one_type_held_or_free():
    assert Trim is OperatingPoint and Orbit is OperatingPoint
    kin = table3_kinematics(1.0)
    t = Trim(1.0, kin, model="quasi-steady", source="test")
    assert t.body == "held" and not t.free and t.aero == t.model == "quasi-steady" and t.insect == DEFAULT_INSECT
    o = shipped_orbit(1.0, "uvlm")
    assert o.body == "free" and o.free and o.initial_state is not None
    assert hash(t) == hash(Trim(1.0, kin, model="quasi-steady", source="test"))  # hashable, as Trim was
    with pytest.raises(ValueError, match="aero or model"):
        OperatingPoint(1.0, kin, aero="uvlm", model="uvlm")
    with pytest.raises(ValueError, match="initial_state"):
        OperatingPoint(1.0, kin, aero="uvlm", body="free")
    with pytest.raises(ValueError, match="body must be"):
        OperatingPoint(1.0, kin, body="clamped")


def test_json_round_trip_and_the_shipped_tables_read_unchanged():
    table = shipped_table("orbit_table_uvlm.json")
    for row in table["rows"]:  # each shipped row reads and writes back as it is stored
        p = OperatingPoint.from_json(row)
        assert p.free and p.to_json() == row
    held = Trim(0.5, table3_kinematics(0.5), model="paper", source="Table 3", fitness=0.25, search_seed=3)
    back = OperatingPoint.from_json(json.loads(json.dumps(held.to_json())))
    assert back.body == "held" and back.kinematics == held.kinematics and back.fitness == 0.25
    assert back.search_seed == 3 and back.aero == "paper"


def test_registry_is_keyed_by_insect_backend_speed_and_model():
    a, b = shipped_point(1.0, "uvlm"), shipped_point(1.0, "uvlm")
    assert a is not None and a is b  # loaded once
    assert shipped_orbit(1.0, "uvlm") is a
    assert shipped_point(1.0, "uvlm", insect=HEAVY) is None  # the tables are the default insect's
    assert shipped_point(1.0, "uvlm", model=load_model(morph=HEAVY.morphology)) is None
    assert shipped_point(1.0, "uvlm", model=load_model()) is a  # the default MJCF: the same key
    assert shipped_point(1.25, "uvlm") is None
    k = point_key(1.0, "uvlm")
    assert k == point_key(1.0, "uvlm", DEFAULT_INSECT, load_model())
    assert point_key(1.0, "uvlm", HEAVY) != k and point_key(1.0, "quasi-steady") != k
    assert point_key(2.0, "uvlm") != k


def test_find_operating_point():
    assert find_operating_point(1.0, aero="uvlm") is shipped_point(1.0, "uvlm")
    held = find_operating_point(1.0, aero="quasi-steady", body="held")
    assert held.body == "held" and held.aero == "quasi-steady"
    given = find_operating_point(1.0, body="held", kinematics=table3_kinematics(1.0), insect=HEAVY)
    assert given.insect == HEAVY and given.source == "given"
    with pytest.raises(ValueError, match="no shipped held-body trim"):
        find_operating_point(1.0, body="held", insect=HEAVY)
    with pytest.raises(ValueError, match="body must be"):
        find_operating_point(1.0, body="orbit")
    assert hawksim.find_operating_point is find_operating_point and hawksim.OperatingPoint is OperatingPoint


def test_linearize_beat_is_the_per_beat_model_exactly(orbit):
    lin = hawksim.linearize(orbit, map="beat")
    ref = linearize_beat(orbit)
    assert isinstance(lin, LinearModel) and hawksim.LinearModel is LinearModel
    assert lin.map == "beat" and lin.states == XI_NAMES and lin.inputs == INPUTS
    assert lin.dt == orbit.kinematics.period and not lin.continuous and lin.phases == 1
    for k in ("A", "B0", "B1", "scale"):
        assert np.array_equal(getattr(lin, k), getattr(ref, k))
    A, B0, B1 = lin.block("long")
    assert A.shape == (5, 5) and B1.shape == (5, 4)
    assert np.array_equal(A, lin.A[np.ix_([0, 2, 4, 7, 9], [0, 2, 4, 7, 9])])
    g = lqr_gain(lin, "long", 1)
    assert g.spectral_radius < 1.0 and g.K.shape == (4, 5 + 2 * 4)
    # the monodromy's A: the same beat without inputs, its Floquet analysis a view of it
    mono = hawksim.linearize(orbit, map="monodromy")
    fl = monodromy(orbit)
    assert mono.map == "monodromy" and mono.inputs == () and np.array_equal(mono.A, fl.monodromy)
    assert np.array_equal(floquet_analysis(mono).multipliers_long, fl.multipliers_long)
    assert np.abs(mono.A - lin.monodromy).max() < 1e-3  # two differencings of one map
    with pytest.raises(ValueError, match="held-body trim"):
        hawksim.linearize(find_operating_point(1.0, body="held"), map="beat")
    with pytest.raises(ValueError, match="map must be"):
        hawksim.linearize(orbit, map="quarter-stroke")


def test_linearize_half_stroke_is_periodic(orbit):
    h = hawksim.linearize(orbit, map="half-stroke")
    assert h.phases == 2 and h.dt == pytest.approx(orbit.kinematics.period / 2)
    assert np.array_equal(h.period_map, h.A[1] @ h.A[0]) and np.array_equal(h.monodromy, (h.A[1] @ h.A[0])[:8, :8])
    gains = periodic_lqr_gain(h, "long", 2)
    assert len(gains) == 2 and gains[0].spectral_radius < 1.0
    with pytest.raises(ValueError, match="give the phase"):
        h.block("long")


def test_averaged_model_is_continuous(orbit):
    avg = hawksim.linearize(orbit, map="averaged")
    assert avg.continuous and avg.states[:4] == ("u", "w", "q", "theta")
    assert np.all(avg.A[:4, 4:] == 0) and np.all(avg.A[4:, :4] == 0)
    ev = avg.eigenvalues()
    assert np.all(np.diff(-ev.real) >= 0)  # sorted by real part, descending


def test_two_insects_in_one_process_get_their_own_points_and_gains():
    from hawksim.control.schedule import _POINTS, schedule_point

    hawk, heavy = schedule_point(1.0), schedule_point(1.0, insect=HEAVY)
    assert point_key(1.0, "quasi-steady") in _POINTS and point_key(1.0, "quasi-steady", HEAVY) in _POINTS
    assert heavy.orbit.insect == HEAVY and hawk.orbit.insect == DEFAULT_INSECT
    assert heavy.orbit.kinematics.f > hawk.orbit.kinematics.f + 1.5
    assert np.abs(heavy.long.K - hawk.long.K).max() > 1e-3
    hawk_h, heavy_h = schedule_point(1.0, rate="half-stroke"), schedule_point(1.0, rate="half-stroke", insect=HEAVY)
    assert heavy_h.half.point.insect == HEAVY and hawk_h.half.point.insect == DEFAULT_INSECT
    assert np.abs(heavy_h.long_half.K - hawk_h.long_half.K).max() > 1e-3
    # the same insect on another MJCF (the heavier one's) is another key too
    assert point_key(1.0, "quasi-steady", None, load_model(morph=HEAVY.morphology)) not in _POINTS
