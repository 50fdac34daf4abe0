"""One cycle-averaged evaluation of a kinematics at an ascent speed: the unit of work of data sets, trim checks
and `hawksim aero`.

``evaluate(kin, speed, resolution)`` runs :func:`hawksim.held.held_flight` with the backend and resolution
given, and returns the last cycle's L+, D+, M+, P+ (paper Eq. 2) and the required power [W].
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace

import numpy as np

from hawksim.held import CycleAverages, HeldResult, held_flight
from hawksim.kinematics import Kinematics


@dataclass(frozen=True)
class Resolution:
    """Numerical resolution of one evaluation.

    aero: 'uvlm' or 'quasi-steady'; n_chord, n_span: UVLM panels per wing (chordwise, spanwise);
    steps_per_cycle: time steps per wingbeat; cycles: wingbeats simulated; average_cycles: wingbeats at the end
    that are averaged (the first ones carry the start-up transient of the wake).
    """

    aero: str = "uvlm"
    n_chord: int = 6
    n_span: int = 12
    steps_per_cycle: int = 40
    cycles: int = 3
    average_cycles: int = 1

    def __post_init__(self):
        if self.aero not in ("uvlm", "quasi-steady"):
            raise ValueError(f"resolution aero must be 'uvlm' or 'quasi-steady', got {self.aero!r}")
        for k in ("n_chord", "n_span", "steps_per_cycle", "cycles", "average_cycles"):
            if int(getattr(self, k)) != getattr(self, k) or getattr(self, k) < 1:
                raise ValueError(f"resolution {k} must be a positive integer, got {getattr(self, k)}")
        if self.average_cycles > self.cycles:
            raise ValueError(f"average_cycles {self.average_cycles} exceeds cycles {self.cycles}")

    def to_dict(self) -> dict:
        return asdict(self)


DEFAULT = Resolution()
"""``hawksim aero`'s default resolution: 6 x 12 rings per wing, 40 steps per beat, 3 beats, the last averaged.
Convergence study (results/uvlm_convergence_v1.json, docs/uvlm.md): doubling the rings in both directions
and the steps per beat changes L+ and P+ by less than 3 %."""

TRAINING = Resolution(n_chord=4, n_span=8, steps_per_cycle=30, cycles=3)
"""Resolution of the surrogate's training data (0.4 s per sample, 2.5x cheaper than DEFAULT): P+ within 2 % and
L+ within 8 % of DEFAULT at Table 3's kinematics; the trim is re-balanced on the UVLM at DEFAULT afterwards."""

FLY_UVLM = DEFAULT
"""Lattice and UVLM update rate of `hawksim fly --aero uvlm` (the MuJoCo step is finer; loads are held)."""


def make_backend(res: Resolution, *, symmetric: bool = True, freestream=None):
    """The backend of a resolution. symmetric: the motion is left/right symmetric (UVLM mirror images);
    freestream: an ``aero.uvlm.FreeStream`` disturbance field (UVLM only)."""
    if res.aero == "quasi-steady":
        from hawksim.qs_backend import QuasiSteadyBackend

        return QuasiSteadyBackend()
    from hawksim.uvlm_backend import UVLMBackend

    return UVLMBackend(n_chord=res.n_chord, n_span=res.n_span, symmetric=symmetric, freestream=freestream)


def run(kin: Kinematics, speed: float, res: Resolution = DEFAULT, progress=None) -> HeldResult:
    """The held-body run of one evaluation (time series and averages)."""
    return held_flight(kin, speed, make_backend(res), cycles=res.cycles, average_cycles=res.average_cycles,
                       steps_per_cycle=res.steps_per_cycle, progress=progress)


def evaluate(kin: Kinematics, speed: float, res: Resolution = DEFAULT) -> CycleAverages:
    """Cycle averages of one evaluation."""
    return run(kin, speed, res).averages


OUTPUTS = ("L_plus", "D_plus", "M_plus", "P_plus")
"""The normalised cycle averages (paper Eq. 2) that data sets store and surrogates predict, in column order."""


def beat_averages(kin: Kinematics, speed: float, res: Resolution, beats: int) -> np.ndarray:
    """Each wingbeat's L+, D+, M+, P+ of a run of ``beats`` wingbeats at ``res``'s lattice: shape (beats, 4),
    columns :data:`OUTPUTS`. Row ``res.cycles - 1`` is the label ``evaluate(kin, speed, res)`` gives when
    ``res.average_cycles`` is 1 (the run is deterministic and does not depend on later beats).
    Raises FloatingPointError when the UVLM diverges."""
    r = run(kin, speed, replace(res, cycles=int(beats), average_cycles=1))
    return np.array([[getattr(c, n) for n in OUTPUTS] for c in r.per_cycle])
