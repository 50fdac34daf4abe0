"""The MuJoCo flight loop: prescribed wing kinematics on a free body, aerodynamic loads each step.

Method (docs/conventions.md, "MuJoCo coupling"). The integrator is RK4. Inside ``mjcb_control``,
called by MuJoCo at every RK4 stage, the six wing-joint torques are solved by computed torque so that the wing
joint accelerations equal the prescribed ones (plus a stiff PD term that only removes round-off drift):
with zero wing torque, ``mj_fwdActuation`` + ``mj_fwdAcceleration`` give the generalized force f0
(``qfrc_smooth``), and with the dense mass matrix (``mj_fullM``) the equations of motion, split into the body's
dofs b and the wings' w, give the torques of the prescribed wing accelerations a_des in one solve with M_bb:
M_bb a_b = f0_b - M_bw a_des, tau = M_wb a_b + M_ww a_des - f0_w (:func:`prescribed_torque`; the torques of
tau = ([M^-1]_ww)^-1 (a_des - a0), a0 = (M^-1 f0)_w, without solving with M). They are internal: the body
responds to the wings' inertia exactly, momentum is conserved (tested); wing qpos/qvel are never overwritten.
Aerodynamic loads come from an :class:`hawksim.backends.base.AeroBackend` once per update (held in between) and
enter through ``data.xfrc_applied`` of the wing bodies (world-frame force and torque at their ``xipos``).
"""

from __future__ import annotations

import contextlib
import math
import sys

import mujoco
import numpy as np
from numba import njit

from hawksim.backends.base import AeroBackend, FlightState, NoAero, WingLoads, read_state
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE, MIN_STEPS_PER_CYCLE
from hawksim.flight.steps import StepBatch, StepRecord
from hawksim.frames import cross
from hawksim.insect.accessors import ModelIndex
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.morphology import G

FEEDBACK_BANDWIDTH = 5.0
"""PD correction bandwidth in units of the flapping angular frequency 2 pi f (critically damped)."""


@njit(cache=True)
def spd_solve_in_place(A, b):
    """b <- A^-1 b for a symmetric positive definite A (n, n), by Cholesky (A = L L^T): L overwrites A's lower
    triangle, which is all that is read of A. No allocation, as it runs at every RK4 stage."""
    n = b.shape[0]
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= A[j, k] * A[j, k]
        dj = math.sqrt(s)
        A[j, j] = dj
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= A[i, k] * A[j, k]
            A[i, j] = s / dj
    for i in range(n):  # L y = b
        s = b[i]
        for k in range(i):
            s -= A[i, k] * b[k]
        b[i] = s / A[i, i]
    for i in range(n - 1, -1, -1):  # L^T x = y
        s = b[i]
        for k in range(i + 1, n):
            s -= A[k, i] * b[k]
        b[i] = s / A[i, i]


@njit(cache=True)
def prescribed_torque(M, f0, acc, work):
    """The joint torques that give the last six dofs (the wings' hinges) the accelerations acc (6,), in place
    (acc <- tau): with the dense mass matrix M (nv, nv) and the generalized force f0 (nv,) without those torques
    (MuJoCo's qfrc_smooth: passive - bias + applied + the wings' loads through xfrc_applied), the equations of
    motion M qacc = f0 + [0, tau] split into the body's block b (the first nv - 6 dofs) and the wings' w:

        M_bb a_b = f0_b - M_bw acc,    tau = M_wb a_b + M_ww acc - f0_w,

    the body's accelerations a_b by Cholesky of M_bb (overwritten; M_bb is SPD as a diagonal block of the SPD M).
    One (nv - 6)-square solve and no solve with M itself, at every RK4 stage; work: scratch (nv,). The native
    callback (:mod:`hawksim.flight.native`) and the Python one call this same function, so the two give the same
    floats."""
    nb = M.shape[0] - 6
    ab = work[:nb]
    for i in range(nb):
        s = f0[i]
        for k in range(6):
            s -= M[i, nb + k] * acc[k]
        ab[i] = s
    spd_solve_in_place(M[:nb, :nb], ab)
    for k in range(6):
        r = nb + k
        s = -f0[r]
        for i in range(nb):
            s += M[r, i] * ab[i]
        for j in range(6):
            s += M[r, nb + j] * acc[j]
        work[nb + k] = s
    for k in range(6):
        acc[k] = work[nb + k]


