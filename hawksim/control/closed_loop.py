"""The controlled flight: the wingbeat-to-wingbeat LQR in the loop of the nonlinear free flight.

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
from hawksim.control.derivatives import stability_position
from hawksim.control.plant import command_of, controlled_plant, saturate
from hawksim.control.schedule import Schedule
from hawksim.flight.orbit import STEPS_PER_CYCLE, backend_record, read_body_state, set_body_state
from hawksim.flight.power import P_plus
from hawksim.flight.result import FlightResult
from hawksim.frames import attitude_of, pitch_of, quat_from_matrices
from hawksim.insect.insect import DEFAULT_INSECT, Insect
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.insect.morphology import Morphology

SPEED_RATE = 0.2
"""Largest change of the speed reference per wingbeat [m/s]."""


SATURATION_TOL = 1e-9
"""A wing counts as saturated when Table 2 clipped a parameter by more than this [SI] (the orbit sits on
phi_a = 60 deg, so round-off-level antisymmetric commands are clipped all the time)."""


def body_length(morph: Morphology | None = None) -> float:
    """Head tip to abdomen tip along body x [m] of ``morph``'s segments (default the default insect's, 0.0425 m)."""
    morph = DEFAULT_INSECT.morphology if morph is None else morph
    lo = min(s.centre[0] - s.semi_axes[0] for s in morph.segments)
    hi = max(s.centre[0] + s.semi_axes[0] for s in morph.segments)
    return float(hi - lo)


@dataclass(frozen=True)
class Gust:
    """A uniform air velocity ``velocity`` (3,) world [m/s] over wingbeats start .. start + beats - 1 (1-based)."""

    velocity: np.ndarray
    start: int
    beats: int

    def at(self, beat: int) -> np.ndarray:
        return np.asarray(self.velocity, float) if self.start <= beat < self.start + self.beats else np.zeros(3)


def profile_speeds(profile: list[tuple[float, int]] | None, speed: float, beats: int) -> np.ndarray:
    """Commanded speed (beats,) per wingbeat: the profile's (speed, beats) pieces in turn, its last speed held
    after it (or ``speed`` throughout without a profile)."""
    if not profile:
        return np.full(beats, float(speed))
    seq = [float(v) for v, n in profile for _ in range(int(n))]
    seq += [seq[-1]] * max(0, beats - len(seq))
    return np.array(seq[:beats])


class ControlledFlightResult(FlightResult):
    """A :class:`FlightResult` whose wingbeats may differ in length (f changes; the per-beat means of
    :meth:`FlightResult.beats` are over each beat's own time span), with the departure test against each beat's
    speed reference (the rate-limited command): a beat's mean vertical speed departs when it is more than
    DEPARTURE_SPEED outside the range of this beat's and the previous beat's reference (a reference change reaches
    the flight one beat late: the new kinematics blend in over the beat)."""

    def __init__(self, *args, beat_steps: int, speed_commands: np.ndarray, **kw):
        super().__init__(*args, **kw)
        object.__setattr__(self, "_speed_commands", np.asarray(speed_commands, float))

    def departed_at_beat(self, beats=None):
        from hawksim.flight.result import DEPARTURE_ANGLE_DEG, DEPARTURE_SPEED

        beats = self.beats() if beats is None else beats
        ref = beats[0]
        r = self._speed_commands
        for k, b in enumerate(beats, 1):
            a, c = r[min(k - 1, len(r) - 1)], r[max(0, min(k - 2, len(r) - 1))]
            vz = b["mean_vertical_speed"]
            off = max(min(a, c) - vz, vz - max(a, c), 0.0)
            if (off > DEPARTURE_SPEED or b["horizontal_speed"] > DEPARTURE_SPEED
                    or any(abs(b[a] - ref[a]) > DEPARTURE_ANGLE_DEG for a in ("pitch_deg", "roll_deg", "yaw_deg"))):
                return k
        return None


@dataclass
class ClosedLoop:
    """What :func:`fly_closed_loop` returns: ``beats`` (one dict per wingbeat: commanded and reference speed,
    the beat's mean vertical speed and its error, pitch error against the orbit's mean pitch, roll and yaw [deg]
    (beat means of :func:`hawksim.frames.attitude_of`, as the CLI contract's ``beats``),
    horizontal offset from the start point [m], the air velocity, the body state at the beat's end (SI,
    hawksim.flight.orbit.STATE_NAMES), the commands (edge units) and whether a wing saturated, P+),
    the time series ``result`` (None without ``record``) and the schedule."""

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


def _edge_command(kin: Kinematics, du: np.ndarray) -> dict:
    return {"f_hz": float(kin.f * (1 + du[0])), "phi0_deg": float(np.rad2deg(kin.phi0 + du[1])),
            "alpha0_deg": float(np.rad2deg(kin.alpha0 + du[2])), "theta0_deg": float(np.rad2deg(kin.theta0 + du[3])),
            "dphi_a_deg": float(np.rad2deg(du[4])), "dphi0_deg": float(np.rad2deg(du[5])),
            "dalpha0_deg": float(np.rad2deg(du[6]))}


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
    ``insect``: the insect flown (default :data:`hawksim.insect.insect.DEFAULT_INSECT`): the schedule made here is of
    its own orbits and gains (quasi-steady: solved here; ``control='clqr'`` and backends of shipped orbits take the
    default insect only, ValueError), its wings in the backend, its MJCF unless ``model`` is given, its kinematic
    bounds for the saturation, its weight and P0 in ``result``; a given ``schedule`` must be of the same insect."""
    if control not in ("lqr", "clqr", "none"):
        raise ValueError(f"--control {control!r}: choose lqr, clqr, none")
    t_start = time.perf_counter()
    insect = DEFAULT_INSECT if insect is None else insect
    desc = descriptor(aero)
    gusts = list(gusts or [])
    cmd = profile_speeds(profile, speed, beats)
    dd = delay if design_delay is None else design_delay
    if schedule is None and control == "clqr":
        from hawksim.control.constrained import ConstrainedSchedule

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
    p_orbit = kin0.as_array()
    sim.set_wings(kin0, kin0)
    n = STEPS_PER_CYCLE
    rec = {k: [] for k in ("t", "pos", "R", "v", "w", "wR", "wo", "F", "M", "Pa", "Pj")}
    warm = exact[0].orbit.warm_beats if exact else 0
    starts = [(1.0, exact[0].orbit)] if exact else [(w, pt.orbit) for w, pt in schedule.weights(speed)]
    if all(o.record is not None for _, o in starts):  # a history network: start with the orbit's record
        sim.backend.seed(sum(w * o.record for w, o in starts), sum(w * o.record_dt for w, o in starts))
    if warm:  # UVLM: launch, develop the wake open loop, then sense the periodic beat's start
        set_body_state(sim, exact[0].orbit.launch_state.as_array() + (x0 - exact[0].orbit.initial_state.as_array()),
                       chi0)
        for _ in range(warm):
            sim.begin_beat(kin0, kin0)
            sim.advance(n)
        x0 = read_body_state(sim, chi0)
    else:
        set_body_state(sim, x0, chi0)
    hold = stability_position(sim.d.qpos[:3])
    nseg = schedule.per_beat  # control updates per beat: 1 (phase 0) or 2 (phases 0 and 0.5)
    lag, design_lag = delay * nseg, schedule.delay * nseg  # the sensing delay and the gains' one, in updates
    keep = max(lag, design_lag) + 2 * nseg
    flown = [(p_orbit, p_orbit)] * keep  # (left, right) of the updates before the first
    # the past commands the gains see: those flown (saturated), or for derivatives taken through the saturation
    # (hawksim.control.derivatives.SATURATED_DERIVATIVES) those sent, which is what that model's inputs are
    sent = any(p.model.clipped for p in schedule.points)
    feeds = schedule.feeds_record  # a history network's gains read its record of calls
    rec0 = backend_record(sim.backend, sim.aero_every) if feeds else None
    if nseg == 1:
        sensed = [(x0, np.zeros(2), rec0)] * keep
    else:  # the entry m updates before the start was sensed at phase m mod 2 (the orbit's state there)
        _, x_h, _, _ = schedule.reference(speed, 1)
        pos_h = sum(w * pt.reference_state(1)[1] for w, pt in schedule.weights(speed))
        rec_h = schedule.reference_record(speed, 1) if feeds else None
        sensed = [(x0, np.zeros(2), rec0) if (keep - 1 - i) % 2 == 0 else (x_h, pos_h, rec_h) for i in range(keep)]
    out, refs = [], []
    v_ref = float(speed)
    if speed_rate is None:
        speed_rate = desc.speed_rate if desc.speed_rate is not None else SPEED_RATE
    speed_rate = float(speed_rate)
    rate_limit = speed_rate / nseg  # the reference moves at each update, speed_rate per beat
    if progress is not None:
        progress(0, beats)
    try:
        for k in range(1, beats + 1):
            air = sum((g.at(k) for g in gusts), np.zeros(3))
            sim.air_v = air
            t0, z0 = sim.d.time, sim.d.qpos[2]
            pitch, Rs, pj = np.empty(n), np.empty((n, 3, 3)), np.empty(n)
            applied, saturated, pitch_refs = [], False, []
            for seg in range(nseg):
                v_ref += float(np.clip(cmd[k - 1] - v_ref, -rate_limit, rate_limit))
                kin_ref, _, chi_ref, pitch_ref = schedule.reference(v_ref)
                pitch_refs.append(pitch_ref)
                if control != "none":
                    x_s, pos_s, rec_s = sensed[-1 - lag]
                    lp, rp = schedule.wings(v_ref, x_s, pos_s, flown[-1 - design_lag:], phase=seg, record=rec_s)
                else:
                    lp = rp = p_orbit
                ls, rs = saturate(lp, insect), saturate(rp, insect)
                saturated |= bool(max(np.abs(ls - lp).max(), np.abs(rs - rp).max()) > SATURATION_TOL)
                applied.append(_edge_command(kin_ref, command_of(kin_ref, ls, rs)))
                if nseg == 1:
                    sim.begin_beat(Kinematics.from_array(ls), Kinematics.from_array(rs))
                else:
                    sim.begin_beat(Kinematics.from_array(ls), Kinematics.from_array(rs), phase=np.pi * seg, span=0.5)
                i0, i1 = seg * n // nseg, (seg + 1) * n // nseg
                b = sim.advance(i1 - i0)
                pitch[i0:i1], Rs[i0:i1], pj[i0:i1] = pitch_of(b.body_R), b.body_R, b.power_joint
                if record:
                    for key, val in (("t", b.t), ("pos", b.body_pos), ("R", b.body_R), ("v", b.body_v),
                                     ("w", b.body_omega), ("wR", b.wing_R), ("wo", b.wing_origin), ("F", b.force),
                                     ("M", b.moment_about_body()), ("Pa", b.power_aero), ("Pj", b.power_joint)):
                        rec[key].append(val)
                if not np.all(np.isfinite(sim.d.qpos)):
                    raise FloatingPointError(f"controlled flight diverged in beat {k}")
                x = read_body_state(sim, chi_ref)
                pos = stability_position(sim.d.qpos[:3]) - hold
                flown.append((lp, rp) if sent else (ls, rs))
                sensed.append((x, pos, backend_record(sim.backend, sim.aero_every) if feeds else None))
                flown, sensed = flown[-keep:], sensed[-keep:]
            refs.append(v_ref)
            pitch_ref = sum(pitch_refs) / nseg
            T = sim.d.time - t0
            vz = (sim.d.qpos[2] - z0) / T
            att = attitude_of(Rs)  # roll and yaw as the CLI contract's `beats` (pitch-first angles)
            out.append({"beat": k, "speed_command": float(cmd[k - 1]), "speed_reference": v_ref,
                        "mean_vertical_speed": float(vz), "speed_error": float(vz - cmd[k - 1]),
                        "pitch_error_deg": float(np.rad2deg(pitch.mean() - pitch_ref)),
                        "roll_deg": float(np.rad2deg(att[:, 1].mean())), "yaw_deg": float(np.rad2deg(att[:, 2].mean())),
                        "horizontal_offset_m": [float(pos[0]), float(pos[1])],
                        "horizontal_drift_m": float(np.hypot(*pos)),
                        "air_velocity": [float(a) for a in air],
                        "state": [float(a) for a in x],
                        "commands": applied[0], "saturated": saturated,
                        "P_plus": P_plus(pj, sim.aero_every, P0=insect.P0)})
            if nseg > 1:
                out[-1]["commands_half_stroke"] = applied[1]
            if progress is not None:  # after the beat is complete (an interrupt raised here keeps it)
                progress(k, beats)
        end_t, end_pos = float(sim.d.time), sim.body_com()
    except KeyboardInterrupt:
        end_t = end_pos = None
        done = min(len(v) for v in rec.values())  # the segments completed
        if not (partial_on_interrupt and record and done > 0):
            raise
        rec = {k: v[:done] for k, v in rec.items()}
    result = None
    if record:
        a = {k: np.concatenate(v) if v else np.zeros(0) for k, v in rec.items()}
        result = ControlledFlightResult(
            speed_target=float(speed), cycles=int(beats), aero=aero, kinematics=kin0, steps_per_cycle=n,
            t=a["t"], body_pos=a["pos"], body_quat=quat_from_matrices(a["R"]), body_v=a["v"], body_omega=a["w"],
            wing_R=a["wR"], wing_origin=a["wo"], force=a["F"], moment=a["M"], power_aero=a["Pa"],
            power_joint=a["Pj"], wall_time_s=time.perf_counter() - t_start,
            trim_source=f"periodic orbit of the free body, {control} control", beat_steps=n,
            speed_commands=np.array(refs), end_t=end_t, end_pos=end_pos, aero_every=sim.aero_every, insect=insect)
    return ClosedLoop(beats=out, schedule=schedule, result=result, wall_time_s=time.perf_counter() - t_start,
                      control=control, delay=int(delay), gusts=gusts, speed_rate=speed_rate)
