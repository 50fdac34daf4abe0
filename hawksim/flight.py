"""`hawksim fly`: a free flight from the trim kinematics at an ascent speed, and its summary.

The insect starts at the origin, pitched nose-up so that its cycle-mean body angle is chi, moving straight up
at the target speed (world z), wings on their prescribed motion; perturbations (stability axes, DESIGN.md: x forward
horizontal, y right, z down) are added to that start. Results are world-frame time series (SI).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from hawksim.backend import AeroBackend
from hawksim.kinematics import Kinematics
from hawksim.model import load_model
from hawksim.morphology import HAWKMOTH, P0_W
from hawksim.rotations import quat_to_matrix
from hawksim.simulation import Simulator
from hawksim.trim_table import trim_kinematics, trim_source

PERTURBATIONS = {
    "u": "forward velocity disturbance [m/s] (stability axes)",
    "v": "rightward velocity disturbance [m/s]",
    "w": "downward velocity disturbance [m/s]",
    "p": "roll rate [deg/s] (right wing down positive)",
    "q": "pitch rate [deg/s] (nose up positive)",
    "r": "yaw rate [deg/s] (nose right positive)",
    "theta": "initial pitch offset [deg] (nose up positive)",
    "phi": "initial roll offset [deg] (right wing down positive)",
}
"""Names accepted by ``--perturb NAME=VALUE``."""


FLY_WAKE_CYCLES = 3
"""`hawksim fly --aero uvlm` keeps the wake of the last 3 wingbeats (older rows are far below the insect and the
cost of a free wake grows with the square of its length)."""


def make_backend(name: str, *, symmetric: bool = True, keep_panels: bool = False,
                 kinematics: Kinematics | None = None) -> AeroBackend:
    """Backend by CLI name, at `hawksim fly`'s resolution. Raises ValueError for an unknown or unavailable one.

    symmetric: the flight stays left/right symmetric (no lateral perturbation), so the UVLM may mirror.
    """
    if name == "quasi-steady":
        from hawksim.qs_backend import QuasiSteadyBackend

        return QuasiSteadyBackend()
    if name == "none":
        from hawksim.backend import NoAero

        return NoAero()
    if name == "uvlm":
        from hawksim.evaluate import FLY_UVLM
        from hawksim.uvlm_backend import UVLMBackend

        return UVLMBackend(n_chord=FLY_UVLM.n_chord, n_span=FLY_UVLM.n_span, symmetric=symmetric,
                           keep_panels=keep_panels, max_wake_rows=FLY_WAKE_CYCLES * FLY_UVLM.steps_per_cycle)
    if name == "surrogate":
        from hawksim.surrogate_backend import SurrogateBackend

        if kinematics is None:
            raise ValueError("the surrogate backend needs the flight's kinematics")
        return SurrogateBackend(kinematics)
    raise ValueError(f"unknown --aero {name!r}; choose uvlm, surrogate or quasi-steady")


@dataclass(frozen=True)
class FlightResult:
    """Time series of a flight, one row per step (state at the step start, loads held over the step).

    Shapes: n steps. t (n,) [s]; body_pos (n, 3) [m]; body_quat (n, 4) (w, x, y, z); body_v (n, 3) [m/s];
    body_omega (n, 3) [rad/s] world; wing_R (n, 2, 3, 3); wing_origin (n, 2, 3) [m]; force (n, 2, 3) [N] per
    wing; moment (n, 3) total aerodynamic moment about the body centre of mass [N m]; power_aero (n,) [W];
    power_joint (n,) [W] (aerodynamic + inertial power of the wings, relative to the body).
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
    """Backend extras (e.g. UVLM pressure and wake) for the steps where they were kept, as (step, dict)."""

    @property
    def body_R(self) -> np.ndarray:
        """(n, 3, 3) body frame -> world."""
        return quat_to_matrix(self.body_quat)

    def pitch(self) -> np.ndarray:
        """Body pitch (n,) [rad]: elevation of the body x axis above the horizontal (nose up positive)."""
        R = self.body_R
        return np.arcsin(np.clip(R[:, 2, 0], -1, 1))

    def roll(self) -> np.ndarray:
        """Body roll (n,) [rad], Z-Y-X Euler angles, right wing down positive (stability-axes sense)."""
        R = self.body_R
        return -np.arctan2(R[:, 2, 1], R[:, 2, 2])

    def lift_drag(self) -> tuple[np.ndarray, np.ndarray]:
        """Total lift (world z) and drag (along minus the initial horizontal heading) [N], each (n,)."""
        F = self.force.sum(1)
        return F[:, 2], -F[:, 0]

    def pitching_moment(self) -> np.ndarray:
        """Nose-up pitching moment about the body centre of mass (n,) [N m] (about minus body y)."""
        y_body = self.body_R[:, :, 1]
        return -(self.moment * y_body).sum(1)

    def summary(self) -> dict:
        """The CLI contract's `fly` keys plus cycle-averaged coefficients of the last cycle."""
        n = self.steps_per_cycle
        first, last = slice(0, n), slice(len(self.t) - n, len(self.t))
        T = n * (self.t[1] - self.t[0])
        vz = (self.body_pos[-1, 2] - self.body_pos[-n, 2]) / (T * (n - 1) / n)
        pitch = self.pitch()
        horiz = self.body_pos[-1, :2] - self.body_pos[0, :2]
        L, D = self.lift_drag()
        W = HAWKMOTH.weight
        return {
            "speed_target": self.speed_target,
            "cycles": self.cycles,
            "aero": self.aero,
            "mean_vertical_speed": float(vz),
            "pitch_change_deg": float(np.rad2deg(pitch[last].mean() - pitch[first].mean())),
            "max_abs_roll_deg": float(np.rad2deg(np.abs(self.roll()).max())),
            "horizontal_drift": float(np.hypot(*horiz)),
            "wall_time_s": self.wall_time_s,
            "kinematics": self.kinematics.to_edge(),
            "trim_source": self.trim_source,
            "steps_per_cycle": n,
            "last_cycle": {
                "L_plus": float(L[last].mean() / W),
                "D_plus": float(D[last].mean() / W),
                "M_plus": float(self.pitching_moment()[last].mean() / (W * HAWKMOTH.cbar)),
                "P_plus": float(np.maximum(self.power_joint[last], 0).mean() / P0_W),
            },
        }


