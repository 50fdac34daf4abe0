"""The one flight loop's Controller protocol (issue 50, item 4): a user's plain class flies, the loop hands it what
the protocol says (sensed state, past commands, its update phases), and a controller that returns the wrong thing
fails with an error naming it."""

import numpy as np
import pytest

import hawksim
from hawksim.control.controller import NoControl
from hawksim.flight.loop import Gust
from hawksim.flight.result import FlightResult
from hawksim.insect.kinematics import PARAM_NAMES

PHI0 = PARAM_NAMES.index("phi0")


@pytest.fixture(scope="module")
def orbit():
    return hawksim.shipped_orbit(1.0, "quasi-steady")


class Hold:
    """The point's kinematics every update, noting what it was given."""

    def __init__(self, rate="beat", dphi0=0.0):
        self.rate, self.dphi0, self.seen = rate, dphi0, []

    def reset(self, point):
        self.p = point.kinematics.as_array().copy()
        self.p[PHI0] += self.dphi0

    def update(self, obs):
        self.seen.append(obs)
        return self.p, self.p


def test_a_user_controller_flies_and_is_a_controller(orbit):
    hold = Hold()
    assert isinstance(hold, hawksim.Controller)
    r = hawksim.fly(orbit, cycles=3, controller=hold)
    assert isinstance(r, FlightResult) and len(r.t) == 3 * 200 and len(r.beat_log) == 3
    assert [o.beat for o in hold.seen] == [1, 2, 3] and all(o.half == 0 for o in hold.seen)
    # the same flight as the shipped no-control controller, bit for bit
    same = hawksim.fly(orbit, cycles=3, controller=NoControl())
    assert np.array_equal(r.body_pos, same.body_pos) and np.array_equal(r.force, same.force)
    # held on the orbit: 1 m/s, and the past holds what was flown
    assert all(abs(b["mean_vertical_speed"] - 1.0) < 2e-3 for b in r.beats())
    assert np.array_equal(hold.seen[-1].past[-1][0], hold.p)
    np.testing.assert_allclose(hold.seen[0].state, orbit.launch_state.as_array(), atol=1e-12)
    # what it commands is flown: 2 deg of phi0 changes the flight and is in the beat log
    moved = hawksim.fly(orbit, cycles=3, controller=Hold(dphi0=np.deg2rad(2.0)))
    assert abs(moved.beats()[-1]["pitch_deg"] - r.beats()[-1]["pitch_deg"]) > 0.5
    assert moved.beat_log[0]["wings"][0][0][PHI0] == pytest.approx(orbit.kinematics.phi0 + np.deg2rad(2.0))


def test_half_stroke_rate_and_sensing_delay(orbit):
    half = Hold("half-stroke")
    r = hawksim.fly(orbit, cycles=2, controller=half)
    assert [(o.beat, o.half) for o in half.seen] == [(1, 0), (1, 1), (2, 0), (2, 1)]
    assert half.seen[1].time == pytest.approx(r.t[100]) and len(r.beat_log[0]["wings"]) == 2
    for delay in (0, 1):
        c = Hold()
        r = hawksim.fly(orbit, cycles=4, controller=c, sensing_delay=delay)
        # beat k sees the state at the end of beat k - 1 - delay
        for k in range(2 + delay, 5):
            assert c.seen[k - 1].state.tolist() == r.beat_log[k - 2 - delay]["state"]


class BadShape(Hold):
    def update(self, obs):
        return self.p[:5], self.p


class NotAPair(Hold):
    def update(self, obs):
        return None


class TwoFrequencies(Hold):
    def update(self, obs):
        q = self.p.copy()
        q[0] += 1.0
        return self.p, q


class NotFinite(Hold):
    def update(self, obs):
        q = self.p.copy()
        q[PHI0] = np.nan
        return q, q


