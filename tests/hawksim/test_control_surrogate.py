"""The LQR with the per-step surrogate in the loop (issue 20 with issue 21's backend; docs/control.md "The per-step
surrogate in the loop"): the controlled surrogate backend reads the commanded kinematics, the shipped control models
are those of the shipped orbits, the closed loop is stable and the linear model predicts the nonlinear flight, the
flights hold (CI: 1 m/s, short; `slow`: 100 beats at every speed, the ascent profile), the CLI; per half-stroke (the
surrogate's default) every target of issue 20 at every speed (`slow`; CI: the gust and the delay at 1 m/s)."""

import json
from hawksim.trim.registry import shipped_table

import numpy as np
import pytest

from hawksim.backends.step_surrogate import StepSurrogateBackend
from hawksim.control.closed_loop import body_length, fly_closed_loop
from hawksim.control.derivatives import XI_NAMES, linearize
from hawksim.control.lqr import augment
from hawksim.control.plant import controlled_plant, wing_kinematics
from hawksim.control.schedule import Schedule, schedule_point, shipped_control_model, surrogate_schedule_speeds
from hawksim.control.surrogate import ControlledStepSurrogate
from hawksim.flight.orbit import set_body_state, shipped_orbit
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from regeneration import REGRESSED_ON_THE_SOURCED_HAWKMOTH

L = body_length()
SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)


def _speeds(regressed=()):
    """SPEEDS as test parameters, those in ``regressed`` marked REGRESSED_ON_THE_SOURCED_HAWKMOTH."""
    return [pytest.param(v, marks=REGRESSED_ON_THE_SOURCED_HAWKMOTH) if v in regressed else v for v in SPEEDS]


def _within(b, speed=0.02, angle=2.0):
    return (abs(b["speed_error"]) <= speed and abs(b["pitch_error_deg"]) <= angle and abs(b["roll_deg"]) <= angle
            and b["horizontal_drift_m"] < L)


@pytest.fixture(scope="module")
def schedule():
    return Schedule(0.0, 2.0, aero="surrogate")


def test_schedule_covers_the_shipped_orbits():
    """Orbits shipped for this network at all five speeds (0.5 m/s added for issue 20's targets)."""
    assert surrogate_schedule_speeds() == SPEEDS
    assert all(shipped_orbit(v, "surrogate").converged for v in SPEEDS)


def test_controlled_backend_reads_the_plant_kinematics():
    """Unbound, or bound to a plant on its base kinematics, the controlled backend gives the base backend's loads
    (to the round-off of the phase's time round trip; from the same record of past calls); within a blend it sees
    each wing's blended parameters and the blended phase, so an antisymmetric command gives unequal wing loads."""
    orb = shipped_orbit(1.0, "surrogate")
    kin = orb.kinematics
    sim = controlled_plant(load_model(), kin, "surrogate")
    assert isinstance(sim.backend, ControlledStepSurrogate)
    set_body_state(sim, orb.launch_state.as_array(), orb.chi_ref)
    for _ in range(37):
        sim.step()
    st = sim.state()
    plain = StepSurrogateBackend(kin)
    plain.history[:] = sim.backend.history  # a history network: the same record of past calls
    base = plain.loads(st)
    mine = sim.backend.loads(st)
    assert np.allclose(mine.force, base.force, rtol=1e-6, atol=1e-9)
    assert mine.power == pytest.approx(base.power, rel=1e-6)
    du = np.zeros(7)
    du[5] = np.deg2rad(4.0)  # dphi0: left minus right
    lp, rp = (Kinematics.from_array(p) for p in wing_kinematics(kin, du))
    sim.begin_beat(lp, rp)
    t_mid = sim.d.time + 0.5 * lp.period
    params, phase = sim.network_kinematics(t_mid)
    s = 0.5  # the quintic smoothstep at mid-blend
    assert np.allclose(params[0], (1 - s) * kin.as_array() + s * lp.as_array())
    assert np.allclose(params[1], (1 - s) * kin.as_array() + s * rp.as_array())
    assert phase == pytest.approx(np.pi)
    p_end, _ = sim.network_kinematics(sim.d.time + lp.period)
    assert np.allclose(p_end, np.stack([lp.as_array(), rp.as_array()]))


