"""The descriptors of hawksim's built-in backends (:mod:`hawksim.backends.registry`), and the per-backend numbers
they hold: finite-difference steps, orbit tolerances, warm-up beats, with the measurements that chose them.

Each factory imports its backend's module when called, so that looking a descriptor up loads no network and no
lattice code.
"""

from __future__ import annotations

from hawksim.backends.memory import MEMORYLESS, PREVIOUS_CALL, RECORD, WAKE
from hawksim.backends.registry import YES, BackendDescriptor, FiniteDifferenceSteps, OrbitTolerance, no
from hawksim.backends.resolution import DEFAULT, FLY_UVLM

# ---- finite-difference steps (normalized; :class:`FiniteDifferenceSteps`) ----------------------------------------
FD_STEP = 1e-6
"""Forward-difference step of the shooting Jacobian in the normalized unknowns (quasi-steady)."""

FD_DELTA = 1e-5
"""Central-difference step in the normalized states and inputs of the monodromy matrix and the control derivatives
(u/U, q T, rad). The map's round-off is ~1e-13, its curvature O(1): the derivative error is ~1e-8 relative (checked
by halving the step)."""

UVLM_FD_STEP = 1e-3
"""The UVLM's step (orbit, monodromy and control derivatives): its free wake amplifies round-off (docs/uvlm.md,
kinematics.realization), so a 1e-6 step differences noise; with 1e-6 the Newton solve stalls at 2e-3."""

SURROGATE_FD_STEP = 1e-4
"""The per-step surrogate's step of the orbit and the monodromy (normalized): its float32 network rounds the loads
at a relative 6e-8, so a 1e-6 step would difference round-off (an error ~6e-8 / h in the Jacobian; 1e-4 keeps it
~1e-3 while the truncation error, ~h times the map's curvature, stays ~1e-4)."""

SURROGATE_FD_DELTA = 1e-3
"""The per-step surrogate's step of the control derivatives. Measured at 1 m/s (largest entry of A, B0, B1 ~1.4):
steps 1e-4 / 3e-4 / 1e-3 / 3e-3 differ by 4.1e-3, 1.2e-3, 1.8e-3 between neighbours, i.e. round-off ~4e-4 and
truncation ~2e-4 at 1e-3, the smallest total (the orbit solver's 1e-4 step, :data:`SURROGATE_FD_STEP`, carries
~4e-3 of round-off here); the closed-loop multipliers agree to 1e-4 at every step (docs/control.md, "The per-step
surrogate in the loop")."""

# ---- orbit tolerances (:class:`OrbitTolerance`) ------------------------------------------------------------------
ORBIT_TOL = 1e-8
"""Newton stops when the max abs normalized residual is below this (the map is deterministic; its round-off
floor, measured by re-evaluating the converged orbit at perturbed f, is ~1e-12)."""

SURROGATE_ORBIT_TOL = 1e-6
"""Newton tolerance (normalized residual) of the per-step surrogate's orbit: its float32 loads (relative round-off
6e-8 per step) leave a periodicity floor near 1e-7, so :data:`ORBIT_TOL` (1e-8) is out of reach."""

UVLM_TOL_VELOCITY = 1e-3
"""The UVLM orbit counts as converged when its periodicity and mean-velocity residuals are within this [m/s]
(issue 19's target: the free wake's beat-to-beat variation, :attr:`hawksim.flight.orbit.Orbit.floor`, keeps a 1e-8
residual out of reach) ..."""
UVLM_TOL_RATE = 1e-2
"""... its pitch-rate periodicity within this [rad/s] and its pitch periodicity within this times T [rad]."""

SURROGATE_SPEED_RATE = 0.05
"""The per-step surrogate's slower speed reference under control [m/s per wingbeat]. Tuned: its orbits flap at
32-36 Hz (the quasi-steady ones at 25-31 Hz), so a 0.2 or 0.1 m/s-per-beat ramp from hover drives f to Table 2's
40 Hz within 2-3 beats, and the saturated flight pitches away (pitch errors of 34 and 120 deg on the 0 -> 1 -> 2 m/s
profile); at 0.05 f stays <= 39.1 Hz and the profile is tracked without overshoot (docs/control.md, "The per-step
surrogate in the loop"). What it moves: the ramp's duration (20 beats per m/s) and the lag behind the reference."""

UVLM_WARM_BEATS = 2
"""Wingbeats that develop the UVLM wake before the measured beat of its orbits."""


# ---- factories ----------------------------------------------------------------------------------------------------
def _morph_kw(morphology) -> dict:
    """The ``morph`` keyword of a backend built from the insect's morphology (none for the default: the class's)."""
    return {} if morphology is None else {"morph": morphology}


def _default_morphology_only(morphology, name: str) -> None:
    """ValueError naming ``morphology`` unless it is None or the default hawkmoth's (a network's training insect)."""
    if morphology is not None:
        from hawksim.insect.folder import default_insect

        if morphology != default_insect().morphology:
            raise ValueError(f"morphology: the {name} backend's network was trained on the default hawkmoth only; "
                             f"fly the insect {morphology.name!r} with the quasi-steady model or the UVLM")


def _quasi_steady(*, morphology=None, **_):
    from hawksim.backends.quasi_steady import QuasiSteadyBackend

    return QuasiSteadyBackend(**_morph_kw(morphology))


def _vacuum(**_):
    from hawksim.backends.base import NoAero

    return NoAero()


