"""Aerodynamic models of the hawkmoth's wings, behind one protocol (:class:`hawksim.backends.base.AeroBackend`:
flight state in, wing loads out, world frame, SI).

Modules: ``base`` (the protocol, :class:`FlightState`, :class:`WingLoads`, vacuum), ``averages`` (the paper's
Eq. 2 cycle averages every model is compared in), ``resolution`` (lattices and time steps), ``quasi_steady``,
``uvlm``, ``network`` (the cycle-mean ANN surrogate's files and inference), ``surrogate`` (that network as the
``surrogate-mean`` flight backend), ``step_network`` and ``step_surrogate`` (the per-step surrogate of the UVLM, the
``surrogate`` flight backend).
:func:`make_backend` builds any of them by the name the CLI uses.
"""

from __future__ import annotations

from hawksim.backends.resolution import DEFAULT, FLY_UVLM, FLY_WAKE_CYCLES, Resolution
from hawksim.lazy import lazy_exports

FLIGHT_BACKENDS = ("quasi-steady", "uvlm", "surrogate", "surrogate-mean")
"""The built-in backends `hawksim fly` accepts (``--aero``; with any registered later:
:func:`hawksim.backends.registry.names`): "surrogate" is the per-step network of the UVLM's instantaneous wing loads
(:mod:`hawksim.backends.step_surrogate`), "surrogate-mean" the cycle-mean network's averaged loads
(:mod:`hawksim.backends.surrogate`); "none" (vacuum) is for tests."""


def make_backend(name: str, *, resolution: Resolution | None = None, symmetric: bool = True, freestream=None,
                 keep_panels: bool = False, max_wake_rows: int | None = None, kinematics=None,
                 wake_summation: str = "direct", wake_precision: str = "float64", morphology=None):
    """The backend called ``name`` (a registered one, :func:`hawksim.backends.registry.names`, or "none"), built by
    its descriptor's factory. ValueError for an unknown one.

    Args:
        resolution: the UVLM lattice (n_chord x n_span rings per wing; default :data:`DEFAULT`).
        symmetric: the motion stays left/right symmetric, so the UVLM may solve one wing and mirror it.
        freestream: an ``aero.uvlm.FreeStream`` disturbance field (UVLM only).
        keep_panels: keep panel pressure and the wake for recordings (UVLM only).
        max_wake_rows: truncate the UVLM wake to this many newest rows (None: keep all).
        kinematics: the flight's kinematics (the surrogate backends' network input).
        wake_summation: the UVLM's wake-on-wake summation ("direct", "tree", "auto":
            ``aero.uvlm.UVLMConfig.wake_summation``).
        wake_precision: the UVLM's wake-on-wake pair evaluations ("float64", "mixed":
            ``aero.uvlm.UVLMConfig.wake_precision``).
        morphology: the insect's wings (:class:`hawksim.insect.morphology.Morphology`; None: the default
            hawkmoth's). The quasi-steady model and the UVLM build their wings from it; the networks, trained on
            the default hawkmoth, refuse another (ValueError naming ``morphology``).
    """
    from hawksim.backends.registry import descriptor

    return descriptor(name).make(resolution=resolution, symmetric=symmetric, freestream=freestream,
                                 keep_panels=keep_panels, max_wake_rows=max_wake_rows, kinematics=kinematics,
                                 wake_summation=wake_summation, wake_precision=wake_precision,
                                 morphology=morphology)


def backend_for(res: Resolution, *, symmetric: bool = True, freestream=None, morphology=None):
    """The backend of a held-body resolution (``res.aero`` at ``res``'s lattice) for ``morphology`` (None: the
    default hawkmoth's)."""
    return make_backend(res.aero, resolution=res, symmetric=symmetric, freestream=freestream, morphology=morphology)


def flight_backend(name: str, *, kinematics=None, symmetric: bool = True, keep_panels: bool = False,
                   wake_cycles: int = FLY_WAKE_CYCLES, wake_summation: str = "auto", wake_precision: str = "float64",
                   morphology=None):
    """The backend of `hawksim fly --aero NAME`: the UVLM at :data:`FLY_UVLM` keeping the last ``wake_cycles``
    wingbeats of wake (default :data:`FLY_WAKE_CYCLES`), its wake-on-wake velocities summed with
    ``wake_summation`` (default "auto": the direct sum below ``aero.uvlm.TREE_MIN_SEGMENTS`` wake segments, so
    that the default 3-beat wake, 3012 segments, is the direct sum bit for bit; above, the treecode where its plan
    says it is the faster, which a hawkmoth flight's stretched wake of up to 10 beats is not:
    docs/performance.md, "Treecode"), in ``wake_precision`` (default "float64"; "mixed" is opt-in: docs/uvlm.md;
    the treecode is float64 only, so with "mixed" "auto" means the direct sum). ``morphology``: the insect's
    (None: the default hawkmoth's; :func:`make_backend`)."""
    if int(wake_cycles) != wake_cycles or wake_cycles < 1:
        raise ValueError(f"wake_cycles must be a positive integer, got {wake_cycles!r}")
    if wake_precision != "float64" and wake_summation == "auto":
        wake_summation = "direct"
    return make_backend(name, resolution=FLY_UVLM, symmetric=symmetric, keep_panels=keep_panels,
                        max_wake_rows=int(wake_cycles) * FLY_UVLM.steps_per_cycle, kinematics=kinematics,
                        wake_summation=wake_summation, wake_precision=wake_precision, morphology=morphology)


_LAZY, __getattr__, __dir__ = lazy_exports(__name__, {
    ".base": ("AeroBackend", "FlightState", "WingLoads", "NoAero"),
    ".averages": ("CycleAverages", "cycle_averages"),
    ".held": ("held_flight", "HeldResult"),
    ".quasi_steady": ("QuasiSteadyBackend",),
    ".uvlm": ("UVLMBackend",),
    ".surrogate": ("SurrogateBackend",),
    ".step_surrogate": ("StepSurrogateBackend",),
    ".registry": ("BackendDescriptor", "Support", "FiniteDifferenceSteps", "OrbitTolerance", "register",
                  "unregister", "descriptor", "descriptor_of", "find", "names"),
    ".memory": ("MEMORYLESS", "PREVIOUS_CALL", "RECORD", "WAKE", "PrimedMemory", "RecordMemory"),
    ".far_wake": ("FarWake", "far_wake_for", "momentum_downwash"),
})
__all__ = ["FLIGHT_BACKENDS", "make_backend", "backend_for", "flight_backend", "Resolution", "DEFAULT", *_LAZY]
