"""The per-step neural surrogate (:mod:`hawksim.backends.step_surrogate`) as the backend of the controlled plant.

The surrogate's network takes the seven kinematic parameters and the wing phase as inputs; its flight backend holds
the kinematics it was built with and the phase 2 pi f t of their f. Under control both change from beat to beat and
differ between the wings (antisymmetric commands), so :class:`ControlledStepSurrogate` feeds the network, at every
call, each wing's parameters and the phase of the controlled plant
(:meth:`hawksim.control.plant.ControlledSimulator.network_kinematics`: the blend of the previous beat's kinematics
into the new one, as the prescribed wing motion blends them); everything else (body velocity relative to the air and
angular velocity in body axes, the mirror image for the right wing, the world-frame loads, the power) is the base
backend's. Until :meth:`ControlledStepSurrogate.bind` it is the base backend.

A network with history lags reads its record of past calls at the flight's own time (the plant's phase is a
separate input); its one-beat and half-stroke maps then start from the orbit's record
(:mod:`hawksim.control.derivatives`, :mod:`hawksim.control.halfstroke`).
"""

from __future__ import annotations

from dataclasses import replace

from hawksim.backends.base import FlightState, WingLoads
from hawksim.backends.step_surrogate import StepSurrogateBackend
from hawksim.insect.kinematics import Kinematics


class ControlledStepSurrogate(StepSurrogateBackend):
    """The per-step surrogate with per-wing kinematics and phase from the controlled plant (module docstring)."""

    def __init__(self, kin: Kinematics, network=None):
        super().__init__(kin, network)
        self._plant = None
        self._plant_phase = 0.0

    def bind(self, plant) -> None:
        """Read the kinematic inputs from ``plant`` (a :class:`hawksim.control.plant.ControlledSimulator`)."""
        self._plant = plant

    def native(self, every: int):
        """The network for the flight loop's native callback: bound to a plant, its kinematic inputs and phase are
        the plant's blend, which the callback evaluates itself (``plant_kinematics``; the plant keeps the blend in
        the callback's parameters, :meth:`hawksim.control.plant.ControlledSimulator._sync_native`)."""
        net = super().native(every)
        if net is None or self._plant is None:
            return net
        return replace(net, plant_kinematics=True)

    def loads(self, state: FlightState) -> WingLoads:
        if self._plant is None:
            return super().loads(state)
        params, self._plant_phase = self._plant.network_kinematics(state.t)
        self._x[:, :7] = params
        return super().loads(state)

    def _phase(self, state: FlightState) -> float:
        return self._plant_phase if self._plant is not None else super()._phase(state)