@pytest.mark.parametrize(("cls", "what"), [(BadShape, "left wing of shape"), (NotAPair, "NoneType"),
                                           (TwoFrequencies, "two wingbeat frequencies"), (NotFinite, "non-finite")])
def test_bad_output_names_the_controller(orbit, cls, what):
    with pytest.raises(ValueError, match=f"controller {cls.__name__}.update .*{what}"):
        hawksim.fly(orbit, cycles=1, controller=cls())


def test_bad_rate_and_gusts_without_a_controller(orbit):
    c = Hold(rate="twice")
    with pytest.raises(ValueError, match="controller Hold.rate is 'twice'"):
        hawksim.fly(orbit, cycles=1, controller=c)
    with pytest.raises(ValueError, match="gusts"):
        hawksim.fly(orbit, cycles=1, gusts=[Gust(np.array([0, 0.5, 0]), 1, 1)])


def test_a_controlled_flight_saves_and_loads(orbit, tmp_path):
    r = hawksim.fly(orbit, cycles=2, controller=NoControl(), gusts=[Gust(np.array([0.0, 0.3, 0.0]), 2, 1)])
    assert r.beat_log[0]["air_velocity"] == [0, 0, 0] and r.beat_log[1]["air_velocity"] == [0.0, 0.3, 0.0]
    back = FlightResult.load(r.save(tmp_path / "f.npz"))
    assert back.beat_log == r.beat_log and np.array_equal(back.speed_references, r.speed_references)
    assert np.array_equal(back.body_pos, r.body_pos) and back.departed_at_beat() == r.departed_at_beat()


def test_the_lqr_through_fly_is_fly_closed_loops():
    """``hawksim.fly(ctl.point, controller=LQR.at(...))`` flies what ``fly_closed_loop`` flies (the same loop, the
    same controller; the start state is read back from the plant instead of given: round-off only)."""
    from hawksim.control.closed_loop import fly_closed_loop
    from hawksim.control.controller import LQR

    for rate in ("beat", "half-stroke"):
        ctl = LQR.at(1.0, rate=rate)
        r = hawksim.fly(ctl.point, cycles=3, controller=ctl, perturb={"q": 20.0})
        x = np.zeros(9)
        x[4] = np.deg2rad(20.0)
        cl = fly_closed_loop(1.0, 3, perturbation=x, record=True, schedule=ctl.schedule)
        np.testing.assert_allclose(r.body_pos, cl.result.body_pos, rtol=0, atol=1e-12)
        for mine, theirs in zip(r.beat_log, cl.beats, strict=True):
            assert mine["commands"] == pytest.approx(theirs["commands"], abs=1e-9)
            assert mine.keys() == theirs.keys() and mine["speed_reference"] == theirs["speed_reference"]
        assert r.beat_log[0]["commands"]["phi0_deg"] != pytest.approx(np.rad2deg(ctl.point.kinematics.phi0),
                                                                       abs=1e-3)  # the LQR acted


def test_per_wing_moments_and_joint_angles(orbit, tmp_path):
    """The one FlightResult's per-step arrays: each wing's moment (their sum is the total, to round-off) and the
    joint angles (the sweep of Eq. 1 about its mean phi0); saved and loaded."""
    r = hawksim.fly(orbit, cycles=1, perturb={"phi": 2.0})
    assert r.wing_moment.shape == (200, 2, 3)
    np.testing.assert_allclose(r.wing_moment.sum(1), r.moment, rtol=0, atol=1e-15)
    assert abs(r.wing_moment[:, 0, 0] - r.wing_moment[:, 1, 0]).max() > 1e-9  # the wings differ (rolled start)
    sweep = r.wing_angles()[:, 0, 0]
    assert abs(sweep.mean() - orbit.kinematics.phi0) < 0.02 and np.ptp(sweep) == pytest.approx(
        2 * orbit.kinematics.phi_a, rel=1e-3)
    back = FlightResult.load(r.save(tmp_path / "f.npz"))
    assert np.array_equal(back.wing_moment, r.wing_moment)
