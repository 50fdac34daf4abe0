"""Stability derivatives from UVLM runs with disturbance velocities (paper Eq. 15), and mass properties.

A disturbance is a body motion relative to the air at the trim: translational (u, v, w) [m/s] and rotational
(p, q, r) [rad/s], in stability axes (x forward horizontal, y right, z down). In the body-carried frame of a
held-body run it is an air-velocity field v_air(x) = -(v_d + omega_d x (x - x_cg)) (world frame), which enters
the no-penetration condition and convects the wake (``aero.uvlm.FreeStream``).

Central differences of the cycle-averaged forces and moments about the centre of mass over the last
``average_cycles`` wingbeats. The disturbance is switched on after a shared undisturbed start (the first
``cycles - average_cycles`` wingbeats; the solver state is copied), so the + and - runs start from the same
wake: at low speed the free wake is not periodic and two independent runs would differ by more than the
disturbance's effect. Symmetric disturbances (u, w, q) keep the flapping left/right symmetric, so the UVLM
solves one wing and mirrors it; antisymmetric ones (v, p, r) need both wings.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from hawksim.backends import backend_for
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT, Resolution
from hawksim.frames import STABILITY_TO_WORLD as S_WORLD
from hawksim.frames import quat_from_matrix, rot_y
from hawksim.insect.accessors import ModelIndex
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.stability.system import MassProperties

DERIVATIVE_RESOLUTION = replace(DEFAULT, cycles=4, average_cycles=2)
"""Lattice and time step of the derivative runs: `hawksim aero`'s default (docs/uvlm.md convergence study),
4 wingbeats with the last 2 averaged (the beat-to-beat scatter of the free wake is differenced otherwise)."""

DELTA_VELOCITY = 0.05
"""Translational disturbance as a fraction of the reference speed U = 2 phi_a f r2 (step-size study:
``python scripts/studies/derivative_step_study.py``, results/stability/step_study_v*.json, docs/stability.md)."""

DELTA_RATE = 0.05
"""Rotational disturbance in units of 1/T (q T = 0.05; the same step-size study)."""


def mass_properties(kin: Kinematics, model: mujoco.MjModel | None = None) -> MassProperties:
    """Total mass and inertia about the centre of mass with the wings at their mean position (phi0, theta0,
    90 deg + alpha0) and the body at the trim attitude chi, in stability axes, and the body's own centre of mass
    relative to it (``body_cg``, stability axes [m]; ~0.75 mm below it)."""
    m = model if model is not None else load_model()
    d = mujoco.MjData(m)
    d.qpos[3:7] = quat_from_matrix(rot_y(-kin.chi))
    mean = np.array([kin.phi0, kin.theta0, np.pi / 2 + kin.alpha0])
    d.qpos[ModelIndex.of(m).wing_qpos] = np.tile(mean, 2)
    mujoco.mj_kinematics(m, d)
    mujoco.mj_comPos(m, d)
    bodies = range(1, m.nbody)
    mass = sum(m.body_mass[b] for b in bodies)
    com = sum(m.body_mass[b] * d.xipos[b] for b in bodies) / mass
    I = np.zeros((3, 3))
    for b in bodies:
        R = d.ximat[b].reshape(3, 3)
        r = d.xipos[b] - com
        I += R @ np.diag(m.body_inertia[b]) @ R.T + m.body_mass[b] * (r @ r * np.eye(3) - np.outer(r, r))
    Is = S_WORLD @ I @ S_WORLD
    a = S_WORLD @ (d.xipos[ModelIndex.of(m).body] - com)
    return MassProperties(m=float(mass), Ix=float(Is[0, 0]), Iy=float(Is[1, 1]), Iz=float(Is[2, 2]),
                          Ixz=float(-Is[0, 2]), body_cg=(float(a[0]), 0.0 if abs(a[1]) < 1e-15 else float(a[1]),
                                                         float(a[2])))


@dataclass(frozen=True)
class DerivativeRuns:
    """Dimensional derivatives (stability axes, SI) and what produced them."""

    derivatives: dict[str, float]
    deltas: dict[str, float]
    resolution: Resolution
    wall_time_s: float


def _air_field(v_d_s, w_d_s):
    from aero.uvlm import FreeStream

    return FreeStream(v0=-(S_WORLD @ v_d_s), omega=-(S_WORLD @ w_d_s), ref=np.zeros(3))


def _loads_stability(kin, speed, res, v_d_s, w_d_s, symmetric, base=None, forward_speed=0.0) -> np.ndarray:
    """Cycle-mean (X, Y, Z, L, M, N) in stability axes for a disturbance (v_d_s, w_d_s) (stability axes).

    base: (backend, cycles already run) of an undisturbed run to continue from (a copy is disturbed), so that
    the + and - runs of a central difference share the wake they start from; else a run from rest.
    forward_speed: U [m/s] of the condition; where > 0 the body's own loads in the disturbed stream are added (its
    translation only, as :class:`hawksim.insect.body_aero.BodyAero` takes it).
    """
    if base is None:
        backend, start = backend_for(res, symmetric=symmetric, freestream=_air_field(v_d_s, w_d_s)), 0
        cycles = res.cycles
    else:
        backend, start = copy.deepcopy(base[0]), base[1]
        backend.freestream = _air_field(v_d_s, w_d_s)
        cycles = res.cycles - start
    fwd = {} if not forward_speed else {"forward_speed": forward_speed, "body_loads": False}
    r = held_flight(kin, speed, backend, cycles=cycles, average_cycles=res.average_cycles,
                    steps_per_cycle=res.steps_per_cycle, start_cycle=start, **fwd)
    F, M = r.mean_loads(res.average_cycles)
    if forward_speed:
        from hawksim.backends.held import body_loads_world
        from hawksim.condition import air_velocity
        from hawksim.insect.folder import default_insect

        fb, mb = body_loads_world(rot_y(-kin.chi), air_velocity(speed, forward_speed) - S_WORLD @ v_d_s,
                                  default_insect())
        F, M = F + fb, M + mb
    return np.concatenate([S_WORLD @ F, S_WORLD @ M])


def _base_run(kin, speed, res, symmetric, cycles, forward_speed=0.0):
    """An undisturbed run of ``cycles`` wingbeats whose backend state the disturbed runs continue."""
    backend = backend_for(res, symmetric=symmetric)
    held_flight(kin, speed, backend, cycles=cycles, average_cycles=1, steps_per_cycle=res.steps_per_cycle,
                **({"forward_speed": forward_speed} if forward_speed else {}))
    return backend, cycles


def dimensional_derivatives(kin: Kinematics, speed: float, res: Resolution = DERIVATIVE_RESOLUTION, *,
                            delta_velocity: float = DELTA_VELOCITY, delta_rate: float = DELTA_RATE,
                            client=None, progress=None, forward_speed: float = 0.0) -> DerivativeRuns:
    """All 18 derivatives of the paper at a trim (ascent ``speed``, forward speed ``forward_speed`` [m/s]:
    :mod:`hawksim.condition`; the body's own loads count where U > 0); progress(done, total) is called as the 12
    disturbed runs finish.
    With a dask.distributed ``client``
    (`hawksim.cluster.dask_client`) the 2 shared starts and the 12 disturbed runs go to its workers (the starts
    stay there as futures); without, they run in this process. The results do not depend on where the runs go."""
    import time

    from hawksim.stability.system import Scales

    sc = Scales.of(kin)
    dv, dw = delta_velocity * sc.U, delta_rate / sc.T
    unit = np.eye(3)
    cases = []  # (name, sign, v_d, w_d, symmetric)
    for i, name in ((0, "u"), (2, "w")):
        cases += [(name, s, s * dv * unit[i], np.zeros(3), True) for s in (1, -1)]
    cases += [("q", s, np.zeros(3), s * dw * unit[1], True) for s in (1, -1)]
    cases += [("v", 1, dv * unit[1], np.zeros(3), False), ("p", 1, np.zeros(3), dw * unit[0], False),
              ("r", 1, np.zeros(3), dw * unit[2], False)]
    t0 = time.perf_counter()
    # the disturbed runs continue a shared undisturbed start (the first cycles - average_cycles wingbeats), so
    # a central difference compares two runs from the same wake rather than two independent free wakes
    warm = res.cycles - res.average_cycles
    cases += [("v", -1, -dv * unit[1], np.zeros(3), False), ("p", -1, np.zeros(3), -dw * unit[0], False),
              ("r", -1, np.zeros(3), -dw * unit[2], False)]
    if client is not None:
        bases = {s: client.submit(_base_run, kin, speed, res, s, warm, forward_speed, pure=False) if warm > 0
                 else None for s in (True, False)}
        futures = [client.submit(_loads_stability, kin, speed, res, c[2], c[3], c[4], bases[c[4]], forward_speed,
                                 pure=False) for c in cases]
        if progress is not None:
            from dask.distributed import as_completed

            progress(0, len(futures))
            for k, _ in enumerate(as_completed(futures), 1):
                progress(k, len(futures))
        loads = client.gather(futures)
    else:
        bases = {s: _base_run(kin, speed, res, s, warm, forward_speed) if warm > 0 else None for s in (True, False)}
        loads = []
        for c in cases:
            loads.append(_loads_stability(kin, speed, res, c[2], c[3], c[4], bases[c[4]], forward_speed))
            if progress is not None:
                progress(len(loads), len(cases))
    got = {(c[0], c[1]): y for c, y in zip(cases, loads)}
    step = {"u": dv, "w": dv, "q": dw, "v": dv, "p": dw, "r": dw}
    out = {}
    comp = dict(X=0, Y=1, Z=2, L=3, M=4, N=5)
    for var, forces in (("u", "XZM"), ("w", "XZM"), ("q", "XZM"), ("v", "YLN"), ("p", "YLN"), ("r", "YLN")):
        diff = (got[(var, 1)] - got[(var, -1)]) / (2 * step[var])
        for f in forces:
            out[f + var] = float(diff[comp[f]])
    return DerivativeRuns(derivatives=out, deltas={"velocity_m_s": dv, "rate_rad_s": dw},
                          resolution=res, wall_time_s=time.perf_counter() - t0)