def test_shipped_control_models_are_about_the_shipped_orbits():
    """insects/hawkmoth/data/control_models_surrogate.json: made by its reproduce step for this network, one row per
    schedule speed about exactly the shipped orbit, differenced through the Table 2 saturation; a fresh linearization at
    1 m/s gives the same matrices (deterministic within a vector width and CPU kind; the bound allows other float32
    sums: another BLAS's moved them by < 5e-6, and the 512-bit code AMD Zen 5 compiles by default by 4.5e-5 to 1.7e-4
    (1.2e-4 of the largest entry) against the table's 256-bit rows, 2026-12-04: aero/vector_width.py)."""
    from hawksim.backends.step_network import network_sha256

    table = shipped_table("control_models_surrogate.json")
    assert table["command"] == "hawksim reproduce --only control_surrogate" and "seed" in table
    assert table["network_sha256"] == network_sha256()
    for v in SPEEDS:
        m = shipped_control_model(v, "surrogate")
        assert m is not None and m.clipped and m.coupling < 1e-9 and m.delta == 1e-3
    m1 = shipped_control_model(1.0, "surrogate")
    fresh = linearize(m1.orbit)
    for a, b in ((fresh.A, m1.A), (fresh.B0, m1.B0), (fresh.B1, m1.B1)):
        assert np.abs(a - b).max() < CONTROL_MODEL_RTOL * np.abs(b).max()


CONTROL_MODEL_RTOL = 1e-3
"""Largest difference allowed between a fresh linearization and the shipped one, relative to the matrix's
largest entry (test above)."""


def test_monodromy_agrees_with_the_orbit_table_floquet():
    """The shipped control model's A (step 1e-3; the history network's record held at the orbit's) against the
    Floquet monodromy of the same map (step 1e-4, hawksim.stability.floquet.monodromy): multipliers within 1e-3 at
    1 m/s (|mu| 1.608 long: the record-held map, not the flight's; the augmented map's is 1.564, test below; both in
    results/surrogate/step_orbits.json, `floquet` and `floquet_augmented`, from the regeneration's
    `scripts/studies/step_surrogate_orbits.py --validate` on hawksim 0.3.0's network and orbit table; hawksim 0.2's:
    1.53 and 1.42)."""
    from hawksim.stability.floquet import LAT, LONG, monodromy

    m = shipped_control_model(1.0, "surrogate")
    fq = monodromy(m.orbit)
    for ix in (LONG, LAT):
        a = np.sort(np.abs(np.linalg.eigvals(m.monodromy[np.ix_(ix, ix)])))
        b = np.sort(np.abs(np.linalg.eigvals(fq.monodromy[np.ix_(ix, ix)])))
        assert np.abs(a - b).max() < 1e-3
    assert np.abs(np.linalg.eigvals(m.monodromy)).max() == pytest.approx(1.608, abs=0.01)


@pytest.mark.parametrize("delay", [0, 1])
def test_closed_loop_multipliers_inside_the_unit_circle(schedule, delay):
    """Every schedule speed: open loop unstable (|mu| 1.35-2.62), closed loop inside the unit circle (0.964-0.974
    measured, hawksim 0.3.0's control_models_surrogate.json; hawksim 0.2's: 1.29-2.38 and 0.966-0.969). theta0 is in
    the design at every orbit: hawksim.control.schedule.symmetric_inputs leaves a symmetric channel out only where
    its parameter sits on a Table 2 bound, and hawksim 0.3.0's orbits (orbit_table_surrogate.json) have theta0 at
    9.5-19.4 deg, off its 25 deg bound (hawksim 0.2's sat on it at every speed, so it was left out)."""
    s = schedule if delay == 0 else Schedule(0.0, 2.0, aero="surrogate", delay=1)
    assert list(s.speeds) == list(SPEEDS)
    for p in s.points:
        assert np.abs(p.long.open_loop).max() > 1.25
        assert p.long.spectral_radius < 0.975 and p.lat.spectral_radius < 0.975
        assert p.long.inputs == (0, 1, 2, 3)  # f, phi0, alpha0, theta0


