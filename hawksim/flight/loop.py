"""The one flight loop: ``fly(point, backend, cycles, controller=...)``, open loop or under a :class:`Controller`.

Every free flight of hawksim runs through :func:`run` (``hawksim fly`` with and without ``--control``, gusts,
ascent profiles, every backend; :func:`hawksim.flight.fly.fly` and :func:`hawksim.control.closed_loop.
fly_closed_loop` are its wrappers). Per wingbeat k (1-based):

1. the air velocity of the beat's gusts (:class:`Gust`) is set on the plant;
2. per update (once per beat at phase 0, or at phases 0 and 0.5 for a controller whose ``rate`` is
   ``'half-stroke'``), the controller is handed an :class:`Observation` (time, the body state sensed
   ``sensing_delay`` wingbeats ago, the past wing kinematics) and returns each wing's Eq. 1 parameters; they are
   clipped at the insect's kinematic bounds and the plant blends into them over the update
   (:class:`hawksim.flight.plant.ControlledSimulator`); without a controller the wings keep their prescribed motion
   and the plant is a plain :class:`hawksim.flight.simulator.Simulator`;
3. the plant advances the update's steps (all in native code where it can) and the steps are kept;
4. with a controller, the body state is sensed (:func:`hawksim.flight.body_state.read_body_state`) and a per-beat
   row is written (:meth:`FlightResult.beat_log`).

The result is one :class:`hawksim.flight.result.FlightResult` whatever flew it.

Units: SI inside and out, angles in radians (the CLI's degrees are converted at its edge; ``perturb`` keeps the
CLI's units, :data:`hawksim.flight.start.PERTURBATIONS`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE
from hawksim.flight.body_state import read_body_state
from hawksim.flight.plant import saturate
from hawksim.flight.power import P_plus
from hawksim.flight.result import FlightResult
from hawksim.frames import (STABILITY_TO_WORLD, attitude_of, cross, pitch_of, quat_from_matrices,
                            stability_position)
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics

RATES = ("beat", "half-stroke")
"""A controller's update rate: once per wingbeat (phase 0) or once per half-stroke (phases 0 and 0.5)."""

UPDATES_PER_BEAT = {"beat": 1, "half-stroke": 2}

SATURATION_TOL = 1e-9
"""A wing counts as saturated when the kinematic bounds clipped a parameter by more than this [SI] (the orbit sits on
phi_a = 60 deg, so round-off-level antisymmetric commands are clipped all the time)."""


@dataclass(frozen=True)
class Gust:
    """A uniform air velocity ``velocity`` (3,) world [m/s] over wingbeats start .. start + beats - 1 (1-based)."""

    velocity: np.ndarray
    start: int
    beats: int

    def at(self, beat: int) -> np.ndarray:
        return np.asarray(self.velocity, float) if self.start <= beat < self.start + self.beats else np.zeros(3)


@dataclass(frozen=True)
class Observation:
    """What a :class:`Controller` is given at each update.

    beat: the wingbeat about to be flown (1-based); half: the update within it (0 at phase 0; 1 at phase 0.5 for a
    ``'half-stroke'`` controller); time [s]: the plant's time now. state (9,): the body state sensed
    ``sensing_delay`` wingbeats ago at this update's phase, in :data:`hawksim.flight.body_state.STATE_NAMES` order
    (u, v, w [m/s], p, q, r [rad/s], phi, theta, psi [rad]; stability axes of the body pitch ``chi_ref``: the
    controller's :attr:`Controller.chi_ref` if it has one, else the operating point's); position (2,): the
    horizontal position (X forward, Y right) [m] from the start point, sensed with the state; record: a history
    network's record of its calls (n, 6) SI sensed with it (None unless the controller's ``senses_record``).
    past and past_sent: the (left, right) wing parameter vectors (7,) SI (:data:`hawksim.insect.kinematics.
    PARAM_NAMES` order) of the previous updates, oldest first (the last is the update just flown): ``past`` as flown
    (clipped at the bounds), ``past_sent`` as the controller returned them. point: the operating point flown from
    (an :class:`hawksim.flight.orbit.Orbit` or :class:`hawksim.trim.point.Trim`; None if not given)."""

    beat: int
    half: int
    time: float
    state: np.ndarray
    position: np.ndarray
    record: np.ndarray | None
    past: tuple
    past_sent: tuple
    point: object = None


