"""Control derivatives: the one-beat map's sensitivities to the wingbeat commands, beside its monodromy.

The controlled one-beat map (:mod:`hawksim.control.plant`): beat k blends the previous command u_{k-1} into the
new one u_k, so

    xi_{k+1} = A xi_k + B0 u_{k-1} + B1 u_k,

linearized about a periodic orbit (:func:`hawksim.flight.orbit.periodic_orbit`, quasi-steady: the state is
settable, so each derivative is one beat from the orbit's phase-0 state). xi (11,) is the body state of
:data:`hawksim.flight.orbit.STATE_NAMES` (u, v, w, p, q, r, phi, theta, psi) plus the horizontal position
(X forward, Y right; stability axes), NORMALIZED as the Floquet states (:func:`hawksim.stability.floquet.state_scale`):
velocities / U, rates x T, angles in rad, positions / (U T) (U = 2 phi_a f r2, T = 1/f of the orbit).
u (7,) are the commands of :data:`hawksim.control.plant.INPUTS` (f relative, angles in rad).

Central differences (step :data:`FD_DELTA` in the normalized states and inputs): A's columns over the 8
states u..theta (psi, X, Y are neutral: identity columns, since the map's velocities are in the heading axes
and the orbit's mean horizontal velocity is zero); B1 from a beat that blends the orbit's kinematics into
orbit + du; Bt = B0 + B1 from a beat at orbit + du throughout (previous and new command equal); B0 = Bt - B1.
16 + 28 one-beat flights (~2-4 s quasi-steady). Blocks: longitudinal states :data:`LONG_X` with the symmetric
inputs, lateral :data:`LAT_X` with the antisymmetric ones; the cross blocks vanish for the symmetric orbit
(their largest entry is reported as ``coupling``).
"""

from __future__ import annotations

import math
import time

import mujoco
import numpy as np

from hawksim.backends.builtin import BUILTINS, QUASI_STEADY, SURROGATE, UVLM
from hawksim.backends.registry import descriptor
from hawksim.control.plant import (ANTI_INPUTS, INPUTS, SYM_INPUTS, ControlledSimulator, controlled_plant, saturate,
                                   wing_kinematics)
from hawksim.flight.orbit import STEPS_PER_CYCLE, Orbit, read_body_state, scales, set_body_state
from hawksim.frames import stability_position
from hawksim.insect.morphology import Morphology
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.stability.history_floquet import RECORD_LAT, RECORD_LONG
from hawksim.stability.linear_model import LinearModel, record_names

XI_NAMES = ("u", "v", "w", "p", "q", "r", "phi", "theta", "psi", "X", "Y")
"""The extended state: body state (hawksim.flight.orbit.STATE_NAMES) and horizontal position X (forward), Y (right)."""

LONG_X = (0, 2, 4, 7, 9)
"""Longitudinal states u, w, q, theta, X in :data:`XI_NAMES`."""

LAT_X = (1, 3, 5, 6, 8, 10)
"""Lateral states v, p, r, phi, psi, Y in :data:`XI_NAMES`."""

# The per-backend steps are the backends' descriptors' ``fd.control`` (:mod:`hawksim.backends.builtin`); these
# names are theirs.
FD_DELTA = QUASI_STEADY.fd.control
"""Central-difference step in the normalized states and inputs of a settable map (the quasi-steady backend's)."""

UVLM_FD_DELTA = UVLM.fd.control
"""The same for the UVLM, whose free wake amplifies round-off (as hawksim.flight.orbit.UVLM_FD_STEP)."""

SURROGATE_FD_DELTA = SURROGATE.fd.control
"""The same for the per-step surrogate (:data:`hawksim.backends.builtin.SURROGATE_FD_DELTA`: the measurement that
chose it)."""


def xi_scale(kin: Kinematics, morph: Morphology | None = None) -> np.ndarray:
    """(11,) SI per normalized unit of :data:`XI_NAMES`: U, 1/T, 1 (angles), U T (positions) (U the reference speed
    with the wing of ``morph``, the insect's: :func:`hawksim.flight.orbit.scales`)."""
    U, T = scales(kin, morph)
    return np.array([U, U, U, 1 / T, 1 / T, 1 / T, 1.0, 1.0, 1.0, U * T, U * T])


def normalized_xi(sc: np.ndarray):
    """The map from a beat's output (state (9,), displacement (2,), SI) to the normalized extended state xi (11,)
    of scale ``sc`` (:func:`xi_scale`)."""
    def xi(out):
        x, disp = out
        return np.concatenate([x, disp]) / sc

    return xi


