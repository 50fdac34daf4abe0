"""Cycle-averaged loads and power with the body held on its equilibrium path (the paper's setting).

The body translates straight up at the ascent speed V (and forward at U, ``forward_speed``, issue 51) with the
constant attitude chi (nose up) and no rotation; the wings follow Eq. 1. The computation runs in the body-carried
frame (an inertial frame, since the body's velocity is constant): the body stays at the origin and the air streams
at (-U, 0, -V) (``FlightState.air_v``, :func:`hawksim.condition.air_velocity`), so wakes and disturbance fields stay
near the insect. In forward flight (U > 0) the body's own loads (:mod:`hawksim.insect.body_aero`, constant on the
held path) are added to the wings'; at U = 0 they are left out, as in the paper (vertical ascent stays bit for bit
what it was; ``body_loads`` overrides).
This is how the paper evaluates L+, D+, M+ and P+ for the training data,
the trim and the stability derivatives. The wing poses and velocities come from the same MuJoCo model and
the same :func:`hawksim.backends.base.read_state` as the free flights, so a backend sees identical inputs.

Power (docs/conventions.md): P(t) = P_aero(t) + P_inertial(t), the mechanical power of the six wing joints; P_aero is
the backend's power relative to the body, P_inertial = tau_in . qdot with tau_in the joint torques that drive the
wings' inertia (MuJoCo inverse dynamics, gravity off: the wings' weight is left out, as in the paper);
required power = cycle mean of max(0, P) (no elastic storage, negative power dissipated).

Nondimensional outputs (paper Eq. 2): L+ = L/W, D+ = D/W, M+ = M/(W cbar), P+ = P/P0, with lift along world z,
drag along minus the body's horizontal heading (world -x), and M the nose-up pitching moment about the body's
centre of mass.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import mujoco
import numpy as np

from hawksim.backends import backend_for
from hawksim.backends.averages import OUTPUTS, CycleAverages, cycle_averages
from hawksim.backends.base import AeroBackend, read_state
from hawksim.backends.resolution import DEFAULT, Resolution
from hawksim.condition import air_velocity, check_forward_speed
from hawksim.frames import quat_from_matrix, rot_y
from hawksim.insect.accessors import ModelIndex
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect


@dataclass(frozen=True)
class HeldResult:
    """Time series (n steps) and the cycle averages of the last ``average_cycles`` wingbeats.

    t (n,) [s]; lift, drag (n,) [N]; moment (n,) nose-up pitching moment about the centre of mass [N m];
    power_aero, power_inertial (n,) [W]; per_cycle: averages of every wingbeat (periodic convergence);
    force_world, moment_world (n, 3): total aerodynamic force [N] and moment about the centre of mass [N m]
    (the body's loads included where counted); forward_speed: U [m/s]; body_force, body_moment (3,): the body's
    own loads (world, [N] and [N m] about the centre of mass; zero where not counted), in every step's total;
    body_averages: their share of the averages (L+, D+, M+ as the totals'; P+ 0: the body does no work on the held
    path), None where not counted.
    """

    kinematics: Kinematics
    speed: float
    steps_per_cycle: int
    t: np.ndarray
    lift: np.ndarray
    drag: np.ndarray
    moment: np.ndarray
    power_aero: np.ndarray
    power_inertial: np.ndarray
    averages: CycleAverages
    per_cycle: tuple[CycleAverages, ...]
    wall_time_s: float
    force_world: np.ndarray
    moment_world: np.ndarray
    forward_speed: float = 0.0
    body_force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    body_moment: np.ndarray = field(default_factory=lambda: np.zeros(3))
    body_averages: CycleAverages | None = None

    def mean_loads(self, average_cycles: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Mean force (3,) [N] and moment (3,) [N m] (world) over the last ``average_cycles`` wingbeats."""
        last = slice(len(self.t) - average_cycles * self.steps_per_cycle, len(self.t))
        return self.force_world[last].mean(0), self.moment_world[last].mean(0)


def held_flight(kin: Kinematics, speed: float, backend: AeroBackend, *, cycles: int = 3,
                average_cycles: int = 1, steps_per_cycle: int = 40, model: mujoco.MjModel | None = None,
                insect: Insect | None = None, progress=None, start_cycle: int = 0, forward_speed: float = 0.0,
                body_loads: bool | None = None) -> HeldResult:
    """Run ``backend`` for ``cycles`` wingbeats with the body held at ascent ``speed`` [m/s] and ``forward_speed``
    [m/s] (:mod:`hawksim.condition`).

    ``body_loads``: whether the body's own loads (:class:`hawksim.insect.body_aero.BodyAero` of the insect's
    morphology) enter the totals; default: in forward flight only (forward_speed > 0).

    The averages are over the last ``average_cycles`` wingbeats (the earlier ones carry the start-up transient).
    start_cycle > 0 continues a backend that has already run that many wingbeats (its state, e.g. a wake, is
    kept: no reset), starting at t = start_cycle T. ``insect`` (default :func:`hawksim.insect.folder.default_insect`):
    its MJCF unless ``model`` is given, and its weight, mean chord and P0 are the units of the averages; ``backend``
    must be built for its wings (:func:`hawksim.backends.make_backend`'s ``morphology``).
    """
    if not (np.isfinite(speed) and speed >= 0):
        raise ValueError(f"speed must be a finite ascent speed >= 0 m/s, got {speed}")
    forward_speed = check_forward_speed(forward_speed)
    if not 1 <= average_cycles <= cycles:
        raise ValueError(f"average_cycles must be in [1, cycles={cycles}], got {average_cycles}")
    insect = default_insect() if insect is None else insect
    m = model if model is not None else load_model(morph=insect.morphology)
    m.opt.gravity[:] = 0.0
    d = mujoco.MjData(m)
    ix = ModelIndex.of(m)
    body, wings, qadr, vadr = ix.body, ix.wings, ix.wing_qpos, ix.wing_dof
    R_body = rot_y(-kin.chi)
    quat = quat_from_matrix(R_body)
    dt = kin.period / steps_per_cycle
    air = air_velocity(speed, forward_speed)
    body_f = body_m = None
    if (forward_speed > 0) if body_loads is None else body_loads:
        body_f, body_m = body_loads_world(R_body, air, insect)
    n = cycles * steps_per_cycle
    out = np.zeros((5, n))
    FM = np.zeros((n, 6))
    times = (start_cycle * steps_per_cycle + np.arange(n)) * dt
    t0 = time.perf_counter()
    for i, t in enumerate(times):
        d.time = t
        d.qpos[:3] = 0.0
        d.qpos[3:7] = quat
        q = kin.motion(t)  # both wings move alike
        d.qpos[qadr] = np.concatenate((q[0], q[0]))
        d.qvel[:] = 0.0
        d.qvel[vadr] = np.concatenate((q[1], q[1]))
        d.qacc[:] = 0.0
        d.qacc[vadr] = np.concatenate((q[2], q[2]))
        mujoco.mj_inverse(m, d)  # also brings kinematics and com velocities up to date
        st = replace(read_state(m, d, body, wings, dt), air_v=air)
        if i == 0 and start_cycle == 0:
            backend.reset(st)
        loads = backend.loads(st)
        F = loads.force.sum(0)
        M = loads.moment_about(st, st.body_pos)
        if body_f is not None:
            F, M = F + body_f, M + body_m
        out[:, i] = (F[2], -F[0], -(M @ R_body[:, 1]), loads.power, d.qfrc_inverse[vadr] @ d.qvel[vadr])
        FM[i, :3], FM[i, 3:] = F, M
        if progress is not None:
            progress(i + 1, n)
    wall = time.perf_counter() - t0
    per_cycle = tuple(
        cycle_averages(*out[:3, c * steps_per_cycle:(c + 1) * steps_per_cycle],
                       out[3, c * steps_per_cycle:(c + 1) * steps_per_cycle]
                       + out[4, c * steps_per_cycle:(c + 1) * steps_per_cycle], insect)
        for c in range(cycles)
    )
    last = slice(n - average_cycles * steps_per_cycle, n)
    avg = cycle_averages(*out[:3, last], out[3, last] + out[4, last], insect)
    return HeldResult(kinematics=kin, speed=float(speed), steps_per_cycle=steps_per_cycle, t=times,
                      lift=out[0], drag=out[1], moment=out[2], power_aero=out[3], power_inertial=out[4],
                      averages=avg, per_cycle=per_cycle, wall_time_s=wall, force_world=FM[:, :3],
                      moment_world=FM[:, 3:], forward_speed=forward_speed,
                      body_force=np.zeros(3) if body_f is None else body_f,
                      body_moment=np.zeros(3) if body_m is None else body_m,
                      body_averages=None if body_f is None else _body_plus(body_f, body_m, R_body, insect))


def body_loads_world(R_body: np.ndarray, air: np.ndarray, insect: Insect) -> tuple[np.ndarray, np.ndarray]:
    """The body's own loads on the held path (:class:`hawksim.insect.body_aero.BodyAero` of ``insect``'s
    morphology): force (3,) [N] and moment (3,) [N m] about the centre of mass, world, for the body attitude
    ``R_body`` (body -> world) at rest in the air stream ``air`` (3,) [m/s], world."""
    from hawksim.insect.body_aero import BodyAero

    fb, mb = BodyAero.of(insect.morphology).loads(R_body.T @ air)
    return R_body @ fb, R_body @ mb


def _body_plus(body_f, body_m, R_body, insect) -> CycleAverages:
    """The constant body loads in the units of the averages (P+ 0: the body does no work on the held path)."""
    return cycle_averages([body_f[2]], [-body_f[0]], [-(body_m @ R_body[:, 1])], [0.0], insect)


def body_averages(kin: Kinematics, speed: float, forward_speed: float, insect: Insect | None = None
                  ) -> CycleAverages:
    """The body's share of a held run's averages at ``kin``'s body angle chi, ascent ``speed`` and
    ``forward_speed`` [m/s] (L+, D+, M+ as the totals' in :func:`held_flight` where the body counts; P+ 0): what
    :attr:`HeldResult.body_averages` holds, without running the wings."""
    insect = default_insect() if insect is None else insect
    R_body = rot_y(-kin.chi)
    f, m = body_loads_world(R_body, air_velocity(speed, check_forward_speed(forward_speed)), insect)
    return _body_plus(f, m, R_body, insect)


# ---- one evaluation: the unit of work of data sets, trim checks and `hawksim aero` ----------------------

def run(kin: Kinematics, speed: float, res: Resolution = DEFAULT, progress=None, insect: Insect | None = None,
        forward_speed: float = 0.0) -> HeldResult:
    """The held-body run of one evaluation (time series and averages) of ``insect`` (default
    :func:`hawksim.insect.folder.default_insect`) at ascent ``speed`` and ``forward_speed`` [m/s]."""
    return held_flight(kin, speed, backend_for(res, morphology=None if insect is None else insect.morphology),
                       cycles=res.cycles, average_cycles=res.average_cycles, steps_per_cycle=res.steps_per_cycle,
                       progress=progress, insect=insect, forward_speed=forward_speed)


def evaluate(kin: Kinematics, speed: float, res: Resolution = DEFAULT, forward_speed: float = 0.0
             ) -> CycleAverages:
    """Cycle averages of one evaluation."""
    return run(kin, speed, res, forward_speed=forward_speed).averages


def beat_averages(kin: Kinematics, speed: float, res: Resolution, beats: int) -> np.ndarray:
    """Each wingbeat's L+, D+, M+, P+ of a run of ``beats`` wingbeats at ``res``'s lattice: shape (beats, 4),
    columns :data:`OUTPUTS`. Row ``res.cycles - 1`` is the label ``evaluate(kin, speed, res)`` gives when
    ``res.average_cycles`` is 1 (the run is deterministic and does not depend on later beats).
    Raises FloatingPointError when the UVLM diverges."""
    r = run(kin, speed, replace(res, cycles=int(beats), average_cycles=1))
    return np.array([[getattr(c, n) for n in OUTPUTS] for c in r.per_cycle])
