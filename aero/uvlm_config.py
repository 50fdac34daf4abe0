"""The extended UVLM's constants and switches (:class:`UVLMConfig`) and the choices they take.

The stepper that reads them is :class:`aero.uvlm.UVLM`; every name here is also importable from :mod:`aero.uvlm`.
Units SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aero.biot_savart import PRECISIONS
from aero.treecode import TreeParams

SHED_RULES = ("ring", "travel")
"""Placements of the newest wake vortex (:class:`UVLMConfig` ``shed_rule``)."""


POTENTIAL_JUMPS = ("panel", "ring")
"""How the unsteady load term reads the potential jump of each panel (:class:`UVLMConfig` ``potential_jump``)."""

TIME_DERIVATIVES = ("bdf2", "euler")
"""The backward difference of the potential jump's time derivative (:class:`UVLMConfig` ``time_derivative``)."""

LEGACY_0_2 = dict(shed_rule="ring", potential_jump="ring", time_derivative="euler")
"""``UVLMConfig(**LEGACY_0_2)`` is hawksim 0.2's UVLM, that of the shipped data sets, networks and tables until
they are regenerated (its unsteady loads exceed Theodorsen's by 10-40 % at k = 1: docs/validation.md)."""

WAKE_SUMMATIONS = ("direct", "tree", "auto")
"""How the wake-on-wake velocities that convect the free wake are summed (:class:`UVLMConfig` ``wake_summation``)."""

TREE_MIN_SEGMENTS = 4000
"""``wake_summation="auto"`` considers the treecode from this many wake segments (edges with circulation, all
solved wings, before mirror images) on, and below takes the direct sum: above the 3-beat wake `hawksim fly`
keeps by default (3012 segments), so that its flights stay the direct sum bit for bit. The crossover depends on
the wake's shape, not only its size (scripts/benchmarks/bench_treecode.py, docs/performance.md, "Treecode"): an
unstretched wake-like lattice 1300-2500 segments, the stretched free wake of a hawkmoth flight none up to 10 beats
(10 000 segments); above this floor "auto" therefore asks the tree's own plan."""

TREE_REPLAN_STEPS = 40
"""``wake_summation="auto"``: steps between two plans of the treecode (a wingbeat at the default resolution; the
wake's shape changes over beats, and a plan costs ~10 % of a direct sum)."""


ROTOR_A_PRIME = 6.5e-5
"""Ramasamy & Leishman (2007)'s a' for rotor tip vortices (J. Am. Helicopter Soc. 52:214)."""


