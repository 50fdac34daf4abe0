"""The per-step neural surrogate as the backend of the controlled plant: moved to
:mod:`hawksim.backends.controlled_step_surrogate` (the backend's descriptor builds it for the plant,
:func:`hawksim.control.plant.controlled_plant`); this name stays for imports of it."""

from hawksim.backends.controlled_step_surrogate import ControlledStepSurrogate

__all__ = ["ControlledStepSurrogate"]
