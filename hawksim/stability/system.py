"""Cycle-averaged flight dynamics: nondimensionalisation (paper Eq. 8), A matrices (Eqs. 11-12) and modes.

Axes: stability axes (docs/conventions.md; Etkin 1972): x forward horizontal, y right, z down at equilibrium; the ascent
at speed V has w_e = -V. Forward flight (issue 51, :mod:`hawksim.condition`): the same axes, x horizontal along the
heading (for level flight, V = 0, x along the flight velocity: Etkin's stability axes); the equilibrium velocity is
(u_e, 0, w_e) = (U, 0, -V), and the reference speed of Eq. 8 stays the wing's U_ref = 2 phi_a f r2 at every
condition (the flight speed enters as u_e+ = U / U_ref and w_e+ = -V / U_ref; at U = 0 this is the paper's,
unchanged). u_e adds the Coriolis terms of Etkin's body-axes equations: dw' += u_e dq (Z_q / m + u_e) and
dv' -= u_e dr (Y_r / m - u_e); gravity's terms are those of Theta_e = 0 (level axes).
Nondimensional variables follow Eq. 8 literally: U = 2 phi_a f r2 (r2 dimensional),
T = 1/f, S_t = 2 S, cbar the mean chord, rho the air density:

    m+ = m / (0.5 rho U S_t T),   g+ = g T / U,   I+ = I / (0.5 rho U^2 S_t cbar T^2),   w_e+ = w_e / U,
    X+ = X / (0.5 rho U^2 S_t),   M+ = M / (0.5 rho U^2 S_t cbar),   u+ = u / U,   q+ = q T,   t+ = t / T.

Longitudinal state (du+, dw+, dq+, dTheta), Eq. 11. Lateral state (dv+, dp+, dr+, dPhi): the printed Eq. 12 has
typos (a misplaced w_e in the denominator of Y_p / m, I_z for I_xz, a missing N_r); we use Etkin's standard
lateral form for Theta_e = 0 and U_e = 0:

    dv'  = Y_v/m dv + (Y_p/m + w_e) dp + Y_r/m dr + g dPhi
    dp'  = (I_z L' + I_xz N') / (I_x I_z - I_xz^2),   dr' = (I_xz L' + I_x N') / (I_x I_z - I_xz^2)
    dPhi' = dp,     with L' = L_v dv + L_p dp + L_r dr and N' likewise,

the paper's last state (written dPsi) being the bank angle that gravity acts through.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hawksim.insect.kinematics import Kinematics, reference_speed
from hawksim.insect.folder import default_insect
from hawksim.insect.morphology import RHO_AIR, G, Morphology

LONG_DERIVATIVES = ("Xu", "Xw", "Xq", "Zu", "Zw", "Zq", "Mu", "Mw", "Mq")
LAT_DERIVATIVES = ("Yv", "Yp", "Yr", "Lv", "Lp", "Lr", "Nv", "Np", "Nr")
MODE_KINDS = ("oscillatory", "subsidence", "divergence")
REAL_TOL = 1e-9
"""|Im| below this (relative to |lambda|) counts as a real eigenvalue."""


@dataclass(frozen=True)
class Scales:
    """Reference quantities of Eq. 8 (SI): U [m/s], T [s], S_t [m^2], cbar [m], rho [kg/m^3]."""

    U: float
    T: float
    S_t: float
    cbar: float
    rho: float

    @classmethod
    def of(cls, kin: Kinematics, morph: Morphology | None = None, rho: float = RHO_AIR) -> Scales:
        """The scales of ``kin`` flown by ``morph`` (default the default insect's morphology)."""
        morph = default_insect().morphology if morph is None else morph
        return cls(U=reference_speed(kin, morph), T=kin.period, S_t=2 * morph.wing_area, cbar=morph.cbar, rho=rho)

    @property
    def force(self) -> float:
        """0.5 rho U^2 S_t [N]."""
        return 0.5 * self.rho * self.U**2 * self.S_t

    @property
    def moment(self) -> float:
        """0.5 rho U^2 S_t cbar [N m]."""
        return self.force * self.cbar

    def mass(self, m: float) -> float:
        return m / (0.5 * self.rho * self.U * self.S_t * self.T)

    def inertia(self, I: float) -> float:
        return I / (0.5 * self.rho * self.U**2 * self.S_t * self.cbar * self.T**2)

    def derivative(self, name: str, value: float) -> float:
        """Nondimensionalise a dimensional derivative d(force or moment)/d(velocity or rate), e.g. 'Mq'."""
        num = self.moment if name[0] in "LMN" else self.force
        den = 1.0 / self.U if name[1] in "uvw" else self.T
        return value / (num * den)


@dataclass(frozen=True)
class MassProperties:
    """Mass [kg] and inertia about the centre of mass in stability axes [kg m^2] (Ix, Iy, Iz, Ixz = +int xz dm,
    Etkin's sign); body_cg (3,) [m]: the body's own centre of mass relative to the system's (stability axes), the
    point the derivative runs take their moments and rotations about (:func:`about_centre_of_mass`)."""

    m: float
    Ix: float
    Iy: float
    Iz: float
    Ixz: float
    body_cg: tuple[float, float, float] = (0.0, 0.0, 0.0)


def about_centre_of_mass(derivs: dict[str, float], body_cg) -> dict[str, float]:
    """The 18 dimensional derivatives (stability axes, SI) of runs that rotate the body about, and take moments
    about, the body's own centre of mass O, moved to the system's centre of mass P, where the inertia is
    (issue 22: one reference point), by rigid-body kinematics to first order. a = O - P = ``body_cg``:

    - a rotation omega about P moves O at omega x a: F_q += a_z F_u - a_x F_w, F_p -= a_z F_v, F_r += a_x F_v for
      every force and moment F (e_y x a = (a_z, 0, -a_x), e_x x a = (0, -a_z, 0), e_z x a = (0, a_x, 0));
    - moments about P are M_P = M_O + a x F: M += a_z X - a_x Z, L -= a_z Y, N += a_x Y, per disturbance.

    a_y must be 0 (a left/right symmetric insect): otherwise the two systems would couple."""
    ax, ay, az = (float(c) for c in body_cg)
    if abs(ay) > 1e-9:
        raise ValueError(f"body_cg must lie in the plane of symmetry (a_y = 0), got a_y = {ay:g} m")
    d = dict(derivs)
    for F in "XZM":
        d[F + "q"] = derivs[F + "q"] + az * derivs[F + "u"] - ax * derivs[F + "w"]
    for F in "YLN":
        d[F + "p"] = derivs[F + "p"] - az * derivs[F + "v"]
        d[F + "r"] = derivs[F + "r"] + ax * derivs[F + "v"]
    for v in "uwq":
        d["M" + v] += az * d["X" + v] - ax * d["Z" + v]
    for v in "vpr":
        d["L" + v] -= az * d["Y" + v]
        d["N" + v] += ax * d["Y" + v]
    return d


def a_long(d: dict[str, float], m: float, Iy: float, g: float, w_e: float, u_e: float = 0.0) -> np.ndarray:
    """A_long+ of Eq. 11 from nondimensional derivatives d, m+, Iy+, g+ and w_e+ (4, 4); ``u_e``: u_e+ = U / U_ref of
    forward flight (the module docstring), which adds to the (w, q) entry (Etkin: Z_q / m + u_e)."""
    return np.array([
        [d["Xu"] / m, d["Xw"] / m, d["Xq"] / m - w_e, -g],
        [d["Zu"] / m, d["Zw"] / m, d["Zq"] / m + u_e if u_e else d["Zq"] / m, 0.0],
        [d["Mu"] / Iy, d["Mw"] / Iy, d["Mq"] / Iy, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ])


def a_lat(d: dict[str, float], m: float, Ix: float, Iz: float, Ixz: float, g: float, w_e: float,
          u_e: float = 0.0) -> np.ndarray:
    """A_lat+ (Etkin's form, see the module docstring) from nondimensional quantities (4, 4); ``u_e``: u_e+ of
    forward flight, which subtracts from the (v, r) entry (Etkin: Y_r / m - u_e)."""
    den = Ix * Iz - Ixz**2
    L = np.array([d["Lv"], d["Lp"], d["Lr"]])
    N = np.array([d["Nv"], d["Np"], d["Nr"]])
    return np.array([
        [d["Yv"] / m, d["Yp"] / m + w_e, d["Yr"] / m - u_e if u_e else d["Yr"] / m, g],
        [*((Iz * L + Ixz * N) / den), 0.0],
        [*((Ixz * L + Ix * N) / den), 0.0],
        [0.0, 1.0, 0.0, 0.0],
    ])


@dataclass(frozen=True)
class Mode:
    eigenvalue: complex
    kind: str
    stable: bool
    eigenvector: np.ndarray


def classify(eigenvalue: complex) -> tuple[str, bool]:
    """('oscillatory' | 'subsidence' | 'divergence', stable) of one eigenvalue."""
    lam = complex(eigenvalue)
    if abs(lam.imag) > REAL_TOL * max(abs(lam), 1e-300):
        return "oscillatory", lam.real < 0
    return ("subsidence", True) if lam.real < 0 else ("divergence", False)


def modes(A: np.ndarray) -> list[Mode]:
    """Eigen-decomposition of A: one Mode per eigenvalue, sorted by real part (complex pairs adjacent)."""
    w, V = np.linalg.eig(A)
    order = np.lexsort((-w.imag, w.real))
    out = []
    for i in order:
        kind, stable = classify(w[i])
        out.append(Mode(complex(w[i]), kind, stable, V[:, i]))
    return out


def modes_json(A: np.ndarray) -> dict:
    """The CLI contract's block for one A matrix (without derivatives)."""
    ms = modes(A)
    return {
        "matrix": A.tolist(),
        "eigenvalues": [[m.eigenvalue.real, m.eigenvalue.imag] for m in ms],
        "modes": [{"eigenvalue": [m.eigenvalue.real, m.eigenvalue.imag], "kind": m.kind, "stable": m.stable,
                   "eigenvector_abs": np.abs(m.eigenvector).tolist()} for m in ms],
    }


def nondimensional_system(kin: Kinematics, speed: float, derivs_dim: dict[str, float], mp: MassProperties,
                          morph: Morphology | None = None, g: float = G, forward_speed: float = 0.0
                          ) -> tuple[dict, np.ndarray, np.ndarray, dict]:
    """(nondimensional derivatives, A_long+, A_lat+, scalars) from dimensional derivatives in stability axes about
    the body's centre of mass (what the derivative runs give), moved to the system's (:func:`about_centre_of_mass`,
    ``mp.body_cg``) where ``mp``'s inertia is (its mass and inertia are the insect's: :func:`hawksim.stability.
    derivatives.mass_properties` of its MJCF). ``morph``: the insect's morphology, the wing of Eq. 8's scales
    (default the default insect's). ``forward_speed`` U [m/s]: the equilibrium's u_e+ = U / U_ref (the scalars
    carry ``u_e_plus`` where U > 0); the reference speed stays the wing's (module docstring)."""
    sc = Scales.of(kin, morph)
    d = {k: sc.derivative(k, v) for k, v in about_centre_of_mass(derivs_dim, mp.body_cg).items()}
    m = sc.mass(mp.m)
    Ix, Iy, Iz, Ixz = (sc.inertia(v) for v in (mp.Ix, mp.Iy, mp.Iz, mp.Ixz))
    g_p = g * sc.T / sc.U
    w_e = -speed / sc.U
    u_e = forward_speed / sc.U if forward_speed else 0.0
    scalars = {"m_plus": m, "Ix_plus": Ix, "Iy_plus": Iy, "Iz_plus": Iz, "Ixz_plus": Ixz, "g_plus": g_p,
               "w_e_plus": w_e, "U": sc.U, "T": sc.T} | ({"u_e_plus": u_e} if u_e else {})
    return d, a_long(d, m, Iy, g_p, w_e, u_e), a_lat(d, m, Ix, Iz, Ixz, g_p, w_e, u_e), scalars
