"""Harmonic wing kinematics of the paper's Eq. 1, the Table 2 bounds, and wing-frame orientations.

Angles (all radians inside the core):

* sweep phi(t) = phi_0 - phi_a cos(2 pi f t)   (Eq. 1 as printed: phi_a sin(2 pi f t + 3 pi / 2) + phi_0),
  positive toward the head; the downstroke (forward sweep) occupies the first half of each cycle;
* elevation theta(t) = theta_0, positive with the wing tip above the stroke plane;
* rotation alpha(t) = pi/2 + alpha_0 - alpha_a sin(2 pi f t).

Reading of the rotation angle (docs/conventions.md). alpha is the pitch of the chord out of the stroke plane, leading
edge up: alpha = 0 lays the wing flat in the stroke plane with the leading edge forward, alpha = 90 deg stands
it vertical. The printed Eq. 1 uses the phase 3 pi / 2 for alpha too, which puts alpha's extremes at stroke
reversal and alpha = 90 deg at mid-stroke: a vertical wing with near-zero lift at mid-stroke, contradicting
the paper's own discussion (smaller alpha_a -> larger angle of attack -> more drag, Sec. 4.2). We therefore
shift the rotation by a quarter period: alpha = 90 deg at stroke reversal, extremes at mid-stroke, and the
geometric angle of attack at mid-stroke is 90 deg - alpha_a (+/- alpha_0) on both half strokes.
``tests/hawksim/test_kinematics.py`` checks this.

Frames. The stroke-plane frame S is fixed to the body, rotated about body y by chi + beta = 60 deg
(``STROKE_PLANE_TO_BODY``): R_body_S = Ry(60 deg), so that with the body pitched nose up by chi = 60 deg - beta
the stroke plane is inclined by beta to the horizontal (its forward edge down for beta > 0).
Left wing: R_S_wing = Rz(-phi) Rx(theta) Ry(-alpha) (intrinsic sweep, elevation, rotation), wing frame x toward
the leading edge, y along the span, z = x cross y. Right wing: the mirror image through the body x-z plane,
R = M R_left M with M = diag(1, -1, 1), i.e. Rz(phi) Rx(-theta) Ry(-alpha); its geometry is the left wing's
with y -> -y.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from hawksim.frames import rot_x, rot_y, rot_z
from hawksim.insect.morphology import HAWKMOTH, STROKE_PLANE_TO_BODY, Morphology

PARAM_NAMES = ("f", "beta", "phi0", "theta0", "alpha0", "phi_a", "alpha_a")
"""The seven kinematic parameters, in the paper's order (the ANN's input order)."""

ANGLE_PARAMS = frozenset(PARAM_NAMES[1:])

TABLE2_BOUNDS_DEG = {
    "f": (15.0, 40.0),
    "beta": (0.0, 50.0),
    "phi0": (-25.0, 25.0),
    "theta0": (-25.0, 25.0),
    "alpha0": (-25.0, 25.0),
    "phi_a": (30.0, 60.0),
    "alpha_a": (25.0, 75.0),
}
"""Table 2 of Nguyen et al. (2020): bounds, f in Hz and angles in degrees (edge units)."""

TABLE3_SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)
"""Ascent speeds [m/s] of Table 3 of Nguyen et al. (2020)."""

SPEED_RANGE = (TABLE3_SPEEDS[0], TABLE3_SPEEDS[-1])
"""Ascent-speed range of the study [m/s] (Nguyen et al. 2020: 0 to 2 m/s)."""

TABLE3_DEG = {
    "f": (26.5, 27.9, 29.4, 30.2, 31.0),
    "beta": (1.5, 2.2, 2.8, 0.6, 2.9),
    "phi0": (-5.5, -5.2, -4.7, -4.1, -4.8),
    "theta0": (15.8, 14.0, 15.0, 14.6, 14.8),
    "alpha0": (0.7, 1.0, 1.2, 0.1, 1.3),
    "phi_a": (60.0, 60.0, 60.0, 60.0, 60.0),
    "alpha_a": (66.9, 66.5, 65.0, 61.0, 57.1),
}
"""Table 3 of Nguyen et al. (2020): optimal kinematics at the speeds of ``TABLE3_SPEEDS`` (Hz, deg)."""


def _to_si(name: str, value: float) -> float:
    return float(np.deg2rad(value)) if name in ANGLE_PARAMS else float(value)


def _to_edge(name: str, value: float) -> float:
    return float(np.rad2deg(value)) if name in ANGLE_PARAMS else float(value)


@dataclass(frozen=True)
class Kinematics:
    """The seven parameters of Eq. 1, SI: f [Hz], angles [rad].

    beta: stroke-plane angle; phi0, theta0, alpha0: mean sweep, elevation, rotation; phi_a, alpha_a: sweep
    and rotation amplitudes.
    """

    f: float
    beta: float
    phi0: float
    theta0: float
    alpha0: float
    phi_a: float
    alpha_a: float

    def __post_init__(self):
        for k in PARAM_NAMES:
            if not np.isfinite(getattr(self, k)):
                raise ValueError(f"kinematic parameter {k} is not finite: {getattr(self, k)}")
        if self.f <= 0:
            raise ValueError(f"flapping frequency f must be positive, got {self.f}")

    # ---- construction and conversion at the edges ------------------------------------------------
    @classmethod
    def from_edge(cls, values: dict[str, float], check_bounds: bool = True,
                  bounds_deg: dict | None = None) -> Kinematics:
        """From a dict in edge units (f in Hz, angles in degrees). Unknown or missing keys raise ValueError;
        with ``check_bounds`` a value outside ``bounds_deg`` ({parameter: (lower, upper)}, Hz and degrees; default
        Table 2, the hawkmoth's: an insect's own are :attr:`hawksim.insect.insect.Insect.bounds_deg`) raises
        ValueError naming it."""
        unknown = set(values) - set(PARAM_NAMES)
        if unknown:
            raise ValueError(f"unknown kinematic parameter(s) {sorted(unknown)}; expected {list(PARAM_NAMES)}")
        missing = [k for k in PARAM_NAMES if k not in values]
        if missing:
            raise ValueError(f"missing kinematic parameter(s) {missing}")
        if check_bounds:
            box = "Table 2's" if bounds_deg is None else "the insect's bounds"
            for k in PARAM_NAMES:
                lo, hi = (TABLE2_BOUNDS_DEG if bounds_deg is None else bounds_deg)[k]
                v = float(values[k])
                if not (lo <= v <= hi):
                    unit = "Hz" if k == "f" else "deg"
                    raise ValueError(f"kinematic parameter {k}={v:g} {unit} is outside {box} [{lo:g}, {hi:g}]")
        return cls(**{k: _to_si(k, values[k]) for k in PARAM_NAMES})

    def to_edge(self) -> dict[str, float]:
        """Dict in edge units (Hz, degrees), in PARAM_NAMES order, rounded to 12 significant digits."""
        return {k: float(f"{_to_edge(k, v):.12g}") for k, v in asdict(self).items()}

    def as_array(self) -> np.ndarray:
        """(7,) SI values in PARAM_NAMES order."""
        return np.array([getattr(self, k) for k in PARAM_NAMES])

    @classmethod
    def from_array(cls, x: np.ndarray) -> Kinematics:
        return cls(*map(float, x))

    # ---- derived ----------------------------------------------------------------------------------
    @property
    def period(self) -> float:
        """Wingbeat period T [s]."""
        return 1.0 / self.f

    @property
    def chi(self) -> float:
        """Body angle [rad]: chi = 60 deg - beta."""
        return STROKE_PLANE_TO_BODY - self.beta

    def eq1(self, c, s) -> tuple[tuple, tuple, tuple]:
        """Eq. 1 and its first two time derivatives from c = cos(2 pi f t), s = sin(2 pi f t) (floats or arrays):
        ((phi, theta, alpha) [rad], their rates [rad/s], their accelerations [rad/s^2]). The one place Eq. 1 is
        written; :meth:`angles` (arrays) and the flight loop's per-stage scalar path both evaluate it."""
        w = 2 * math.pi * self.f
        q = (self.phi0 - self.phi_a * c, self.theta0, math.pi / 2 + self.alpha0 - self.alpha_a * s)
        qd = (self.phi_a * w * s, 0.0, -self.alpha_a * w * c)
        qdd = (self.phi_a * w * w * c, 0.0, self.alpha_a * w * w * s)
        return q, qd, qdd

    def _eq1_array(self, t, order: int) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        wt = 2 * math.pi * self.f * t
        out = self.eq1(np.cos(wt), np.sin(wt))[order]
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), t.shape) for v in out])

    def motion(self, t: float) -> np.ndarray:
        """(angles, rates, accelerations) of (phi, theta, alpha) at one time t [s]: shape (3, 3), rows in
        [rad, rad/s, rad/s^2]; :meth:`angles`, :meth:`rates` and :meth:`accelerations` at t, bit for bit, from one
        cosine and one sine (the held-body loop's per-step call)."""
        wt = 2 * math.pi * self.f * np.asarray(t, dtype=float)
        return np.array(self.eq1(np.cos(wt), np.sin(wt)), dtype=float)

    def angles(self, t: np.ndarray) -> np.ndarray:
        """(phi, theta, alpha) [rad] at times t [s]: array of shape ``(3, *t.shape)``."""
        return self._eq1_array(t, 0)

    def rates(self, t: np.ndarray) -> np.ndarray:
        """Time derivatives ``(3, *t.shape)`` of (phi, theta, alpha) [rad/s]."""
        return self._eq1_array(t, 1)

    def accelerations(self, t: np.ndarray) -> np.ndarray:
        """Second derivatives ``(3, *t.shape)`` of (phi, theta, alpha) [rad/s^2]."""
        return self._eq1_array(t, 2)