def set_phase0(sim: ControlledSimulator, x: np.ndarray, chi_ref: float) -> None:
    """Overwrite the body state (9,) and put the wings on their prescribed phase-0 pose and rates of the current
    kinematics (``sim.wing_params``), keeping the backend's memory (the UVLM's wake) and the body's position:
    the state perturbation of the UVLM's derivatives (:func:`linearize`)."""
    from hawksim.flight.orbit import state_to_world
    from hawksim.frames import quat_from_matrix

    R, v_w, om_w = state_to_world(np.asarray(x, float), chi_ref)
    d = sim.d
    d.qpos[3:7] = quat_from_matrix(R)
    d.qvel[:3] = v_w
    d.qvel[3:6] = R.T @ om_w
    q, qd, _ = sim.desired(sim.d.time)
    d.qpos[sim.wing_qpos] = q
    d.qvel[sim.wing_dof] = qd
    mujoco.mj_forward(sim.m, d)


class Snapshot:
    """A controlled flight launched from the orbit's launch state (with its record,
    :meth:`hawksim.flight.orbit.Orbit.seed`) and flown over its warm-up beats at the orbit's kinematics, so that its
    backend's memory is the orbit's (the UVLM's wake, a history network's record of past calls); :meth:`beat`
    branches one controlled beat, or half-stroke, from a copy of it. ``clip``: each wing saturated at Table 2 (the
    surrogate's plant, :data:`SATURATED_DERIVATIVES`)."""

    def __init__(self, orbit: Orbit, model, *, clip: bool = False, sim=None):
        import copy

        self._copy = copy.deepcopy
        self.orbit, self.clip = orbit, clip
        self.sat = (lambda p: saturate(p, orbit.insect)) if clip else (lambda p: p)
        if sim is None:
            kin = orbit.kinematics
            sim = controlled_plant(model, kin, orbit.aero, insect=orbit.insect, far_wake=orbit.far_wake,
                                   forward_speed=orbit.forward_speed)
            orbit.seed(sim.backend)
            sim.set_wings(kin, kin)
            set_body_state(sim, orbit.launch_state.as_array(), orbit.chi_ref)
            for _ in range(orbit.warm_beats):
                sim.begin_beat(kin, kin)
                sim.advance(STEPS_PER_CYCLE)
        self.sim = sim
        self._shared = _immutables(sim)

    @property
    def record(self) -> np.ndarray | None:
        """The history network's record (n, 6) at the snapshot (:func:`hawksim.flight.orbit.backend_record`; None
        for a backend without one)."""
        from hawksim.flight.orbit import backend_record

        return backend_record(self.sim.backend, self.sim.aero_every)

    def beat(self, x0, du_prev, du, *, half: int | None = None, keep: bool = False, record=None,
             wings=wing_kinematics):
        """One controlled beat (``half`` None) or half-stroke (0: from phase 0, 1: from phase 0.5) from a copy of
        the snapshot with the body state overwritten by x0 (9,) (:func:`set_phase0`; the backend's memory kept),
        the wings on the orbit's kinematics + du_prev before and blended into + du: (state (9,) at its end,
        horizontal displacement (2,) [m]), and with ``keep`` the branch's simulator as a :class:`Snapshot` there.
        ``record`` (n, 6): a history network's record overwritten by it (its values; times kept) before the beat,
        and then the record at the beat's end is returned after the displacement. ``wings``: the command's
        parameterization, as :func:`one_beat`'s."""
        sim = self._copy(self.sim, dict(self._shared))
        if record is not None:
            sim.backend.restore(np.asarray(record, float))
        kin, chi = self.orbit.kinematics, self.orbit.chi_ref
        lp, rp = (Kinematics.from_array(self.sat(p)) for p in wings(kin, du_prev))
        sim._new = sim._old = (lp, rp)
        sim._same, sim._phase, sim._span = True, 0.0, 1.0
        # phase 0 of the previous command's kinematics at the beat's start, half a period earlier at phase 0.5
        sim._t0 = float(sim.d.time) - (0.5 * lp.period if half == 1 else 0.0)
        sim._sync_native()
        set_phase0(sim, x0, chi)
        p0 = stability_position(sim.d.qpos[:3])
        ln, rn = (Kinematics.from_array(self.sat(p)) for p in wings(kin, du))
        if half is None:
            sim.begin_beat(ln, rn)
            n = STEPS_PER_CYCLE
        else:
            sim.begin_beat(ln, rn, phase=math.pi * half, span=0.5)
            n = STEPS_PER_CYCLE // 2
        sim.advance(n)  # as n calls of step (the native loop where there is one)
        if not np.all(np.isfinite(sim.d.qpos)):
            raise FloatingPointError("controlled beat diverged (non-finite state)")
        out = (read_body_state(sim, chi), stability_position(sim.d.qpos[:3]) - p0)
        if record is not None:
            from hawksim.flight.orbit import backend_record

            out = (*out, backend_record(sim.backend, sim.aero_every))
        return (*out, Snapshot(self.orbit, None, sim=sim, clip=self.clip)) if keep else out


