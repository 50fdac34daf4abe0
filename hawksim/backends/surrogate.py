"""`hawksim fly --aero surrogate-mean`: cycle-averaged loads from the speed-input surrogate network.

(`--aero surrogate` is the per-step surrogate of :mod:`hawksim.backends.step_surrogate`.)

The network (:mod:`hawksim.backends.network`, the shipped ``uvlm_all_speeds`` file) predicts the cycle averages
L+, D+, M+, P+ (paper Eq. 2) of the UVLM for the flight's wing kinematics at an ascent speed V in [0, 2] m/s.
Each step this backend reads V as the body's upward velocity relative to the air (clipped to that range) and
applies the predicted mean loads: lift L+ W upward (world z), drag D+ W opposite to the heading (world -x, the
held runs' convention), the nose-up pitching moment M+ W cbar about the body's lateral axis, all about the
centre of mass, split equally over the two wing hinges. Power P+ P0 [W].

What it leaves out, by construction: the loads' variation within a wingbeat (the wings' inertia still shakes
the body), and any dependence on the horizontal velocity, the body rates or attitude, which are not network
inputs. It is the cheap, averaged model for long flights and for checking that a trim holds; the UVLM backend
is the reference.
"""

from __future__ import annotations

import numpy as np

from hawksim.backends.base import FlightState, WingLoads
from hawksim.backends.network import SPEED_BOUNDS, Surrogate, load, shipped_path
from hawksim.frames import cross
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.folder import default_insect
from hawksim.insect.morphology import Morphology


class SurrogateBackend:
    """Mean loads of ``network`` (a speed-input :class:`Surrogate`; default: the shipped one) for ``kin``."""

    name = "surrogate-mean"

    def __init__(self, kin: Kinematics, network: Surrogate | None = None, morph: Morphology | None = None):
        net = network if network is not None else load(shipped_path(None))
        if net.inputs.speed is not None:
            raise ValueError("--aero surrogate-mean needs the speed-input network (the ascent speed changes in "
                             f"flight), not one trained at {net.inputs.speed:g} m/s only")
        self.net, self.x = net, kin.as_array()[None, :]
        self.morph = default_insect().morphology if morph is None else morph  # None: the default insect's
        self.P0 = default_insect().P0  # the network's P+ is in its training insect's P0
        self._cache: tuple[float, np.ndarray] | None = None

    def reset(self, state: FlightState) -> None:
        self._cache = None

    def mean_loads(self, speed: float) -> np.ndarray:
        """(L+, D+, M+, P+) at ascent speed [m/s], clipped to the network's range."""
        v = float(np.clip(speed, *SPEED_BOUNDS))
        if self._cache is None or self._cache[0] != v:
            self._cache = (v, self.net.predict(self.x, v)[0])
        return self._cache[1]

    def loads(self, state: FlightState) -> WingLoads:
        L, D, M, P = self.mean_loads(state.body_v[2] - state.air_v[2])
        W = self.morph.weight
        F = np.array([-D * W, 0.0, L * W])
        moment_com = -M * W * self.morph.cbar * state.body_R[:, 1]  # nose-up = -(moment . body y)
        f_wing = np.tile(F / 2, (2, 1))
        m_wing = moment_com / 2 - cross(state.wing_origin - state.body_pos, f_wing)
        return WingLoads(force=f_wing, moment=m_wing, power=float(P * self.P0))
