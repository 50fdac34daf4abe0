"""The operating point: one frozen :class:`Trim` that flows through the API (python-control's
find_operating_point -> linearize shape): the trim searches return it, `hawksim.flight.fly` flies from it,
the stability analysis linearises about it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from hawksim.backends.averages import OUTPUTS, CycleAverages
from hawksim.insect.kinematics import Kinematics


@dataclass(frozen=True)
class Trim:
    """Kinematics that balance the insect at ascent speed ``speed`` [m/s] on the aerodynamic model ``model``.

    Attributes:
        speed: ascent speed V [m/s].
        kinematics: the seven parameters of Eq. 1 (SI: angles in radians, f in Hz).
        model: the aerodynamic model it balances on ("uvlm", "quasi-steady", "surrogate"; "paper" for Table 3).
        source: where it comes from, in words (a search, a balance, a shipped table and its command).
        averages: the model's cycle averages there (Eq. 2), None where not recorded (an interpolated table row).
        converged: whether the search or balance met its tolerance ``tolerance``.
        fitness: Eq. 3's F at the point (surrogate searches).
        evaluations: model evaluations spent (Nelder-Mead or UVLM runs).
        wall_time_s: wall time of the search [s].
        seed: seed of a random search.
        start: the trim a balance started from.
        search: the genetic algorithm's result (:class:`hawksim.trim.search.GAResult`: per-generation history).
    """

    speed: float
    kinematics: Kinematics
    model: str
    source: str
    averages: CycleAverages | None = None
    converged: bool = True
    tolerance: float | None = None
    fitness: float | None = None
    evaluations: int = 0
    wall_time_s: float = 0.0
    seed: int | None = None
    start: Trim | None = None
    search: Any = None

    @property
    def outputs(self) -> dict[str, float]:
        """{L_plus, D_plus, M_plus, P_plus} of :attr:`averages` (empty if not recorded)."""
        return {} if self.averages is None else {k: float(getattr(self.averages, k)) for k in OUTPUTS}
