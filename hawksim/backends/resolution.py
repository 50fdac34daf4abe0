"""Numerical resolutions of the aerodynamic models: lattice, time step, wingbeats simulated and averaged.

One home for the resolutions every command uses: :data:`DEFAULT` (`hawksim aero`, trim checks, stability),
:data:`TRAINING` (the surrogate's data sets), :data:`REFERENCE` (the reference-lattice labels of the multi-fidelity
surrogate, equal to DEFAULT) and :data:`FLY_UVLM` (`hawksim fly --aero uvlm`); :data:`NAMED` maps the names
`hawksim dataset --resolution` accepts to them.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

AERO_MODELS = ("uvlm", "quasi-steady")
"""The built-in models that a :class:`Resolution` can name (the held-body evaluations; any registered backend whose
descriptor supports ``held_body``, :mod:`hawksim.backends.registry`)."""


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
        if self.aero not in AERO_MODELS:  # the built-in ones without the registry (it needs this module)
            from hawksim.backends.registry import names

            held = names(listed=False, having="held_body")
            if self.aero not in held:
                raise ValueError(f"resolution aero must be one of {', '.join(map(repr, held))}, got {self.aero!r}")
        for k in ("n_chord", "n_span", "steps_per_cycle", "cycles", "average_cycles"):
            if int(getattr(self, k)) != getattr(self, k) or getattr(self, k) < 1:
                raise ValueError(f"resolution {k} must be a positive integer, got {getattr(self, k)}")
        if self.average_cycles > self.cycles:
            raise ValueError(f"average_cycles {self.average_cycles} exceeds cycles {self.cycles}")

    def to_dict(self) -> dict:
        return asdict(self)


DEFAULT = Resolution()
"""``hawksim aero`'s default resolution: 6 x 12 rings per wing, 40 steps per beat, 3 beats, the last averaged.

Its error, measured against the Richardson limit of the lattice and the step refined together (4 x 8 / 40 ->
8 x 16 / 80 -> 16 x 32 / 160 at Table 3's kinematics; ``python scripts/studies/uvlm_resolution.py``,
results/uvlm_resolution.json, docs/validation.md section 4): L+ -1.4 % and -0.2 %, P+ -0.4 % and -0.2 %, the
within-beat lift peak -0.6 % and -0.7 % at 1 and 2 m/s (targets: 2 % for the averages, 5 % for the peak; the levels
are not monotone, so the limit is known to ~0.5 %). Cost: 1.3-2.4 s a run, against 10-11 s and 6-8 min for the two
finer levels (one sitting, load 3-7). Hover has no converged limit (L+ 0.86, 0.82, 0.91 along the path: the
wake's encounters with the wings are irregular). The step alone is not converged at this lattice: L+ moves +4.6 %
(1 m/s) and +2.4 % (2 m/s) from 40 to 160 steps (docs/validation.md section 3): refine lattice and step together."""

TRAINING = Resolution(n_chord=4, n_span=8, steps_per_cycle=30, cycles=3)
"""Resolution of the surrogate's training data (0.4 s per sample, 2.5x cheaper than DEFAULT; 3.8x measured on
2026-12-02, 0.16 against 0.60 s, results/surrogate/reference_label_cost.json): P+ within 2 % and
L+ within 8 % of DEFAULT at Table 3's kinematics; the trim is re-balanced on the UVLM at DEFAULT afterwards."""

REFERENCE = DEFAULT
"""Resolution of the reference labels (``hawksim dataset --resolution reference``): `hawksim aero`'s default lattice,
so a reference label is exactly what a fresh `hawksim aero` run gives at those kinematics (docs/surrogate.md,
"A surrogate of the reference UVLM")."""

NAMED = {"training": TRAINING, "reference": REFERENCE}
"""Named resolutions of `hawksim dataset --resolution NAME` (the options --n-chord etc. override single fields)."""

FLY_UVLM = DEFAULT
"""Lattice and UVLM update rate of `hawksim fly --aero uvlm` (the MuJoCo step is finer; loads are held)."""

FLY_WAKE_CYCLES = 3
"""`hawksim fly --aero uvlm` keeps the wake of the last 3 wingbeats (older rows are far below the insect and the
cost of a free wake grows with the square of its length)."""

FLY_STEPS_PER_CYCLE = 200
"""Integration steps per wingbeat of a free flight (`hawksim fly`'s default; RK4's body-velocity error is then
~1e-6 m/s, tests/hawksim/test_simulation.py)."""

MIN_STEPS_PER_CYCLE = 20
"""Fewest integration steps per wingbeat the flight loop accepts."""