@njit(cache=True)
def _computed_torque(t, p, kp, kd, q, qd, M, f0, work):
    """The six wing-joint torques of one RK4 stage, compiled (one call instead of a dozen numpy operations per
    stage): Eq. 1 at time t for both wings (p = (f, phi0, theta0, alpha0, phi_a, alpha_a), SI; the arithmetic of
    :meth:`Kinematics.eq1`), the PD-corrected desired acceleration a_des = qdd + kp (q_des - q) + kd (qd_des - qd)
    of the joint angles q (6,) and rates qd (6,), and the torques that give it (:func:`prescribed_torque` with the
    dense mass matrix M, overwritten, and the force f0; work: scratch (nv,))."""
    f, phi0, theta0, alpha0, phi_a, alpha_a = p[0], p[1], p[2], p[3], p[4], p[5]
    w = 2.0 * math.pi * f
    c, s = math.cos(w * t), math.sin(w * t)
    qs = (phi0 - phi_a * c, theta0, 0.5 * math.pi + alpha0 - alpha_a * s)
    qds = (phi_a * w * s, 0.0, -alpha_a * w * c)
    qdds = (phi_a * w * w * c, 0.0, alpha_a * w * w * s)
    acc = np.empty(6)
    for k in range(6):
        j = k % 3
        acc[k] = qdds[j] + kp * (qs[j] - q[k]) + kd * (qds[j] - qd[k])
    prescribed_torque(M, f0, acc, work)
    return acc


@njit(cache=True)
def _computed_torque_given(q_des, qd_des, qdd_des, kp, kd, q, qd, M, f0, work):
    """As :func:`_computed_torque` for a desired motion (6,) computed elsewhere (a subclass's ``desired``)."""
    acc = np.empty(6)
    for k in range(6):
        acc[k] = qdd_des[k] + kp * (q_des[k] - q[k]) + kd * (qd_des[k] - qd[k])
    prescribed_torque(M, f0, acc, work)
    return acc


UNSTABLE_WARNINGS = ("mjWARN_BADQPOS", "mjWARN_BADQVEL", "mjWARN_BADQACC")
"""MuJoCo warnings after which it resets the state to the model's qpos0 and carries on: a flight that meets one
has failed (a numerical blow-up), and :meth:`Simulator.step` raises instead of returning the reset state."""


class _MujocoLog:
    """MuJoCo's warning handler: each message to stderr, or, while :meth:`Simulator.step` runs ``mj_step``, held
    (``held`` a list) for the step to report: a fatal one inside its one-line error, the others printed after."""

    def __init__(self):
        self.held: list[str] | None = None

    def __call__(self, message: str) -> None:
        if self.held is None:
            print(f"MuJoCo: {message}", file=sys.stderr)
        else:
            self.held.append(message.strip())


_MUJOCO_LOG = _MujocoLog()


