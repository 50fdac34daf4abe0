"""Per-half-stroke control: the controlled one-beat map sampled at phase 0 and 0.5, linearized half by half.

Issue 20 asks to update the kinematics once per wingbeat *or* per half-stroke. Per half-stroke the controller
senses the body at phase 0 (a stroke reversal: the sweep at phi0 - phi_a) and at phase 0.5 (the other
reversal, phi0 + phi_a), and each half-stroke blends the previous segment's kinematics into the new ones
over the half (:meth:`hawksim.control.plant.ControlledSimulator.begin_beat` with ``span=0.5``; the quintic
smoothstep over T/2, C2 at both ends, the step T/200 as in the per-beat plant). The sampled system is periodic
with two phases, j = 0 (phase 0 -> 0.5) and j = 1 (phase 0.5 -> 1):

    xi_{j+1} = A_j xi_j + B0_j u_{j-1} + B1_j u_j,     (A_j, B0_j, B1_j) alternating between the two halves,

xi, u normalized as the per-beat model (:mod:`hawksim.control.derivatives`: velocities / U, rates x T, rad,
positions / (U T); f relative, angles in rad). Each half's matrices by central differences about the orbit
(step :data:`hawksim.control.derivatives.FD_DELTA`) over u .. psi: the first half launched from the orbit's
phase-0 state, the second from the orbit's phase-0.5 state :attr:`HalfStrokeModel.x_half` (the state set at
t = T/2 with the quasi-steady memory primed there, :func:`hawksim.flight.orbit.set_body_state`), 46 half-beat
flights per half. X and Y are neutral (identity columns); psi is not, unlike per beat: the body moves by
:attr:`HalfStrokeModel.pos_half` (~2 mm back) over a half-stroke, and a heading change turns that displacement
(dY/dpsi = X displacement), so psi's column is differenced too (over a whole beat the orbit's displacement is
zero, which is why the per-beat map may take psi as neutral). Quasi-steady backend only: the UVLM's wake cannot be
set at phase 0.5 from the body state.

The product A_1 A_0 of the two halves' body-state blocks is the one-beat monodromy up to the two half-beats'
finite-difference and priming errors (tested).
"""

from __future__ import annotations

import math
import time
import mujoco
import numpy as np

from hawksim.backends.record import record_scale
from hawksim.backends.registry import descriptor
from hawksim.control.derivatives import (LAT_X, LONG_X, XI_NAMES, Snapshot, central_jacobians, normalized_xi,
                                         record_jacobians, xi_scale)
from hawksim.frames import stability_position
from hawksim.control.plant import (ANTI_INPUTS, INPUTS, SYM_INPUTS, controlled_plant, saturate,
                                   wing_kinematics)
from hawksim.flight.orbit import STEPS_PER_CYCLE, Orbit, read_body_state, set_body_state
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.stability.linear_model import LinearModel, record_names

HALVES = 2
"""Control updates per wingbeat in the half-stroke mode (phases 0 and 0.5)."""


