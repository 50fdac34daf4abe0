"""The flight loop's computed torque as a native MuJoCo control callback (issue 21: a compiled loop).

:class:`hawksim.flight.simulator.Simulator` solves the six wing-joint torques at every RK4 stage inside
``mjcb_control`` (the method in that module's docstring). As a Python callback that costs four Python calls
(and a dozen numpy operations each) per step, more than the RK4 step itself. Here the same arithmetic is a numba
``cfunc`` installed as MuJoCo's ``mjcb_control``: MuJoCo calls it from C, and it calls ``mj_fwdActuation``,
``mj_fwdAcceleration`` and ``mj_fullM`` of the loaded ``libmujoco`` through their addresses, so a step makes no
Python call at all and ``mj_step(m, d, nstep)`` can run many steps in one call.

What the callback reads and writes. The callback receives (mjModel*, mjData*). The mjData fields it needs (time,
qpos, qvel, qfrc_smooth, qfrc_applied, xfrc_applied, xpos, xipos, xmat, cvel) are found once per process
(:func:`hawksim.flight.mujoco_abi.layout`: offsets from the wheel's ``mjdata.h``, checked on a probe MjData).
Everything else (the prescribed motion's parameters, the PD gains, scratch space, the held loads, the recorder)
lives in a per-simulator float64 ``ctx`` array (:class:`NativeControl`). The callback's body takes a third
argument, an int64 array of what differs between processes (the ctx address, the offsets, the function addresses),
so numba caches it; the ``mjcb_control`` MuJoCo calls is a two-instruction trampoline that passes this process's
array (:class:`hawksim.flight.mujoco_abi.Trampoline`), compiled by llvmlite in milliseconds. One callback per
process, as ``mjcb_control`` is one global per process.

Prescribed motion. Mode 0: Eq. 1 of one kinematics for both wings (:meth:`Simulator.desired`); mode 1: the
per-wing blend of :class:`hawksim.control.plant.ControlledSimulator` (quintic smoothstep from the previous beat's
kinematics to the new one). The arithmetic is the Python one's, operation for operation, so a flight is
bit-identical with the Python callback (tested, tests/hawksim/test_native.py).

Where it is unavailable (the header or a field check fails, e.g. a future mujoco with another layout) ``layout``
returns None and the simulator keeps the Python callback: slower, same results.

The numba body is compiled once per install (cached like the other kernels).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numba import carray, cfunc, njit, types

from hawksim.flight.mujoco_abi import Trampoline, address, call_md, call_mdx, voidptr, layout
from hawksim.backends.record import HISTORY_ROW, MAX_NATIVE_LAGS, lagged_states
from hawksim.flight.network_kernel import mlp
from hawksim.flight.simulator import prescribed_torque

# ---- ctx layout (float64 slots) ------------------------------------------------------------------------------
C_MODE, C_KP, C_KD, C_CAPTURE = 0, 1, 2, 3
C_TAU = 4            # 6: the torque of the first stage after a capture request
C_P = 10             # 6: mode 0, (f, phi0, theta0, alpha0, phi_a, alpha_a) SI
C_T0, C_PHASE, C_SPAN, C_T, C_SAME = 16, 17, 18, 19, 20   # mode 1: the beat's start, phase, span, period, same
C_NEW, C_OLD = 21, 33  # 12 each: mode 1, left then right (f, phi0, theta0, alpha0, phi_a, alpha_a)
C_Q0, C_V0, C_NV = 45, 46, 47  # first wing qpos index, first wing dof index, nv
C_STAGE = 48         # RK4 stage of the next call, 0..3 (advance: reset to 0 before each mj_step(nstep))
C_APPLY = 49         # 1: at each step's first stage, write the held loads below into xfrc_applied
C_FORCE, C_MOMENT = 50, 56  # 6 each: the held world force and moment about the hinge of (left, right) [N, N m]
C_BODY, C_WING0, C_WING1 = 62, 63, 64  # body ids
C_REC_ADDR, C_REC_ROWS, C_ROW = 65, 66, 67  # the recorder: address of a (rows, REC_WIDTH) float64 array, next row
C_POWER = 68         # the held loads' aerodynamic power [W]
# the per-step surrogate evaluated in the callback (set_network): on, weights' address, members K, inputs, hidden
# width, layers; update every C_EVERY steps counted from step C_I0 of the chunk's first row; 2 pi f; the seven
# kinematic inputs; the air velocity (world, m/s); the mirror signs V, W, F, M (3 each)
C_NET_ON, C_NET_ADDR, C_NET_K, C_NET_IN, C_NET_H, C_NET_L, C_EVERY, C_I0, C_OMEGA_F = range(69, 78)
C_KIN, C_AIR, C_MIRROR = 78, 85, 88
C_NET_PLANT = 100    # 1: the network's kinematic inputs and phase follow the mode-1 blend (the controlled plant)
C_BETA_NEW, C_BETA_OLD = 101, 103  # 2 each (left, right): the stroke-plane angle beta of the blend's kinematics
# a network with history lags: the address of its backend's record (StepSurrogateBackend.history), the number of
# lags, the lags [wingbeats] (MAX_NATIVE_LAGS slots), the period they are counted in [s]
C_HIST_ADDR, C_NLAG, C_LAGS, C_PERIOD = 105, 106, 107, 111
# a network with the wake-age input (its last): the input's saturation [wingbeats] (0: none), the frequency it
# counts wingbeats in [Hz], the address of the backend's launch time (StepSurrogateBackend.launch, one float64 [s];
# -inf: a developed wake)
C_AGE, C_AGE_F, C_LAUNCH_ADDR = 112, 113, 114
C_SCRATCH = 115      # nv^2: the dense mass matrix of the stage (mj_fullM), then N_WORK
N_FIXED = 115
N_WORK = 64          # after the mass matrix: the stage's scratch (blend_desired's motion and its own, and
                     # prescribed_torque's, nv <= 37)

REC_T, REC_POS, REC_R, REC_QVEL, REC_WR, REC_WO, REC_TAU, REC_QD = 0, 1, 4, 13, 19, 37, 43, 49
REC_F, REC_M, REC_PA = 55, 61, 67
REC_WIDTH = 68
"""A recorder row, each step's state at its start: t, the body's centre of mass xipos (3), xmat (9), qvel[:6],
the wings' xmat (2 x 9) and xpos (2 x 3), the step's first-stage wing torques (6), the wing joint rates (6), and the
loads applied over the step: force (2 x 3), moment about the hinges (2 x 3), aerodynamic power."""

MODE_EQ1, MODE_BLEND = 0.0, 1.0


# ---- the prescribed motion, the arithmetic of Kinematics.eq1 and ControlledSimulator.desired --------------------
@njit(cache=True)
def _eq1_into(k, c, s, q, qd, qdd, j0):
    """Eq. 1 of the kinematics k (6,) = (f, phi0, theta0, alpha0, phi_a, alpha_a) at c = cos, s = sin of the phase,
    into q, qd, qdd [j0:j0+3] (the operations of :meth:`Kinematics.eq1`)."""
    w = 2 * math.pi * k[0]
    q[j0], q[j0 + 1], q[j0 + 2] = k[1] - k[4] * c, k[2], math.pi / 2 + k[3] - k[5] * s
    qd[j0], qd[j0 + 1], qd[j0 + 2] = k[4] * w * s, 0.0, -k[5] * w * c
    qdd[j0], qdd[j0 + 1], qdd[j0 + 2] = k[4] * w * w * c, 0.0, k[5] * w * w * s


@njit(cache=True)
def blend_desired(t, ctx, q, qd, qdd, work):
    """Mode 1: the per-wing blend of :meth:`hawksim.control.plant.ControlledSimulator.desired` at time t into
    q, qd, qdd (6,); work: scratch (9,)."""
    tau = t - ctx[C_T0]
    ph = ctx[C_PHASE]
    Tb = ctx[C_T] if ctx[C_SPAN] == 1.0 else ctx[C_SPAN] * ctx[C_T]
    x = min(max(tau / Tb, 0.0), 1.0)
    x2 = x * x
    s = x2 * x * (10 - 15 * x + 6 * x2)
    s1 = 30 * x2 * (1 - x) ** 2
    s2 = 60 * x * (1 - x) * (1 - 2 * x)
    s1, s2 = s1 / Tb, s2 / (Tb * Tb)
    same = ctx[C_SAME] != 0.0
    qo, qdo, qddo = work[0:3], work[3:6], work[6:9]
    for wng in range(2):
        kn = ctx[C_NEW + 6 * wng:C_NEW + 6 * wng + 6]
        wt = 2 * math.pi * kn[0] * tau if ph == 0.0 else ph + 2 * math.pi * kn[0] * tau
        j0 = 3 * wng
        _eq1_into(kn, math.cos(wt), math.sin(wt), q, qd, qdd, j0)
        if same or s >= 1.0:
            continue
        ko = ctx[C_OLD + 6 * wng:C_OLD + 6 * wng + 6]
        wt = 2 * math.pi * ko[0] * tau if ph == 0.0 else ph + 2 * math.pi * ko[0] * tau
        _eq1_into(ko, math.cos(wt), math.sin(wt), qo, qdo, qddo, 0)
        for j in range(3):
            dq, dqd = q[j0 + j] - qo[j], qd[j0 + j] - qdo[j]
            q[j0 + j] = qo[j] + s * dq
            qdd[j0 + j] = qddo[j] + s * (qdd[j0 + j] - qddo[j]) + 2 * s1 * dqd + s2 * dq
            qd[j0 + j] = qdo[j] + s * dqd + s1 * dq


@njit(cache=True)
def _torque(t, ctx, qpos, qvel, M, f0, tau, work):
    """The six torques of one stage into tau (6,) from the dense mass matrix M (nv, nv; overwritten) and the
    generalized force f0 (nv,) without them; work: scratch (:data:`N_WORK`). The arithmetic of the Python callback
    (``hawksim.flight.simulator._computed_torque`` and ``_computed_torque_given``, both ending in
    :func:`hawksim.flight.simulator.prescribed_torque`); nothing is allocated (this runs at every RK4 stage)."""
    q0, v0 = int(ctx[C_Q0]), int(ctx[C_V0])
    kp, kd = ctx[C_KP], ctx[C_KD]
    if ctx[C_MODE] == MODE_EQ1:
        p = ctx[C_P:C_P + 6]
        w = 2.0 * math.pi * p[0]
        c, s = math.cos(w * t), math.sin(w * t)
        # the one-wing expressions of _computed_torque (0.5 pi + alpha0, w = 2.0 pi f)
        a = (p[1] - p[4] * c, p[2], 0.5 * math.pi + p[3] - p[5] * s)
        ad = (p[4] * w * s, 0.0, -p[5] * w * c)
        add = (p[4] * w * w * c, 0.0, p[5] * w * w * s)
        for k in range(6):
            j = k % 3
            tau[k] = add[j] + kp * (a[j] - qpos[q0 + k]) + kd * (ad[j] - qvel[v0 + k])
    else:
        qs, qds, qdds = work[0:6], work[6:12], work[12:18]
        blend_desired(t, ctx, qs, qds, qdds, work[18:27])
        for k in range(6):
            tau[k] = qdds[k] + kp * (qs[k] - qpos[q0 + k]) + kd * (qds[k] - qvel[v0 + k])
    prescribed_torque(M, f0, tau, work[27:])


@njit(cache=True)
def _apply_loads(ctx, xfrc, xpos, xipos):
    """The held loads into xfrc_applied at the wings' centres of mass: force, and the moment about the hinge
    carried to the centre of mass, moment + (hinge - com) x force (the arithmetic of ``Simulator.step``)."""
    for w in range(2):
        b = int(ctx[C_WING0 + w])
        f = ctx[C_FORCE + 3 * w:C_FORCE + 3 * w + 3]
        mo = ctx[C_MOMENT + 3 * w:C_MOMENT + 3 * w + 3]
        a0, a1, a2 = xpos[b, 0] - xipos[b, 0], xpos[b, 1] - xipos[b, 1], xpos[b, 2] - xipos[b, 2]
        xfrc[b, 0], xfrc[b, 1], xfrc[b, 2] = f[0], f[1], f[2]
        xfrc[b, 3] = mo[0] + (a1 * f[2] - a2 * f[1])
        xfrc[b, 4] = mo[1] + (a2 * f[0] - a0 * f[2])
        xfrc[b, 5] = mo[2] + (a0 * f[1] - a1 * f[0])


@njit(cache=True)
def _record(ctx, rec, t, qvel, tau, xpos, xipos, xmat):
    """One recorder row (:data:`REC_WIDTH`) of the step's start."""
    body, v0 = int(ctx[C_BODY]), int(ctx[C_V0])
    rec[REC_T] = t
    for j in range(3):
        rec[REC_POS + j] = xipos[body, j]
    for j in range(9):
        rec[REC_R + j] = xmat[body, j]
    for j in range(6):
        rec[REC_QVEL + j] = qvel[j]
        rec[REC_TAU + j] = tau[j]
        rec[REC_QD + j] = qvel[v0 + j]
    for w in range(2):
        b = int(ctx[C_WING0 + w])
        for j in range(9):
            rec[REC_WR + 9 * w + j] = xmat[b, j]
        for j in range(3):
            rec[REC_WO + 3 * w + j] = xpos[b, j]
    for j in range(6):
        rec[REC_F + j] = ctx[C_FORCE + j]
        rec[REC_M + j] = ctx[C_MOMENT + j]
    rec[REC_PA] = ctx[C_POWER]


