"""The shipped flight controllers: implementations of :class:`hawksim.flight.loop.Controller`.

- :class:`NoControl`: open loop on the controlled plant: the operating point's kinematics every beat.
- :class:`LQR`: the gain-scheduled LQR of :class:`hawksim.control.schedule.Schedule`, per wingbeat (a schedule of
  ``rate='beat'``) or per half-stroke (``rate='half-stroke'``), tracking a speed command (a constant or an ascent
  profile) through a rate-limited speed reference.
- :class:`ConstrainedLQR`: the same over a :class:`hawksim.control.constrained.ConstrainedSchedule` (plans within the
  kinematic bounds, per wingbeat).

The gains, reference orbits and commands are the schedules' own (:meth:`Schedule.reference`, :meth:`Schedule.wings`);
these classes hold what changes during a flight: the speed reference, the reference's body pitch the state is sensed
in, and the per-beat record of commands. Per update (module docstring of :mod:`hawksim.control.closed_loop`):

1. the speed reference V moves toward the beat's commanded speed by at most ``speed_rate`` m/s per beat (split over
   the updates of a beat);
2. the schedule's reference at V gives the kinematics, the state and the gains (interpolated between grid speeds);
3. the sensed deviation from it and the past commands give each wing's parameters.
"""

from __future__ import annotations

import numpy as np

from hawksim.control.plant import command_of
from hawksim.control.schedule import Schedule
from hawksim.flight.loop import Observation
from hawksim.insect.kinematics import Kinematics

SPEED_RATE = 0.2
"""Largest change of the speed reference per wingbeat [m/s] (a backend descriptor's ``speed_rate`` overrides it for
some backends; a rate-limited prefilter: a step of 1 m/s is far outside the linear model)."""


FORWARD_SPEED_RATE = 0.05
"""Largest change of a forward-flight schedule's speed reference per wingbeat [m/s] (about 1.3-1.9 m/s^2 at 25-37
Hz). Model choice, from a measurement (scripts/studies/forward_control.py, docs/forward_flight.md): at
:data:`SPEED_RATE` (0.2 m/s per beat, about half a g) the hover-to-4 m/s profile saturated f and alpha0 and departed
in its 7th beat; at 0.05 it holds there and back."""


def profile_speeds(profile: list[tuple[float, int]] | None, speed: float, beats: int) -> np.ndarray:
    """Commanded speed (beats,) per wingbeat: the profile's (speed, beats) pieces in turn, its last speed held
    after it (or ``speed`` throughout without a profile)."""
    if not profile:
        return np.full(beats, float(speed))
    seq = [float(v) for v, n in profile for _ in range(int(n))]
    seq += [seq[-1]] * max(0, beats - len(seq))
    return np.array(seq[:beats])


def edge_command(kin: Kinematics, du: np.ndarray) -> dict:
    """A command ``du`` (7,) of :data:`hawksim.control.plant.INPUTS` about ``kin`` in edge units (Hz, deg)."""
    return {"f_hz": float(kin.f * (1 + du[0])), "phi0_deg": float(np.rad2deg(kin.phi0 + du[1])),
            "alpha0_deg": float(np.rad2deg(kin.alpha0 + du[2])), "theta0_deg": float(np.rad2deg(kin.theta0 + du[3])),
            "dphi_a_deg": float(np.rad2deg(du[4])), "dphi0_deg": float(np.rad2deg(du[5])),
            "dalpha0_deg": float(np.rad2deg(du[6]))}


class NoControl:
    """Open loop on the controlled plant: both wings on ``kinematics`` (default the operating point's) every beat.
    Flown by :func:`hawksim.flight.loop.fly` with gusts (wind needs the controlled plant)."""

    rate = "beat"

    def __init__(self, kinematics: Kinematics | None = None):
        self.kinematics = kinematics
        self._p = None if kinematics is None else kinematics.as_array()

    def reset(self, point) -> None:
        if self.kinematics is None:
            if point is None:
                raise ValueError("NoControl without kinematics flies the operating point's: pass point to fly")
            self._p = point.kinematics.as_array()

    def update(self, obs: Observation):
        return self._p, self._p