def test_linear_model_predicts_the_controlled_flight():
    """A 0.01 deg bank at 2 m/s under the LQR: the nonlinear flight's lateral states follow the linear closed loop
    (z_{k+1} = (Az - Bz K) z_k) to 5 % of the initial bank over 12 beats. Guards the saturation handling: with the
    flown (clipped) dphi_a fed back instead of the one sent, this flight's bank grew 46-fold in 22 beats."""
    p = schedule_point(2.0, aero="surrogate")
    A, B0, B1 = p.model.block("lat")
    Az, Bz = augment(A, B0, B1, 0)
    amp = np.deg2rad(0.01)
    pert = np.zeros(9)
    pert[6] = amp
    cl = fly_closed_loop(2.0, 12, schedule=Schedule(2.0, 2.0, aero="surrogate"), aero="surrogate", perturbation=pert)
    z = np.zeros(Az.shape[0])
    z[3] = amp
    x0, sc = p.orbit.initial_state.as_array(), p.model.scale
    lat = [XI_NAMES.index(k) for k in ("v", "p", "r", "phi")]
    for b in cl.beats:
        z = (Az - Bz @ p.lat.K) @ z
        nl = (np.array(b["state"]) - x0)[lat] / sc[lat]
        assert np.abs(nl - z[:4]).max() < 0.05 * amp * 10  # states up to ~10x the bank (rates x T)


def test_holds_and_recovers_at_1_m_s(schedule):
    """20 beats from the orbit within 1e-5 m/s (measured 1.9e-6); from the perturbed start (v, w +0.05 m/s, bank and
    pitch +1 deg) within issue 20's bounds from beat 7 (measured 7, within issue 20's 10 beats; hawksim 0.2's network
    from beat 3: the regenerated one's lateral oscillation, roll up to 2.8 deg at beat 5, decays more slowly, with
    theta0 in the design or left out alike, measured 2026-12-07)."""
    cl = fly_closed_loop(1.0, 20, schedule=schedule, aero="surrogate")
    assert max(abs(b["speed_error"]) for b in cl.beats) < 1e-5 and all(_within(b) for b in cl.beats)
    pert = np.zeros(9)
    pert[[1, 2, 6, 7]] = 0.05, 0.05, np.deg2rad(1.0), np.deg2rad(1.0)
    cp = fly_closed_loop(1.0, 20, schedule=schedule, aero="surrogate", perturbation=pert)
    assert all(_within(b) for b in cp.beats[6:])


def test_cli_surrogate_under_control(capsys):
    import json as js

    from hawksim.cli import main

    assert main(["fly", "--speed", "0.5", "--cycles", "3", "--aero", "surrogate", "--control", "lqr", "--json",
                 "--no-progress"]) == 0
    cap = capsys.readouterr()
    out = js.loads(cap.out)
    ctl = out["control"]
    assert out["aero"] == "surrogate" and ctl["mode"] == "lqr"
    assert [p["speed"] for p in ctl["schedule"]] == [0.5] and ctl["schedule"][0]["aero"] == "surrogate"
    assert ctl["schedule"][0]["inputs_long"] == ["f", "phi0", "alpha0", "theta0"]  # theta0 off its bound: in
    assert all(_within(b) for b in out["beats"]) and "held under LQR control" in cap.err  # issue 52: one table