@njit(cache=True)
def _plant_inputs(ctx, t, x):
    """The controlled plant's network inputs at time t: each wing's seven parameters (PARAM_NAMES order) into
    x[:, :7] and the returned phase [rad], the blend of :meth:`hawksim.control.plant.ControlledSimulator.
    network_kinematics` (the previous beat's parameters and phase into the new ones by the smoothstep s)."""
    tau = t - ctx[C_T0]
    ph = ctx[C_PHASE]
    wn = ph + 2 * math.pi * ctx[C_NEW] * tau
    Tb = ctx[C_T] if ctx[C_SPAN] == 1.0 else ctx[C_SPAN] * ctx[C_T]
    xs = min(max(tau / Tb, 0.0), 1.0)
    s = xs * xs * xs * (10 - 15 * xs + 6 * xs * xs)
    blend = not (ctx[C_SAME] != 0.0 or s >= 1.0)
    for r in range(2):
        kn, ko = C_NEW + 6 * r, C_OLD + 6 * r
        # (f, beta, phi0, theta0, alpha0, phi_a, alpha_a) from the rows (f, phi0, theta0, alpha0, phi_a, alpha_a)
        new = (ctx[kn], ctx[C_BETA_NEW + r], ctx[kn + 1], ctx[kn + 2], ctx[kn + 3], ctx[kn + 4], ctx[kn + 5])
        old = (ctx[ko], ctx[C_BETA_OLD + r], ctx[ko + 1], ctx[ko + 2], ctx[ko + 3], ctx[ko + 4], ctx[ko + 5])
        for j in range(7):
            x[r, j] = (1 - s) * old[j] + s * new[j] if blend else new[j]
    if not blend:
        return wn
    wo = ph + 2 * math.pi * ctx[C_OLD] * tau
    return (1 - s) * wo + s * wn