def _immutables(sim) -> dict:
    """A deepcopy memo that makes copies of ``sim`` share what no flight writes: the MjModel and a per-step
    surrogate's network (its weights, folded layers and the native callback's packed weight buffer). The copy's
    own state (MjData, the plant's blend, the backend's record of calls) is still copied. Measured: a branch of
    the surrogate's snapshot 5.1 -> 2.7 ms (1 m/s, half-stroke)."""
    b = sim.backend
    if hasattr(sim, "_native_network"):
        sim._native_network()  # the callback's network made (and cached) once, so that the copies share it
    keep = [sim.m, getattr(b, "net", None), getattr(b, "layers", None), getattr(b, "blocks", None)]
    net = getattr(sim, "_net", None)
    if net is not None and getattr(sim, "_net_of", None) is b:
        keep.append(net.buffer)
    return {id(o): o for o in keep if o is not None}


def one_beat(orbit: Orbit, x0: np.ndarray, du_prev: np.ndarray, du: np.ndarray, *,
             model: mujoco.MjModel | None = None, clip: bool = False,
             wings=wing_kinematics) -> tuple[np.ndarray, np.ndarray]:
    """One controlled beat from body state x0 (9,) at phase 0, the wings on the orbit's kinematics + du_prev
    before and blended into + du over the beat: (state (9,) at the beat's end, horizontal displacement (2,)
    [m], stability axes). ``clip``: saturate each wing at Table 2 (off for derivatives, which may step past
    a bound the orbit sits on, e.g. phi_a = 60 deg). ``wings(base, du) -> (left, right)``: the command's
    parameterization (default :func:`hawksim.control.plant.wing_kinematics`, the seven channels of INPUTS;
    :func:`hawksim.control.constrained.wing_params` for the per-wing channels)."""
    model = model if model is not None else load_model(morph=orbit.insect.morphology)
    kin = orbit.kinematics
    sim = controlled_plant(model, kin, orbit.aero, insect=orbit.insect, far_wake=orbit.far_wake,
                           forward_speed=orbit.forward_speed)
    sat = (lambda p: saturate(p, orbit.insect)) if clip else (lambda p: p)
    lp, rp = (Kinematics.from_array(sat(p)) for p in wings(kin, du_prev))
    sim.set_wings(lp, rp)
    set_body_state(sim, x0, orbit.chi_ref)
    p0 = stability_position(sim.d.qpos[:3])
    ln, rn = (Kinematics.from_array(sat(p)) for p in wings(kin, du))
    sim.begin_beat(ln, rn)
    sim.advance(STEPS_PER_CYCLE)
    if not np.all(np.isfinite(sim.d.qpos)):
        raise FloatingPointError("controlled beat diverged (non-finite state)")
    return read_body_state(sim, orbit.chi_ref), stability_position(sim.d.qpos[:3]) - p0


BeatMapModel = LinearModel
"""The per-beat model's name of :class:`hawksim.stability.linear_model.LinearModel` (``map="beat"``): A (11, 11),
B0 and B1 (11, 7) normalized (module docstring); on a history network's augmented state (``records`` n) 11 + 6 n
states."""


def beat_model(orbit: Orbit, A, B0, B1, *, scale, coupling: float, delta: float, wall_time_s: float,
               clipped: bool = False, record_ref: np.ndarray | None = None) -> LinearModel:
    """The :class:`LinearModel` of the controlled one-beat map about ``orbit`` (states :data:`XI_NAMES`, then a
    history network's record values when ``record_ref`` (n, 6) is given; inputs :data:`INPUTS`; dt = T)."""
    n = 0 if record_ref is None else len(record_ref)
    return LinearModel(point=orbit, map="beat", states=XI_NAMES + record_names(n), inputs=INPUTS, A=A, B0=B0, B1=B1,
                       scale=scale, dt=orbit.kinematics.period, delta=delta, wall_time_s=wall_time_s,
                       coupling=float(coupling), clipped=bool(clipped), records=n, record_ref=record_ref)


