"""Rigid rectangular flat plates in a uniform stream, run through the UVLM: the classical unsteady cases.

The plate: chord c = 1 m, aspect ratio AR (span AR c), in a stream U = 1 m/s of density rho = 1 kg/m^3, flat,
no thickness. Only the half span y in [0, AR c / 2] is solved; the mirror plane y = 0 adds the other half (exact
for these symmetric motions). Spanwise ring edges are clustered toward the tip, y_j = (AR c / 2) sin(pi j / (2 n)),
where the span loading changes fastest. The wing frame has x toward the leading edge (the stream flows along -x
in world), the leading edge at x = +c/4 and the trailing edge at x = -3c/4, so the frame's origin, about which the
plate pitches, is the quarter chord.

Motions (world frame, z up): heave h(t) = h0 sin(omega t) (up), pitch alpha(t) = alpha0 sin(omega t) (nose up,
about the quarter chord), or an impulsive start at a fixed angle (Wagner). Reduced frequency k = omega b / U and
reduced time s = U t / b on the semichord b = c / 2, as in :mod:`aero.unsteady_theory`; C_L and C_T on the planform
area, C_T positive forward (thrust).

A plate in a uniform stream cannot reach the 2D result at any finite AR; :func:`extrapolate_aspect_ratio` takes a
sequence of aspect ratios to AR -> infinity by a least-squares polynomial in 1/AR (lifting-line theory's 3D
correction is a series in 1/AR).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aero.mesh import WingMesh, wing_mesh
from aero.uvlm import UVLM, FreeStream, UVLMConfig

CHORD = 1.0
"""Plate chord c [m]."""
SPEED = 1.0
"""Free-stream speed U [m/s]."""
RHO = 1.0
"""Air density [kg/m^3] (loads are reported as coefficients)."""

MIRROR_PLANE = (np.zeros(3), np.array([0.0, 1.0, 0.0]))
"""The plate's plane of symmetry, world y = 0 (point, normal)."""

LINEAR_WAKE_CORE_CHORDS = 1e-3
"""Initial wake core [chords] of :data:`PLAIN_CONFIG`: linear theory's wake is a vortex sheet without a core; 0.001 c
lies far below every panel used here (c / 32 at the finest), so that it only regularises. The UVLM's default
0.05 c (a physical viscous core for the insect's free wake) suppresses the near wake once the panels are finer than
it: the heave lift at k = 0.5, AR 20 then grows with refinement (0.976, 0.985, 1.003 of 2D at 8, 16, 32 chordwise
rings) where with this core it converges (0.969, 0.968, 0.967; scripts/studies/theodorsen_candidates.py)."""

PLAIN_CONFIG = UVLMConfig(rho=RHO, free_wake=False, le_suction=False, core_growth=False,
                          wake_core_chords=LINEAR_WAKE_CORE_CHORDS)
"""Linear theory's model: a prescribed wake (convected by the free stream) with a vanishing core and no core growth,
no Polhamus suction (the in-plane suction stays in the loads, as in Garrick's thrust). The other constants are the
UVLM's defaults (shedding rule, unsteady term, bound cores)."""


@dataclass(frozen=True)
class PlateGrid:
    """A plate's lattice and time step.

    aspect_ratio: span / chord; n_chord: chordwise rings; n_span: spanwise rings on the half span;
    steps_per_cycle: time steps per motion period (harmonic cases); for the Wagner case the step is the time
    to travel one cycle's length at k = 1 divided by it, i.e. ds = 2 pi / steps_per_cycle semichords.
    """

    aspect_ratio: float
    n_chord: int = 8
    n_span: int = 24
    steps_per_cycle: int = 80

    def __post_init__(self):
        if not (np.isfinite(self.aspect_ratio) and self.aspect_ratio > 0):
            raise ValueError(f"PlateGrid.aspect_ratio must be positive, got {self.aspect_ratio!r}")
        for name in ("n_chord", "n_span", "steps_per_cycle"):
            if int(getattr(self, name)) < 1:
                raise ValueError(f"PlateGrid.{name} must be >= 1, got {getattr(self, name)!r}")