@njit(cache=True)
def _surrogate_loads(ctx, t, qvel, xmat, cvel, buf):
    """The per-step surrogate's loads at the step's start into ctx (C_FORCE, C_MOMENT, C_POWER): the operations of
    ``StepSurrogateBackend.loads`` on the body's velocity relative to the air and angular velocity in body axes."""
    body = int(ctx[C_BODY])
    R = xmat[body].reshape((3, 3))
    bw = np.empty(3)
    for i in range(3):
        bw[i] = R[i, 0] * qvel[3] + R[i, 1] * qvel[4] + R[i, 2] * qvel[5]
    v, w = np.empty(3), np.empty(3)
    for i in range(3):
        v[i] = (R[0, i] * (qvel[0] - ctx[C_AIR]) + R[1, i] * (qvel[1] - ctx[C_AIR + 1])
                + R[2, i] * (qvel[2] - ctx[C_AIR + 2]))
        w[i] = R[0, i] * bw[0] + R[1, i] * bw[1] + R[2, i] * bw[2]
    n_in = int(ctx[C_NET_IN])
    x = np.zeros((2, n_in), np.float32)
    ph = ctx[C_OMEGA_F] * t
    if ctx[C_NET_PLANT] != 0.0 and ctx[C_MODE] == MODE_BLEND:
        ph = _plant_inputs(ctx, t, x)
    else:
        for r in range(2):
            for j in range(7):
                x[r, j] = ctx[C_KIN + j]
    for r in range(2):
        x[r, 7] = math.sin(ph)
        x[r, 8] = math.cos(ph)
    for j in range(3):
        x[0, 9 + j], x[0, 12 + j] = v[j], w[j]
        x[1, 9 + j], x[1, 12 + j] = v[j] * ctx[C_MIRROR + j], w[j] * ctx[C_MIRROR + 3 + j]
    nlag = int(ctx[C_NLAG])
    if nlag > 0:  # the history inputs, from the backend's own record (the Python path's function and array)
        ha = int(ctx[C_HIST_ADDR])
        hist = carray(voidptr(ha), 3 + HISTORY_ROW * int(carray(voidptr(ha), 1, np.float64)[0]), np.float64)
        s, lagged = np.empty(6), np.empty((nlag, 6))
        for j in range(3):
            s[j], s[3 + j] = v[j], w[j]
        lagged_states(hist, t, s, ctx[C_LAGS:C_LAGS + nlag], ctx[C_PERIOD], lagged)
        for k in range(nlag):
            for j in range(6):
                x[0, 15 + 6 * k + j] = lagged[k, j]
                x[1, 15 + 6 * k + j] = lagged[k, j] * ctx[C_MIRROR + j]
    if ctx[C_AGE] > 0.0:  # the wake's age: wake_age's arithmetic, at the frequency of the phase input
        age = min(ctx[C_AGE_F] * (t - carray(voidptr(int(ctx[C_LAUNCH_ADDR])), 1, np.float64)[0]), ctx[C_AGE])
        x[0, n_in - 1] = age
        x[1, n_in - 1] = age
    y = mlp(x, buf, int(ctx[C_NET_K]), n_in, int(ctx[C_NET_H]), int(ctx[C_NET_L]))  # NativeNetwork's layout
    power = 0.0
    for wg in range(2):
        WR = xmat[int(ctx[C_WING0 + wg])].reshape((3, 3))
        fw, mw = np.empty(3), np.empty(3)
        for j in range(3):
            fw[j] = np.float64(y[wg, j]) * (ctx[C_MIRROR + 6 + j] if wg == 1 else 1.0)
            mw[j] = np.float64(y[wg, 3 + j]) * (ctx[C_MIRROR + 9 + j] if wg == 1 else 1.0)
        for i in range(3):
            f = WR[i, 0] * fw[0] + WR[i, 1] * fw[1] + WR[i, 2] * fw[2]
            mo = WR[i, 0] * mw[0] + WR[i, 1] * mw[1] + WR[i, 2] * mw[2]
            ctx[C_FORCE + 3 * wg + i] = f
            ctx[C_MOMENT + 3 * wg + i] = mo
    for wg in range(2):
        wid = int(ctx[C_WING0 + wg])
        for j in range(3):
            power += (cvel[wid, j] - bw[j]) * ctx[C_MOMENT + 3 * wg + j]
    ctx[C_POWER] = -power


