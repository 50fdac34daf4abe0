"""The controlled flight: the wingbeat-to-wingbeat LQR in the loop of the nonlinear free flight
(:func:`fly_closed_loop`, a wrapper of the one flight loop :func:`hawksim.flight.loop.run` with the controllers of
:mod:`hawksim.control.controller`).

Per wingbeat k, at phase 0 (:func:`fly_closed_loop`; per half-stroke steps 3-4 run at phases 0 and 0.5, with
the gains and reference state of each phase):

1. the speed reference V_k moves toward the commanded speed (the ascent profile) by at most
   :data:`SPEED_RATE` m/s per beat (a backend descriptor's ``speed_rate`` for some backends; a rate-limited
   prefilter: a step of 1 m/s is far outside the linear model);
2. the schedule (:class:`hawksim.control.schedule.Schedule`, periodic orbits and LQR gains at grid speeds) gives
   the reference at V_k by linear interpolation between the two neighbouring orbits: state, kinematics, gains;
3. the sensed state (body state and horizontal position of beat k - d, d the sensing delay) and the commands
   already flown (as saturated at Table 2; for a schedule whose derivatives were taken through the saturation, the
   surrogate's, as sent) make the augmented deviation z (:mod:`hawksim.control.lqr`); each neighbour's gain gives
   u = -K z in its own normalization, and the two are blended with the interpolation weights;
4. each wing's kinematics (reference + command, :func:`hawksim.control.plant.wing_kinematics`) saturate at
   Table 2 and the beat blends into them (:class:`hawksim.control.plant.ControlledSimulator`); a gust is a
   uniform air velocity over whole beats.

The horizontal position is held at the start point (X, Y in the state, weighted lightly); altitude is free (the
vertical speed, not the height, is commanded).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from hawksim.backends.memory import WAKE
from hawksim.backends.registry import descriptor
from hawksim.control.constrained import ConstrainedSchedule
from hawksim.control.controller import SPEED_RATE, ConstrainedLQR, LQR, profile_speeds
from hawksim.control.plant import controlled_plant
from hawksim.control.schedule import Schedule
from hawksim.flight.body_state import read_body_state, set_body_state
from hawksim.flight.loop import SATURATION_TOL, Gust, run
from hawksim.flight.orbit import STEPS_PER_CYCLE
from hawksim.flight.result import FlightResult
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.model import load_model
from hawksim.insect.morphology import Morphology

__all__ = ["SPEED_RATE", "SATURATION_TOL", "Gust", "ClosedLoop", "body_length", "profile_speeds", "fly_closed_loop"]


def body_length(morph: Morphology | None = None) -> float:
    """Head tip to abdomen tip along body x [m] of ``morph``'s segments (default the default insect's, 0.0425 m)."""
    morph = default_insect().morphology if morph is None else morph
    lo = min(s.centre[0] - s.semi_axes[0] for s in morph.segments)
    hi = max(s.centre[0] + s.semi_axes[0] for s in morph.segments)
    return float(hi - lo)


@dataclass
class ClosedLoop:
    """What :func:`fly_closed_loop` returns (a view of its :class:`FlightResult` and controller): ``beats`` (one dict
    per wingbeat, :attr:`FlightResult.beat_log`: commanded and reference speed, the beat's mean vertical speed and
    its error, pitch error against the orbit's mean pitch, roll and yaw [deg] (beat means of
    :func:`hawksim.frames.attitude_of`, as the CLI contract's ``beats``), horizontal offset from the start point [m],
    the air velocity, the body state at the beat's end (SI, hawksim.flight.orbit.STATE_NAMES), the commands (edge
    units) and whether a wing saturated, P+), the time series ``result`` (None without ``record``) and the schedule."""

    beats: list[dict]
    schedule: Schedule
    result: FlightResult | None
    wall_time_s: float
    control: str = "lqr"
    delay: int = 0
    gusts: list = field(default_factory=list)
    speed_rate: float = SPEED_RATE

    def series(self, key: str) -> np.ndarray:
        return np.array([b[key] for b in self.beats])

    def to_json(self) -> dict:
        return {"mode": self.control, "update_rate": self.schedule.rate, "delay_beats": self.delay,
                "speed_rate_m_s_per_beat": self.speed_rate,
                "body_length_m": body_length(self.schedule.insect.morphology),
                "schedule": [p.to_json() for p in self.schedule.points],
                "gusts": [{"velocity": list(map(float, g.velocity)), "start": g.start, "beats": g.beats}
                          for g in self.gusts],
                "beats": self.beats} | ({"constrained": self.schedule.to_json_constrained()}
                                        if hasattr(self.schedule, "to_json_constrained") else {})


def fly_closed_loop(speed: float, beats: int, *, profile: list[tuple[float, int]] | None = None,
                    gusts: list[Gust] | None = None, delay: int = 0, control: str = "lqr",
                    perturbation: np.ndarray | None = None, schedule: Schedule | None = None,
                    model: mujoco.MjModel | None = None, record: bool = False, log=None,
                    progress: Callable[[int, int], None] | None = None,
                    design_delay: int | None = None, aero: str = "quasi-steady", rate: str = "beat",
                    partial_on_interrupt: bool = False, speed_rate: float | None = None,
                    insect: Insect | None = None) -> ClosedLoop:
    """Fly ``beats`` wingbeats from the quasi-steady orbit at ``speed`` [m/s] (plus ``perturbation`` (9,) SI in
    :data:`hawksim.flight.orbit.STATE_NAMES` order: angles in radians, rates in rad/s) under the LQR
    (``control='lqr'``) or open loop (``'none'``:
    the orbit's kinematics throughout), commanded by ``profile`` [(speed, beats)] (default: ``speed``), with
    ``gusts``, sensing ``delay`` [beats]. ``design_delay``: the delay the gains were designed for (default
    ``delay``; a smaller one tests a controller unaware of the delay). ``record``: keep the per-step time series
    (``ClosedLoop.result``, a FlightResult for summary() and write_rrd). ``aero='uvlm'``: the schedule's
    orbits must be UVLM orbits (:class:`Schedule` with ``aero='uvlm'``: the shipped orbits at 1, 1.5, 2 m/s), the
    flight starts on one of them (``speed`` a schedule speed; a ValueError otherwise) and is launched from the
    orbit's launch state and flies its warm-up beats open loop before the ``beats`` controlled ones (only those
    are reported). ``rate``: control updates once per ``'beat'`` or per ``'half-stroke'`` (phases 0 and 0.5,
    quasi-steady only) for the schedule made here (a given ``schedule`` brings its own).
    ``speed_rate``: the speed reference's largest change per beat [m/s] (default the backend descriptor's
    ``speed_rate``, else :data:`SPEED_RATE`). ``progress(k, beats)`` is called before the first beat (k = 0) and
    after each complete beat.
    ``partial_on_interrupt`` (with ``record``): a KeyboardInterrupt during the beats returns the steps and beats
    completed so far (``result`` with fewer than beats x 200 rows, ``beats`` the complete ones) instead of
    propagating; with no step completed it propagates.
    ``insect``: the insect flown (default :func:`hawksim.insect.folder.default_insect`): the schedule made here is of
    its own orbits and gains (quasi-steady: solved here; ``control='clqr'`` and backends of shipped orbits take the
    default insect only, ValueError), its wings in the backend, its MJCF unless ``model`` is given, its kinematic
    bounds for the saturation, its weight and P0 in ``result``; a given ``schedule`` must be of the same insect.

    The flight is the one flight loop (:func:`hawksim.flight.loop.run`) under :class:`hawksim.control.controller.LQR`
    (``'none'``: with ``feedback=False``; ``'clqr'``: :class:`hawksim.control.controller.ConstrainedLQR`), started
    from the schedule's reference at ``speed``; ``hawksim.fly(orbit, cycles=..., controller=LQR.at(speed))`` flies
    the same from an orbit."""
    if control not in ("lqr", "clqr", "none"):
        raise ValueError(f"--control {control!r}: choose lqr, clqr, none")
    t_start = time.perf_counter()
    insect = default_insect() if insect is None else insect
    desc = descriptor(aero)
    gusts = list(gusts or [])
    cmd = profile_speeds(profile, speed, beats)
    dd = delay if design_delay is None else design_delay
    if schedule is None and control == "clqr":
        schedule = ConstrainedSchedule(min(speed, cmd.min()), max(speed, cmd.max()), delay=dd, model=model, log=log,
                                       aero=aero, rate=rate, insect=insect)
    if schedule is None:
        schedule = Schedule(min(speed, cmd.min()), max(speed, cmd.max()), delay=dd, model=model, log=log, aero=aero,
                            rate=rate, insect=insect)
    if any(p.orbit.aero != aero for p in schedule.points):
        raise ValueError(f"the schedule's orbits are not {aero} orbits")
    if any(p.orbit.insect != insect for p in schedule.points):
        raise ValueError(f"the schedule's orbits are not of the insect {insect.name!r}")
    if desc.memory == WAKE and not any(p.speed == speed for p in schedule.points):  # the wake needs its launch
        raise ValueError(f"speed={speed:g} with aero={aero!r} under control: the flight starts on a shipped orbit "
                         f"({', '.join(f'{p.speed:g}' for p in schedule.points)} m/s here), whose launch develops "
                         "the wake; command speeds in between with profile")
    model = model if model is not None else load_model(morph=insect.morphology)
    start = schedule.reference(speed)
    kin0, x0, chi0, _ = start
    exact = [p for p in schedule.points if p.speed == speed]
    if exact:  # start exactly on the orbit
        kin0, x0, chi0 = exact[0].orbit.kinematics, exact[0].orbit.initial_state.as_array(), exact[0].orbit.chi_ref
    if perturbation is not None:
        x0 = x0 + np.asarray(perturbation, float)
    sim = controlled_plant(model, kin0, aero, insect=insect)
    sim.set_wings(kin0, kin0)
    warm = exact[0].orbit.warm_beats if exact else 0
    starts = [(1.0, exact[0].orbit)] if exact else [(w, pt.orbit) for w, pt in schedule.weights(speed)]
    if all(o.record is not None for _, o in starts):  # a history network: start with the orbit's record
        sim.backend.seed(sum(w * o.record for w, o in starts), sum(w * o.record_dt for w, o in starts))
    if warm:  # UVLM: launch, develop the wake open loop, then sense the periodic beat's start
        set_body_state(sim, exact[0].orbit.launch_state.as_array() + (x0 - exact[0].orbit.initial_state.as_array()),
                       chi0)
        for _ in range(warm):
            sim.begin_beat(kin0, kin0)
            sim.advance(STEPS_PER_CYCLE)
        x0 = read_body_state(sim, chi0)
    else:
        set_body_state(sim, x0, chi0)
    ctl_class = ConstrainedLQR if control == "clqr" and isinstance(schedule, ConstrainedSchedule) else LQR
    ctl = ctl_class(schedule, speed, profile=profile, speed_rate=speed_rate, feedback=control != "none",
                    kinematics=kin0)
    result = run(sim, beats, kinematics=kin0, speed=speed, aero=aero,
                 source=f"periodic orbit of the free body, {control} control", controller=ctl, chi_ref=chi0,
                 gusts=gusts, sensing_delay=delay, progress=progress,
                 partial_on_interrupt=partial_on_interrupt and record, insect=insect, t_start=t_start, state0=x0)
    return ClosedLoop(beats=result.beat_log, schedule=schedule, result=result if record else None,
                      wall_time_s=time.perf_counter() - t_start, control=control, delay=int(delay), gusts=gusts,
                      speed_rate=ctl.speed_rate)