def _uvlm(*, resolution=None, symmetric: bool = True, freestream=None, keep_panels: bool = False,
          max_wake_rows: int | None = None, wake_summation: str = "direct", wake_precision: str = "float64",
          morphology=None, **_):
    from hawksim.backends.uvlm import UVLMBackend

    res = resolution if resolution is not None else DEFAULT
    return UVLMBackend(n_chord=res.n_chord, n_span=res.n_span, symmetric=symmetric, freestream=freestream,
                       keep_panels=keep_panels, max_wake_rows=max_wake_rows, wake_summation=wake_summation,
                       wake_precision=wake_precision, **_morph_kw(morphology))


def _step_surrogate(*, kinematics=None, morphology=None, **_):
    from hawksim.backends.step_surrogate import StepSurrogateBackend

    _default_morphology_only(morphology, "surrogate")
    if kinematics is None:
        raise ValueError("the surrogate backend needs the flight's kinematics")
    return StepSurrogateBackend(kinematics)


def _controlled_step_surrogate(kinematics):
    from hawksim.backends.controlled_step_surrogate import ControlledStepSurrogate

    return ControlledStepSurrogate(kinematics)


def _mean_surrogate(*, kinematics=None, morphology=None, **_):
    from hawksim.backends.surrogate import SurrogateBackend

    _default_morphology_only(morphology, "surrogate-mean")
    if kinematics is None:
        raise ValueError("the surrogate-mean backend needs the flight's kinematics")
    return SurrogateBackend(kinematics)


def _network_sha256() -> str:
    from hawksim.backends.step_network import network_sha256

    return network_sha256()


NO_ORBIT = "the cycle-mean network has no within-beat loads, so no periodic orbit of the free body"

QUASI_STEADY = BackendDescriptor(
    name="quasi-steady", summary="blade-element quasi-steady model (fast, the default)", factory=_quasi_steady,
    fd=FiniteDifferenceSteps(orbit=FD_STEP, monodromy=FD_DELTA, control=FD_DELTA),
    orbit_tolerance=OrbitTolerance(residual=ORBIT_TOL), memory=PREVIOUS_CALL,
    linear_prediction=YES, held_body=YES, default_control="lqr",
    trim_table="trim_table_quasi_steady.json", orbit_table="orbit_table_quasi_steady.json")

UVLM = BackendDescriptor(
    name="uvlm", summary="the extended unsteady vortex-lattice method (the reference)", factory=_uvlm,
    calls_per_beat=FLY_UVLM.steps_per_cycle,
    fd=FiniteDifferenceSteps(orbit=UVLM_FD_STEP, monodromy=UVLM_FD_STEP, control=UVLM_FD_STEP),
    orbit_tolerance=OrbitTolerance(residual=ORBIT_TOL, velocity=UVLM_TOL_VELOCITY, rate=UVLM_TOL_RATE),
    memory=WAKE, warm_beats=UVLM_WARM_BEATS, orbits_on_demand=False,
    half_stroke=no("the UVLM's wake cannot be set at phase 0.5 to linearize the half-stroke maps"),
    constrained_control=no("the UVLM's wake is neither a settable state nor a record to difference per-wing "
                           "derivatives from"),
    held_body=YES, shipped_orbits_only=True, linearize_cost="minutes",
    flight_options=("wake_cycles", "wake_precision", "keep_panels"),
    trim_table="trim_table.json", orbit_table="orbit_table_uvlm.json", control_model_table="control_models_uvlm.json")

SURROGATE = BackendDescriptor(
    name="surrogate", summary="the per-step neural surrogate of the UVLM (each wing's instantaneous loads)",
    factory=_step_surrogate, calls_per_beat=FLY_UVLM.steps_per_cycle,
    fd=FiniteDifferenceSteps(orbit=SURROGATE_FD_STEP, monodromy=SURROGATE_FD_STEP, control=SURROGATE_FD_DELTA),
    orbit_tolerance=OrbitTolerance(residual=SURROGATE_ORBIT_TOL), memory=RECORD, history=YES,
    averaged_system=no("the per-step surrogate's averaged A is not implemented (its Floquet multipliers are)"),
    default_control="lqr", default_control_rate="half-stroke", speed_rate=SURROGATE_SPEED_RATE,
    shipped_orbits_only=True,
    saturated_plant=True, drop_bound_channels=True, controlled_factory=_controlled_step_surrogate,
    orbit_guess="uvlm", trim_table="trim_table.json", orbit_table="orbit_table_surrogate.json",
    control_model_table="control_models_surrogate.json", tables_digest=_network_sha256)

SURROGATE_MEAN = BackendDescriptor(
    name="surrogate-mean", summary="the cycle-mean network's averaged L+, D+, M+ (no within-beat loads, no damping)",
    factory=_mean_surrogate, memory=MEMORYLESS, orbits=no(NO_ORBIT), orbits_on_demand=False,
    half_stroke=no(NO_ORBIT), control=no(NO_ORBIT), constrained_control=no(NO_ORBIT), averaged_system=no(NO_ORBIT),
    trim_table="trim_table_surrogate.json")

VACUUM = BackendDescriptor(
    name="none", summary="vacuum: zero loads (momentum-conservation and inertia tests)", factory=_vacuum,
    orbits=no("no aerodynamic loads hold the insect up"), orbits_on_demand=False,
    half_stroke=no("no aerodynamic loads"), control=no("no aerodynamic loads"),
    constrained_control=no("no aerodynamic loads"), averaged_system=no("no aerodynamic loads"), listed=False)

BUILTINS = (QUASI_STEADY, UVLM, SURROGATE, SURROGATE_MEAN, VACUUM)
"""Registered in this order (the order of the ``--aero`` choices)."""