# the callback's parameters, one int64 array per process (the third argument of _control_impl)
P_CTX, P_TIME, P_QPOS, P_QVEL, P_F0, P_QFRC, P_XFRC, P_XPOS, P_XIPOS, P_XMAT, P_CVEL, P_ACT, P_ACC, P_FULLM = \
    range(14)
N_PARAMS = 14


@cfunc(types.void(types.voidptr, types.voidptr, types.voidptr), cache=True)
def _control_impl(m, d, params):
    """The callback's body; everything that differs between processes (the ctx array's address, the mjData
    offsets, the libmujoco functions' addresses) comes in ``params`` (int64, ``P_*``), so numba caches it."""
    prm = carray(params, N_PARAMS, np.int64)
    da = address(d)
    ca = prm[P_CTX]
    nv = int(carray(voidptr(ca + 8 * C_NV), 1, np.float64)[0])
    ctx = carray(voidptr(ca), N_FIXED + nv * nv + N_WORK, np.float64)
    nq = nv + 1  # a free body (7 qpos, 6 dofs) and hinges
    qpos = carray(voidptr(carray(voidptr(da + prm[P_QPOS]), 1, np.int64)[0]), nq, np.float64)
    qvel = carray(voidptr(carray(voidptr(da + prm[P_QVEL]), 1, np.int64)[0]), nv, np.float64)
    f0 = carray(voidptr(carray(voidptr(da + prm[P_F0]), 1, np.int64)[0]), nv, np.float64)
    qfrc = carray(voidptr(carray(voidptr(da + prm[P_QFRC]), 1, np.int64)[0]), nv, np.float64)
    t = carray(voidptr(da + prm[P_TIME]), 1, np.float64)[0]
    v0 = int(ctx[C_V0])
    nb = int(ctx[C_WING1]) + 1
    stage = int(ctx[C_STAGE])
    ctx[C_STAGE] = (stage + 1) % 4
    if stage == 0 and ctx[C_NET_ON] != 0.0 and (int(ctx[C_I0]) + int(ctx[C_ROW])) % int(ctx[C_EVERY]) == 0:
        xmat = carray(voidptr(carray(voidptr(da + prm[P_XMAT]), 1, np.int64)[0]), (nb, 9), np.float64)
        cvel = carray(voidptr(carray(voidptr(da + prm[P_CVEL]), 1, np.int64)[0]), (nb, 6), np.float64)
        n_buf = int(carray(voidptr(int(ctx[C_NET_ADDR])), 1, np.float64)[0])
        buf = carray(voidptr(int(ctx[C_NET_ADDR]) + 8), n_buf, np.float32)
        _surrogate_loads(ctx, t, qvel, xmat, cvel, buf)
    if stage == 0 and ctx[C_APPLY] != 0.0:
        xfrc = carray(voidptr(carray(voidptr(da + prm[P_XFRC]), 1, np.int64)[0]), (nb, 6), np.float64)
        xpos = carray(voidptr(carray(voidptr(da + prm[P_XPOS]), 1, np.int64)[0]), (nb, 3), np.float64)
        xipos = carray(voidptr(carray(voidptr(da + prm[P_XIPOS]), 1, np.int64)[0]), (nb, 3), np.float64)
        _apply_loads(ctx, xfrc, xpos, xipos)
    for k in range(6):
        qfrc[v0 + k] = 0.0
    call_md(prm[P_ACT], m, d)
    call_md(prm[P_ACC], m, d)
    call_mdx(prm[P_FULLM], m, d, voidptr(ca + 8 * C_SCRATCH))
    M = ctx[C_SCRATCH:C_SCRATCH + nv * nv].reshape((nv, nv))
    tau = qfrc[v0:v0 + 6]
    _torque(t, ctx, qpos, qvel, M, f0, tau, ctx[C_SCRATCH + nv * nv:])
    if stage == 0 and ctx[C_REC_ADDR] != 0.0 and ctx[C_ROW] < ctx[C_REC_ROWS]:
        xpos = carray(voidptr(carray(voidptr(da + prm[P_XPOS]), 1, np.int64)[0]), (nb, 3), np.float64)
        xipos = carray(voidptr(carray(voidptr(da + prm[P_XIPOS]), 1, np.int64)[0]), (nb, 3), np.float64)
        xmat = carray(voidptr(carray(voidptr(da + prm[P_XMAT]), 1, np.int64)[0]), (nb, 9), np.float64)
        row = int(ctx[C_ROW])
        rec = carray(voidptr(int(ctx[C_REC_ADDR]) + 8 * REC_WIDTH * row), REC_WIDTH, np.float64)
        _record(ctx, rec, t, qvel, tau, xpos, xipos, xmat)
        ctx[C_ROW] = row + 1
    if ctx[C_CAPTURE] != 0.0:
        for k in range(6):
            ctx[C_TAU + k] = tau[k]
        ctx[C_CAPTURE] = 0.0