def central_jacobians(beat, xi, x0: np.ndarray, sc: np.ndarray, delta: float,
                      n_states: int, n_inputs: int = len(INPUTS), *, entries=None,
                      columns=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A (N, N), B0 (N, m), B1 (N, m)) of a controlled map ``beat(x, du_prev, du)`` about ``x0`` by central
    differences of step ``delta`` (normalized; ``sc`` SI per unit of x, ``xi`` the normalized extended state of a
    beat's output: 11 long, or N with ``columns``): A's columns from x's first ``n_states`` entries (or the entries
    ``entries``), into column ``columns[k]`` for the k-th (default the entry's index; the other columns identity,
    all of them for ``n_states=0``), B1 from a blend into +-du, Bt = B0 + B1 from +-du held over the beat and the
    one before (module docstring); m = ``n_inputs`` channels (default the seven of INPUTS)."""
    m = int(n_inputs)
    zero = np.zeros(m)
    ents = list(range(n_states)) if entries is None else list(entries)
    cols = ents if columns is None else list(columns)
    x_ref = np.asarray(x0, float)
    N = 11 if columns is None else len(xi(beat(x_ref.copy(), zero, zero)))  # with a record: its rows too
    A = np.eye(N)
    for j, c in zip(ents, cols):
        r = []
        for s in (1, -1):
            x = x_ref.copy()
            x[j] += s * delta * sc[j]
            r.append(xi(beat(x, zero, zero)))
        A[:, c] = (r[0] - r[1]) / (2 * delta)
    B1, Bt = np.zeros((N, m)), np.zeros((N, m))
    for j in range(m):
        e = np.zeros(m)
        e[j] = delta
        B1[:, j] = (xi(beat(x0, zero, e)) - xi(beat(x0, zero, -e))) / (2 * delta)
        Bt[:, j] = (xi(beat(x0, e, e)) - xi(beat(x0, -e, -e))) / (2 * delta)
    return A, Bt - B1, B1


def record_index(which: str, records: int) -> list[int]:
    """Indices in the augmented state (the 11 of :data:`XI_NAMES`, then each record's 6 values, oldest first) of
    the records' longitudinal (v_x, v_z, omega_y) or lateral (v_y, omega_x, omega_z) values
    (:data:`hawksim.stability.history_floquet.RECORD_LONG`, ``RECORD_LAT``; record-major)."""
    comps = RECORD_LONG if which == "long" else RECORD_LAT
    return [11 + 6 * k + c for k in range(records) for c in comps]


def record_jacobians(beat, x0: np.ndarray, rec0: np.ndarray, kin: Kinematics, delta: float,
                     n_body: int, n_inputs: int = len(INPUTS), *,
                     states: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`central_jacobians` on the augmented state of a history network (the body state and horizontal
    position, normalized by :func:`xi_scale` of the kinematics ``kin``, then the record's n x 6 values normalized
    by :func:`hawksim.backends.record.record_scale`): ``beat(x (9,), du_prev, du,
    record (n, 6)) -> (state (9,), displacement (2,), record (n, 6))`` branches from the orbit's flight with its
    record replaced; A's columns from the first ``n_body`` body states and every record value (psi's, when not
    among them, and X's, Y's identity). A (11 + 6 n) square, B0 and B1 (11 + 6 n, m). Each record value is one
    more pair of flights: 2 (n_body + 6 n) + 4 m in all. ``states`` False: B0 and B1 only (A the identity), 4 m
    flights; m = ``n_inputs`` channels."""
    from hawksim.backends.record import record_scale

    n = len(rec0)
    sc, rsc = xi_scale(kin), record_scale(kin)

    def xi(out):
        x, disp, rec = out
        return np.concatenate([np.concatenate([x, disp]) / sc, (rec / rsc).ravel()])

    def aug(xa, du_prev, du):
        return beat(xa[:9], du_prev, du, xa[9:].reshape(n, 6))

    return central_jacobians(aug, xi, np.concatenate([x0, np.asarray(rec0, float).ravel()]),
                             np.concatenate([sc[:9], np.tile(rsc, n)]), delta, 0, n_inputs,
                             entries=list(range(n_body)) + list(range(9, 9 + 6 * n)) if states else [],
                             columns=list(range(n_body)) + list(range(11, 11 + 6 * n)) if states else [])


SATURATED_DERIVATIVES = tuple(d.name for d in BUILTINS if d.saturated_plant)
"""The built-in backends (any backend: its descriptor's ``saturated_plant``) whose control derivatives are taken on the
map as flown, each wing saturated at Table 2 (:func:`one_beat` with ``clip``). The per-step surrogate's network never
saw parameters outside Table 2 (its training kinematics are clipped there), and its orbits sit on phi_a = 60 deg (the
bound): a central difference that steps one wing past it differences the network's extrapolation (the unclipped
dphi_a column's one-beat response is off by 11 % at 1 deg and 45 % at 3 deg at 1 m/s). With the clip, a small
antisymmetric dphi_a lowers one wing's amplitude whichever its sign, so the central difference gives the lateral
response of the flown plant (odd in dphi_a by mirror symmetry, half the unclipped slope) and no longitudinal one
(even). The quasi-steady and UVLM models are smooth across the bound and keep the unclipped derivatives of their
shipped tables."""


def linearize(orbit: Orbit, *, delta: float | None = None, model: mujoco.MjModel | None = None,
              clip: bool | None = None, records: bool = False) -> LinearModel:
    """:class:`BeatMapModel` about ``orbit`` by central differences (module docstring), in normalized states and
    inputs (angles in radians before normalizing: :func:`xi_scale`). Quasi-steady and surrogate:
    each derivative beat is launched from the orbit's phase-0 state (the state is settable). UVLM (an orbit with
    warm-up beats): one flight is launched and flown over the warm-up beats, and every derivative beat branches from
    a copy of it at the periodic beat's start, with the body state overwritten there (:func:`set_phase0`) and the
    wake kept: the derivatives hold the wake at the orbit's (its memory of the perturbation is left out). ``clip``:
    difference the map with each wing saturated at Table 2 (default: for :data:`SATURATED_DERIVATIVES`).
    ``records``: for an orbit with a record (a history network's, :attr:`hawksim.flight.orbit.Orbit.record`), the
    map on the augmented state (:func:`record_jacobians`, 2 (8 + 6 n) + 28 beats, ~2 s; kept in the per-user cache
    of :mod:`hawksim.control.cache` and read from it next time); without it the record is held at the orbit's,
    which is that map's body block."""
    t0 = time.perf_counter()
    desc = descriptor(orbit.aero)
    if clip is None:
        clip = desc.saturated_plant
    if delta is None:
        delta = desc.fd.control
    model = model if model is not None else load_model(morph=orbit.insect.morphology)
    kin = orbit.kinematics
    sc = xi_scale(kin, orbit.insect.morphology)
    if orbit.has_memory:
        snap = Snapshot(orbit, model, clip=clip)
        x0 = orbit.initial_state.as_array()

        def beat(x, du_prev, du):
            return snap.beat(x, du_prev, du)
    else:
        x0 = orbit.launch_state.as_array()

        def beat(x, du_prev, du):
            return one_beat(orbit, x, du_prev, du, model=model, clip=clip)

    rec0 = None
    if records and orbit.record is not None:  # seconds: kept in the per-user cache (hawksim.control.cache)
        from hawksim.control import cache

        key = cache.map_key("beat", orbit, model, delta=delta, clip=bool(clip))
        z = cache.load(key)
        if z is not None:
            return beat_model(orbit, z["A"], z["B0"], z["B1"], scale=z["scale"], coupling=float(z["coupling"]),
                              delta=delta, wall_time_s=time.perf_counter() - t0, clipped=bool(clip),
                              record_ref=z["record_ref"])
        rec0 = snap.record
        A, B0, B1 = record_jacobians(lambda x, dp, d, r: snap.beat(x, dp, d, record=r), x0, rec0, kin, delta, 8)
    else:
        A, B0, B1 = central_jacobians(beat, normalized_xi(sc), x0, sc, delta, 8)
    # the neutral rows: psi and position do not feed back (identity columns set above); psi's own row from the map
    cross = max(np.abs(M[np.ix_(a, b)]).max() for M, (a, b) in
                ((A, (LONG_X, LAT_X)), (A, (LAT_X, LONG_X)), (B0, (LONG_X, ANTI_INPUTS)), (B0, (LAT_X, SYM_INPUTS)),
                 (B1, (LONG_X, ANTI_INPUTS)), (B1, (LAT_X, SYM_INPUTS))))
    out = beat_model(orbit, A, B0, B1, scale=sc, coupling=float(cross), delta=delta,
                     wall_time_s=time.perf_counter() - t0, clipped=bool(clip), record_ref=rec0)
    if rec0 is not None:
        cache.store(key, {"A": A, "B0": B0, "B1": B1, "scale": sc, "coupling": np.array(out.coupling),
                          "record_ref": rec0})
    return out
