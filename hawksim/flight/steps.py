"""What the flight loop's steps produce: one step's :class:`StepRecord` and ``n`` consecutive steps'
:class:`StepBatch` (world frame, SI), as :class:`hawksim.flight.simulator.Simulator`'s ``step`` and ``advance``
return them; both are also importable from :mod:`hawksim.flight.simulator`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hawksim.backends.base import FlightState, WingLoads
from hawksim.frames import cross


@dataclass(frozen=True)
class StepRecord:
    """What one step produced (world frame, SI)."""

    state: FlightState
    loads: WingLoads
    joint_power: float
    """Mechanical power delivered by the six wing joints, sum of tau_j qdot_j at the step start [W]."""


@dataclass(frozen=True)
class StepBatch:
    """What ``n`` consecutive steps produced (world frame, SI), each step's state at its start: t (n,),
    body_pos (n, 3) (the body's centre of mass), body_R (n, 3, 3), body_v (n, 3), body_omega (n, 3) (world),
    wing_R (n, 2, 3, 3), wing_origin (n, 2, 3) (hinges), force (n, 2, 3), moment (n, 2, 3) (about each hinge),
    power_aero (n,) [W], power_joint (n,) [W] (as :class:`StepRecord`), extras [(step index, dict)], and
    ``first``: the index of the first step since the last reset."""

    t: np.ndarray
    body_pos: np.ndarray
    body_R: np.ndarray
    body_v: np.ndarray
    body_omega: np.ndarray
    wing_R: np.ndarray
    wing_origin: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    power_aero: np.ndarray
    power_joint: np.ndarray
    extras: list
    first: int

    def __len__(self) -> int:
        return len(self.t)

    def moment_about_body(self) -> np.ndarray:
        """(n, 3) total aerodynamic moment about the body's centre of mass [N m] (``WingLoads.moment_about``)."""
        arm = self.wing_origin - self.body_pos[:, None, :]
        return (self.moment + cross(arm, self.force)).sum(1)

    @classmethod
    def of(cls, records: list[StepRecord], extras_every: int, first: int) -> StepBatch:
        """From :meth:`hawksim.flight.simulator.Simulator.step`'s records."""
        n = len(records)
        st = [r.state for r in records]
        ld = [r.loads for r in records]

        def arr(values, shape):
            return np.array(values, dtype=float).reshape((n, *shape))

        extras = [(first + j, r.loads.extras) for j, r in enumerate(records)
                  if extras_every and (first + j) % extras_every == 0 and r.loads.extras]
        return cls(t=arr([s.t for s in st], ()), body_pos=arr([s.body_pos for s in st], (3,)),
                   body_R=arr([s.body_R for s in st], (3, 3)), body_v=arr([s.body_v for s in st], (3,)),
                   body_omega=arr([s.body_omega for s in st], (3,)), wing_R=arr([s.wing_R for s in st], (2, 3, 3)),
                   wing_origin=arr([s.wing_origin for s in st], (2, 3)), force=arr([x.force for x in ld], (2, 3)),
                   moment=arr([x.moment for x in ld], (2, 3)), power_aero=arr([x.power for x in ld], ()),
                   power_joint=arr([r.joint_power for r in records], ()), extras=extras, first=first)

    @classmethod
    def from_record(cls, rec: np.ndarray, extras, first: int) -> StepBatch:
        """From the native callback's recorder rows (:data:`hawksim.flight.native.REC_WIDTH`); the derived rows
        (body_omega = R w, power_joint = tau . qd) by the stacked products that give
        :meth:`hawksim.flight.simulator.Simulator.step`'s floats."""
        from hawksim.flight import native as N

        n = len(rec)
        R = rec[:, N.REC_R:N.REC_R + 9].reshape(n, 3, 3)
        qv = rec[:, N.REC_QVEL:N.REC_QVEL + 6]
        tau, qd = rec[:, N.REC_TAU:N.REC_TAU + 6], rec[:, N.REC_QD:N.REC_QD + 6]
        return cls(t=rec[:, N.REC_T].copy(), body_pos=rec[:, N.REC_POS:N.REC_POS + 3].copy(), body_R=R.copy(),
                   body_v=qv[:, :3].copy(), body_omega=np.matmul(R, qv[:, 3:, None])[..., 0],
                   wing_R=rec[:, N.REC_WR:N.REC_WR + 18].reshape(n, 2, 3, 3).copy(),
                   wing_origin=rec[:, N.REC_WO:N.REC_WO + 6].reshape(n, 2, 3).copy(),
                   force=rec[:, N.REC_F:N.REC_F + 6].reshape(n, 2, 3).copy(),
                   moment=rec[:, N.REC_M:N.REC_M + 6].reshape(n, 2, 3).copy(), power_aero=rec[:, N.REC_PA].copy(),
                   power_joint=np.matmul(tau[:, None, :], qd[:, :, None])[:, 0, 0], extras=extras,
                   first=first)