@lru_cache(maxsize=1)
def _callback() -> Trampoline | None:
    """This process's callback (None where :func:`layout` is None)."""
    lay = layout()
    if lay is None:
        return None
    params = np.zeros(N_PARAMS, dtype=np.int64)
    params[[P_TIME, P_QPOS, P_QVEL, P_F0, P_QFRC, P_XFRC, P_XPOS, P_XIPOS, P_XMAT, P_CVEL, P_ACT, P_ACC,
            P_FULLM]] = (lay.time, lay.qpos, lay.qvel, lay.qfrc_smooth, lay.qfrc_applied, lay.xfrc_applied, lay.xpos,
                         lay.xipos, lay.xmat, lay.cvel, lay.fwd_actuation, lay.fwd_acceleration, lay.full_m)
    return Trampoline(_control_impl.address, params)


class NativeControl:
    """One simulator's ctx array and the compiled callback (None where unavailable: use the Python callback).

    Args:
        nq, nv: the model's sizes (a free body first: nq = nv + 1).
        q0, v0: the first wing joint's qpos and dof index (the six wing joints contiguous).
        kp, kd: the PD gains [1/s^2], [1/s].
    """

    def __init__(self, nq: int, nv: int, q0: int, v0: int, kp: float, kd: float, body: int, wings):
        if nq != nv + 1:
            raise ValueError("the native callback needs a model of one free body and hinges (nq = nv + 1)")
        if not body < wings[0] < wings[1]:
            raise ValueError(f"the native callback needs the body before the wings, got {body}, {tuple(wings)}")
        if v0 != nv - 6 or nv + 27 > N_WORK:
            raise ValueError(f"the native callback needs the six wing dofs last and nv <= {N_WORK - 27}, got v0 = {v0}"
                             f" of nv = {nv}")
        self.ctx = np.zeros(N_FIXED + nv * nv + N_WORK)
        self.ctx[C_Q0], self.ctx[C_V0], self.ctx[C_NV] = q0, v0, nv
        self.ctx[C_BODY], self.ctx[C_WING0], self.ctx[C_WING1] = body, wings[0], wings[1]
        self._net = None
        self.ctx[C_KP], self.ctx[C_KD] = kp, kd
        self._tramp = _callback()
        self.callback = self._tramp.callback if self._tramp is not None else None
        self.no_timer = self._tramp.no_timer if self._tramp is not None else None
        """MuJoCo's timers switched off for the flight's steps (:attr:`Trampoline.no_timer`)."""
        """The ctypes function pointer for ``mujoco.set_mjcb_control`` (None: unavailable)."""

    def __deepcopy__(self, memo):
        """A copy for a copied simulator (:class:`hawksim.control.derivatives.Snapshot`): its own ctx, the
        process's trampoline shared, and the network's buffer and history record the copy's (deep-copied with the
        simulator's backend through ``memo``), their addresses written into the new ctx."""
        import copy

        new = copy.copy(self)
        memo[id(self)] = new
        new.ctx = self.ctx.copy()
        new.ctx[C_REC_ADDR] = new.ctx[C_REC_ROWS] = 0.0
        new._net = copy.deepcopy(self._net, memo)
        if new._net is not None:
            new.set_network(new._net)
        return new

    @property
    def available(self) -> bool:
        return self.callback is not None

    def set_eq1(self, p: np.ndarray) -> None:
        """Mode 0: both wings on Eq. 1 of p = (f, phi0, theta0, alpha0, phi_a, alpha_a)."""
        self.ctx[C_MODE] = MODE_EQ1
        self.ctx[C_P:C_P + 6] = p

    def set_blend(self, old: tuple[np.ndarray, np.ndarray], new: tuple[np.ndarray, np.ndarray], *, t0: float,
                  phase: float, span: float, period: float, same: bool, beta_old=(0.0, 0.0),
                  beta_new=(0.0, 0.0)) -> None:
        """Mode 1: the blend of ControlledSimulator (old, new: (left, right) parameter rows as in set_eq1; the
        stroke-plane angles beta [rad] of each, which the prescribed motion does not use but a network reads)."""
        c = self.ctx
        c[C_MODE] = MODE_BLEND
        c[C_BETA_NEW:C_BETA_NEW + 2], c[C_BETA_OLD:C_BETA_OLD + 2] = beta_new, beta_old
        c[C_NEW:C_NEW + 6], c[C_NEW + 6:C_NEW + 12] = new
        c[C_OLD:C_OLD + 6], c[C_OLD + 6:C_OLD + 12] = old
        c[C_T0], c[C_PHASE], c[C_SPAN], c[C_T], c[C_SAME] = t0, phase, span, period, float(same)

    def capture(self) -> None:
        """Ask for the next stage's torque (the step's first stage) in :attr:`tau`; the next call is a first stage."""
        self.ctx[C_CAPTURE] = 1.0
        self.ctx[C_STAGE] = 0.0

    @property
    def tau(self) -> np.ndarray:
        return self.ctx[C_TAU:C_TAU + 6]

    def hold(self, force: np.ndarray, moment: np.ndarray, power: float) -> None:
        """Apply these loads (2, 3) (world force [N], moment about each hinge [N m]) at every step's start (and
        record them with their power [W])."""
        c = self.ctx
        c[C_FORCE:C_FORCE + 6] = force.ravel()
        c[C_MOMENT:C_MOMENT + 6] = moment.ravel()
        c[C_POWER] = power
        c[C_APPLY] = 1.0

    def set_network(self, net) -> None:
        """Evaluate the per-step surrogate ``net`` (a :class:`hawksim.backends.step_surrogate.NativeNetwork`, by
        its :func:`mlp`) in the callback (None: the loads come from :meth:`hold`);
        the simulator keeps ``net`` (its buffer, whose address the callback reads) alive with this object."""
        c = self.ctx
        self._net = net
        if net is None:
            c[C_NET_ON] = 0.0
            return
        c[C_NET_ADDR] = float(net.buffer.ctypes.data)
        c[C_NET_K], c[C_NET_IN], c[C_NET_H], c[C_NET_L] = net.members, net.n_in, net.hidden, net.layers
        c[C_EVERY], c[C_OMEGA_F] = net.every, net.omega_f
        c[C_KIN:C_KIN + 7] = net.kinematics
        c[C_MIRROR:C_MIRROR + 12] = net.mirrors
        c[C_NET_PLANT] = float(net.plant_kinematics)
        nlag = len(net.lags)
        if nlag > MAX_NATIVE_LAGS or (nlag and net.history is None):
            raise ValueError(f"the native callback evaluates up to {MAX_NATIVE_LAGS} history lags of a network with "
                             f"its record, got {tuple(net.lags)}")
        c[C_NLAG] = nlag
        c[C_LAGS:C_LAGS + nlag] = net.lags
        c[C_HIST_ADDR] = float(net.history.ctypes.data) if nlag else 0.0
        c[C_PERIOD] = net.period
        if net.age_beats > 0 and net.launch is None:
            raise ValueError("a network with the wake-age input needs its backend's launch time (launch)")
        c[C_AGE], c[C_AGE_F] = net.age_beats, net.age_frequency
        c[C_LAUNCH_ADDR] = float(net.launch.ctypes.data) if net.age_beats > 0 else 0.0
        c[C_NET_ON] = 1.0

    def set_air(self, air_v) -> None:
        """The uniform air velocity (world, m/s) the callback's surrogate sees."""
        self.ctx[C_AIR:C_AIR + 3] = air_v

    def start_network_chunk(self, rec: np.ndarray, first_step: int) -> None:
        """As :meth:`start_chunk`, the loads from the network every ``every`` steps counted from step 0 (this
        chunk's first row is step ``first_step`` since the reset)."""
        self.start_chunk(rec)
        self.ctx[C_I0] = first_step
        self.ctx[C_APPLY] = 1.0

    def held(self) -> tuple[np.ndarray, np.ndarray, float]:
        """The loads held now: force, moment (2, 3) and power."""
        c = self.ctx
        return c[C_FORCE:C_FORCE + 6].reshape(2, 3).copy(), c[C_MOMENT:C_MOMENT + 6].reshape(2, 3).copy(), float(
            c[C_POWER])

    def start_chunk(self, rec: np.ndarray) -> None:
        """Before ``mj_step(m, d, nstep=len(rec))``: record each step's start into rec (n, REC_WIDTH), a C-contiguous
        float64 array that must live until :meth:`end_chunk`."""
        c = self.ctx
        c[C_STAGE] = 0.0
        c[C_REC_ADDR], c[C_REC_ROWS], c[C_ROW] = float(rec.ctypes.data), float(len(rec)), 0.0

    def end_chunk(self) -> int:
        """After the chunk: the rows recorded (the caller checks them against the steps taken); recording and
        applying stop."""
        c = self.ctx
        rows, stage = int(c[C_ROW]), int(c[C_STAGE])
        c[C_REC_ADDR] = c[C_REC_ROWS] = c[C_ROW] = 0.0
        c[C_APPLY] = 0.0
        return rows if stage == 0 else -1

    def install(self) -> None:
        """Point the callback at this simulator's ctx (call before each mj_step while the callback is set)."""
        self._tramp.params[P_CTX] = self.ctx.ctypes.data