def inertial_pitch_offset(model_path, kin: Kinematics, steps_per_cycle: int) -> float:
    """Mean minus initial body pitch [rad] over one wingbeat in vacuum, from a start at pitch chi.

    The wings' inertia makes the body pitch oscillate within each beat (several degrees for a hawkmoth);
    the paper's body angle chi is the cycle mean, so the flight starts at chi minus this offset.
    """
    from hawksim.backend import NoAero

    sim = Simulator(load_model(model_path), kin, NoAero(), steps_per_cycle=steps_per_cycle, gravity=False)
    sim.reset()
    pitch = []
    for _ in range(steps_per_cycle):
        st = sim.step().state
        pitch.append(np.arcsin(np.clip(st.body_R[2, 0], -1, 1)))
    return float(np.mean(pitch) - kin.chi)


def _start_on_orbit(sim: Simulator, kin: Kinematics, speed: float, pitch_guess: float):
    """(pitch0 [rad], velocity (3,) [m/s], nose-up pitch rate q0 [rad/s]) so that the first wingbeat's mean
    pitch is chi, its mean pitch rate zero and its mean velocity straight up at ``speed``.

    The aerodynamic and inertial loads oscillate within each beat; starting from rest in pitch rate at t = 0
    leaves the oscillation's integral as a mean rate (the body drifts by ~15 deg in the first beat). One
    calibration beat from the guess measures the means; the start is corrected by them (removing a mean rate q
    also lowers the mean pitch by q T / 2).
    """
    from hawksim.rotations import quat_from_matrix, rot_y

    up = np.array([0.0, 0.0, speed])
    sim.reset(velocity=up, quat=quat_from_matrix(rot_y(-pitch_guess)))
    pitch, q, v = [], [], []
    for _ in range(sim.steps_per_cycle):
        st = sim.step().state
        pitch.append(np.arcsin(np.clip(st.body_R[2, 0], -1, 1)))
        q.append(-st.body_omega[1])
        v.append(st.body_v)
    q_mean = float(np.mean(q))
    v_mean = np.mean(v, axis=0)
    pitch0 = pitch_guess - (float(np.mean(pitch)) - kin.chi) + q_mean * kin.period / 2
    v0 = up - (v_mean - up)
    v0[1] = 0.0
    return pitch0, v0, -q_mean


def parse_perturbations(perturb: dict[str, float]) -> dict[str, float]:
    """Validate perturbation names (ValueError naming the bad one)."""
    for k, v in perturb.items():
        if k not in PERTURBATIONS:
            raise ValueError(f"unknown perturbation {k!r}; choose from {', '.join(PERTURBATIONS)}")
        if not np.isfinite(v):
            raise ValueError(f"perturbation {k}={v} is not finite")
    return perturb


