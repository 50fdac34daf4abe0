"""The result of a free flight: world-frame time series, one row per step, and the CLI contract's summary."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hawksim.flight.power import P_plus
from hawksim.frames import attitude_of, pitch_of, quat_to_matrix, roll_of
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect

DEPARTURE_SPEED = 0.1
"""A flight has departed when a wingbeat's mean vertical speed leaves the target, or its horizontal speed leaves
zero (in forward flight: the forward target, :attr:`FlightResult.forward_speed_target`), by more than this [m/s]
(issue 19's definition)."""
DEPARTURE_ANGLE_DEG = 10.0
"""... or when its mean pitch, roll or yaw leaves the first wingbeat's by more than this [deg]."""


@dataclass(frozen=True)
class FlightResult:
    """Time series of a flight, one row per step (state at the step start, loads held over the step).

    Shapes: n steps. t (n,) [s]; body_pos (n, 3) [m]; body_quat (n, 4) (w, x, y, z); body_v (n, 3) [m/s];
    body_omega (n, 3) [rad/s] world; wing_R (n, 2, 3, 3); wing_origin (n, 2, 3) [m]; force (n, 2, 3) [N] per
    wing; moment (n, 3) total aerodynamic moment about the body centre of mass [N m] (wing_moment (n, 2, 3): each
    wing's; :meth:`wing_angles`: the joint angles); power_aero (n,) [W];
    power_joint (n,) [W] (aerodynamic + inertial power of the wings, relative to the body). end_t [s] and end_pos
    (3,) [m]: time and body centre of mass after the last step (None where the flight was interrupted), so that
    the last wingbeat's mean speed spans the whole beat like the others. aero_every: steps per backend update (the
    loads are held in between; row 0 is an update), which the required power samples
    (:mod:`hawksim.flight.power`).

    :meth:`save` and :meth:`load` write and read it as the ``.npz`` file of ``hawksim fly --out``
    (:mod:`hawksim.flight.export`, docs/output.md), readable by numpy alone.
    """

    speed_target: float
    cycles: int
    aero: str
    kinematics: Kinematics
    steps_per_cycle: int
    t: np.ndarray
    body_pos: np.ndarray
    body_quat: np.ndarray
    body_v: np.ndarray
    body_omega: np.ndarray
    wing_R: np.ndarray
    wing_origin: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    power_aero: np.ndarray
    power_joint: np.ndarray
    wall_time_s: float
    trim_source: str = "given"
    extras: list = field(default_factory=list, repr=False)
    end_t: float | None = None
    end_pos: np.ndarray | None = None
    """Backend extras (e.g. UVLM pressure and wake) for the steps where they were kept, as (step, dict)."""
    aero_every: int = 1
    insect: Insect = field(default_factory=default_insect)
    """The insect flown (:class:`hawksim.insect.insect.Insect`): its weight, mean chord and P0 are the units of
    :meth:`summary`'s L+, D+, M+ and P+."""
    beat_log: list[dict] | None = field(default=None, repr=False)
    """A flight under a controller (:func:`hawksim.flight.loop.run`): one row per complete wingbeat as the loop
    measured it and the controller described it (:class:`hawksim.control.controller.LQR`: speed command and
    reference, tracking errors, commands in edge units, saturation, end state; docs/output.md); None open loop."""
    wing_moment: np.ndarray | None = field(default=None, repr=False)
    """(n, 2, 3) each wing's (left, right) aerodynamic moment about the body centre of mass [N m], world frame (its
    own moment plus its force's about the centre of mass; the sum over the wings is :attr:`moment`); None in a file
    saved before it was kept."""
    speed_references: np.ndarray | None = None
    """A flight under a controller: the speed each beat was flown to (beats,) [m/s] (a scheduled controller's
    rate-limited reference; else the target), which :meth:`departed_at_beat` tests against; None open loop."""
    forward_speed_target: float = 0.0
    """The forward speed U [m/s] flown to (:mod:`hawksim.condition`; 0: vertical flight), which the horizontal speed
    of :meth:`departed_at_beat` is tested against; in the summary only where nonzero."""
    reference_axis: str = "vertical"
    """What :attr:`speed_references` are: vertical speeds (the ascent's) or "forward" speeds (a forward-flight
    schedule's, :attr:`hawksim.control.schedule.Schedule.axis`: the horizontal speed is tested against them, the
    vertical one against :attr:`speed_target`)."""
    pitch_references: np.ndarray | None = None
    """A flight under a forward-flight schedule: each beat's reference body pitch (beats,) [deg] (the orbits' mean
    pitch interpolated at the speed reference), which the pitch of :meth:`departed_at_beat` is tested against (the
    body angle changes by tens of degrees from hover to 4 m/s); None otherwise."""

    @property
    def body_R(self) -> np.ndarray:
        """(n, 3, 3) body frame -> world."""
        return quat_to_matrix(self.body_quat)

    def wing_angles(self) -> np.ndarray:
        """(n, 2, 3) the joint angles: sweep phi, elevation theta, rotation alpha [rad] of the left and right wing
        (paper Eq. 1's angles, read back from the wing frames; :func:`hawksim.flight.export.wing_angles`)."""
        from hawksim.flight.export import wing_angles

        return wing_angles(self)

    def pitch(self) -> np.ndarray:
        """Body pitch (n,) [rad]: elevation of the body x axis above the horizontal (nose up positive)."""
        return pitch_of(self.body_R)

    def roll(self) -> np.ndarray:
        """Body roll (n,) [rad], Z-Y-X Euler angles, right wing down positive (stability-axes sense)."""
        return roll_of(self.body_R)

    def lift_drag(self) -> tuple[np.ndarray, np.ndarray]:
        """Total lift (world z) and drag (along minus the initial horizontal heading) [N], each (n,)."""
        F = self.force.sum(1)
        return F[:, 2], -F[:, 0]

    def pitching_moment(self) -> np.ndarray:
        """Nose-up pitching moment about the body centre of mass (n,) [N m] (about minus body y)."""
        y_body = self.body_R[:, :, 1]
        return -(self.moment * y_body).sum(1)

    def attitude(self) -> np.ndarray:
        """(n, 3) pitch, roll, yaw [rad] that do not wrap (:func:`hawksim.frames.attitude_of`)."""
        return attitude_of(self.body_R)

    def beats(self) -> list[dict]:
        """One object per wingbeat (CLI contract): cycle means of the vertical speed (up positive) and horizontal
        speed of the centre of mass [m/s], and of pitch, roll, yaw [deg] (:meth:`attitude`)."""
        n, N = self.steps_per_cycle, len(self.t)
        att = np.rad2deg(self.attitude())
        out = []
        for k in range(N // n):
            a = k * n
            vel = self.mean_velocity(a, (k + 1) * n)
            vz, vh = vel[2], np.hypot(*vel[:2])
            m = att[a:a + n].mean(0)
            out.append({"mean_vertical_speed": float(vz), "horizontal_speed": float(vh), "pitch_deg": float(m[0]),
                        "roll_deg": float(m[1]), "yaw_deg": float(m[2])})
        return out

    def mean_velocity(self, a: int, b: int) -> np.ndarray:
        """Mean velocity (3,) [m/s] of the body centre of mass from the start of step a to the start of step b
        (b = n: the end of the flight, from end_pos; without it, the start of the last step)."""
        if b >= len(self.t):
            if self.end_pos is not None:
                return (np.asarray(self.end_pos) - self.body_pos[a]) / (self.end_t - self.t[a])
            b = len(self.t) - 1
        return (self.body_pos[b] - self.body_pos[a]) / (self.t[b] - self.t[a] if b > a else 1.0)

    def departed_at_beat(self, beats: list[dict] | None = None) -> int | None:
        """First wingbeat (1-based) whose cycle mean is more than :data:`DEPARTURE_SPEED` from the target speed
        (vertical) or from zero (horizontal), or more than :data:`DEPARTURE_ANGLE_DEG` from the first beat's pitch,
        roll or yaw; None if the flight never departed. A flight with :attr:`speed_references` (under a
        controller; its beats may differ in length as f changes) tests the vertical speed against them instead: a
        beat departs when it is more than DEPARTURE_SPEED outside the range of this beat's and the previous beat's
        reference (a reference change reaches the flight one beat late: the new kinematics blend in over the
        beat)."""
        beats = self.beats() if beats is None else beats
        ref = beats[0]
        r, pr = self.speed_references, self.pitch_references
        forward = r is not None and self.reference_axis == "forward"

        def outside(v, k):  # how far v is outside this beat's and the previous beat's reference (the first beat's:
            # the start's, the forward target)
            a = r[min(k - 1, len(r) - 1)]
            c = r[max(0, min(k - 2, len(r) - 1))] if k > 1 or not forward else self.forward_speed_target
            return max(min(a, c) - v, v - max(a, c), 0.0)

        def pitch_off(b, k):  # against the first beat's, or (a forward schedule) against the reference's change
            if pr is None:
                return b["pitch_deg"] - ref["pitch_deg"]
            return (b["pitch_deg"] - pr[min(k - 1, len(pr) - 1)]) - (ref["pitch_deg"] - pr[0])

        for k, b in enumerate(beats, 1):
            vz = b["mean_vertical_speed"]
            off = outside(vz, k) if r is not None and not forward else abs(vz - self.speed_target)
            if forward:
                vh = outside(b["horizontal_speed"], k)
            else:
                vh = b["horizontal_speed"] - self.forward_speed_target if self.forward_speed_target else \
                    b["horizontal_speed"]
            if (off > DEPARTURE_SPEED or abs(vh) > DEPARTURE_SPEED or abs(pitch_off(b, k)) > DEPARTURE_ANGLE_DEG
                    or any(abs(b[a] - ref[a]) > DEPARTURE_ANGLE_DEG for a in ("roll_deg", "yaw_deg"))):
                return k
        return None

    def summary(self) -> dict:
        """The CLI contract's `fly` keys plus cycle-averaged coefficients of the last cycle."""
        n = self.steps_per_cycle
        first, last = slice(0, n), slice(len(self.t) - n, len(self.t))
        vz = self.mean_velocity(len(self.t) - n, len(self.t))[2]
        att = self.attitude()
        pitch = att[:, 0]
        beats = self.beats()
        horiz = self.body_pos[-1, :2] - self.body_pos[0, :2]
        return {
            "speed_target": self.speed_target,
            "cycles": self.cycles,
            "aero": self.aero,
            "mean_vertical_speed": float(vz),
            "pitch_change_deg": float(np.rad2deg(pitch[last].mean() - pitch[first].mean())),
            "max_abs_roll_deg": float(np.rad2deg(np.abs(att[:, 1]).max())),
            "horizontal_drift": float(np.hypot(*horiz)),
            "wall_time_s": self.wall_time_s,
            "beats": beats,
            "departed_at_beat": self.departed_at_beat(beats),
            "kinematics": self.kinematics.to_edge(),
            "trim_source": self.trim_source,
            "steps_per_cycle": n,
            "last_cycle": self.coefficients(last.start, last.stop),
        } | ({"forward_speed_target": self.forward_speed_target} if self.forward_speed_target else {})

    def coefficients(self, a: int, b: int) -> dict[str, float]:
        """L+, D+, M+, P+ of steps a..b-1 (one wingbeat: the cycle means of the paper's Eq. 2): the mean lift and
        drag (:meth:`lift_drag`) over the insect's weight, the mean nose-up pitching moment about the centre of mass
        (:meth:`pitching_moment`) over weight x mean chord, and :func:`hawksim.flight.power.P_plus` of the joint
        power over the insect's P0."""
        s = slice(a, b)
        L, D = self.lift_drag()
        W = self.insect.weight
        return {"L_plus": float(L[s].mean() / W), "D_plus": float(D[s].mean() / W),
                "M_plus": float(self.pitching_moment()[s].mean() / (W * self.insect.cbar)),
                "P_plus": P_plus(self.power_joint[s], self.aero_every, first=a, P0=self.insect.P0)}

    def beat_table(self, log: list[dict] | None = None) -> list[dict]:
        """The full per-beat table: :meth:`beats` (the contract's means) numbered from 1 with each beat's P+
        (:func:`hawksim.flight.power.P_plus` over the beat's steps), merged with the controller's per-beat rows
        ``log`` (default :attr:`beat_log`; their own vertical speed, roll and yaw are the same means measured on the
        body origin and are not repeated)."""
        log = self.beat_log if log is None else log
        n = self.steps_per_cycle
        rows = []
        for k, b in enumerate(self.beats(), 1):
            row = {"beat": k, **b}
            a = (k - 1) * n
            row["P_plus"] = P_plus(self.power_joint[a:a + n], self.aero_every, first=a, P0=self.insect.P0)
            if log is not None and k <= len(log):
                c = log[k - 1]
                row["P_plus"] = c.get("P_plus", row["P_plus"])
                row.update({key: v for key, v in c.items() if key not in row and key not in ("roll_deg", "yaw_deg")})
            rows.append(row)
        return rows

    def save(self, path: str | Path, *, beats: list[dict] | None = None) -> Path:
        """Write the flight to ``path`` as the ``.npz`` file of ``hawksim fly --out`` (:mod:`hawksim.flight.export`:
        the per-step arrays, the per-beat table, the metadata with units), all or nothing. ``beats``: the per-beat
        table (default :meth:`beats` open loop, :meth:`beat_table` with the controller's rows under a controller).
        The backend's ``extras`` are not saved. OSError naming the path when it cannot be written. Returns
        ``path``."""
        from hawksim.flight.export import save_flight

        if beats is None:
            beats = self.beats() if self.beat_log is None else self.beat_table()
        return save_flight(path, self, beats, summary=self.summary())

    @classmethod
    def load(cls, path: str | Path) -> FlightResult:
        """The flight saved at ``path`` (:meth:`save` or ``hawksim fly --out``): every per-step array and scalar field
        as saved, bit for bit (``extras`` empty: they are not saved). Read with ``np.load(allow_pickle=False)``; a file
        of another format is refused with a one-line ValueError naming the path
        (:func:`hawksim.flight.export.read_flight`). A file written before the metadata held ``kinematics_si``,
        ``aero_every`` and ``flight_wall_time_s`` loads with the kinematics to 12 significant digits, the backend's
        update interval and the summary's flight wall time."""
        from hawksim.flight.export import STEP_ARRAYS, read_flight

        arrays, meta = read_flight(path)
        derived = ("attitude", "wing_angles")
        optional = ("wing_moment",)  # files written before it was kept load without it
        missing = [k for k in STEP_ARRAYS if k not in derived + optional and k not in arrays]
        if missing:
            raise ValueError(f"{str(path)!r} is a hawksim flight file without the array(s) {missing}")
        if "kinematics_si" in meta:
            kin = Kinematics(**{k: float(meta["kinematics_si"][k]) for k in PARAM_NAMES})
        else:
            kin = Kinematics.from_edge(meta["kinematics"], check_bounds=False)
        aero_every = meta.get("aero_every")
        if aero_every is None:
            from hawksim.backends.registry import descriptor

            aero_every = descriptor(meta["aero"]).update_interval(meta["steps_per_cycle"])
        wall = meta.get("flight_wall_time_s", (meta.get("summary") or {}).get("flight_wall_time_s", 0.0))
        end_pos = meta.get("end_pos_m")
        insect = Insect.from_dict(meta["insect"]) if meta.get("insect") is not None else default_insect()
        return cls(speed_target=meta["speed_target_m_s"], cycles=meta["cycles"], aero=meta["aero"], kinematics=kin,
                   steps_per_cycle=meta["steps_per_cycle"],
                   **{k: arrays.get(k) for k in STEP_ARRAYS if k not in derived},
                   wall_time_s=wall, trim_source=meta["trim_source"], end_t=meta.get("end_t_s"),
                   end_pos=None if end_pos is None else np.array(end_pos, dtype=float), aero_every=int(aero_every),
                   insect=insect, beat_log=meta.get("beat_log"),
                   speed_references=None if meta.get("speed_references_m_s") is None
                   else np.array(meta["speed_references_m_s"], dtype=float),
                   forward_speed_target=float(meta.get("forward_speed_target_m_s", 0.0)),
                   reference_axis=meta.get("reference_axis", "vertical"),
                   pitch_references=None if meta.get("pitch_references_deg") is None
                   else np.array(meta["pitch_references_deg"], dtype=float))