def reference_speed(kin: Kinematics, morph: Morphology = HAWKMOTH) -> float:
    """U = 2 phi_a f r2 [m/s], the mean wing speed at the second-moment radius r2 (paper Eq. 8, r2 dimensional):
    the velocity unit of every nondimensional state and derivative."""
    return 2 * kin.phi_a * kin.f * morph.r2


def bounds_si() -> tuple[np.ndarray, np.ndarray]:
    """Table 2 bounds as two (7,) SI arrays (lower, upper) in PARAM_NAMES order."""
    lo = np.array([_to_si(k, TABLE2_BOUNDS_DEG[k][0]) for k in PARAM_NAMES])
    hi = np.array([_to_si(k, TABLE2_BOUNDS_DEG[k][1]) for k in PARAM_NAMES])
    return lo, hi


ROUND_OFF_STEP = 1e-10
"""Relative change of f between two realizations of a kinematics (round-off level; docs/uvlm.md)."""


def realization(kin: Kinematics, k: int = 1) -> Kinematics:
    """kin with its flapping frequency scaled by 1 + k ROUND_OFF_STEP (k = 0 gives kin's values): a change at the
    round-off level, to measure how much the UVLM's free wake amplifies round-off."""
    x = kin.as_array()
    x[0] *= 1.0 + k * ROUND_OFF_STEP
    return Kinematics.from_array(x)


