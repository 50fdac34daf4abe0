"""A free flight from an operating point: ``fly(trim, backend, cycles)``.

The insect starts at the origin, pitched nose-up so that its cycle-mean body angle is chi, moving straight up
at the trim's ascent speed (world z), wings on their prescribed motion; perturbations (stability axes,
docs/conventions.md: x forward horizontal, y right, z down) are added to that start (:mod:`hawksim.flight.start`).
Or the flight starts on a periodic orbit of the free body (``start_state``, :mod:`hawksim.flight.orbit`). Results
are world-frame time series (SI, :class:`hawksim.flight.result.FlightResult`).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import mujoco
import numpy as np

from hawksim.backends.base import AeroBackend
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE
from hawksim.flight.result import FlightResult
from hawksim.flight.simulator import Simulator, aero_every_for
from hawksim.flight.start import inertial_pitch_offset, parse_perturbations, start_on_orbit
from hawksim.frames import STABILITY_TO_WORLD, quat_from_matrices, quat_from_matrix, rot_x, rot_y
from hawksim.insect.insect import DEFAULT_INSECT, Insect
from hawksim.insect.model import load_model, model_total_mass
from hawksim.trim.point import Trim


def fly(trim: Trim, backend: AeroBackend, cycles: int, *, perturb: dict[str, float] | None = None,
        model: mujoco.MjModel | None = None, steps_per_cycle: int = FLY_STEPS_PER_CYCLE, gravity: bool = True,
        keep_extras_every: int = 0, periodic_start: bool = True, start_state: tuple | None = None,
        progress: Callable[[int, int], None] | None = None, partial_on_interrupt: bool = False,
        insect: Insect | None = None) -> FlightResult:
    """Fly for ``cycles`` wingbeats from ``trim`` (its kinematics and ascent speed) with ``backend``'s loads. SI in
    and out (angles in radians, rates in rad/s), except ``perturb``, which takes the CLI's units: m/s, and deg and
    deg/s for the angles and rates (:data:`hawksim.flight.start.PERTURBATIONS`).

    Args:
        perturb: stability-axes disturbances of the initial state (see :data:`hawksim.flight.start.PERTURBATIONS`).
        model: the MuJoCo model (default: generated from the insect's morphology,
            :func:`hawksim.insect.model.load_model`); given, its total mass must be the insect's (ValueError naming
            ``model`` otherwise: the result's L+ and D+ are in units of the insect's weight).
        insect: the insect flown (default :data:`hawksim.insect.insect.DEFAULT_INSECT`, the hawkmoth): its MJCF,
            and the units of the result's L+, D+, M+ and P+ (:attr:`FlightResult.insect`). ``backend`` must be built
            for its wings (:func:`hawksim.backends.flight_backend`'s ``morphology``).
        keep_extras_every: keep the backend's extras every this many steps (0: never).
        periodic_start: start on the trim's periodic path by one calibration wingbeat (``start_on_orbit``).
        start_state: (x (9,), chi_ref) the body state at phase 0 of a periodic orbit of the free body
            (:func:`hawksim.flight.orbit.periodic_orbit`; state order :data:`hawksim.flight.orbit.STATE_NAMES`):
            the flight starts exactly there (plus ``perturb``), with no calibration beat.
        progress: called as progress(step, n_steps).
        partial_on_interrupt: a KeyboardInterrupt during the steps returns the steps completed so far (a result
            with fewer than cycles x steps_per_cycle rows) instead of propagating; none completed: it propagates.
    """
    speed, kin = trim.speed, trim.kinematics
    if not (np.isfinite(speed) and speed >= 0):
        raise ValueError(f"--speed must be a finite ascent speed >= 0 m/s, got {speed}")
    if int(cycles) != cycles or cycles < 1:
        raise ValueError(f"--cycles must be a positive integer, got {cycles}")
    if speed == 0:
        from hawksim.backends.registry import descriptor_of

        descriptor_of(backend).hover.require("hover (speed 0)", getattr(backend, "name", type(backend).__name__))
    perturb = parse_perturbations(perturb or {})
    insect = DEFAULT_INSECT if insect is None else insect
    if model is None:
        model = load_model(morph=insect.morphology)
    else:
        m_model, m_insect = model_total_mass(model), insect.morphology.total_mass
        if abs(m_model - m_insect) > 1e-6 * m_insect:
            raise ValueError(f"model: its total mass {m_model * 1e6:.2f} mg is not the insect's "
                             f"({insect.name!r}, {m_insect * 1e6:.2f} mg); pass the insect the model was generated "
                             "from (insect=, --insect)")
    sim = Simulator(model, kin, backend, steps_per_cycle=steps_per_cycle, gravity=gravity,
                    aero_every=aero_every_for(backend, steps_per_cycle))

    deg = np.pi / 180
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

    n = int(cycles) * steps_per_cycle
    batches = []
    done = 0
    t0 = time.perf_counter()
    try:
        while done < n:  # a wingbeat per call: Simulator.advance runs its steps with no Python per step
            k = min(steps_per_cycle, n - done)
            b = sim.advance(k, extras_every=keep_extras_every)
            batches.append(b)
            done += k
            if not np.all(np.isfinite(sim.d.qpos)):
                raise FloatingPointError(f"flight diverged in steps {done - k}-{done - 1} (from t = {b.t[0]:.5f} s): "
                                         "non-finite state")
            if progress is not None:
                progress(done, n)
        end_t, end_pos = float(sim.d.time), sim.body_com()
    except KeyboardInterrupt as exc:
        end_t = end_pos = None
        part = getattr(exc, "partial", None)
        if part is not None and len(part):
            batches.append(part)
        if not partial_on_interrupt or not batches:
            raise
    wall = time.perf_counter() - t0
    a = {k: np.concatenate([getattr(b, k) for b in batches]) for k in
         ("t", "body_pos", "body_R", "body_v", "body_omega", "wing_R", "wing_origin", "force", "power_aero",
          "power_joint")}
    a["moment"] = np.concatenate([b.moment_about_body() for b in batches])
    extras = [e for b in batches for e in b.extras]
    return FlightResult(
        speed_target=float(speed), cycles=int(cycles), aero=backend.name, kinematics=kin,
        steps_per_cycle=steps_per_cycle, t=a["t"], body_pos=a["body_pos"], body_quat=quat_from_matrices(a["body_R"]),
        body_v=a["body_v"], body_omega=a["body_omega"], wing_R=a["wing_R"], wing_origin=a["wing_origin"],
        force=a["force"], moment=a["moment"], power_aero=a["power_aero"], power_joint=a["power_joint"],
        wall_time_s=wall, extras=extras, trim_source=trim.source, end_t=end_t, end_pos=end_pos,
        aero_every=sim.aero_every, insect=insect,
    )