@dataclass(frozen=True)
class UVLMConfig:
    """Solver constants and switches (set them False for a plain UVLM).

    rho [kg/m^3], nu [m^2/s] (air); core_fraction: core radius of the bound vortices as a fraction of the mean
    chordwise panel length: small, so that the influence at a collocation point half a panel away changes by
    < 0.2 %; the wake edges on the trailing edge share it, so a freshly shed wake segment cancels the bound
    trailing-edge segment it leaves exactly; wake_core_chords: initial core of the wake vortices in mean
    chords (a physical viscous core, independent of the lattice so that refining converges), which then
    grows with age (core_growth); a model parameter, not sourced: once the panels are finer than it, it
    suppresses the near wake (the heave lift at k = 0.5, AR 20 reads 0.985 of 2D at 16 chordwise rings against
    0.968 with a vanishing core; the classical cases run with 0.001 c, :data:`aero.plate.PLAIN_CONFIG`);
    convection_core_chords: the core of the bound vortices when they convect
    the wake, in mean chords (a wake vortex passing a lattice must not be flung by the lattice's near field,
    which the panels do not resolve); a_prime: Ramasamy-Leishman's turbulent-viscosity coefficient a' in
    delta = 1 + a' ``|Gamma|`` / nu (their rotor value is ROTOR_A_PRIME = 6.5e-5). The default, 1e-2, is a numerical
    regularisation chosen by the wake-sensitivity study (scripts/studies/wake_sensitivity.py, docs/uvlm.md): with the
    rotor value the low-speed free wake amplifies round-off (a relative 1e-10 change of the kinematics) into up
    to 0.17 of L+ within 4 beats at hover; with 1e-2 the change stays below 1e-8 over those beats at every
    speed, and L+ changes by -0.2 % at 2 m/s and -4 % at 1 m/s against the rotor value;
    max_wake_rows: keep only this many of the newest wake rows (None: no truncation);
    shed_rule: where the trailing edge of the last bound ring row lies, and so the newest wake vortex (the
    starting vortex of each step's shed row): "travel" (the default since issue 48): ``shed_fraction`` x
    (v_air - v_wing) dt behind each trailing-edge corner, Katz & Plotkin's (2001, Sec. 13.7 and 13.12) 0.2-0.3 of
    the distance travelled in the step, so that the near wake scales with dt and the loads converge in the time
    step; "ring" (hawksim 0.2): a quarter of a chordwise panel behind the wing's trailing edge (the ring lattice's
    own geometry) whatever the step's travel, which makes the loads depend on the step (the heave lift at k = 1,
    AR 20, 8 chordwise rings: 1.00, 1.09, 1.15 of 2D theory at 25, 50, 100 steps a period, against 0.99, 1.00,
    1.02 with "travel"; docs/validation.md). The collocation points, normals and areas stay those of the panels.
    potential_jump: the panel's potential jump in the unsteady term -rho d(jump)/dt A n: "panel" (default since
    issue 48) the mean of the two rings that bound it chordwise (the trapezoid rule over the plate), "ring"
    (hawksim 0.2) ring i's own circulation (a right-endpoint sum: heave lift 10-40 % above Theodorsen's).
    time_derivative: that term's backward difference, "bdf2" (default since issue 48; second order, unequal
    steps allowed) or "euler" (hawksim 0.2; first order, half a step of lag). :data:`LEGACY_0_2` gives 0.2's
    three choices together.
    near_wake_zones: opt-in study (0: off): the wing sees the wake within this many chordwise panels of the
    trailing edge lumped panel by panel (:func:`aero.wake.lump_near_wake`); with "ring" and 2 it makes a plate's
    lift independent of the step, not the hawkmoth's (docs/validation.md section 3).
    The sensitivity of L+ and P+ to every tuned constant here: docs/fidelity.md (section 5).
    wake_precision: the pair evaluations of the wake-on-wake velocities that convect the free wake, "float64" or
    "mixed" (float32 evaluations, float64 sums: :data:`aero.biot_savart.PRECISIONS`; opt-in, its effect on the
    cycle averages is measured by scripts/studies/mixed_precision.py, docs/uvlm.md, "Speed"). The wings'
    velocities, and the wake's velocity at the wings, stay float64.
    wake_summation: how the same wake-on-wake velocities are summed: "direct" (default: every segment on every
    corner, O(N^2) in the wake size), "tree" (:mod:`aero.treecode`, a Barnes-Hut treecode with opening angle
    ``tree_theta``, ~O(N log N)) or "auto" (the direct sum below :data:`TREE_MIN_SEGMENTS` wake segments; above,
    the tree where its own plan says it is the faster, checked once every :data:`TREE_REPLAN_STEPS` steps). With
    the tree, the wings' share stays the direct float64 sum; the wake's velocity at the wings (the solve and the
    loads) is always the direct sum. Opt-in (the default's results are bit for bit those of the direct sum); at
    the default tree_theta = 0.2 the cycle averages stay within 1e-4 of the direct sum's on the reference case
    (L, D, M, P) and at hover and 2 m/s (L+, D+, M+, P+); at 0.3 and 0.4 the reference case misses it (python
    scripts/benchmarks/bench_treecode.py --sections accuracy, docs/performance.md, "Treecode"). Needs
    wake_precision "float64".
    tree_theta: the treecode's opening angle (:class:`aero.treecode.TreeParams`; 0 gives the direct sum).
    free_wake_age: opt-in (None: the whole wake is free): wake corners older than this [s] leave the free wake and
    move with the free stream plus ``far_wake_drift`` instead of the velocity the wings and the wake induce there
    (a prescribed far wake; they still induce velocity on the wings and on the free part). A model choice for the
    hover orbit (issue 49, item 4; docs/free_flight.md "A periodic orbit at hover"): at hover the free wake stays
    under the wings and amplifies any change of the flight ~300-fold within three beats, so the one-beat map has no
    derivative a Newton solver can use; a wake free only while young keeps its roll-up near the wings and makes
    the far wake a smooth function of the flight.
    far_wake_drift: (3,) world-frame velocity [m/s] added to the free stream for the prescribed far wake (the
    caller's model of the mean induced velocity there, e.g. momentum theory's downwash).
    """

    rho: float = 1.225
    nu: float = 1.5e-5
    core_growth: bool = True
    le_suction: bool = True
    free_wake: bool = True
    core_fraction: float = 0.02
    wake_core_chords: float = 0.05
    convection_core_chords: float = 0.1
    a_prime: float = 1e-2
    max_wake_rows: int | None = None
    shed_rule: str = "travel"
    shed_fraction: float = 0.25
    potential_jump: str = "panel"
    time_derivative: str = "bdf2"
    near_wake_zones: int = 0
    wake_precision: str = "float64"
    wake_summation: str = "direct"
    tree_theta: float = TreeParams.theta
    free_wake_age: float | None = None
    far_wake_drift: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        if self.free_wake_age is not None and not (np.isfinite(self.free_wake_age) and self.free_wake_age >= 0.0):
            raise ValueError(f"UVLMConfig.free_wake_age must be None or a finite age >= 0 s, "
                             f"got {self.free_wake_age!r}")
        drift = np.asarray(self.far_wake_drift, dtype=float)
        if drift.shape != (3,) or not np.all(np.isfinite(drift)):
            raise ValueError(f"UVLMConfig.far_wake_drift must be 3 finite velocities [m/s], "
                             f"got {self.far_wake_drift!r}")
        if self.shed_rule not in SHED_RULES:
            raise ValueError(f"UVLMConfig.shed_rule must be one of {', '.join(SHED_RULES)}, got {self.shed_rule!r}")
        if int(self.near_wake_zones) != self.near_wake_zones or self.near_wake_zones < 0:
            raise ValueError(f"UVLMConfig.near_wake_zones must be a non-negative integer, got {self.near_wake_zones!r}")
        if self.potential_jump not in POTENTIAL_JUMPS:
            raise ValueError(f"UVLMConfig.potential_jump must be one of {', '.join(POTENTIAL_JUMPS)}, "
                             f"got {self.potential_jump!r}")
        if self.time_derivative not in TIME_DERIVATIVES:
            raise ValueError(f"UVLMConfig.time_derivative must be one of {', '.join(TIME_DERIVATIVES)}, "
                             f"got {self.time_derivative!r}")
        if not (np.isfinite(self.shed_fraction) and 0.0 < self.shed_fraction <= 1.0):
            raise ValueError(f"UVLMConfig.shed_fraction must lie in (0, 1], got {self.shed_fraction!r}")
        if self.wake_precision not in PRECISIONS:
            raise ValueError(f"UVLMConfig.wake_precision must be one of {PRECISIONS}, got {self.wake_precision!r}")
        if self.wake_summation not in WAKE_SUMMATIONS:
            raise ValueError(f"UVLMConfig.wake_summation must be one of {WAKE_SUMMATIONS}, "
                             f"got {self.wake_summation!r}")
        TreeParams(theta=self.tree_theta)  # checks it
        if self.wake_summation != "direct" and self.wake_precision != "float64":
            raise ValueError("UVLMConfig.wake_summation 'tree' / 'auto' needs wake_precision 'float64'")