@runtime_checkable
class Controller(Protocol):
    """A flight controller for :func:`fly`: a plain class with these members (no base class needed).

    - ``rate``: ``'beat'`` (one update per wingbeat, at phase 0) or ``'half-stroke'`` (at phases 0 and 0.5).
    - ``reset(point)``: called once before the first update with the operating point flown from (an
      :class:`hawksim.flight.orbit.Orbit` or :class:`hawksim.trim.point.Trim`, its ``kinematics`` the wings' start;
      None if not given): forget any state of a previous flight.
    - ``update(obs)``: given an :class:`Observation`, return the (left, right) wings' Eq. 1 parameters for the
      update about to be flown: two arrays (7,) SI in :data:`hawksim.insect.kinematics.PARAM_NAMES` order (f [Hz],
      beta, phi0, theta0, alpha0, phi_a, alpha_a [rad]; both wings at one f), or two
      :class:`hawksim.insect.kinematics.Kinematics`. The loop clips each at the insect's kinematic bounds
      (``Observation.past`` holds what was flown) and blends the wings into them over the update. A wrong shape, a
      non-finite value or two frequencies is a ValueError naming the controller.

    Optional members, read with ``getattr``:

    - ``chi_ref`` [rad]: the body pitch of the stability axes the state is sensed in (default the operating
      point's; a scheduled controller moves it with its reference; read after each update).
    - ``history`` (int, default 1): how many past updates ``Observation.past`` must hold.
    - ``senses_record`` (bool): whether the observation carries a history network's record.
    - ``sensed_before_start(half)``: the (state, position, record) taken as sensed before the start at update
      ``half`` (default the start).
    - ``beat_row(row, steps)``: the per-beat row of :attr:`FlightResult.beat_log` given the loop's measured one and
      the beat's :class:`hawksim.flight.steps.StepBatch` list, one per update (default that row).
    - ``speed_reference()`` [m/s]: the speed the beat is flown to (default the operating point's speed), recorded
      per beat for the departure test.
    - ``axis``: what the speed references are, ``"vertical"`` (default) or ``"forward"`` speeds.
    - ``pitch_reference()`` [rad] or None: the beat's reference body pitch, recorded per beat for the departure test
      where given (a forward-flight schedule's).
    - ``hold_velocity()`` (2,) [m/s] or None: the velocity (stability X, Y) the held horizontal point moves at from
      this update on (default: it stays, or moves at the forward speed flown).

    The shipped implementations: :class:`hawksim.control.controller.NoControl`, :class:`hawksim.control.controller.
    LQR` (per beat or per half-stroke) and :class:`hawksim.control.controller.ConstrainedLQR`;
    examples/your_own_controller.py is a user's.
    """

    rate: str

    def reset(self, point) -> None: ...

    def update(self, obs: Observation): ...