def plate_mesh(grid: PlateGrid) -> WingMesh:
    """The half plate's mesh (wing frame), tip-clustered spanwise edges."""
    half = 0.5 * grid.aspect_ratio * CHORD
    y = half * np.sin(0.5 * np.pi * np.arange(grid.n_span + 1) / grid.n_span)
    n = y.size
    return wing_mesh(y, np.full(n, 0.25 * CHORD), np.full(n, -0.75 * CHORD), grid.n_chord)


def _pitch_matrix(a: float) -> np.ndarray:
    """Wing frame -> world for a nose-up pitch a [rad] (a rotation about -y)."""
    c, s = np.cos(-a), np.sin(-a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@dataclass(frozen=True)
class PlateRun:
    """A plate run's time series: t (nt,) [s], s (nt,) semichords travelled, c_l, c_t (nt,) on the planform."""

    t: np.ndarray
    s: np.ndarray
    c_l: np.ndarray
    c_t: np.ndarray


def run_plate(grid: PlateGrid, motion: str, amplitude: float, k: float | None = None, cycles: float = 3.0,
              config: UVLMConfig = PLAIN_CONFIG, s_end: float | None = None) -> PlateRun:
    """Run the UVLM on the plate.

    motion: "heave" (amplitude h0 [m]), "pitch" (amplitude alpha0 [rad]) at reduced frequency k, for ``cycles``
    periods; or "start" (a fixed angle ``amplitude`` [rad], impulsively started at t = 0) until s_end semichords.
    """
    if motion not in ("heave", "pitch", "start"):
        raise ValueError(f"run_plate: motion must be 'heave', 'pitch' or 'start', got {motion!r}")
    b = 0.5 * CHORD
    if motion == "start":
        if s_end is None or not s_end > 0:
            raise ValueError(f"run_plate: the 'start' motion needs s_end > 0, got {s_end!r}")
        dt = 2 * np.pi / grid.steps_per_cycle * b / SPEED
        nt = int(np.ceil(s_end * b / SPEED / dt)) + 1
        omega = 0.0
    else:
        if k is None or not (np.isfinite(k) and k > 0):
            raise ValueError(f"run_plate: the reduced frequency k must be positive, got {k!r}")
        omega = k * SPEED / b
        dt = 2 * np.pi / omega / grid.steps_per_cycle
        nt = int(round(cycles * grid.steps_per_cycle))
    solver = UVLM([plate_mesh(grid)], config)
    fs = FreeStream(v0=np.array([-SPEED, 0.0, 0.0]))
    q_area = 0.5 * RHO * SPEED**2 * (0.5 * grid.aspect_ratio * CHORD * CHORD)
    t = np.arange(nt) * dt
    c_l, c_t = np.empty(nt), np.empty(nt)
    zero = np.zeros((1, 3))
    for i, ti in enumerate(t):
        if motion == "heave":
            R = np.eye(3)[None]
            o = np.array([[0.0, 0.0, amplitude * np.sin(omega * ti)]])
            v = np.array([[0.0, 0.0, amplitude * omega * np.cos(omega * ti)]])
            w = zero
        elif motion == "pitch":
            a, ad = amplitude * np.sin(omega * ti), amplitude * omega * np.cos(omega * ti)
            R, o, v, w = _pitch_matrix(a)[None], zero, zero, np.array([[0.0, -ad, 0.0]])
        else:
            R, o, v, w = _pitch_matrix(amplitude)[None], zero, zero, zero
        f = solver.step(dt, R, o, v, w, fs, MIRROR_PLANE).force[0]
        c_l[i], c_t[i] = f[2] / q_area, f[0] / q_area
    return PlateRun(t=t, s=SPEED * t / b, c_l=c_l, c_t=c_t)


def first_harmonic(run: PlateRun, k: float, steps_per_cycle: int) -> complex:
    """H of C_L over the run's last cycle for a drive amplitude * sin(omega t): C_L = mean + drift +
    Re(H e^{i (omega t - pi/2)}), i.e. H is the complex response to the drive's phasor (the convention of
    :mod:`aero.unsteady_theory`), fitted with a mean and a linear drift that absorbs what is left of the start's
    transient."""
    omega = k * SPEED / (0.5 * CHORD)
    t, y = run.t[-steps_per_cycle:], run.c_l[-steps_per_cycle:]
    tm = t - t.mean()
    X = np.column_stack([np.ones_like(t), tm, np.cos(omega * t), np.sin(omega * t)])
    _, _, ac, as_ = np.linalg.lstsq(X, y, rcond=None)[0]
    return complex(as_, ac)


def cycle_mean_thrust(run: PlateRun, steps_per_cycle: int) -> float:
    """C_T averaged over the run's last cycle."""
    return float(run.c_t[-steps_per_cycle:].mean())


def extrapolate_aspect_ratio(aspect_ratios, values, degree: int = 2):
    """The AR -> infinity limit of values (real or complex, one per aspect ratio) by a least-squares polynomial of
    the given degree in 1/AR; returns (limit, coefficients lowest order first)."""
    x = 1.0 / np.asarray(aspect_ratios, dtype=float)
    y = np.asarray(values)
    if x.size <= degree:
        raise ValueError(f"extrapolate_aspect_ratio: {x.size} aspect ratios cannot fit degree {degree}")
    V = np.vander(x, degree + 1, increasing=True)
    coef = np.linalg.lstsq(V.astype(y.dtype), y, rcond=None)[0]
    return coef[0], coef


def consistent_steps(k: float, n_chord: int) -> int:
    """Steps per period at reduced frequency k for which the wake moves one chordwise panel per step,
    U dt = c / n_chord (the shed rows then continue the bound lattice): round(pi n_chord / k)."""
    return int(round(np.pi * n_chord / k))


HEAVE_AMPLITUDE = 0.02 * CHORD
"""Heave amplitude h0 [m] of the harmonic cases (small: linear theory)."""
PITCH_AMPLITUDE = np.radians(1.0)
"""Pitch amplitude alpha0 [rad] of the harmonic cases and the angle of the impulsive start."""


@dataclass(frozen=True)
class Harmonic:
    """A harmonic case's response: H, C_L's first harmonic per unit drive (per h0 / b for heave, per radian for
    pitch; the convention of :func:`aero.unsteady_theory.heave_lift`); c_t, the cycle-mean thrust coefficient."""

    H: complex
    c_t: float


def harmonic_response(grid: PlateGrid, motion: str, k: float, cycles: float = 3.0,
                      config: UVLMConfig = PLAIN_CONFIG) -> Harmonic:
    """The plate's first harmonic in heave (amplitude :data:`HEAVE_AMPLITUDE`) or pitch about the quarter chord
    (:data:`PITCH_AMPLITUDE`) at reduced frequency k, over the last of ``cycles`` periods."""
    amp, scale = (HEAVE_AMPLITUDE, HEAVE_AMPLITUDE / (0.5 * CHORD)) if motion == "heave" else (PITCH_AMPLITUDE,) * 2
    r = run_plate(grid, motion, amp, k=k, cycles=cycles, config=config)
    return Harmonic(H=first_harmonic(r, k, grid.steps_per_cycle) / scale,
                    c_t=cycle_mean_thrust(r, grid.steps_per_cycle))


def indicial_lift(grid: PlateGrid, s, s_end: float = 20.0, config: UVLMConfig = PLAIN_CONFIG) -> np.ndarray:
    """C_L / (2 pi alpha) at reduced times s (semichords) after an impulsive start to :data:`PITCH_AMPLITUDE`
    (the finite wing's counterpart of Wagner's function; linear interpolation between steps)."""
    r = run_plate(grid, "start", PITCH_AMPLITUDE, s_end=s_end, config=config)
    return np.interp(s, r.s, r.c_l) / (2 * np.pi * PITCH_AMPLITUDE)