def test_cli_surrogate_refusals(capsys, monkeypatch):
    """The constrained LQR per half-stroke and speeds outside the schedule are refused in one line, exit 2."""
    from hawksim.cli import main
    from hawksim.control import command

    assert main(["fly", "--speed", "1", "--cycles", "2", "--aero", "surrogate", "--control", "clqr",
                 "--control-rate", "half-stroke", "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--control clqr" in err[0] and "--control-rate beat" in err[0]
    monkeypatch.setattr("hawksim.control.schedule.shipped_schedule_speeds", lambda aero: (1.0, 1.5, 2.0))
    with pytest.raises(ValueError, match="covers 1 to 2 m/s"):
        command.check_surrogate_control(0.5, None)
    with pytest.raises(ValueError, match="--ascent-profile speed 0"):
        command.check_surrogate_control(1.0, [(0.0, 3)])
    monkeypatch.setattr("hawksim.control.schedule.shipped_schedule_speeds", lambda aero: ())
    with pytest.raises(ValueError, match="no shipped surrogate orbit"):
        command.check_surrogate_control(1.0, None)


@pytest.mark.slow
@pytest.mark.parametrize("speed", SPEEDS)
def test_100_beats_from_each_orbit(schedule, speed):
    """Issue 20's hold target at every speed: 100 controlled beats within the bounds (measured: speed error
    <= 2e-6 m/s, pitch <= 3e-4 deg, drift <= 2e-6 m; ~5 s per speed)."""
    cl = fly_closed_loop(speed, 100, schedule=schedule, aero="surrogate")
    assert all(_within(b) for b in cl.beats)
    assert max(abs(b["speed_error"]) for b in cl.beats) < 1e-4


def _pert(scale=1.0):
    p = np.zeros(9)
    p[[1, 2, 6, 7]] = 0.05 * scale, 0.05 * scale, np.deg2rad(scale), np.deg2rad(scale)
    return p


def test_small_gust_recovered_at_1_m_s(schedule):
    """A 0.2 m/s lateral gust over beats 5-6 at 1 m/s: within the bounds again 6 beats after it (measured 6; the
    0.5 m/s gust of issue 20 takes 11, docs/control.md)."""
    from hawksim.control.closed_loop import Gust

    cl = fly_closed_loop(1.0, 30, schedule=schedule, aero="surrogate", gusts=[Gust(np.array([0, 0.2, 0]), 5, 2)])
    assert all(_within(b) for b in cl.beats[12:])


@pytest.mark.slow
@pytest.mark.parametrize("speed", _speeds(regressed=(0.0, 0.5, 1.5, 2.0)))
def test_perturbed_start_recovers(schedule, speed):
    """From the perturbed start every speed is within the bounds from beat 10 on and stays there (measured: from
    beat 9, 3, 3, 3, 6 at 0, 0.5, 1, 1.5, 2 m/s)."""
    cl = fly_closed_loop(speed, 100, schedule=schedule, aero="surrogate", perturbation=_pert())
    assert all(_within(b) for b in cl.beats[9:])


@pytest.mark.slow
@REGRESSED_ON_THE_SOURCED_HAWKMOTH
def test_ascent_profile_without_overshoot(schedule):
    """0:2, 1:25, 2:25 then 2 m/s (60 beats; the surrogate's reference moves 0.05 m/s per beat): no beat above its
    command by 0.1 m/s (measured: none above it at all), within 0.02 m/s of 2 m/s from beat 55 on (measured 52)."""
    cl = fly_closed_loop(0.0, 60, schedule=schedule, aero="surrogate", profile=[(0.0, 2), (1.0, 25), (2.0, 25)])
    assert max(b["mean_vertical_speed"] - b["speed_command"] for b in cl.beats) < 0.1
    assert all(abs(b["mean_vertical_speed"] - 2.0) <= 0.02 for b in cl.beats[54:])


@pytest.mark.slow
@pytest.mark.parametrize("speed", _speeds(regressed=(0.0, 0.5, 1.0, 1.5, 2.0)))
def test_one_beat_delay_half_perturbation(speed):
    """Delay-aware gains with a one-beat sensing delay (per beat, on the augmented state): the half-size perturbed
    start is within the bounds from beat 9 on at every speed (measured from beat 2, 2, 2, 2, 8 at 0-2 m/s; the
    full-size start departs at 0.5 and 2 m/s; scripts/studies/control_surrogate.py, docs/control.md)."""
    s = Schedule(0.0, 2.0, aero="surrogate", delay=1)
    cl = fly_closed_loop(speed, 60, schedule=s, aero="surrogate", delay=1, perturbation=_pert(0.5))
    assert all(_within(b) for b in cl.beats[8:])


@pytest.fixture(scope="module")
def half_1():
    return Schedule(1.0, 1.0, aero="surrogate", speeds=(1.0,), rate="half-stroke")


def test_half_stroke_maps_of_the_surrogate_compose_to_its_beat_map(half_1):
    """The half-stroke maps (hawksim.control.halfstroke; for the history network on the augmented state, branched
    from the orbit's flight and its record): the body block of their product is the one-beat record-held monodromy
    up to the two half-beats' finite differences (step 1e-3 through the float32 network: ~1e-3 per entry, measured
    1.4e-4 at 1 m/s with the memoryless network); the periodic LQR closes the loop."""
    p = half_1.points[0]
    assert np.abs(p.half.monodromy - p.model.monodromy).max() < 2e-3
    assert p.long.spectral_radius < 0.99 and p.lat.spectral_radius < 0.99
    assert p.long.inputs == p.long_half.inputs and 3 in p.long.inputs  # theta0 (off its bound since 0.3.0) in


def test_half_stroke_control_rejects_the_gust_the_per_beat_lqr_does_not(half_1):
    """Issue 20's gust, 0.5 m/s lateral over beats 5-6 at 1 m/s: per half-stroke recovered within the bounds 3 beats
    after it (scripts/studies/control_surrogate.py --rate half-stroke), per beat after 11 (docs/control.md)."""
    from hawksim.control.closed_loop import Gust

    gust = [Gust(np.array([0.0, 0.5, 0.0]), 5, 2)]
    cl = fly_closed_loop(1.0, 20, aero="surrogate", schedule=half_1, gusts=gust)
    ok = [_within(b) for b in cl.beats]
    k = next(cl.beats[i]["beat"] for i in range(len(ok)) if all(ok[i:]))
    assert k - 6 <= 10
    assert max(abs(b["roll_deg"]) for b in cl.beats) < 10


def test_cli_half_stroke_with_the_surrogate(capsys):
    from hawksim.cli import main

    assert main(["fly", "--speed", "1", "--cycles", "4", "--aero", "surrogate", "--control-rate", "half-stroke",
                 "--no-progress", "--json"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert out["departed_at_beat"] is None and out["control"]["update_rate"] == "half-stroke"
    assert "updated per half-stroke" in cap.err


def test_half_stroke_with_a_one_beat_delay_recovers_the_full_start_at_1_m_s():
    """Delay-aware half-stroke gains (the delay is two half-strokes, the record sensed with the state): the
    full-size perturbed start at 1 m/s is within the bounds from beat 10 on (measured from beat 10 with hawksim
    0.3.0's network, pitch error up to 4.6 deg at beats 5-6; with theta0 left out of the design it departs; hawksim
    0.2's network: from beat 5, scripts/studies/control_surrogate.py --rate half-stroke, docs/control.md)."""
    s = Schedule(1.0, 1.0, aero="surrogate", speeds=(1.0,), rate="half-stroke", delay=1)
    cl = fly_closed_loop(1.0, 30, schedule=s, aero="surrogate", delay=1, perturbation=_pert())
    assert all(_within(b) for b in cl.beats[9:])


def test_half_stroke_maps_compose_to_the_augmented_monodromy(half_1):
    """The history network's half-stroke maps are on the augmented state (body and the record of its last 40
    calls): the product of the two halves has the body modes of the one-beat augmented monodromy
    (hawksim.stability.history_floquet.history_monodromy, step 1e-4; the maps' step is 1e-3): the dominant modes
    within 2e-3 at 1 m/s (|mu| 1.564 long, 1.201 lat: results/surrogate/step_orbits.json, `floquet_augmented`,
    regenerated for hawksim 0.3.0; hawksim 0.2's 1.422 and 1.258). The second lateral mode, a complex pair |mu| 0.737
    beside a real 0.700, comes out 0.742 (6.3e-3 relative; 0.7414 and 0.7408 with the maps' step 3e-4 and 1e-4, so
    not the difference step), held at SUBDOMINANT_RTOL; measured 2026-12-07, not explained yet."""
    from hawksim.stability.history_floquet import history_monodromy

    p = half_1.points[0]
    h = p.half
    assert h.records == 40 and h.A[0].shape == (251, 251)
    M = h.A[1] @ h.A[0]
    hf = history_monodromy(p.orbit)
    assert hf.residual < 1e-5  # the orbit is periodic in the augmented state
    for which, ref in (("long", hf.body_modes("long", count=2)), ("lat", hf.body_modes("lat", count=2))):
        ix = ([0, 2, 4, 7] if which == "long" else [1, 3, 5, 6]) + h.record_index(which)
        mu = np.linalg.eigvals(M[np.ix_(ix, ix)])
        got = np.sort(np.abs(mu))[::-1][:2]
        np.testing.assert_allclose(got[0], np.abs(ref[0]), rtol=2e-3)
        np.testing.assert_allclose(got[1], np.abs(ref[1]), rtol=2e-3 if which == "long" else SUBDOMINANT_RTOL)
    assert np.abs(hf.body_modes("long", count=1))[0] == pytest.approx(1.564, abs=2e-3)
    assert p.lat.record and p.long.record  # the gains feed the record back


SUBDOMINANT_RTOL = 8e-3
"""The half-stroke maps' product against the augmented monodromy in the second lateral mode at 1 m/s: measured
6.3e-3 (test above), hawksim 0.2's network 2e-3."""


# issue 20's targets with the surrogate's default controller, per half-stroke (scripts/studies/control_surrogate.py
# --rate half-stroke, results/control/control_surrogate_half_stroke.json; docs/control.md)
@pytest.fixture(scope="module")
def half():
    return Schedule(0.0, 2.0, aero="surrogate", rate="half-stroke")


@pytest.mark.slow
@pytest.mark.parametrize("speed", _speeds(regressed=(0.0,)))
def test_half_stroke_holds_recovers_and_rejects_the_gust(half, speed):
    """At every speed: 100 beats from the orbit within the bounds (measured speed error <= 7e-7 m/s); the perturbed
    start within them from beat 4 on (measured 3); issue 20's 0.5 m/s lateral gust over beats 5-6 recovered within 10
    beats (measured 2-3)."""
    from hawksim.control.closed_loop import Gust

    cl = fly_closed_loop(speed, 100, schedule=half, aero="surrogate")
    assert all(_within(b) for b in cl.beats) and max(abs(b["speed_error"]) for b in cl.beats) < 1e-4
    cp = fly_closed_loop(speed, 100, schedule=half, aero="surrogate", perturbation=_pert())
    assert all(_within(b) for b in cp.beats[3:])
    cg = fly_closed_loop(speed, 30, schedule=half, aero="surrogate", gusts=[Gust(np.array([0, 0.5, 0]), 5, 2)])
    assert all(_within(b) for b in cg.beats[16:])


@pytest.mark.slow
@pytest.mark.parametrize("speed", _speeds(regressed=(0.0, 0.5, 1.0, 1.5, 2.0)))
def test_half_stroke_one_beat_delay_full_start(speed):
    """One-beat sensing delay, delay-aware gains: the half-size perturbed start within the bounds from beat 4 on at
    every speed (measured from beat 3, 2, 2, 2, 2 at 0-2 m/s), the full-size one from beat 8 on at 0, 1 and 1.5 m/s
    (measured 7, 5, 5; it departs at 0.5 and 2 m/s: scripts/studies/control_surrogate.py --rate half-stroke,
    docs/control.md; the memoryless network it replaced recovered it at every speed)."""
    s = Schedule(0.0, 2.0, aero="surrogate", rate="half-stroke", delay=1)
    cl = fly_closed_loop(speed, 60, schedule=s, aero="surrogate", delay=1, perturbation=_pert(0.5))
    assert all(_within(b) for b in cl.beats[3:])
    if speed in (0.0, 1.0, 1.5):
        cl = fly_closed_loop(speed, 60, schedule=s, aero="surrogate", delay=1, perturbation=_pert())
        assert all(_within(b) for b in cl.beats[7:])


@pytest.mark.slow
@REGRESSED_ON_THE_SOURCED_HAWKMOTH
def test_half_stroke_ascent_profile_without_overshoot(half):
    """0:2, 1:25, 2:25 then 2 m/s (60 beats): no beat above its command by 0.1 m/s (measured -1.5e-7), pitch error
    within 2 deg throughout (measured 1.06), within 0.02 m/s of 2 m/s from beat 55 on (measured 50)."""
    cl = fly_closed_loop(0.0, 60, schedule=half, aero="surrogate", profile=[(0.0, 2), (1.0, 25), (2.0, 25)])
    assert max(b["mean_vertical_speed"] - b["speed_command"] for b in cl.beats) < 0.1
    assert max(abs(b["pitch_error_deg"]) for b in cl.beats) < 2.0
    assert all(abs(b["mean_vertical_speed"] - 2.0) <= 0.02 for b in cl.beats[54:])


def test_stability_floquet_prints_the_surrogate_control_derivatives(capsys):
    """Issue 20 item 1 for the surrogate: `hawksim stability --floquet --json` prints the B matrices beside the
    monodromy, the shipped control model's (about the shipped orbit), and the flight's multipliers from the
    augmented monodromy."""
    from hawksim.cli import main

    assert main(["stability", "--speed", "1", "--aero", "surrogate", "--floquet", "--json", "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    # the history network's flight modes: the augmented monodromy's (1.564 at 1 m/s, results/surrogate/
    # step_orbits.json `floquet_augmented`, hawksim 0.3.0's network; 0.2's: 1.422), not the record-held map's (1.608
    # there, `floquet`; 0.2's: 1.53)
    assert out["floquet"]["records"] == 40
    assert out["floquet"]["max_abs_multiplier"] == pytest.approx(1.564, abs=2e-3)
    assert out["floquet_record_held"]["max_abs_multiplier"] == pytest.approx(1.608, abs=0.01)
    c = out["control_derivatives"]
    ref = shipped_control_model(1.0, "surrogate")
    assert c["source"].startswith("shipped") and np.array_equal(np.array(c["B1"]), ref.B1)
    assert np.array(c["B0"]).shape == (11, 7)


def test_augmented_half_stroke_maps_are_cached_exactly(monkeypatch, tmp_path):
    """The history network's half-stroke maps (seconds to difference) go to the per-user cache
    (hawksim.control.cache): a second call reads the same arrays bit for bit, a corrupt file is recomputed, and
    HAWKSIM_NO_CACHE turns it off."""
    from hawksim.control import cache
    from hawksim.control.halfstroke import linearize_half_stroke

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv(cache.ENV_OFF, raising=False)
    orbit = shipped_orbit(1.0, "surrogate")
    first = linearize_half_stroke(orbit)
    files = list(cache.cache_dir().glob("*.npz"))
    assert len(files) == 1
    again = linearize_half_stroke(orbit)
    for a, b in zip(first.A + first.B0 + first.B1 + first.record_ref, again.A + again.B0 + again.B1 + again.record_ref):
        assert np.array_equal(a, b)
    assert np.array_equal(first.x_half, again.x_half) and again.records == first.records == 40
    files[0].write_bytes(b"not a numpy archive")
    fixed = linearize_half_stroke(orbit)
    assert np.array_equal(fixed.A[0], first.A[0])
    monkeypatch.setenv(cache.ENV_OFF, "1")
    files[0].unlink()
    linearize_half_stroke(orbit)
    assert not files[0].exists()


def test_trim_free_flight_reports_the_orbit_record(capsys):
    """`hawksim trim --free-flight --aero surrogate --json`: the shipped orbit, periodic in the body state and in the
    history network's record of its 40 calls (record_change <= hawksim.flight.orbit.RECORD_TOL)."""
    from hawksim.cli import main
    from hawksim.flight.orbit import RECORD_TOL

    assert main(["trim", "--speed", "1", "--free-flight", "--aero", "surrogate", "--json", "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] and out["warm_beats"] == 0
    assert out["record_calls"] == 40 and out["record_change"] <= RECORD_TOL


def test_augmented_beat_map_is_cached_exactly(monkeypatch, tmp_path):
    """The per-beat map on the augmented state (linearize(..., records=True), ~2 s) is cached too: the second call
    reads the same matrices bit for bit."""
    from hawksim.control import cache

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv(cache.ENV_OFF, raising=False)
    orbit = shipped_orbit(2.0, "surrogate")
    first = linearize(orbit, records=True)
    again = linearize(orbit, records=True)
    assert first.records == again.records == 40 and len(list(cache.cache_dir().glob("*.npz"))) == 1
    for a, b in ((first.A, again.A), (first.B0, again.B0), (first.B1, again.B1), (first.record_ref, again.record_ref)):
        assert np.array_equal(a, b)
    assert again.coupling == first.coupling and again.clipped == first.clipped