def half_beat(orbit: Orbit, x0: np.ndarray, du_prev: np.ndarray, du: np.ndarray, half: int, *,
              model: mujoco.MjModel | None = None, snapshot: Snapshot | None = None, record=None) -> tuple:
    """One controlled half-stroke of the quasi-steady flight: from body state x0 (9,) at phase 0 (``half=0``) or
    0.5 (``half=1``), the wings on the orbit's kinematics + du_prev before and blended into + du over the half:
    (state (9,) at the half's end, horizontal displacement (2,) [m], stability axes). An orbit with warm-up beats
    (a surrogate with history inputs) branches from ``snapshot``, the orbit's flight at that phase with its record
    of past calls (:func:`linearize_half_stroke` makes both); ``record`` (n, 6): that record's values replaced by
    it, and the record at the half's end returned third (:meth:`hawksim.control.derivatives.Snapshot.beat`)."""
    if half not in (0, 1):
        raise ValueError(f"half must be 0 (phase 0 -> 0.5) or 1 (phase 0.5 -> 1), got {half}")
    if orbit.has_memory:
        if snapshot is None:
            raise ValueError("a half-stroke of an orbit with warm-up beats branches from a snapshot of the orbit's "
                             "flight at that phase (linearize_half_stroke)")
        return snapshot.beat(x0, du_prev, du, half=half, record=record)
    model = model if model is not None else load_model(morph=orbit.insect.morphology)
    kin = orbit.kinematics
    # the controlled plant (in forward flight with the body's own loads, as on the orbit's flights); the surrogate's
    # with each wing clipped at Table 2
    sim = controlled_plant(model, kin, orbit.aero, insect=orbit.insect, forward_speed=orbit.forward_speed)
    sat = (lambda p: saturate(p, orbit.insect)) if descriptor(orbit.aero).saturated_plant else None
    lp, rp = (Kinematics.from_array(p if sat is None else sat(p)) for p in wing_kinematics(kin, du_prev))
    sim.set_wings(lp, rp)
    set_body_state(sim, x0, orbit.chi_ref, t=0.5 * lp.period if half else 0.0)
    p0 = stability_position(sim.d.qpos[:3])
    ln, rn = (Kinematics.from_array(p if sat is None else sat(p)) for p in wing_kinematics(kin, du))
    sim.begin_beat(ln, rn, phase=math.pi * half, span=0.5)
    sim.advance(STEPS_PER_CYCLE // HALVES)
    if not np.all(np.isfinite(sim.d.qpos)):
        raise FloatingPointError("controlled half-stroke diverged (non-finite state)")
    return read_body_state(sim, orbit.chi_ref), stability_position(sim.d.qpos[:3]) - p0


HalfStrokeModel = LinearModel
"""The half-stroke model's name of :class:`hawksim.stability.linear_model.LinearModel` (``map="half-stroke"``): A,
B0, B1 each a pair (first half, second half) of (11, 11) / (11, 7) normalized (module docstring); ``x_half`` (9,)
SI: the orbit's body state at phase 0.5; ``pos_half`` (2,) [m]: its horizontal displacement (X forward, Y right)
over the first half (the phase-0.5 reference of the hold point); ``block(which, half)``; ``monodromy``: the product
of the two halves' state maps' body block. A history network's orbit: the n records of its calls in the state after
the 11 of xi, normalized by ``record_scale``; ``record_ref``: its record (n, 6) SI at phase 0 and at phase 0.5."""


def half_stroke_model(orbit: Orbit, mats, *, x_half, pos_half, scale, coupling: float, delta: float,
                      wall_time_s: float, record_ref=None, record_scale=None) -> LinearModel:
    """The :class:`LinearModel` of the two half-stroke maps ``mats`` [(A, B0, B1) of half 0, of half 1]."""
    n = 0 if record_ref is None else len(record_ref[0])
    return LinearModel(point=orbit, map="half-stroke", states=XI_NAMES + record_names(n), inputs=INPUTS,
                       A=tuple(m[0] for m in mats), B0=tuple(m[1] for m in mats),
                       B1=tuple(m[2] for m in mats), scale=scale, dt=orbit.kinematics.period / HALVES,
                       delta=delta, wall_time_s=wall_time_s, coupling=float(coupling), records=n,
                       record_ref=None if record_ref is None else tuple(record_ref),
                       record_scale=record_scale, x_half=x_half, pos_half=pos_half)


def linearize_half_stroke(orbit: Orbit, *, delta: float | None = None,
                          model: mujoco.MjModel | None = None) -> HalfStrokeModel:
    """:class:`HalfStrokeModel` about the quasi-steady or surrogate ``orbit`` by central differences (module
    docstring; the surrogate's through the Table 2 clip with step SURROGATE_FD_DELTA, as its one-beat model):
    1 reference half-beat + 2 x 46 half-beat flights (~2-3 s). An orbit with a record (a history network's:
    2 x 526 half-beats, 3-4 s) is kept in the per-user cache of :mod:`hawksim.control.cache` and read from it
    next time."""
    t0 = time.perf_counter()
    desc = descriptor(orbit.aero)
    desc.half_stroke.require("a half-stroke controller", orbit.aero)
    if delta is None:
        delta = desc.fd.control
    model = model if model is not None else load_model(morph=orbit.insect.morphology)
    key = None
    if orbit.record is not None:
        from hawksim.control import cache

        key = cache.map_key("half-stroke", orbit, model, delta=delta, clip=desc.saturated_plant)
        z = cache.load(key)
        if z is not None:
            return _from_arrays(orbit, z, delta, time.perf_counter() - t0)
    h = _linearize_half_stroke(orbit, delta, model, t0)
    if key is not None:
        cache.store(key, _to_arrays(h))
    return h


def _to_arrays(h: HalfStrokeModel) -> dict[str, np.ndarray]:
    out = {f"{name}{j}": getattr(h, name)[j] for name in ("A", "B0", "B1") for j in range(HALVES)}
    out.update(x_half=h.x_half, pos_half=h.pos_half, scale=h.scale, coupling=np.array(h.coupling),
               records=np.array(h.records))
    if h.records:
        out.update(record_ref0=h.record_ref[0], record_ref1=h.record_ref[1], record_scale=h.record_scale)
    return out


def _from_arrays(orbit: Orbit, z: dict, delta: float, wall: float) -> HalfStrokeModel:
    n = int(z["records"])
    return half_stroke_model(orbit, [(z[f"A{j}"], z[f"B0{j}"], z[f"B1{j}"]) for j in range(HALVES)],
                             x_half=z["x_half"], pos_half=z["pos_half"], scale=z["scale"],
                             coupling=float(z["coupling"]), delta=delta, wall_time_s=wall,
                             record_ref=(z["record_ref0"], z["record_ref1"]) if n else None,
                             record_scale=z["record_scale"] if n else None)


def _linearize_half_stroke(orbit: Orbit, delta: float, model, t0: float) -> HalfStrokeModel:
    sc = xi_scale(orbit.kinematics, orbit.insect.morphology)
    zero = np.zeros(len(INPUTS))
    snaps, recs = (None, None), None
    if orbit.has_memory:  # the surrogate with history inputs: branch from the orbit's flight and its record
        snap0 = Snapshot(orbit, model, clip=descriptor(orbit.aero).saturated_plant)
        x0 = orbit.initial_state.as_array()
        x_half, pos_half, snap1 = snap0.beat(x0, zero, zero, half=0, keep=True)
        snaps = (snap0, snap1)
        if orbit.record is not None:  # solved on the augmented state: the record is part of the maps' state
            recs = (snap0.record, snap1.record)
    else:
        x0 = orbit.launch_state.as_array()
        x_half, pos_half = half_beat(orbit, x0, zero, zero, 0, model=model)
    n = 0 if recs is None else len(recs[0])
    mats = []
    for half, xs in ((0, x0), (1, x_half)):
        if recs is None:
            def beat(x, du_prev, du, h=half):
                return half_beat(orbit, x, du_prev, du, h, model=model, snapshot=snaps[h])

            # psi too (9 columns): it turns the half-stroke's horizontal displacement (X, Y rows)
            mats.append(central_jacobians(beat, normalized_xi(sc), xs, sc, delta, 9))
        else:  # the body's 9 columns and each record value's, which sit after X, Y in the augmented state
            def beat(x, du_prev, du, rec, h=half):
                return half_beat(orbit, x, du_prev, du, h, snapshot=snaps[h], record=rec)

            mats.append(record_jacobians(beat, xs, recs[half], orbit.kinematics, delta, 9))
    cross = max(np.abs(M[np.ix_(a, b)]).max() for A, B0, B1 in mats for M, (a, b) in
                ((A, (LONG_X, LAT_X)), (A, (LAT_X, LONG_X)), (B0, (LONG_X, ANTI_INPUTS)), (B0, (LAT_X, SYM_INPUTS)),
                 (B1, (LONG_X, ANTI_INPUTS)), (B1, (LAT_X, SYM_INPUTS))))
    return half_stroke_model(orbit, mats, x_half=x_half, pos_half=pos_half, scale=sc, coupling=float(cross),
                             delta=delta, wall_time_s=time.perf_counter() - t0, record_ref=recs,
                             record_scale=record_scale(orbit.kinematics) if n else None)
