"""Cycle averages in the paper's nondimensional form (Nguyen et al. 2020, Eq. 2): the one quantity every
aerodynamic model, data set, surrogate and trim is compared in.

L+ = L/W, D+ = D/W, M+ = M/(W cbar), P+ = P/P0, with W = m g and P0 the insect's (:class:`hawksim.insect.insect.
Insect`; the default hawkmoth's P0 = 84.2 mW);
lift along world z, drag along minus the body's horizontal heading (world -x), M the nose-up pitching moment
about the body's centre of mass. Required power: the cycle mean of max(0, P) (no elastic storage; negative power
is dissipated, docs/conventions.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect

OUTPUTS = ("L_plus", "D_plus", "M_plus", "P_plus")
"""The normalised cycle averages (Eq. 2) in the column order that data sets store and surrogates predict."""


@dataclass(frozen=True)
class CycleAverages:
    """Nondimensional cycle averages (paper Eq. 2) and the required power [W]."""

    L_plus: float
    D_plus: float
    M_plus: float
    P_plus: float
    power_W: float

    def as_tuple(self) -> tuple[float, float, float, float]:
        """(L+, D+, M+, P+), the order of :data:`OUTPUTS`."""
        return tuple(getattr(self, k) for k in OUTPUTS)

    def to_dict(self) -> dict[str, float]:
        return {k: float(getattr(self, k)) for k in (*OUTPUTS, "power_W")}

    @staticmethod
    def from_plus(values, power_W: float | None = None) -> CycleAverages:
        """From (L+, D+, M+, P+) (order of :data:`OUTPUTS`); power_W defaults to P+ P0 (the default insect's: the
        networks' training insect)."""
        L, D, M, P = (float(v) for v in values)
        return CycleAverages(L, D, M, P, P * default_insect().P0 if power_W is None else float(power_W))


def cycle_averages(lift, drag, moment, power, insect: Insect | None = None) -> CycleAverages:
    """Averages of one or more whole cycles of the time series (each (n,), SI: N, N, N m, W), in units of
    ``insect``'s weight, mean chord and P0 (None: :func:`hawksim.insect.folder.default_insect`)."""
    insect = default_insect() if insect is None else insect
    W = insect.weight
    p_req = float(np.maximum(power, 0.0).mean())
    return CycleAverages(L_plus=float(np.mean(lift) / W), D_plus=float(np.mean(drag) / W),
                         M_plus=float(np.mean(moment) / (W * insect.cbar)), P_plus=p_req / insect.P0, power_W=p_req)
