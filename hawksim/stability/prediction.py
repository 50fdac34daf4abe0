"""Linear predictions of a perturbed free flight about its periodic orbit (issue 19, item 7): what the Floquet
matrix and the cycle-averaged A matrices say a `hawksim fly --perturb ...` flight does, beat by beat, and the
body pose ("ghost") that follows from them.

States. The per-beat state deviation d_k (8,) is the perturbed flight's body state at phase 0 of beat k
(t = k T) minus the unperturbed orbit flight's, in the order of the Floquet states
(:data:`FLOQUET_NAMES` = u, v, w, p, q, r, phi, theta; :data:`hawksim.flight.orbit.STATE_NAMES` without the
heading psi) and in SI: u, v, w [m/s] in the level heading axes (x forward horizontal, y right, z down), p, q, r
[rad/s] in the same axes, phi (bank, right wing down), theta (body pitch, nose up) [rad]. The linear models act on
NORMALIZED states d / s, s = :func:`hawksim.stability.floquet.state_scale` (U for velocities, 1/T for rates, 1
for angles; U = 2 phi_a f r2, T = 1/f):

* Floquet: d_k = s M^k (d_0 / s), M (8, 8) the monodromy (:func:`hawksim.stability.floquet.monodromy`);
* cycle-averaged: per system (longitudinal (u, w, q, theta), lateral (v, p, r, phi)),
  d_k = s T^-1 expm(A k) T (d_0 / s), A (4, 4) the nondimensional matrix (t+ = t/T,
  :func:`hawksim.stability.floquet.quasi_steady_system`) and T the chart map from the orbit's level-frame
  velocities to Etkin's body-fixed ones (:func:`hawksim.stability.validation.chart_map`).

Ghost pose (:func:`ghost_pose`): the unperturbed flight's pose plus the predicted deviation, linearly interpolated
in time between the phase-0 samples: bank and pitch from d_k; heading psi and position from the NEUTRAL rows of
the one-beat map (:func:`extended_monodromy`, :func:`neutral_prediction`): psi_{k+1} - psi_k and the beat's
displacement (its mean velocity times T, i.e. the integrated velocity deviation) are linear in d_k. Integrating
the phase-0 samples of r and (u, v, w) instead fails: within a beat the deviation oscillates (a banked body's
large within-beat pitch rate shows up in the level-frame r), so the phase-0 value is not the beat mean
(measured at 1 m/s, phi = 0.5 deg: the integrated phase-0 r turned the heading the wrong way). The within-beat
part of the attitude deviation is not predicted (the ghost moves smoothly between the phase-0 samples).

Everything here is a pure function of arrays and :class:`hawksim.flight.result.FlightResult` objects, except
:func:`predict_flight`, which solves the linear models and flies the unperturbed orbit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hawksim.flight.orbit import STATE_NAMES, state_to_world, world_to_state
from hawksim.flight.result import FlightResult
from hawksim.frames import quat_from_matrices

FLOQUET_NAMES = STATE_NAMES[:8]
"""Order of the 8 deviation states: u, v, w, p, q, r, phi, theta (the monodromy's)."""

LONG = (0, 2, 4, 7)
"""Longitudinal (u, w, q, theta) indices into :data:`FLOQUET_NAMES` (the order of A_long)."""

LAT = (1, 3, 5, 6)
"""Lateral (v, p, r, phi) indices into :data:`FLOQUET_NAMES` (the order of A_lat)."""

_ANGULAR = ("p", "q", "r", "theta", "phi")


def launch_deviation(perturb: dict[str, float]) -> np.ndarray:
    """(8,) SI launch deviation in :data:`FLOQUET_NAMES` order of a `--perturb` dict (edge units, the meaning of
    :func:`hawksim.flight.fly.fly`'s ``perturb`` with a ``start_state``: u, v, w [m/s], p, q, r [deg/s], theta, phi
    [deg], added to the orbit's launch state in the level heading axes)."""
    d = np.zeros(8)
    for k, v in perturb.items():
        if k not in FLOQUET_NAMES:
            raise ValueError(f"unknown perturbation {k!r}; choose from {', '.join(FLOQUET_NAMES)}")
        d[FLOQUET_NAMES.index(k)] = float(v) * (np.pi / 180 if k in _ANGULAR else 1.0)
    return d


def floquet_prediction(M: np.ndarray, d0: np.ndarray, scale: np.ndarray, beats: int) -> np.ndarray:
    """(beats + 1, 8) SI: d_k = scale * M^k (d0 / scale), k = 0 .. beats. M (8, 8) nondimensional monodromy,
    d0 (8,) SI launch deviation, scale (8,) SI per normalized unit (:func:`~hawksim.stability.floquet.state_scale`)."""
    x = np.asarray(d0, float) / scale
    out = [x]
    for _ in range(beats):
        out.append(M @ out[-1])
    return np.array(out) * scale


def averaged_prediction(A_long: np.ndarray, A_lat: np.ndarray, d0: np.ndarray, scale: np.ndarray, beats: int,
                        V_over_U: float) -> np.ndarray:
    """(beats + 1, 8) SI: per system d_k = scale T^-1 expm(A k) T (d0 / scale), k = 0 .. beats (beats = t+).
    A_long (4, 4) in (u, w, q, theta), A_lat (4, 4) in (v, p, r, phi), nondimensional (t+ = t/T); T =
    :func:`~hawksim.stability.validation.chart_map` with w_e+ = -V/U (``V_over_U`` = ascent speed / U)."""
    from scipy.linalg import expm

    from hawksim.stability.validation import chart_map

    x = np.asarray(d0, float) / scale
    out = np.zeros((beats + 1, 8))
    for name, A, idx in (("longitudinal", A_long, LONG), ("lateral", A_lat, LAT)):
        Tc = chart_map(name, V_over_U)
        Ad = np.linalg.solve(Tc, np.asarray(A, float) @ Tc)
        E = expm(Ad)  # expm(Ad k) = E^k
        y = x[list(idx)]
        for k in range(beats + 1):
            out[k, list(idx)] = y.real
            y = E @ y
    return out * scale


def flight_states(result: FlightResult, chi_ref: float, rows=None) -> np.ndarray:
    """(m, 9) body states (:data:`~hawksim.flight.orbit.STATE_NAMES`, SI, chart reference ``chi_ref`` [rad]) of the
    flight's rows (default all n rows; the row holds the state at the step start)."""
    rows = np.arange(len(result.t)) if rows is None else np.asarray(rows)
    R = result.body_R[rows]
    return np.array([world_to_state(R[i], result.body_v[j], result.body_omega[j], chi_ref)
                     for i, j in enumerate(rows)]).reshape(len(rows), 9)


def beat_deviation(perturbed: FlightResult, reference: FlightResult, chi_ref: float) -> np.ndarray:
    """(nb, 8) SI per-beat deviation d_k of ``perturbed`` from ``reference`` at phase 0 (rows k steps_per_cycle,
    k = 0 .. nb - 1, nb = the complete-or-started beats both flights hold)."""
    n = perturbed.steps_per_cycle
    m = min(len(perturbed.t), len(reference.t))
    rows = np.arange(0, m, n)
    return flight_states(perturbed, chi_ref, rows)[:, :8] - flight_states(reference, chi_ref, rows)[:, :8]


def interpolate_beats(d: np.ndarray, t_beats: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(len(t), m): each column of d (nb, m), sampled at t_beats (nb,) [s], linearly interpolated at t [s] (held
    constant outside)."""
    return np.stack([np.interp(t, t_beats, d[:, j]) for j in range(d.shape[1])], axis=1)


def neutral_prediction(J: np.ndarray, d_beats: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """(nb + 1, 4) SI: heading deviation dpsi [rad] and world position deviation (3,) [m] at phase 0 of beats
    0 .. nb, from the per-beat state deviation d_beats ((nb + 1, 8) SI) and the neutral rows J (4, 8) of the
    one-beat map (:func:`extended_monodromy`: the change over one beat of psi [rad] and of the position [m] per
    normalized unit of the state at the beat's start): n_{k+1} = n_k + J (d_k / scale), n_0 = 0 (the launch
    deviation has no heading or position part). The last row of d_beats is not used."""
    steps = (np.asarray(d_beats, float)[:-1] / scale) @ np.asarray(J, float).T
    return np.concatenate([np.zeros((1, 4)), np.cumsum(steps, axis=0)])


def ghost_pose(reference: FlightResult, d_beats: np.ndarray, neutral: np.ndarray,
               chi_ref: float) -> tuple[np.ndarray, np.ndarray]:
    """(position (n, 3) [m] world, quaternion (n, 4) (w, x, y, z) body -> world) of the ghost at the reference's n
    rows: ``reference``'s pose plus the predicted deviation, linearly interpolated between the phase-0 samples
    t_k = t_0 + k T (k = 0 .. nb): bank and pitch from d_beats ((nb + 1, 8) SI), heading and position from
    ``neutral`` ((nb + 1, 4): dpsi [rad], dx, dy, dz world [m], :func:`neutral_prediction`). The attitude is
    rebuilt in the state chart (:func:`hawksim.flight.orbit.state_to_world`, reference angle ``chi_ref`` [rad])."""
    t = np.asarray(reference.t, float)
    T = reference.steps_per_cycle * (t[1] - t[0])
    tb = t[0] + T * np.arange(len(d_beats))
    d = interpolate_beats(np.asarray(d_beats, float)[:, [6, 7]], tb, t)
    nt = interpolate_beats(np.asarray(neutral, float), tb, t)
    x = flight_states(reference, chi_ref)
    x[:, 6:8] += d
    x[:, 8] += nt[:, 0]
    R = np.array([state_to_world(xx, chi_ref)[0] for xx in x])
    return reference.body_pos + nt[:, 1:], quat_from_matrices(R)


def extended_monodromy(orbit, *, delta: float | None = None, model=None) -> tuple[np.ndarray, np.ndarray]:
    """(M (8, 8), J (4, 8)) of a quasi-steady orbit (no warm-up beats) by central differences, as
    :func:`hawksim.stability.floquet.monodromy` (same step, same 16 one-beat flights): M the nondimensional
    monodromy (rows and columns :data:`FLOQUET_NAMES`, normalized), J the neutral rows: the change over the beat of
    the heading psi [rad] and of the world position (3,) [m] (the beat's mean velocity times T) per normalized
    unit of each launch state. NOT pure: it flies."""
    from hawksim.flight.orbit import OrbitFlight
    from hawksim.stability.floquet import FD_DELTA, state_scale

    if orbit.has_memory:
        raise ValueError("extended_monodromy: orbits without warm-up beats only (quasi-steady)")
    h = FD_DELTA if delta is None else delta
    kin = orbit.kinematics
    sc = state_scale(kin, orbit.insect.morphology)
    x0 = orbit.launch_state.as_array()
    fl = {s: OrbitFlight(orbit.aero, symmetric=s, model=model) for s in (True, False)}
    M, J = np.zeros((8, 8)), np.zeros((4, 8))
    for j in range(8):
        outs = []
        for sgn in (1, -1):
            x = x0.copy()
            x[j] += sgn * h * sc[j]
            b = fl[j in LONG].fly(kin, x, 1, orbit.chi_ref)
            outs.append((b.states[1][:8] / sc, np.concatenate([[b.states[1][8]], b.mean_velocity[0] * kin.period])))
        M[:, j] = (outs[0][0] - outs[1][0]) / (2 * h)
        J[:, j] = (outs[0][1] - outs[1][1]) / (2 * h)
    return M, J


@dataclass(frozen=True)
class Prediction:
    """Linear predictions of a perturbed flight (SI, :data:`FLOQUET_NAMES` order).

    d0 (8,): launch deviation; beat_t (nb + 1,) [s]: phase-0 times t_0 + k T; nonlinear (nb, 8): the flight's own
    deviation from ``reference``; floquet, averaged (nb + 1, 8); neutral (nb + 1, 4): the Floquet prediction of
    the heading [rad] and world position [m] deviations (:func:`neutral_prediction`); ghost_pos (n, 3) [m] and
    ghost_quat (n, 4) (w, x, y, z): the ghost's pose from the Floquet prediction (:func:`ghost_pose`); reference:
    the unperturbed orbit flight (same kinematics, steps and length); max_multiplier: the largest ``|mu|`` of M;
    notes: how it was made.
    """

    d0: np.ndarray
    beat_t: np.ndarray
    nonlinear: np.ndarray
    floquet: np.ndarray
    averaged: np.ndarray
    neutral: np.ndarray
    ghost_pos: np.ndarray
    ghost_quat: np.ndarray
    reference: FlightResult
    max_multiplier: float = float("nan")
    notes: str = ""


def make_prediction(perturbed: FlightResult, reference: FlightResult, perturb: dict[str, float], M: np.ndarray,
                    J: np.ndarray, A_long: np.ndarray, A_lat: np.ndarray, scale: np.ndarray, chi_ref: float,
                    speed: float, notes: str = "") -> Prediction:
    """:class:`Prediction` of ``perturbed`` (launched from the orbit with ``perturb``, edge units) from the
    unperturbed flight ``reference``, the monodromy M (8, 8) and its neutral rows J (4, 8)
    (:func:`extended_monodromy`), the averaged A_long, A_lat (4, 4), the state scale (8,), the orbit's chart
    reference chi_ref [rad] and the ascent speed [m/s] (pure: no flight)."""
    n = perturbed.steps_per_cycle
    nb = -(-min(len(perturbed.t), len(reference.t)) // n)  # beats started
    d0 = launch_deviation(perturb)
    fq = floquet_prediction(M, d0, scale, nb)
    av = averaged_prediction(A_long, A_lat, d0, scale, nb, speed / scale[0])
    t = np.asarray(reference.t, float)
    beat_t = t[0] + n * (t[1] - t[0]) * np.arange(nb + 1)
    neutral = neutral_prediction(J, fq, scale)
    pos, quat = ghost_pose(reference, fq, neutral, chi_ref)
    mu = float(np.abs(np.linalg.eigvals(M)).max())
    return Prediction(d0=d0, beat_t=beat_t, nonlinear=beat_deviation(perturbed, reference, chi_ref), floquet=fq,
                      averaged=av, neutral=neutral, ghost_pos=pos, ghost_quat=quat, reference=reference,
                      max_multiplier=mu, notes=notes)


def predict_flight(perturbed: FlightResult, perturb: dict[str, float], orbit, *, model=None) -> Prediction:
    """Fly the unperturbed orbit (same kinematics, steps per beat, length), compute the orbit's monodromy and the
    quasi-steady averaged A matrices at its kinematics, and :func:`make_prediction`. Quasi-steady orbits only
    (the monodromy and the orbit flight take ~1 s each; the averaged A ~1 s). NOT pure: it flies."""
    from hawksim.backends import flight_backend
    from hawksim.flight.fly import fly
    from hawksim.stability.floquet import quasi_steady_system, state_scale
    from hawksim.trim.point import Trim

    from hawksim.backends.registry import descriptor

    descriptor(orbit.aero).linear_prediction.require("the linear prediction", orbit.aero)
    kin = orbit.kinematics
    ref = fly(Trim(float(orbit.speed), kin, model=orbit.aero, source="periodic orbit (unperturbed reference)"),
              flight_backend(orbit.aero, kinematics=kin), perturbed.cycles, model=model,
              steps_per_cycle=perturbed.steps_per_cycle,
              start_state=(orbit.launch_state.as_array(), orbit.chi_ref))
    M, J = extended_monodromy(orbit, model=model)
    av = quasi_steady_system(kin, orbit.speed)
    mu = float(np.abs(np.linalg.eigvals(M)).max())
    return make_prediction(perturbed, ref, perturb, M, J, av.A_long, av.A_lat,
                           state_scale(kin, orbit.insect.morphology), orbit.chi_ref,
                           orbit.speed, notes=(f"Floquet: monodromy of the {orbit.aero} orbit at {orbit.speed:g} m/s "
                                               f"(largest |mu| {mu:.3f}); averaged: quasi-steady A at the orbit's "
                                               "kinematics (chart-mapped)"))


class NoPrediction(Exception):
    """Why a flight gets no linear prediction (one line, for stderr)."""


def predict_cli_flight(result: FlightResult, perturb: dict[str, float], *, speed: float, aero: str,
                       kinematics=None, model=None) -> Prediction:
    """The prediction of a `hawksim fly --perturb ...` flight (:func:`predict_flight`), from the same orbit the
    flight started on (the shipped one of ``aero`` at ``speed``, else the one solved at ``kinematics``, as
    :func:`hawksim.cli.fly.fly_named` chooses). Raises :class:`NoPrediction` (one line) when there is none: no
    nonzero perturbation, a flight not started on a periodic orbit, or a backend other than quasi-steady (the
    UVLM's wake makes its monodromy a 20-minute job)."""
    from hawksim.flight.orbit import periodic_orbit, shipped_orbit

    if not any(v != 0 for v in (perturb or {}).values()):
        raise NoPrediction("no perturbation")
    if "periodic orbit" not in result.trim_source:
        raise NoPrediction("the flight did not start on a periodic orbit (--start trim)")
    from hawksim.backends.registry import descriptor

    support = descriptor(aero).linear_prediction
    if not support:
        raise NoPrediction(f"--aero {aero}: {support.why_not}")
    orbit = shipped_orbit(speed, aero) if kinematics is None else None
    if orbit is None:
        orbit = periodic_orbit(speed, aero, kinematics=kinematics)
    return predict_flight(result, perturb, orbit, model=model)
