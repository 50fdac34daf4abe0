"""The plant of a flight with a controller: a :class:`hawksim.flight.simulator.Simulator` whose two wings follow their
own Eq. 1 kinematics, changed at phase 0 (or 0.5), in a uniform wind (the one flight loop,
:mod:`hawksim.flight.loop`, drives it; the LQR's command channels live in :mod:`hawksim.control.plant`).

Transition. A change of any parameter at phase 0 would jump the prescribed wing pose or rate (at phase 0 the
sweep is at phi0 - phi_a, the rotation at 90 deg + alpha0 turning at -alpha_a 2 pi f). Beat k therefore blends
the previous beat's kinematics q_o into the new one q_n over the whole beat, both at the beat's local time
tau = t - t_k: q = (1 - s) q_o + s q_n with the quintic smoothstep s(tau / T_k) (s, s', s'' = 0 at tau = 0 and
1, 0, 0 at T_k), and the rates and accelerations by the product rule. The beat lasts T_k = 1 / f_k of the new
kinematics and the integrator step is T_k / steps_per_cycle (so phase 0 always falls on a step). The one-beat
map thus depends on the state, the new command and the previous one: x_{k+1} = P(x_k, u_{k-1}, u_k)
(:mod:`hawksim.control.derivatives`).

With no change (``begin_beat`` never called, or called with the same kinematics) the prescribed motion is
Eq. 1 of the base kinematics, the same floats as :meth:`Simulator.desired` (tested bit-identical).

Wind: ``air_v`` (3,) world [m/s], a uniform air velocity handed to the backend in every ``state()`` (the
quasi-steady, UVLM and per-step surrogate backends take it); zero by default (then the state is the base class's,
unchanged).

The per-step surrogate reads the kinematic parameters and the phase as network inputs, not the wing motion; under
control it gets each wing's blended parameters and the blended phase of the current beat (:meth:`ControlledSimulator.
network_kinematics`, :mod:`hawksim.control.surrogate`). :func:`controlled_plant` builds the plant of any backend.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from hawksim.backends.base import FlightState
from hawksim.flight.simulator import Simulator
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import Kinematics


def saturate(params: np.ndarray, insect: Insect | None = None) -> np.ndarray:
    """A wing's parameters (7,) SI clipped to ``insect``'s kinematic bounds (:meth:`Insect.bounds_si`; default
    :func:`hawksim.insect.folder.default_insect`'s, Table 2)."""
    lo, hi = (default_insect() if insect is None else insect).bounds_si()
    return np.clip(params, lo, hi)


def _smoothstep(x: float) -> tuple[float, float, float]:
    """Quintic s(x) = 10x^3 - 15x^4 + 6x^5 on [0, 1] and its first two derivatives in x."""
    x = min(max(x, 0.0), 1.0)
    x2 = x * x
    return (x2 * x * (10 - 15 * x + 6 * x2), 30 * x2 * (1 - x) ** 2, 60 * x * (1 - x) * (1 - 2 * x))


class ControlledSimulator(Simulator):
    """A Simulator with per-wing kinematics switched at phase 0 (see the module docstring) and a uniform wind.

    ``kin`` (the base class's) is the base kinematics: both wings follow it until :meth:`begin_beat`.
    """

    def __init__(self, model, kin: Kinematics, backend, **kw):
        super().__init__(model, kin, backend, **kw)
        self.air_v = np.zeros(3)
        self._new: tuple[Kinematics, Kinematics] | None = None  # None: both wings on self.kin
        self._old: tuple[Kinematics, Kinematics] | None = None
        self._same = True
        self._t0 = 0.0
        self._phase, self._span = 0.0, 1.0  # wing phase at _t0 [rad]; blend length in periods
        self._T = kin.period

    # ---- commands -------------------------------------------------------------------------------
    def begin_beat(self, left: Kinematics, right: Kinematics, *, phase: float = 0.0, span: float = 1.0) -> None:
        """Start a wingbeat now (call at phase 0, i.e. at t = 0 or right after the previous beat's last step):
        blend from the current kinematics to (left, right) over this beat, whose period is 1 / left.f.

        Half strokes (:mod:`hawksim.control.halfstroke`): ``phase`` [rad] is the wing phase 2 pi f t at which this
        segment starts (0 or pi) and ``span`` the fraction of the new period it lasts (1 or 0.5); the blend runs
        over the segment, span / left.f, and the step stays period / steps_per_cycle, so the segment is
        span x steps_per_cycle steps."""
        if left.f != right.f:
            raise ValueError(f"both wings flap at one frequency, got {left.f} and {right.f} Hz")
        cur = self._new if self._new is not None else (self.kin, self.kin)
        self._old, self._new = cur, (left, right)
        self._same = cur == self._new
        self._t0 = float(self.d.time)
        self._phase = float(phase)
        self._span = float(span)
        self._T = left.period
        self.dt = self._T / self.steps_per_cycle
        self.m.opt.timestep = self.dt
        self._sync_native()

    def set_wings(self, left: Kinematics, right: Kinematics) -> None:
        """Put both wings on (left, right) from t = 0 with no blend (before ``reset``/``set_body_state``): the
        kinematics of the beat before the first one."""
        if left.f != right.f:
            raise ValueError(f"both wings flap at one frequency, got {left.f} and {right.f} Hz")
        self._old = self._new = (left, right)
        self._same = True
        self._t0 = 0.0
        self._phase, self._span = 0.0, 1.0
        self._T = left.period
        self.dt = self._T / self.steps_per_cycle
        self.m.opt.timestep = self.dt
        self._sync_native()

    native_motion = True  # the native callback's mode 1 is :meth:`desired` (hawksim.flight.native)

    def _sync_native(self) -> None:
        """Hand the current blend to the native callback (hawksim.flight.native), if the simulator uses it."""
        if self._native is None or self._new is None:
            return
        row = lambda k: np.array([k.f, k.phi0, k.theta0, k.alpha0, k.phi_a, k.alpha_a])  # noqa: E731
        self._native.set_blend((row(self._old[0]), row(self._old[1])), (row(self._new[0]), row(self._new[1])),
                               t0=self._t0, phase=self._phase, span=self._span, period=self._T, same=self._same,
                               beta_old=(self._old[0].beta, self._old[1].beta),
                               beta_new=(self._new[0].beta, self._new[1].beta))

    @property
    def wing_params(self) -> tuple[Kinematics, Kinematics]:
        """The (left, right) kinematics of the current beat's end."""
        return self._new if self._new is not None else (self.kin, self.kin)

    # ---- prescribed motion ----------------------------------------------------------------------
    def desired(self, t: float):
        if self._new is None:
            return super().desired(t)
        tau = t - self._t0
        out_q, out_qd, out_qdd = [], [], []
        same = self._same
        ph = self._phase
        Tb = self._T if self._span == 1.0 else self._span * self._T  # the blend's length
        s, s1, s2 = _smoothstep(tau / Tb)
        s1, s2 = s1 / Tb, s2 / (Tb * Tb)
        for w in (0, 1):
            kn = self._new[w]
            wt = 2 * math.pi * kn.f * tau if ph == 0.0 else ph + 2 * math.pi * kn.f * tau
            qn, qdn, qddn = kn.eq1(math.cos(wt), math.sin(wt))
            if same or s >= 1.0:
                out_q += qn
                out_qd += qdn
                out_qdd += qddn
                continue
            ko = self._old[w]
            wt = 2 * math.pi * ko.f * tau if ph == 0.0 else ph + 2 * math.pi * ko.f * tau
            qo, qdo, qddo = ko.eq1(math.cos(wt), math.sin(wt))
            for j in range(3):
                dq, dqd = qn[j] - qo[j], qdn[j] - qdo[j]
                out_q.append(qo[j] + s * dq)
                out_qd.append(qdo[j] + s * dqd + s1 * dq)
                out_qdd.append(qddo[j] + s * (qddn[j] - qddo[j]) + 2 * s1 * dqd + s2 * dq)
        return np.array(out_q), np.array(out_qd), np.array(out_qdd)

    def network_kinematics(self, t: float) -> tuple[np.ndarray, float]:
        """The kinematic inputs of a network backend at time t [s]: (params (2, 7) SI, PARAM_NAMES order, left and
        right wing; the wing phase [rad]). Within a blend (module docstring) each wing's parameters are the blend
        (1 - s) p_old + s p_new of the smoothstep s and the phase (1 - s) w_old + s w_new of the two kinematics'
        phases: the motion q = (1 - s) q_old + s q_new is Eq. 1 of the blended parameters exactly for phi0, phi_a,
        theta0, alpha0, alpha_a at one f (Eq. 1 is linear in them) and to first order in a change of f. Before
        any :meth:`begin_beat` or :meth:`set_wings`: the base kinematics and 2 pi f t."""
        if self._new is None:
            p = self.kin.as_array()
            return np.stack([p, p]), 2 * math.pi * self.kin.f * t
        tau = t - self._t0
        ph = self._phase
        kl, kr = self._new
        pn = np.stack([kl.as_array(), kr.as_array()])
        wn = ph + 2 * math.pi * kl.f * tau
        if self._same:
            return pn, wn
        Tb = self._T if self._span == 1.0 else self._span * self._T
        s = _smoothstep(tau / Tb)[0]
        if s >= 1.0:
            return pn, wn
        ol, orr = self._old
        po = np.stack([ol.as_array(), orr.as_array()])
        wo = ph + 2 * math.pi * ol.f * tau
        return (1 - s) * po + s * pn, (1 - s) * wo + s * wn

    # ---- wind -----------------------------------------------------------------------------------
    def state(self) -> FlightState:
        st = super().state()
        if np.any(self.air_v):
            st = replace(st, air_v=np.array(self.air_v, float))
        return st


def controlled_plant(model, kin: Kinematics, aero: str, *, steps_per_cycle: int | None = None,
                     insect: Insect | None = None, far_wake=None, forward_speed: float = 0.0) -> ControlledSimulator:
    """The controlled plant of `hawksim fly --aero NAME` (``aero``: quasi-steady, uvlm or surrogate) at base
    kinematics ``kin``: the backend of :func:`hawksim.flight.orbit.make_orbit_backend` (both wings solved: the
    commands break the symmetry), updated at its flight rate; a backend whose descriptor has a
    ``controlled_factory`` (the per-step surrogate: :class:`hawksim.backends.controlled_step_surrogate.
    ControlledStepSurrogate`) built by it and bound to the plant, so that it reads the commanded kinematics
    (:meth:`ControlledSimulator.network_kinematics`). ``insect``: whose wings the backend flies (default
    :func:`hawksim.insect.folder.default_insect`); ``model`` must be its MJCF. ``far_wake``: the UVLM's prescribed
    far wake (an orbit's :attr:`~hawksim.trim.point.OperatingPoint.far_wake`; None: the whole wake free).
    ``forward_speed`` [m/s] > 0: the body's own loads act (:attr:`hawksim.flight.simulator.Simulator.body_aero`), as
    on the forward orbit's flights."""
    from hawksim.backends.registry import descriptor
    from hawksim.flight.orbit import STEPS_PER_CYCLE, make_orbit_backend
    from hawksim.flight.simulator import aero_every_for

    n = STEPS_PER_CYCLE if steps_per_cycle is None else steps_per_cycle
    bound = descriptor(aero).controlled_factory
    if bound is not None:  # a backend that reads the commanded kinematics (the per-step surrogate's network)
        if insect is not None and insect.morphology != default_insect().morphology:
            raise ValueError(f"insect {insect.name!r}: the {aero} backend's network was trained on the default "
                             "hawkmoth's morphology")
        backend = bound(kin)
    else:
        backend, _ = make_orbit_backend(aero, symmetric=False, insect=insect,
                                        kinematics=kin if far_wake is not None else None, far_wake=far_wake)
    sim = ControlledSimulator(model, kin, backend, steps_per_cycle=n, gravity=True,
                              aero_every=aero_every_for(backend, n))
    if bound is not None:
        backend.bind(sim)
    if forward_speed:
        from hawksim.insect.body_aero import BodyAero

        sim.body_aero = BodyAero.of((default_insect() if insect is None else insect).morphology)
    return sim