def route_mujoco_warnings() -> None:
    """Send MuJoCo's warnings to stderr instead of its default MUJOCO_LOG.TXT in the working directory (unless the
    user installed a handler)."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(_MUJOCO_LOG)


def idle_stages(model: mujoco.MjModel) -> int:
    """MuJoCo's disable flags for the pipeline stages that cannot act in this model, so each RK4 stage skips them
    (~20 % of a step of the hawkmoth model, whose geoms are visual only): collision detection when no geom can
    collide (every contype and conaffinity 0), the constraint stage when, in addition, there are no equality
    constraints, joint limits or friction loss. The flight is the same float for float (tested)."""
    flags = 0
    if not np.any(model.geom_contype) and not np.any(model.geom_conaffinity):
        flags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        if (model.neq == 0 and not np.any(model.jnt_limited) and not np.any(model.dof_frictionloss)
                and not np.any(model.tendon_limited)):
            flags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    return int(flags)


@contextlib.contextmanager
def control_callback(fn, timer=None):
    """MuJoCo's ``mjcb_control`` set to fn (and ``mjcb_time`` to timer, unless None) for the block, then put back
    (both are one global per process)."""
    previous = mujoco.get_mjcb_control()
    clock = mujoco.get_mjcb_time() if timer is not None else None
    mujoco.set_mjcb_control(fn)
    if timer is not None:
        mujoco.set_mjcb_time(timer)
    try:
        yield
    finally:
        mujoco.set_mjcb_control(previous)
        if timer is not None:
            mujoco.set_mjcb_time(clock)


class Simulator:
    """A hawkmoth flight in MuJoCo with prescribed wing kinematics.

    Args:
        model: the MjModel (see :func:`hawksim.insect.model.load_model`); its options are overwritten: RK4 and a time
            step of one ``steps_per_cycle``-th of the wingbeat period.
        kin: wing kinematics (Eq. 1) for both wings (symmetric flapping).
        backend: aerodynamic model.
        steps_per_cycle: integration steps per wingbeat.
        gravity: whether gravity acts.
        aero_every: call the backend every this many steps (its dt is then aero_every steps); in between the
            loads are held fixed in the world frame (force, and moment about each wing's hinge), so a costly
            backend (the UVLM) can run at a coarser rate than the integrator. The joint power of the steps in
            between pairs the held load with a later wing motion; the required power therefore samples the
            update steps only (:mod:`hawksim.flight.power`).
        native: solve the computed torque in the compiled MuJoCo callback of :mod:`hawksim.flight.native` (the
            same floats as the Python callback, several times faster) where it is available; False: the Python
            callback :meth:`_control` (a subclass that overrides :meth:`desired` always gets it, unless it
            declares ``native_motion = True`` and keeps the native callback's parameters current).
    """

    native_motion = False
    """A subclass whose :meth:`desired` the native callback reproduces (its mode 1) sets this True."""

    body_aero = None
    """None (the paper's setting), or a :class:`hawksim.insect.body_aero.BodyAero` whose loads act on the body in
    forward flight, updated with the backend's (:meth:`~hawksim.insect.body_aero.BodyAero.apply`)."""

    def __init__(self, model: mujoco.MjModel, kin: Kinematics, backend: AeroBackend, *,
                 steps_per_cycle: int = FLY_STEPS_PER_CYCLE, gravity: bool = True, aero_every: int = 1,
                 native: bool = True):
        if steps_per_cycle < MIN_STEPS_PER_CYCLE:
            raise ValueError(f"steps_per_cycle must be >= {MIN_STEPS_PER_CYCLE}, got {steps_per_cycle}")
        self.m = model
        self.kin = kin
        self.backend = backend
        self.dt = kin.period / steps_per_cycle
        self.steps_per_cycle = steps_per_cycle
        if aero_every < 1 or steps_per_cycle % aero_every:
            raise ValueError(f"aero_every={aero_every} must be >= 1 and divide steps_per_cycle={steps_per_cycle}")
        self.aero_every = aero_every
        self._i = 0
        self._held: WingLoads | None = None
        model.opt.timestep = self.dt
        model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
        model.opt.gravity[:] = (0.0, 0.0, -G) if gravity else (0.0, 0.0, 0.0)
        model.opt.disableflags |= idle_stages(model)
        self.d = mujoco.MjData(model)
        ix = ModelIndex.of(model)
        self.body_id, self.wing_ids, self.wing_qpos, self.wing_dof = ix.body, ix.wings, ix.wing_qpos, ix.wing_dof
        if not np.array_equal(self.wing_dof, np.arange(model.nv - 6, model.nv)):
            raise ValueError(f"the wing joints must be the model's last six dofs, got {self.wing_dof} of {model.nv}")
        self._M = np.zeros((model.nv, model.nv))  # the computed torque's dense mass matrix and scratch, per stage
        self._work = np.zeros(model.nv)
        wc = FEEDBACK_BANDWIDTH * 2 * np.pi * kin.f
        self._kp, self._kd = wc * wc, 2 * wc
        self._capture = False
        self._tau = np.zeros(6)
        # the wing joints' qpos / dof ranges as slices (contiguous in the generated model): views, not copies
        def as_slice(ix):
            ix = np.asarray(ix)
            if not np.array_equal(ix, np.arange(ix[0], ix[0] + len(ix))):
                raise ValueError(f"wing joints must be contiguous in the model, got {ix}")
            return slice(int(ix[0]), int(ix[0]) + len(ix))
        self._qslice, self._vslice = as_slice(self.wing_qpos), as_slice(self.wing_dof)
        self._p = np.array([kin.f, kin.phi0, kin.theta0, kin.alpha0, kin.phi_a, kin.alpha_a])
        self._eq1_compiled = type(self).desired is Simulator.desired  # the compiled stage evaluates Eq. 1 itself
        self._warn_ids = [int(getattr(mujoco.mjtWarning, w)) for w in UNSTABLE_WARNINGS]
        route_mujoco_warnings()
        self._native = None
        self._net_of, self._net = None, None  # the backend whose network the native callback holds, and it
        if native and (self._eq1_compiled or type(self).native_motion):
            from hawksim.flight.native import NativeControl

            nc = NativeControl(model.nq, model.nv, self._qslice.start, self._vslice.start, self._kp, self._kd,
                               self.body_id, self.wing_ids)
            if nc.available:
                nc.set_eq1(self._p)
                self._native = nc

    @property
    def native_control(self):
        """The compiled computed-torque callback (:class:`hawksim.flight.native.NativeControl`) that steps this
        flight, or None where the flight's control runs in Python (no compiler, or ``native=False``)."""
        return self._native

    # ---- prescribed motion -------------------------------------------------------------------------
    def desired(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Prescribed (q, qdot, qddot) of the six wing joints at time t, order left (sweep, elev, rot), right.

        Scalar path of :meth:`Kinematics.eq1` (math.cos, no arrays), since this runs at every RK4 stage.
        """
        wt = 2 * math.pi * self.kin.f * t
        q, qd, qdd = self.kin.eq1(math.cos(wt), math.sin(wt))
        return np.array(q + q), np.array(qd + qd), np.array(qdd + qdd)

    def _control(self, m, d):
        qs, vs = self._qslice, self._vslice
        d.qfrc_applied[vs] = 0.0
        mujoco.mj_fwdActuation(m, d)
        mujoco.mj_fwdAcceleration(m, d)
        mujoco.mj_fullM(m, d, self._M)
        if self._eq1_compiled:
            tau = _computed_torque(d.time, self._p, self._kp, self._kd, d.qpos[qs], d.qvel[vs], self._M, d.qfrc_smooth,
                                   self._work)
        else:  # a subclass prescribes another motion (hawksim.control.plant: kinematics changed between beats)
            q, qd, qdd = self.desired(d.time)
            tau = _computed_torque_given(q, qd, qdd, self._kp, self._kd, d.qpos[qs], d.qvel[vs], self._M,
                                         d.qfrc_smooth, self._work)
        d.qfrc_applied[vs] = tau
        if self._capture:
            self._tau[:] = tau
            self._capture = False

    @contextlib.contextmanager
    def vacuum(self):
        """Within the block the flight has no aerodynamic loads and no gravity (the wings' inertia alone); the
        backend and gravity are restored after it. Call :meth:`reset` inside before stepping."""
        backend, gravity, body_aero = self.backend, self.m.opt.gravity.copy(), self.body_aero
        self.backend, self.body_aero = NoAero(), None
        self.m.opt.gravity[:] = 0.0
        try:
            yield self
        finally:
            self.backend, self.body_aero = backend, body_aero
            self.m.opt.gravity[:] = gravity

    # ---- state ---------------------------------------------------------------------------------------
    def reset(self, *, velocity: np.ndarray = (0.0, 0.0, 0.0), quat: np.ndarray | None = None,
              omega_body: np.ndarray = (0.0, 0.0, 0.0), position: np.ndarray = (0.0, 0.0, 0.0)) -> None:
        """Start at t = 0 with the wings on their prescribed motion.

        The body's initial velocity is chosen so that the whole insect's linear and angular momentum equal
        those of a rigid motion at ``velocity`` (world, m/s) and ``omega_body`` (body frame, rad/s): the
        wings' own momentum at t = 0 is cancelled by the body (an insect "at rest" has zero total momentum).
        ``quat`` (w, x, y, z) is the body attitude; default: pitched nose-up by the body angle chi.
        """
        m, d = self.m, self.d
        mujoco.mj_resetData(m, d)
        if quat is None:
            quat = np.array([np.cos(-self.kin.chi / 2), 0.0, np.sin(-self.kin.chi / 2), 0.0])
        d.qpos[:3] = position
        d.qpos[3:7] = quat / np.linalg.norm(quat)
        q, qd, _ = self.desired(0.0)
        d.qpos[self.wing_qpos] = q
        d.qvel[:] = 0.0
        d.qvel[:3] = velocity
        d.qvel[3:6] = omega_body
        d.qvel[self.wing_dof] = qd
        mujoco.mj_forward(m, d)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        b = np.arange(6)
        # generalized momentum of the free dofs must equal that of the rigid motion with still wings
        p_target = M[np.ix_(b, b)] @ d.qvel[b]
        d.qvel[b] = np.linalg.solve(M[np.ix_(b, b)], p_target - M[np.ix_(b, self.wing_dof)] @ qd)
        mujoco.mj_forward(m, d)
        self._i = 0
        self.backend.reset(self.state())

    def state(self) -> FlightState:
        """The current state (kinematics must be up to date: call after reset/step); its dt is the interval
        the backend's loads are held over."""
        return read_state(self.m, self.d, self.body_id, self.wing_ids, self.dt * self.aero_every)

    def step(self) -> StepRecord:
        """Advance one time step: loads from the backend (or held), then one RK4 step."""
        d = self.d
        st = self.state()
        if self._i % self.aero_every == 0:
            # held in the WORLD frame until the next update: force and moment about the hinge stay fixed world
            # vectors (below, the moment is carried to the wing's centre of mass from the hinge's current
            # position); holding them in the wing frame would turn them with the wing and bias the mean force by
            # about (aero_every - 1) dt / 2 mean(omega x F) (tests/hawksim/test_heavy_body.py)
            self._held = self._loads(st)
        loads = self._held
        com = d.xipos[self.wing_ids]
        d.xfrc_applied[self.wing_ids, :3] = loads.force
        d.xfrc_applied[self.wing_ids, 3:] = loads.moment + cross(st.wing_origin - com, loads.force)
        qd = d.qvel[self.wing_dof].copy()
        native = self._native
        if native is not None:
            native.capture()
            native.install()
            callback = native.callback
        else:
            self._capture = True
            callback = self._control
        self._mj_step(1, st.t, callback)
        tau = native.tau if native is not None else self._tau
        return StepRecord(st, loads, float(tau @ qd))

    def advance(self, n: int, *, extras_every: int = 0) -> StepBatch:
        """Advance n steps, as n calls of :meth:`step` (the same floats for the state), and return what they
        produced as arrays.

        With the native callback (:mod:`hawksim.flight.native`) the steps between two backend updates run in one
        ``mj_step(m, d, nstep)``: the callback applies the held loads at each step's start and records the state
        there, so Python runs once per backend update instead of once per step (the per-step surrogate and the
        UVLM update every :func:`aero_every_for` steps). Without it, a loop of :meth:`step`.

        ``extras_every``: keep the backend's extras of the steps i % extras_every == 0 (0: none). A
        KeyboardInterrupt leaves with the steps completed as its ``partial`` attribute (a StepBatch).
        """
        if n < 0 or int(n) != n:
            raise ValueError(f"advance needs a number of steps >= 0, got {n}")
        n = int(n)
        if self._native is None:
            i0, records = self._i, []
            try:
                for _ in range(n):
                    records.append(self.step())
            except KeyboardInterrupt as exc:
                exc.partial = StepBatch.of(records, extras_every, i0)  # the steps completed, for the caller
                raise
            return StepBatch.of(records, extras_every, i0)
        from hawksim.flight.native import REC_WIDTH

        native = self._native
        rec = np.empty((n, REC_WIDTH))
        extras = []
        i0 = self._i
        net = self._native_network()
        try:
            self._advance_native(n, rec, extras, net, extras_every)
        except KeyboardInterrupt as exc:  # between two chunks: the steps completed, for the caller
            self._native.end_chunk()
            done = self._i - i0
            exc.partial = StepBatch.from_record(rec[:done], [e for e in extras if e[0] < i0 + done], i0)
            raise
        if net is not None:
            force, moment, power = native.held()
            self._held = WingLoads(force=force, moment=moment, power=power)
        return StepBatch.from_record(rec, extras, i0)

    def _advance_native(self, n: int, rec: np.ndarray, extras: list, net, extras_every: int) -> None:
        d, native = self.d, self._native
        i = 0
        while i < n:
            if net is not None:  # the whole chunk in one call: the callback evaluates the network
                if self.body_aero is not None:
                    raise ValueError("body_aero: a network backend flies vertical flight only")
                native.set_air(getattr(self, "air_v", np.zeros(3)))
                native.start_network_chunk(rec, self._i)
                k = n
                t = float(d.time)
            else:
                st = self.state()
                if self._i % self.aero_every == 0:
                    self._held = self._loads(st)
                loads = self._held
                k = min(n - i, self.aero_every - self._i % self.aero_every)
                if extras_every and loads.extras:
                    extras += [(j, loads.extras) for j in range(self._i, self._i + k) if j % extras_every == 0]
                native.hold(np.ascontiguousarray(loads.force, float), np.ascontiguousarray(loads.moment, float),
                            float(loads.power))
                native.start_chunk(rec[i:i + k])
                t = st.t
            native.install()
            self._mj_step(k, t, native.callback)
            rows = native.end_chunk()
            if rows != k:
                raise RuntimeError(f"the native callback recorded {rows} of {k} steps (a stage count off)")
            i += k

    def _loads(self, st: FlightState) -> WingLoads:
        """The backend's loads at ``st``; with :attr:`body_aero` also the body's, into its ``xfrc_applied`` row."""
        if self.body_aero is not None:
            self.body_aero.apply(self.d, self.body_id, getattr(self, "air_v", None))
        return self.backend.loads(st)

    def _native_network(self):
        """The backend's network for the callback (:meth:`StepSurrogateBackend.native`), or None: a backend
        without one, or a simulator on the Python callback. Cached per backend."""
        if self._native is None or not hasattr(self.backend, "native"):
            return None
        if self._net_of is not self.backend:
            self._net_of, self._net = self.backend, self.backend.native(self.aero_every)
            self._native.set_network(self._net)
        return self._net

    def _mj_step(self, k: int, t: float, callback) -> None:
        """``mj_step(m, d, nstep=k)`` with ``callback`` as ``mjcb_control``, from step ``self._i`` at time t, then
        ``self._i`` advanced by k and the kinematics brought up to date (mj_kinematics, mj_comPos, mj_comVel) for
        the next :meth:`state`. MuJoCo's instability warnings (:data:`UNSTABLE_WARNINGS`) raise; its other
        messages go to stderr."""
        m, d = self.m, self.d
        before = [d.warning[w].number for w in self._warn_ids]
        _MUJOCO_LOG.held = []
        try:
            with control_callback(callback, self._native.no_timer if self._native is not None else None):
                mujoco.mj_step(m, d, nstep=k)
        finally:
            held, _MUJOCO_LOG.held = _MUJOCO_LOG.held, None
        first = self._i
        self._i += k
        for name, w, n0 in zip(UNSTABLE_WARNINGS, self._warn_ids, before):
            if d.warning[w].number > n0:
                said = f" ({' '.join(held)})" if held else ""
                where = (f"at step {first} (t = {t:.5f} s)" if k == 1
                         else f"in steps {first}-{first + k - 1} (from t = {t:.5f} s)")
                raise FloatingPointError(
                    f"MuJoCo {name[7:]} warning {where}{said}: the state blew up (MuJoCo reset it; index "
                    f"{d.warning[w].lastinfo}), no result")
        for message in held:
            print(f"MuJoCo: {message}", file=sys.stderr)
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_comVel(m, d)

    # ---- diagnostics -------------------------------------------------------------------------------
    def wing_angles(self) -> np.ndarray:
        """Current (6,) wing joint angles [rad]."""
        return self.d.qpos[self.wing_qpos].copy()

    def body_com(self) -> np.ndarray:
        """The body's centre of mass (3,) [m] world at the current qpos (its kinematics computed on a scratch
        copy, so that the data's own derived quantities are left as the last step left them): the position a
        next step's record would start from."""
        scratch = mujoco.MjData(self.m)
        scratch.qpos[:] = self.d.qpos
        mujoco.mj_kinematics(self.m, scratch)
        return scratch.xipos[self.body_id].copy()

    def momentum(self) -> tuple[np.ndarray, np.ndarray]:
        """Total linear momentum [kg m/s] and angular momentum about the system's centre of mass [kg m^2/s],
        world frame."""
        m, d = self.m, self.d
        mujoco.mj_subtreeVel(m, d)
        mass = m.body_subtreemass[self.body_id]
        return mass * d.subtree_linvel[self.body_id].copy(), d.subtree_angmom[self.body_id].copy()


def aero_every_for(backend: AeroBackend, steps_per_cycle: int) -> int:
    """Integrator steps per backend update: its descriptor's update interval
    (:meth:`hawksim.backends.registry.BackendDescriptor.update_interval`; an unregistered backend every step). The
    UVLM updates :data:`FLY_UVLM`'s steps per wingbeat (the largest divisor of ``steps_per_cycle`` not above
    ``steps_per_cycle // FLY_UVLM.steps_per_cycle``), and so does the per-step surrogate ("surrogate"), which learnt
    the UVLM's loads at those updates from flights that held them in between (holding them changes the cycle means by
    ~1 %, docs/free_flight.md: the surrogate must hold them the same way to reproduce the UVLM's orbits); the others
    every step."""
    from hawksim.backends.registry import descriptor_of

    return descriptor_of(backend).update_interval(steps_per_cycle)
