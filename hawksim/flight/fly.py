"""The open-loop flight from a held-body trim or a start state: ``fly(trim, backend, cycles)``, a wrapper of the one
flight loop :func:`hawksim.flight.loop.fly` (which also takes an :class:`hawksim.flight.orbit.Orbit` and a
controller) that reports progress in steps.

The insect starts at the origin, pitched nose-up so that its cycle-mean body angle is chi, moving straight up
at the trim's ascent speed (world z), wings on their prescribed motion; perturbations (stability axes,
docs/conventions.md: x forward horizontal, y right, z down) are added to that start (:mod:`hawksim.flight.start`).
Or the flight starts on a periodic orbit of the free body (``start_state``, :mod:`hawksim.flight.orbit`). Results
are world-frame time series (SI, :class:`hawksim.flight.result.FlightResult`).
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco

from hawksim.backends.base import AeroBackend
from hawksim.backends.resolution import FLY_STEPS_PER_CYCLE
from hawksim.flight.result import FlightResult
from hawksim.insect.insect import Insect
from hawksim.trim.point import Trim


def fly(trim: Trim, backend: AeroBackend, cycles: int, *, perturb: dict[str, float] | None = None,
        model: mujoco.MjModel | None = None, steps_per_cycle: int = FLY_STEPS_PER_CYCLE, gravity: bool = True,
        keep_extras_every: int = 0, periodic_start: bool = True, start_state: tuple | None = None,
        progress: Callable[[int, int], None] | None = None, partial_on_interrupt: bool = False,
        insect: Insect | None = None) -> FlightResult:
    """Fly for ``cycles`` wingbeats from ``trim`` (its kinematics and ascent speed) with ``backend``'s loads, open
    loop: :func:`hawksim.flight.loop.fly` with no controller (its arguments), except ``progress``, called as
    progress(step, n_steps) after each wingbeat. SI in and out (angles in radians, rates in rad/s), except
    ``perturb``, which takes the CLI's units: m/s, and deg and deg/s for the angles and rates
    (:data:`hawksim.flight.start.PERTURBATIONS`).

    Args:
        perturb: stability-axes disturbances of the initial state (see :data:`hawksim.flight.start.PERTURBATIONS`).
        model: the MuJoCo model (default: generated from the insect's morphology,
            :func:`hawksim.insect.model.load_model`); given, its total mass must be the insect's (ValueError naming
            ``model`` otherwise: the result's L+ and D+ are in units of the insect's weight).
        insect: the insect flown (default :data:`hawksim.insect.insect.DEFAULT_INSECT`, the hawkmoth): its MJCF,
            and the units of the result's L+, D+, M+ and P+ (:attr:`FlightResult.insect`). ``backend`` must be built
            for its wings (:func:`hawksim.backends.flight_backend`'s ``morphology``).
        keep_extras_every: keep the backend's extras every this many steps (0: never).
        periodic_start: start on the trim's periodic path by one calibration wingbeat (``start_on_orbit``).
        start_state: (x (9,), chi_ref) the body state at phase 0 of a periodic orbit of the free body
            (:func:`hawksim.flight.orbit.periodic_orbit`; state order :data:`hawksim.flight.orbit.STATE_NAMES`):
            the flight starts exactly there (plus ``perturb``), with no calibration beat.
        progress: called as progress(step, n_steps).
        partial_on_interrupt: a KeyboardInterrupt during the steps returns the steps completed so far (a result
            with fewer than cycles x steps_per_cycle rows) instead of propagating; none completed: it propagates.
    """
    from hawksim.flight.loop import fly as fly_loop

    steps = None
    if progress is not None:
        def steps(k, n):
            progress(k * steps_per_cycle, n * steps_per_cycle)

    return fly_loop(trim, backend, cycles, perturb=perturb, model=model, steps_per_cycle=steps_per_cycle,
                    gravity=gravity, keep_extras_every=keep_extras_every, periodic_start=periodic_start,
                    start_state=start_state, progress=steps, partial_on_interrupt=partial_on_interrupt,
                    insect=insect)
