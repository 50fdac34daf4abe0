"""Quasi-steady blade-element aerodynamics of a flapping wing.

Per spanwise strip (blade element) of a rigid flat wing, three contributions (all forces in the WORLD frame):

* translational lift and drag with the empirical coefficients of Dickinson, Lehmann & Sane (1999),
  Science 284:1954, fitted on a dynamically scaled *Drosophila* wing:
  C_L(a) = 0.225 + 1.58 sin(2.13 a - 7.20 deg), C_D(a) = 1.92 - 1.55 cos(2.04 a - 9.82 deg), a in degrees;
  centre of pressure x_cp / c = 0.82 a / 180 deg + 0.05 behind the leading edge (same source);
* rotational circulation (Sane & Dickinson 2002, J. Exp. Biol. 205:1087), the theoretical coefficient
  C_rot = pi (3/4 - x0) for a rotation axis at x0 chords behind the leading edge: a normal force
  dF = -pi rho |U_t| c w_34 dr n, with w_34 the normal velocity of the 3/4-chord point due to the wing's
  pitch rotation about its axis; it opposes that velocity (Kramer effect), applied at the centre of pressure;
* added mass of a flat plate (Sane & Dickinson 2001, J. Exp. Biol. 204:2607; Sedov): dF = -rho pi c^2 / 4
  dv_n/dt dr n, v_n the normal velocity of the mid-chord relative to the air, applied at mid-chord. The time
  derivative is the backward difference over the flight-loop step (the state of the previous call is kept
  by the caller and passed back).

Velocities are those of the wing relative to the local air and include the body's motion, since the wing
frame's velocity (origin and angular velocity) is given in the world frame. The spanwise velocity component is
discarded (blade-element assumption); the angle of attack a in [0, 90 deg] is the angle between the chordwise
velocity and the chord line, folded so that the wing may move leading or trailing edge first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

DEG = np.pi / 180.0


@dataclass(frozen=True)
class BladeElements:
    """Strips of one wing, wing frame (x toward the leading edge, y along the span, z = x cross y).

    Attributes (all shape (n,)): y: strip centres along the span [m] (negative for a mirrored right wing);
    dy: strip widths [m]; x_le, chord: leading-edge x and local chord [m]. The rotation axis is the wing-frame
    y axis (x = 0), so x0 = x_le / chord.
    """

    y: np.ndarray
    dy: np.ndarray
    x_le: np.ndarray
    chord: np.ndarray

    @classmethod
    def from_planform(cls, span: float, chord_fn, x_le_fn, n: int = 20, side: float = 1.0) -> BladeElements:
        """n equal strips over [0, span]; chord_fn, x_le_fn map ``|y|`` [m] to chord and leading-edge x [m].
        side = +1 for a left wing, -1 for its mirror image (strips at negative y)."""
        edges = np.linspace(0.0, span, n + 1)
        y = 0.5 * (edges[1:] + edges[:-1])
        return cls(y=side * y, dy=np.diff(edges), x_le=np.asarray(x_le_fn(y), float),
                    chord=np.asarray(chord_fn(y), float))

    @property
    def area(self) -> float:
        return float((self.chord * self.dy).sum())


@dataclass(frozen=True)
class QuasiSteadyConfig:
    """Switches and constants. rho: air density [kg/m^3]."""

    rho: float = 1.225
    translational: bool = True
    rotational: bool = True
    added_mass: bool = True


@njit(cache=True)
def lift_coefficient(a_deg):
    """Dickinson et al. (1999) C_L at angle of attack a [deg]."""
    return 0.225 + 1.58 * np.sin((2.13 * a_deg - 7.20) * DEG)


@njit(cache=True)
def drag_coefficient(a_deg):
    """Dickinson et al. (1999) C_D at angle of attack a [deg]."""
    return 1.92 - 1.55 * np.cos((2.04 * a_deg - 9.82) * DEG)


@dataclass(frozen=True)
class WingResultant:
    """Resultant quasi-steady load on one wing (world frame).

    force (3,) [N]; moment (3,) about the wing-frame origin [N m]; power [W] the wing spends on the air,
    P = -sum F_i . (v_i - v_c(p_i)), v_c the velocity of the carrier rigid motion (the body) at p_i;
    vn_mid (n,) the strips' mid-chord normal velocity [m/s], to pass back at the next call.
    """

    force: np.ndarray
    moment: np.ndarray
    power: float
    vn_mid: np.ndarray


def wing_loads(el: BladeElements, R: np.ndarray, origin: np.ndarray, v_origin: np.ndarray, omega: np.ndarray,
               v_air: np.ndarray, vn_mid_prev: np.ndarray | None, dt: float,
               carrier: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
               cfg: QuasiSteadyConfig = QuasiSteadyConfig()) -> WingResultant:
    """Quasi-steady loads on one wing.

    Args:
        el: the wing's strips. R (3, 3): wing frame -> world. origin (3,): wing-frame origin in world [m].
        v_origin (3,): its velocity [m/s]; omega (3,): wing angular velocity [rad/s] (world).
        v_air (3,): air velocity [m/s] (world). vn_mid_prev (n,) or None: ``vn_mid`` of the previous call
        (None: no added-mass force at this call). dt: time since that call [s].
        carrier: (v (3,), omega (3,), point (3,)) rigid motion the power is measured relative to (default:
        none, i.e. power in the world frame).
    """
    if carrier is None:
        carrier = (np.zeros(3), np.zeros(3), np.zeros(3))
    has_prev = vn_mid_prev is not None and dt > 0
    prev = np.asarray(vn_mid_prev, float) if has_prev else np.zeros_like(el.y)
    out = np.zeros(7)
    vn = np.empty_like(el.y)
    _wing_kernel(el.y, el.dy, el.x_le, el.chord, np.ascontiguousarray(R, dtype=float),
                 np.asarray(origin, float), np.asarray(v_origin, float), np.asarray(omega, float),
                 np.asarray(v_air, float), prev, has_prev, float(dt),
                 np.asarray(carrier[0], float), np.asarray(carrier[1], float), np.asarray(carrier[2], float),
                 cfg.rho, cfg.translational, cfg.rotational, cfg.added_mass, out, vn)
    return WingResultant(force=out[:3].copy(), moment=out[3:6].copy(), power=float(out[6]), vn_mid=vn)


@njit(cache=True, inline="always")
def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(cache=True, inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, inline="always")
def _axpy(s, a, b):
    """s * a + b on 3-tuples."""
    return (s * a[0] + b[0], s * a[1] + b[1], s * a[2] + b[2])


@njit(cache=True)
def _wing_kernel(y, dy, x_le, chord, R, o, vo, w, v_air, vn_prev, has_prev, dt, cv, cw, cp,
                 rho, trans, rot, am, out, vn_out):
    """Scalar loop over strips (3-tuples keep everything on the stack). Fills out = (F, M about o, P)."""
    e_c = (R[0, 0], R[1, 0], R[2, 0])
    e_s = (R[0, 1], R[1, 1], R[2, 1])
    n = (R[0, 2], R[1, 2], R[2, 2])
    W = (w[0], w[1], w[2])
    Vo = (vo[0] - v_air[0], vo[1] - v_air[1], vo[2] - v_air[2])  # origin velocity relative to the air
    Vc = (vo[0] - cv[0], vo[1] - cv[1], vo[2] - cv[2])  # origin velocity relative to the carrier at o
    CW = (w[0] - cw[0], w[1] - cw[1], w[2] - cw[2])
    oc = (o[0] - cp[0], o[1] - cp[1], o[2] - cp[2])
    Vc = _axpy(-1.0, _cross((cw[0], cw[1], cw[2]), oc), Vc)
    out[:] = 0.0
    w_pitch = _dot(W, e_s)
    for i in range(y.size):
        c = chord[i]
        r_axis = (y[i] * e_s[0], y[i] * e_s[1], y[i] * e_s[2])  # axis point relative to o
        U = _axpy(1.0, _cross(W, r_axis), Vo)
        U = _axpy(-_dot(U, e_s), e_s, U)
        speed = np.sqrt(_dot(U, U))
        F = (0.0, 0.0, 0.0)
        x_app = x_le[i] - 0.5 * c
        if speed > 1e-12:
            u = (U[0] / speed, U[1] / speed, U[2] / speed)
            un, uc = _dot(u, n), _dot(u, e_c)
            a_deg = np.degrees(np.arctan2(abs(un), abs(uc)))
            e_l = _cross(e_s, u)
            if _dot(e_l, n) * (-un) < 0:
                e_l = (-e_l[0], -e_l[1], -e_l[2])
            q = 0.5 * rho * speed * speed * c * dy[i]
            frac = 0.82 * a_deg / 180.0 + 0.05
            if uc >= 0:  # leading edge first
                x_app, x34 = x_le[i] - frac * c, x_le[i] - 0.75 * c
            else:
                x_app, x34 = x_le[i] - c + frac * c, x_le[i] - 0.25 * c
            if trans:
                F = _axpy(q * lift_coefficient(a_deg), e_l, _axpy(-q * drag_coefficient(a_deg), u, F))
            if rot:
                # normal velocity of the aerodynamic 3/4-chord point from pitch rotation: -w_pitch * x34
                F = _axpy(-np.pi * rho * speed * c * (-w_pitch * x34) * dy[i], n, F)
        r_app = _axpy(x_app, e_c, r_axis)
        r_mid = _axpy(x_le[i] - 0.5 * c, e_c, r_axis)
        vn_out[i] = _dot(_axpy(1.0, _cross(W, r_mid), Vo), n)
        Fa = (0.0, 0.0, 0.0)
        if am and has_prev:
            Fa = _axpy(-rho * np.pi * c * c / 4.0 * (vn_out[i] - vn_prev[i]) / dt * dy[i], n, Fa)
        M = _axpy(1.0, _cross(r_app, F), _cross(r_mid, Fa))
        for k in range(3):
            out[k] += F[k] + Fa[k]
            out[3 + k] += M[k]
        # velocity relative to the carrier: Vc + (w - cw) x r
        out[6] -= _dot(F, _axpy(1.0, _cross(CW, r_app), Vc)) + _dot(Fa, _axpy(1.0, _cross(CW, r_mid), Vc))