def table3_kinematics(speed: float) -> Kinematics:
    """Table 3's optimal kinematics at ascent speed [m/s], linearly interpolated between its speeds; SI (angles
    in radians, f in Hz), as every Kinematics (Table 3 itself prints degrees: :data:`TABLE3_DEG`).

    Raises ValueError outside [0, 2] m/s.
    """
    lo, hi = TABLE3_SPEEDS[0], TABLE3_SPEEDS[-1]
    if not (lo <= speed <= hi):
        raise ValueError(f"speed {speed:g} m/s is outside Table 3's range [{lo:g}, {hi:g}] m/s")
    return Kinematics.from_edge({k: float(np.interp(speed, TABLE3_SPEEDS, v)) for k, v in TABLE3_DEG.items()})


# ---- frames ----------------------------------------------------------------------------------------
MIRROR = np.diag([1.0, -1.0, 1.0])
"""Reflection through the body x-z (sagittal) plane."""

R_BODY_STROKE = rot_y(STROKE_PLANE_TO_BODY)
"""Stroke-plane frame in the body frame (3, 3)."""

JOINT_AXES = {
    "left": ((0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
    "right": ((0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
}
"""Hinge axes (sweep, elevation, rotation) in the stroke-plane frame, applied intrinsically in that order,
so that a positive joint angle is a positive phi, theta, alpha on both wings (mirror images)."""


def wing_rotation_stroke(phi, theta, alpha, side: str) -> np.ndarray:
    """Wing frame in the stroke-plane frame, shape (*phi.shape, 3, 3). side: 'left' or 'right'."""
    if side == "left":
        return rot_z(-np.asarray(phi)) @ rot_x(theta) @ rot_y(-np.asarray(alpha))
    if side == "right":
        return rot_z(phi) @ rot_x(-np.asarray(theta)) @ rot_y(-np.asarray(alpha))
    raise ValueError(f"side must be 'left' or 'right', got {side!r}")


def wing_rotation_body(kin: Kinematics, t, side: str) -> np.ndarray:
    """Wing frame in the body frame at times t [s]: shape (*t.shape, 3, 3)."""
    phi, theta, alpha = kin.angles(t)
    return R_BODY_STROKE @ wing_rotation_stroke(phi, theta, alpha, side)