def fly(speed: float, cycles: int, aero: str = "quasi-steady", *, perturb: dict[str, float] | None = None,
        model_path=None, kinematics: Kinematics | None = None, steps_per_cycle: int = 200,
        gravity: bool = True, keep_extras_every: int = 0, periodic_start: bool = True,
        progress: Callable[[int, int], None] | None = None) -> FlightResult:
    """Fly for ``cycles`` wingbeats from the trim at ascent ``speed`` [m/s].

    Args:
        perturb: stability-axes disturbances of the initial state (see ``PERTURBATIONS``).
        kinematics: override the trim kinematics.
        keep_extras_every: keep the backend's extras every this many steps (0: never).
        periodic_start: start on the periodic orbit (one calibration wingbeat, see ``_start_on_orbit``).
        progress: called as progress(step, n_steps).
    """
    if not (np.isfinite(speed) and speed >= 0):
        raise ValueError(f"--speed must be a finite ascent speed >= 0 m/s, got {speed}")
    if int(cycles) != cycles or cycles < 1:
        raise ValueError(f"--cycles must be a positive integer, got {cycles}")
    perturb = parse_perturbations(perturb or {})
    kin = kinematics if kinematics is not None else trim_kinematics(speed, aero)
    lateral = any(perturb.get(k, 0.0) != 0.0 for k in ("v", "p", "r", "phi"))
    backend = make_backend(aero, symmetric=not lateral, keep_panels=keep_extras_every > 0, kinematics=kin)
    model = load_model(model_path)
    aero_every = 1
    if aero == "uvlm":
        from hawksim.evaluate import FLY_UVLM

        aero_every = max(1, steps_per_cycle // FLY_UVLM.steps_per_cycle)
        while steps_per_cycle % aero_every:
            aero_every -= 1
    sim = Simulator(model, kin, backend, steps_per_cycle=steps_per_cycle, gravity=gravity, aero_every=aero_every)

    from hawksim.rotations import quat_from_matrices, quat_from_matrix, rot_x, rot_y

    deg = np.pi / 180
    # stability axes -> world (heading +x): x_s = x, y_s = -y, z_s = -z
    S = np.diag([1.0, -1.0, -1.0])
    v0 = np.array([0.0, 0.0, speed]) + S @ [perturb.get("u", 0.0), perturb.get("v", 0.0), perturb.get("w", 0.0)]
    omega_world = S @ (np.array([perturb.get("p", 0.0), perturb.get("q", 0.0), perturb.get("r", 0.0)]) * deg)
    pitch0 = kin.chi - inertial_pitch_offset(model_path, kin, steps_per_cycle)
    if periodic_start:
        pitch0, v_start, q_start = _start_on_orbit(sim, kin, speed, pitch0)
        v0 = v0 + v_start - np.array([0.0, 0.0, speed])
        omega_world = omega_world + np.array([0.0, -q_start, 0.0])
    pitch0 += perturb.get("theta", 0.0) * deg
    R0 = rot_x(-perturb.get("phi", 0.0) * deg) @ rot_y(-pitch0)
    sim.reset(velocity=v0, quat=quat_from_matrix(R0), omega_body=R0.T @ omega_world)

    n = int(cycles) * steps_per_cycle
    rec = {k: [] for k in ("t", "pos", "quat", "v", "w", "wR", "wo", "F", "M", "Pa", "Pj")}
    extras = []
    t0 = time.perf_counter()
    for i in range(n):
        r = sim.step()
        st, ld = r.state, r.loads
        rec["t"].append(st.t)
        rec["pos"].append(st.body_pos)
        rec["quat"].append(st.body_R)
        rec["v"].append(st.body_v)
        rec["w"].append(st.body_omega)
        rec["wR"].append(st.wing_R)
        rec["wo"].append(st.wing_origin)
        rec["F"].append(ld.force)
        rec["M"].append(ld.moment_about(st, st.body_pos))
        rec["Pa"].append(ld.power)
        rec["Pj"].append(r.joint_power)
        if keep_extras_every and i % keep_extras_every == 0 and ld.extras:
            extras.append((i, ld.extras))
        if progress is not None:
            progress(i + 1, n)
        if not np.all(np.isfinite(sim.d.qpos)):
            raise FloatingPointError(f"flight diverged at step {i} (t = {st.t:.5f} s): non-finite state")
    wall = time.perf_counter() - t0
    a = {k: np.asarray(v) for k, v in rec.items()}
    a["quat"] = quat_from_matrices(a["quat"])
    return FlightResult(
        speed_target=float(speed), cycles=int(cycles), aero=aero, kinematics=kin, steps_per_cycle=steps_per_cycle,
        t=a["t"], body_pos=a["pos"], body_quat=a["quat"], body_v=a["v"], body_omega=a["w"], wing_R=a["wR"],
        wing_origin=a["wo"], force=a["F"], moment=a["M"], power_aero=a["Pa"], power_joint=a["Pj"],
        wall_time_s=wall, extras=extras, trim_source="given" if kinematics is not None else trim_source(aero),
    )