class LQR:
    """The gain-scheduled LQR of ``schedule`` (:class:`hawksim.control.schedule.Schedule`; its ``rate`` is this
    controller's: ``'beat'`` per wingbeat, ``'half-stroke'`` per half-stroke), flown from ``speed`` [m/s] toward the
    commanded speed of each beat: ``profile`` [(speed [m/s], beats)] (:func:`profile_speeds`; default ``speed``
    throughout) through a speed reference rate-limited to ``speed_rate`` [m/s per beat] (default the backend
    descriptor's ``speed_rate``, else :data:`SPEED_RATE`; on a forward-flight schedule :data:`FORWARD_SPEED_RATE`).
    The speeds are along the schedule's :attr:`axis`: vertical speeds, or forward speeds on a forward-flight schedule
    (whose hold point then moves forward at the speed reference, :meth:`hold_velocity`).

    ``feedback=False``: the schedule's reference is followed for the record (speed reference, pitch error,
    commands in the per-beat rows) but the wings keep ``kinematics`` (default the start's): the open-loop flight of
    ``hawksim fly --gust ... --control none``. ``sent``: feed back the commands as sent rather than as flown (default:
    as the schedule's linear model was made, :data:`hawksim.control.derivatives.SATURATED_DERIVATIVES`).

    After a flight: :attr:`speed_references` per beat, :attr:`schedule` (whose counters, such as the constrained
    schedule's ``bound_active``, count the flight's updates)."""

    def __init__(self, schedule: Schedule, speed: float, *, profile: list[tuple[float, int]] | None = None,
                 speed_rate: float | None = None, feedback: bool = True, kinematics: Kinematics | None = None):
        self.schedule = schedule
        self.rate = schedule.rate
        self.speed = float(speed)
        sp = np.asarray(schedule.speeds, float)
        if self.axis == "forward" and not sp[0] - 1e-9 <= self.speed <= sp[-1] + 1e-9:
            raise ValueError(f"speed {speed:g} m/s is outside the forward-flight schedule's {sp[0]:g} to {sp[-1]:g} "
                             "m/s (on a forward schedule the LQR's speed is the forward speed U)")
        self.profile = profile
        if speed_rate is None:
            from hawksim.backends.registry import descriptor

            aero = schedule.points[0].orbit.aero
            desc = descriptor(aero)
            speed_rate = desc.speed_rate if desc.speed_rate is not None else SPEED_RATE
            if self.axis == "forward":
                speed_rate = FORWARD_SPEED_RATE
        self.speed_rate = float(speed_rate)
        self.feedback = bool(feedback)
        self.kinematics = kinematics
        self.per_beat = schedule.per_beat
        self.history = schedule.delay * self.per_beat + 1
        self.senses_record = schedule.feeds_record
        self.sent = any(p.model.clipped for p in schedule.points)
        self.reset(None)

    @classmethod
    def at(cls, speed: float, *, profile: list[tuple[float, int]] | None = None, aero: str = "quasi-steady",
           rate: str = "beat", delay: int = 0, insect=None, model=None, log=None, **kw):
        """The controller flown from ``speed`` [m/s] (and along ``profile``) with the schedule it needs, designed
        here (:class:`hawksim.control.schedule.Schedule` over the speeds commanded; ``rate`` ``'beat'`` or
        ``'half-stroke'``, sensing ``delay`` [wingbeats], the ``aero`` backend's orbits, ``insect``'s); ``kw`` as
        :class:`LQR`. Fly it from the schedule's orbit at ``speed`` (``controller.schedule.points``)."""
        speeds = [float(speed)] + [float(v) for v, _ in profile or []]
        schedule = cls._schedule(min(speeds), max(speeds), delay=delay, aero=aero, rate=rate, insect=insect,
                                 model=model, log=log)
        return cls(schedule, speed, profile=profile, **kw)

    _schedule = Schedule

    @property
    def axis(self) -> str:
        """What ``speed``, the profile and the speed reference are: "vertical" speeds V or "forward" speeds U (the
        schedule's :attr:`~hawksim.control.schedule.Schedule.axis`)."""
        return getattr(self.schedule, "axis", "vertical")

    @property
    def point(self):
        """The schedule's periodic orbit at the start speed (:class:`hawksim.flight.orbit.Orbit`), the operating
        point to fly this controller from; ValueError if the start speed is between the schedule's grid speeds."""
        for p in self.schedule.points:
            if p.at(self.axis) == self.speed:
                return p.orbit
        raise ValueError(f"speed={self.speed:g} m/s is between the schedule's orbits "
                         f"({', '.join(f'{p.speed:g}' for p in self.schedule.points)} m/s): fly_closed_loop starts "
                         "from the interpolated reference")

    # ---- the protocol -----------------------------------------------------------------------------
    def reset(self, point) -> None:
        self.v_ref = self.speed
        kin, _, chi, _ = self.schedule.reference(self.speed)
        if self.kinematics is not None:
            kin = self.kinematics
        self._hold = kin.as_array()
        self.chi_ref = float(chi) if point is None else float(getattr(point, "chi_ref", chi))
        self._beat = {"refs": [], "pitch": [], "kin": []}
        self.speed_references: list[float] = []

    def command_at(self, beat: int) -> float:
        """The commanded speed of wingbeat ``beat`` (1-based) [m/s]."""
        if not self.profile:
            return self.speed
        return float(profile_speeds(self.profile, self.speed, beat)[-1])

    def update(self, obs: Observation):
        seg = obs.half
        if seg == 0:
            self._beat = {"pitch": [], "kin": []}
        rate_limit = self.speed_rate / self.per_beat  # the reference moves at each update, speed_rate per beat
        self.v_ref += float(np.clip(self.command_at(obs.beat) - self.v_ref, -rate_limit, rate_limit))
        kin_ref, _, chi_ref, pitch_ref = self.schedule.reference(self.v_ref)
        self._beat["pitch"].append(pitch_ref)
        self._beat["kin"].append(kin_ref)
        self.chi_ref = float(chi_ref)
        if not self.feedback:
            return self._hold, self._hold
        past = obs.past_sent if self.sent else obs.past
        lag = self.schedule.delay * self.per_beat
        return self.schedule.wings(self.v_ref, obs.state, obs.position, list(past[-1 - lag:]), phase=seg,
                                   record=obs.record)

    # ---- optional members -------------------------------------------------------------------------
    def hold_velocity(self) -> np.ndarray | None:
        """The velocity (2,) [m/s] (stability X forward, Y right) at which the held horizontal point moves from this
        update on: (U_ref, 0) on a forward schedule (the speed reference), None on a vertical one (the point stays
        where the flight started)."""
        return np.array([self.v_ref, 0.0]) if self.axis == "forward" else None

    def pitch_reference(self) -> float | None:
        """The beat's reference body pitch [rad] (the mean over its updates of the orbits' mean pitch at the speed
        reference) on a forward-flight schedule, None on a vertical one (its departure test keeps the first beat's
        pitch)."""
        if self.axis != "forward" or not self._beat["pitch"]:
            return None
        return self._beat_pitch()

    def _beat_pitch(self) -> float:
        """The mean over the beat's updates of the reference's mean pitch [rad]."""
        return float(sum(self._beat["pitch"]) / self.per_beat)

    def speed_reference(self) -> float:
        self.speed_references.append(self.v_ref)
        return self.v_ref

    def sensed_before_start(self, half: int):
        """The orbit's state at update ``half`` as sensed before the start (half-stroke: the reference there)."""
        s, v = self.schedule, self.speed
        _, x_h, _, _ = s.reference(v, half)
        pos_h = sum(w * pt.reference_state(half)[1] for w, pt in s.weights(v))
        return x_h, pos_h, s.reference_record(v, half) if self.senses_record else None

    def beat_row(self, row: dict, steps) -> dict:
        """The per-beat row of ``hawksim fly --control`` (docs/output.md): the loop's measured row with the speed
        command and reference, the speed and pitch errors against the reference and the commands in edge units."""
        k = row["beat"]
        cmd = self.command_at(k)
        pitch_ref = self._beat_pitch()
        pitch = np.concatenate([b.body_R for b in steps])
        from hawksim.frames import pitch_of

        applied = [edge_command(kin, command_of(kin, np.asarray(ls), np.asarray(rs)))
                   for kin, (ls, rs) in zip(self._beat["kin"], row["wings"], strict=True)]
        along = row["mean_forward_speed"] if self.axis == "forward" else row["mean_vertical_speed"]
        out = {"beat": k, "speed_command": float(cmd), "speed_reference": self.v_ref,
               "mean_vertical_speed": row["mean_vertical_speed"],
               **({"mean_forward_speed": row["mean_forward_speed"]} if self.axis == "forward" else {}),
               "speed_error": float(along - cmd),
               "pitch_error_deg": float(np.rad2deg(pitch_of(pitch).mean() - pitch_ref)),
               "roll_deg": row["roll_deg"], "yaw_deg": row["yaw_deg"],
               "horizontal_offset_m": row["horizontal_offset_m"], "horizontal_drift_m": row["horizontal_drift_m"],
               "air_velocity": row["air_velocity"], "state": row["state"],
               "commands": applied[0], "saturated": row["saturated"], "P_plus": row["P_plus"]}
        if self.per_beat > 1:
            out["commands_half_stroke"] = applied[1]
        return out


class ConstrainedLQR(LQR):
    """The constrained LQR (:class:`hawksim.control.constrained.ConstrainedSchedule`: the same cost minimised over a
    receding horizon within the kinematic bounds), per wingbeat; the arguments as :class:`LQR`."""

    def __init__(self, schedule, speed: float, **kw):
        from hawksim.control.constrained import ConstrainedSchedule

        if not isinstance(schedule, ConstrainedSchedule):
            raise ValueError(f"ConstrainedLQR takes a ConstrainedSchedule, got {type(schedule).__name__} (LQR "
                             "flies a Schedule)")
        super().__init__(schedule, speed, **kw)

    @staticmethod
    def _schedule(v_lo, v_hi, **kw):
        from hawksim.control.constrained import ConstrainedSchedule

        return ConstrainedSchedule(v_lo, v_hi, **kw)