def _wings(out, controller) -> tuple[np.ndarray, np.ndarray]:
    """The controller's output as two (7,) float arrays, or a ValueError naming the controller."""
    name = type(controller).__name__
    try:
        left, right = out
    except (TypeError, ValueError):
        raise ValueError(f"controller {name}.update returned {type(out).__name__}, not a (left, right) pair of wing "
                         f"kinematics (arrays (7,) SI in the order {', '.join(PARAM_NAMES)}, or Kinematics)") from None
    wings = []
    for side, w in (("left", left), ("right", right)):
        a = w.as_array() if isinstance(w, Kinematics) else np.asarray(w, dtype=float)
        if a.shape != (len(PARAM_NAMES),):
            raise ValueError(f"controller {name}.update returned a {side} wing of shape {a.shape}; expected "
                             f"({len(PARAM_NAMES)},) SI in the order {', '.join(PARAM_NAMES)}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"controller {name}.update returned a non-finite {side} wing: {a.tolist()}")
        wings.append(a)
    if wings[0][0] != wings[1][0]:
        raise ValueError(f"controller {name}.update returned two wingbeat frequencies ({wings[0][0]} and "
                         f"{wings[1][0]} Hz): both wings flap at one f")
    return wings[0], wings[1]


def _default_row(row: dict, steps) -> dict:
    """The per-beat row of a controller without ``beat_row``."""
    return row


def run(sim, cycles: int, *, kinematics: Kinematics, speed: float, aero: str, source: str,
        controller: Controller | None = None, point=None, chi_ref: float | None = None,
        gusts: Sequence[Gust] = (), sensing_delay: int = 0, keep_extras_every: int = 0,
        progress: Callable[[int, int], None] | None = None, partial_on_interrupt: bool = False,
        insect: Insect | None = None, t_start: float | None = None,
        state0: np.ndarray | None = None, forward_speed: float = 0.0) -> FlightResult:
    """The loop body (module docstring): ``cycles`` wingbeats of ``sim`` (its body and backend already placed at the
    start) open loop (``controller`` None: ``sim`` a Simulator) or under ``controller`` (``sim`` a
    :class:`hawksim.flight.plant.ControlledSimulator` whose wings start on ``kinematics``). ``chi_ref`` [rad]: the
    stability axes' body pitch of the sensed state where the controller has no ``chi_ref`` (default the kinematics'
    body angle chi). ``progress(k, cycles)`` is called
    before the first beat (k = 0) and after each complete beat. ``partial_on_interrupt``: a KeyboardInterrupt during
    the beats returns the steps flown so far (whole updates under a controller) instead of propagating; with none
    flown it propagates. ``kinematics``, ``speed``, ``aero``, ``source``, ``insect``: the result's record of what was
    flown; ``t_start``: the wall clock the result's ``wall_time_s`` counts from (default the loop's start);
    ``state0`` (9,): the start's body state as the controller senses it before the first update (default read from
    the plant); ``forward_speed`` [m/s]: the condition's U, the result's forward target (:mod:`hawksim.condition`)."""
    insect = default_insect() if insect is None else insect
    t_loop = time.perf_counter()
    t_start = t_loop if t_start is None else t_start
    n = sim.steps_per_cycle
    gusts = list(gusts)
    if controller is not None:
        rate = getattr(controller, "rate", None)
        if rate not in RATES:
            raise ValueError(f"controller {type(controller).__name__}.rate is {rate!r}: choose {', '.join(RATES)}")
        if not hasattr(sim, "begin_beat"):
            raise ValueError("a controller flies the controlled plant (hawksim.flight.plant.ControlledSimulator)")
    nseg = 1 if controller is None else UPDATES_PER_BEAT[controller.rate]
    if gusts and controller is None:
        raise ValueError("gusts: a flight in wind runs on the controlled plant; pass a controller (NoControl for "
                         "the operating point's kinematics)")
    batches, rows, refs, pitch_refs = [], [], [], []
    if controller is not None:
        from hawksim.flight.orbit import backend_record

        lag = int(sensing_delay) * nseg
        keep = max(lag, int(getattr(controller, "history", 1))) + 2 * nseg
        feeds = bool(getattr(controller, "senses_record", False))

        def frame() -> float:  # the controller's, else the given one, else the kinematics' body angle
            c = getattr(controller, "chi_ref", None)
            return float(c if c is not None else chi_ref if chi_ref is not None else kinematics.chi)

        def sense():
            return (read_body_state(sim, frame()), stability_position(sim.d.qpos[:3]) - held(),
                    backend_record(sim.backend, sim.aero_every) if feeds else None)

        controller.reset(point)
        hold_velocity = getattr(controller, "hold_velocity", None)
        # the hold point: where it was at time t and its velocity since (stability X is world x): from the start at
        # the forward speed flown (0: it stays), then at the controller's hold velocity where it gives one
        moving = {"at": stability_position(sim.d.qpos[:3]), "t": float(sim.d.time),
                  "v": np.array([float(forward_speed), 0.0])}

        def held():
            return moving["at"] + moving["v"] * (float(sim.d.time) - moving["t"])
        p0 = kinematics.as_array()
        flown = sent = [(p0, p0)] * keep
        now = (read_body_state(sim, frame()) if state0 is None else np.asarray(state0, float), np.zeros(2),
               backend_record(sim.backend, sim.aero_every) if feeds else None)
        before = getattr(controller, "sensed_before_start", None)
        sensed = [now if (keep - 1 - i) % nseg == 0 or before is None else before((keep - 1 - i) % nseg)
                  for i in range(keep)]
        beat_row = getattr(controller, "beat_row", _default_row)
        speed_ref = getattr(controller, "speed_reference", None)
        pitch_ref = getattr(controller, "pitch_reference", None)
    if progress is not None and controller is not None:
        progress(0, cycles)
    end_t = end_pos = None
    try:
        for k in range(1, int(cycles) + 1):
            t0, x0_, z0 = sim.d.time, sim.d.qpos[0], sim.d.qpos[2]
            if controller is not None:
                air = sum((g.at(k) for g in gusts), np.zeros(3))
                sim.air_v = air
                wings, saturated = [], False
            for seg in range(nseg):
                if controller is not None:
                    x_s, pos_s, rec_s = sensed[-1 - lag]
                    obs = Observation(beat=k, half=seg, time=float(sim.d.time), state=x_s, position=pos_s,
                                      record=rec_s, past=tuple(flown), past_sent=tuple(sent), point=point)
                    lp, rp = _wings(controller.update(obs), controller)
                    v_hold = hold_velocity() if hold_velocity is not None else None
                    if v_hold is not None:  # the hold point moves on at the controller's velocity from here
                        moving.update(at=held(), t=float(sim.d.time), v=np.asarray(v_hold, float))
                    ls, rs = saturate(lp, insect), saturate(rp, insect)
                    saturated |= bool(max(np.abs(ls - lp).max(), np.abs(rs - rp).max()) > SATURATION_TOL)
                    wings.append((ls, rs))
                    if nseg == 1:
                        sim.begin_beat(Kinematics.from_array(ls), Kinematics.from_array(rs))
                    else:
                        sim.begin_beat(Kinematics.from_array(ls), Kinematics.from_array(rs), phase=np.pi * seg,
                                       span=0.5)
                i0, i1 = seg * n // nseg, (seg + 1) * n // nseg
                b = sim.advance(i1 - i0, extras_every=keep_extras_every)
                batches.append(b)
                if not np.all(np.isfinite(sim.d.qpos)):
                    if controller is not None:
                        raise FloatingPointError(f"controlled flight diverged in beat {k}")
                    raise FloatingPointError(f"flight diverged in steps {(k - 1) * n}-{k * n - 1} (from t = "
                                             f"{b.t[0]:.5f} s): non-finite state")
                if controller is not None:
                    flown = (flown + [(ls, rs)])[-keep:]
                    sent = (sent + [(lp, rp)])[-keep:]
                    sensed = (sensed + [sense()])[-keep:]
            if controller is not None:
                steps = batches[-nseg:]
                R = np.concatenate([s.body_R for s in steps])
                pj = np.concatenate([s.power_joint for s in steps])
                x, pos = sensed[-1][0], sensed[-1][1]
                att = attitude_of(R)
                refs.append(float(speed_ref()) if speed_ref is not None else float(speed))
                p_ref = pitch_ref() if pitch_ref is not None else None
                if p_ref is not None:
                    pitch_refs.append(float(np.rad2deg(p_ref)))
                rows.append(beat_row({
                    "beat": k, "mean_vertical_speed": float((sim.d.qpos[2] - z0) / (sim.d.time - t0)),
                    "mean_forward_speed": float((sim.d.qpos[0] - x0_) / (sim.d.time - t0)),
                    "mean_pitch_deg": float(np.rad2deg(pitch_of(R).mean())),
                    "roll_deg": float(np.rad2deg(att[:, 1].mean())), "yaw_deg": float(np.rad2deg(att[:, 2].mean())),
                    "horizontal_offset_m": [float(pos[0]), float(pos[1])],
                    "horizontal_drift_m": float(np.hypot(*pos)), "air_velocity": [float(a) for a in air],
                    "state": [float(a) for a in x], "wings": [[ls.tolist(), rs.tolist()] for ls, rs in wings],
                    "saturated": saturated, "P_plus": P_plus(pj, sim.aero_every, P0=insect.P0)}, steps))
            if progress is not None:  # after the beat is complete (an interrupt raised here keeps it)
                progress(k, cycles)
        end_t, end_pos = float(sim.d.time), sim.body_com()
    except KeyboardInterrupt as exc:
        part = getattr(exc, "partial", None)
        if controller is None and part is not None and len(part):
            batches.append(part)
        if not partial_on_interrupt or not batches:
            raise
    wall = time.perf_counter() - t_start
    a = {k: np.concatenate([getattr(b, k) for b in batches]) for k in
         ("t", "body_pos", "body_R", "body_v", "body_omega", "wing_R", "wing_origin", "force", "power_aero",
          "power_joint")}
    a["moment"] = np.concatenate([b.moment_about_body() for b in batches])
    a["wing_moment"] = np.concatenate([b.moment + cross(b.wing_origin - b.body_pos[:, None, :], b.force)
                                       for b in batches])  # each wing's; their sum is moment_about_body's
    extras = [e for b in batches for e in b.extras]
    return FlightResult(
        speed_target=float(speed), cycles=int(cycles), aero=aero, kinematics=kinematics, steps_per_cycle=n,
        t=a["t"], body_pos=a["body_pos"], body_quat=quat_from_matrices(a["body_R"]), body_v=a["body_v"],
        body_omega=a["body_omega"], wing_R=a["wing_R"], wing_origin=a["wing_origin"], force=a["force"],
        moment=a["moment"], wing_moment=a["wing_moment"], power_aero=a["power_aero"], power_joint=a["power_joint"],
        wall_time_s=wall,
        extras=extras, trim_source=source, end_t=end_t, end_pos=end_pos, aero_every=sim.aero_every, insect=insect,
        beat_log=rows if controller is not None else None,
        speed_references=np.array(refs) if controller is not None else None, forward_speed_target=float(forward_speed),
        reference_axis=getattr(controller, "axis", "vertical"),
        pitch_references=np.array(pitch_refs) if pitch_refs else None)


def fly(point, backend=None, cycles: int | None = None, *, controller: Controller | None = None,
        perturb: dict[str, float] | None = None, gusts: Sequence[Gust] = (), sensing_delay: int = 0,
        model=None, insect: Insect | None = None, steps_per_cycle: int = FLY_STEPS_PER_CYCLE,
        keep_extras_every: int = 0, start_state: tuple | None = None, periodic_start: bool = True,
        progress: Callable[[int, int], None] | None = None, partial_on_interrupt: bool = False,
        gravity: bool = True) -> FlightResult:
    """Fly ``cycles`` wingbeats from the operating point ``point`` with ``backend``'s loads, open loop or under
    ``controller`` (:class:`Controller`); the one flight loop (:func:`run`). SI in and out (angles in radians, rates
    in rad/s), except ``perturb``, which takes the CLI's units: m/s, and deg and deg/s for the angles and rates
    (:data:`hawksim.flight.start.PERTURBATIONS`).

    Args:
        point: where the flight starts: an :class:`hawksim.flight.orbit.Orbit` (a periodic orbit of the free body:
            the flight starts on its launch state, its record seeded into a history network's backend, and under a
            controller its warm-up beats, a UVLM orbit's, flown open loop first and not reported) or a
            :class:`hawksim.trim.point.Trim` (its kinematics and ascent speed; the start on the trim's periodic path
            by one calibration wingbeat, or exactly ``start_state``).
        backend: the aerodynamic backend (:func:`hawksim.backends.flight_backend`); None: built for the point's
            backend name (``point.aero`` or ``point.model``) and the insect's wings (under a controller: the
            controlled plant's, :func:`hawksim.flight.plant.controlled_plant`).
        cycles: wingbeats flown (required).
        controller: None (open loop: the wings keep the point's kinematics) or a :class:`Controller` (e.g.
            :class:`hawksim.control.controller.LQR`, or your own class), updated per beat or per half-stroke.
        perturb: stability-axes disturbances of the initial state (:data:`hawksim.flight.start.PERTURBATIONS`).
        gusts: uniform air-velocity pulses (:class:`Gust`); they need a controller (:class:`hawksim.control.
            controller.NoControl` to fly the point's kinematics in them).
        sensing_delay: the controller senses the state this many wingbeats late.
        model: the MuJoCo model (default: generated from the insect's morphology); its total mass must be the
            insect's (ValueError naming ``model``).
        insect: the insect flown (default :func:`hawksim.insect.folder.default_insect`, the hawkmoth): its MJCF,
            bounds, and the units of the result's L+, D+, M+ and P+.
        steps_per_cycle: integration steps per wingbeat (a controller's plant: the orbit solver's 200).
        keep_extras_every: keep the backend's extras every this many steps (0: never).
        start_state: (x (9,), chi_ref) the body state at phase 0 (:data:`hawksim.flight.orbit.STATE_NAMES`): the
            flight starts exactly there (plus ``perturb``), with no calibration beat.
        periodic_start: from a Trim without ``start_state``, start on its periodic path by one calibration beat.
        progress: called as progress(beat, cycles) (beat 0 before the first under a controller).
        partial_on_interrupt: a KeyboardInterrupt during the beats returns the steps flown so far instead of
            propagating; none flown: it propagates.
        gravity: False flies without gravity (tests).

    Returns:
        :class:`hawksim.flight.result.FlightResult` (with :attr:`~FlightResult.beat_log` under a controller).
    """
    from hawksim.flight.simulator import Simulator, aero_every_for
    from hawksim.flight.start import inertial_pitch_offset, parse_perturbations, start_on_orbit
    from hawksim.frames import quat_from_matrix, rot_x, rot_y
    from hawksim.insect.model import load_model, model_total_mass

    t_start = time.perf_counter()
    is_orbit = point.body == "free"  # one OperatingPoint type: a free-body point (orbit) or a held-body one (trim)
    speed, kin = point.speed, point.kinematics
    forward_speed = point.forward_speed
    aero = point.aero if is_orbit else getattr(point, "model", None)
    if not (np.isfinite(speed) and speed >= 0):
        raise ValueError(f"point: speed must be a finite ascent speed >= 0 m/s, got {speed}")
    if cycles is None or int(cycles) != cycles or cycles < 1:
        raise ValueError(f"cycles must be a positive integer, got {cycles}")
    if forward_speed and start_state is None and not is_orbit:
        raise ValueError(f"point: forward_speed {forward_speed:g} m/s flies from a periodic orbit of the free body or "
                         "a start_state (the calibration start is vertical flight's)")
    if speed == 0 and not forward_speed:
        from hawksim.backends.registry import descriptor, descriptor_of

        desc = descriptor(aero) if backend is None else descriptor_of(backend)
        desc.hover.require("hover (speed 0)", aero if backend is None else getattr(backend, "name",
                                                                                      type(backend).__name__))
    perturb = parse_perturbations(perturb or {})
    insect = (point.insect if is_orbit else default_insect()) if insect is None else insect
    if model is None:
        model = load_model(morph=insect.morphology)
    else:
        m_model, m_insect = model_total_mass(model), insect.morphology.total_mass
        if abs(m_model - m_insect) > 1e-6 * m_insect:
            raise ValueError(f"model: its total mass {m_model * 1e6:.2f} mg is not the insect's "
                             f"({insect.name!r}, {m_insect * 1e6:.2f} mg); pass the insect the model was generated "
                             "from (insect=, --insect)")
    if backend is None and aero is None:
        raise ValueError("backend: none given and the point names no backend (Trim.model)")
    if controller is None:
        if backend is None:
            from hawksim.backends import flight_backend
            from hawksim.flight.start import is_lateral

            backend = flight_backend(aero, kinematics=kin, symmetric=not is_lateral(perturb),
                                     keep_panels=keep_extras_every > 0,
                                     morphology=None if insect == default_insect() else insect.morphology)
            if is_orbit:
                point.seed(backend)  # its record and its far wake
        sim = Simulator(model, kin, backend, steps_per_cycle=steps_per_cycle, gravity=gravity,
                        aero_every=aero_every_for(backend, steps_per_cycle))
    else:
        from hawksim.flight.plant import ControlledSimulator, controlled_plant

        if backend is None:
            sim = controlled_plant(model, kin, aero, steps_per_cycle=steps_per_cycle, insect=insect)
            if is_orbit:
                point.seed(sim.backend)  # its record and its far wake
        else:
            sim = ControlledSimulator(model, kin, backend, steps_per_cycle=steps_per_cycle, gravity=gravity,
                                      aero_every=aero_every_for(backend, steps_per_cycle))
            if hasattr(backend, "bind"):
                backend.bind(sim)
        sim.set_wings(kin, kin)
    # the body's own loads act in forward flight, as in the orbit's flights (hawksim.flight.orbit), and on a
    # forward-flight schedule's flights from hover on (its grid's orbits at U > 0 have them)
    if forward_speed or getattr(controller, "axis", "vertical") == "forward":
        from hawksim.condition import check_forward_backend
        from hawksim.insect.body_aero import BodyAero

        if forward_speed:  # (a forward schedule's backends are checked where its orbits are solved)
            check_forward_backend(aero if aero is not None else getattr(sim.backend, "name", ""), forward_speed)
        sim.body_aero = BodyAero.of(insect.morphology)
    name = getattr(sim.backend, "name", aero)
    deg = np.pi / 180
    if start_state is None and is_orbit:
        start_state = (point.launch_state.as_array(), point.chi_ref)
    if start_state is not None:
        from hawksim.flight.orbit import STATE_NAMES, set_body_state

        x, chi_ref = np.asarray(start_state[0], dtype=float).copy(), float(start_state[1])
        for k, v in perturb.items():
            x[STATE_NAMES.index(k)] += v * (deg if k in ("p", "q", "r", "theta", "phi") else 1.0)
        set_body_state(sim, x, chi_ref)
    else:
        S = STABILITY_TO_WORLD
        v0 = np.array([0.0, 0.0, speed]) + S @ [perturb.get("u", 0.0), perturb.get("v", 0.0), perturb.get("w", 0.0)]
        omega_world = S @ (np.array([perturb.get("p", 0.0), perturb.get("q", 0.0), perturb.get("r", 0.0)]) * deg)
        pitch0 = kin.chi - inertial_pitch_offset(sim, kin)
        if periodic_start:
            pitch0, v_start, q_start = start_on_orbit(sim, kin, speed, pitch0)
            v0 = v0 + v_start - np.array([0.0, 0.0, speed])
            omega_world = omega_world + np.array([0.0, -q_start, 0.0])
        pitch0 += perturb.get("theta", 0.0) * deg
        R0 = rot_x(perturb.get("phi", 0.0) * deg) @ rot_y(-pitch0)  # phi > 0: right wing down
        sim.reset(velocity=v0, quat=quat_from_matrix(R0), omega_body=R0.T @ omega_world)
        chi_ref = kin.chi
    if controller is not None and is_orbit and point.warm_beats:  # develop the wake open loop, unreported
        for _ in range(point.warm_beats):
            sim.begin_beat(kin, kin)
            sim.advance(sim.steps_per_cycle)
    if is_orbit:
        source = f"periodic orbit of the free body at {speed:g} m/s ({point.aero})"
        if forward_speed:
            source = (f"periodic orbit of the free body at {speed:g} m/s vertical, {forward_speed:g} m/s forward "
                      f"({point.aero})")
    else:
        source = point.source
    if controller is not None:
        source += f", {type(controller).__name__} control"
    return run(sim, int(cycles), kinematics=kin, speed=speed, aero=name, source=source, controller=controller,
               point=point, chi_ref=chi_ref, gusts=gusts, sensing_delay=sensing_delay,
               keep_extras_every=keep_extras_every, progress=progress, partial_on_interrupt=partial_on_interrupt,
               insect=insect, t_start=None if controller is None else t_start,
               **({"forward_speed": forward_speed} if forward_speed else {}))
