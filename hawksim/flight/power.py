"""Required power of a free flight whose aerodynamic loads are held between backend updates.

The required power is the cycle mean of max(0, P) with P(t) = P_aero(t) + P_inertial(t), the mechanical power of
the six wing joints (docs/conventions.md; the flight records it per step as ``power_joint`` = tau . qdot at the
step's start, tau the computed torque of the step's first RK4 stage). The flight loop calls the backend every
``aero_every`` steps and holds its loads (fixed world force and moment about each hinge) over the steps in between
(:meth:`hawksim.flight.simulator.Simulator.step`). At an update step the held loads are the backend's loads of
that very state, so the joint power there is P_aero(t_k) + P_inertial(t_k), as in the held-body run
(:func:`hawksim.backends.held.held_flight`, which samples both at the backend's own rate). At the steps in
between the aerodynamic part is the LAGGING load of t_k against the wings' motion at t_k + j dt, paired with the
inertial power of t_k + j dt: the unclipped mean is unbiased to O(dt) (the lag averages out over a beat), but
max(0, .) is not linear, and where P changes sign within a hold the lagging load moves the zero crossings.
Measured (issue 48): a heavy-body UVLM flight (6 x 12 rings, 200 steps, backend every 5) gave P+ 1.1035 against
the held body's 1.1346 (-2.7 %) with L+, D+, M+ within 4e-4 and the unclipped mean within 0.6 %; the quasi-steady
backend forced to the same hold, 0.9206 against 0.9475.

``sampling="updates"`` (the default, :data:`POWER_SAMPLING`) takes the mean of max(0, P) over the update steps
only (the rows whose global step index is a multiple of ``aero_every``): P_aero and P_inertial of the same
instant, the held body's estimator at the backend's rate; the heavy-body check
(tests/hawksim/test_heavy_body.py) then agrees with the held body within 5e-5 (quasi-steady, UVLM and per-step
surrogate every 5 of 200 steps, where every step's joint power gave -2.8 %, -3.0 %, -1.5 %:
scripts/studies/held_power_bias.py, docs/free_flight.md "Required power with held loads"). The dynamics are
unchanged (the loads applied are the same held ones), only the power's estimate changes. With ``aero_every`` = 1
(the quasi-steady backend in `hawksim fly`) both samplings are the same numbers.

``sampling="steps"`` is the estimate before this change (every step's joint power, lag included): the P+ of the
shipped UVLM and surrogate orbit tables (``insects/hawkmoth/data/orbit_table_{uvlm,surrogate}.json``) and of the results
written before this change (issue 48, item 5) were computed this way; set :data:`POWER_SAMPLING` to "steps" (or pass
it) to reproduce them.
"""

from __future__ import annotations

import numpy as np


SAMPLINGS = ("updates", "steps")
"""The two estimators of the required power (module docstring)."""

POWER_SAMPLING = "updates"
"""The default sampling of :func:`required_power` where a caller passes none: "updates" (unbiased against the held
body) or "steps" (the zero-order-hold estimate of artefacts written before issue 48's fix)."""


def update_mask(n: int, aero_every: int, first: int = 0) -> np.ndarray:
    """(n,) bool: which of n consecutive steps, the first with global step index ``first``, are backend updates
    (index % aero_every == 0, :meth:`hawksim.flight.simulator.Simulator.step`)."""
    if aero_every < 1:
        raise ValueError(f"aero_every must be >= 1, got {aero_every}")
    return (first + np.arange(int(n))) % int(aero_every) == 0


def required_power(power_joint: np.ndarray, aero_every: int = 1, *, first: int = 0,
                   sampling: str | None = None) -> float:
    """Mean of max(0, P) [W] over the steps of ``power_joint`` (n,) [W] (joint power at each step's start, the rows
    of one or more whole wingbeats), sampled as ``sampling`` says (None: :data:`POWER_SAMPLING`): "updates", the
    backend-update steps only (row j is one when (first + j) % aero_every == 0); "steps", every row."""
    sampling = POWER_SAMPLING if sampling is None else sampling
    if sampling not in SAMPLINGS:
        raise ValueError(f"power sampling must be one of {SAMPLINGS}, got {sampling!r}")
    p = np.asarray(power_joint, dtype=float)
    if sampling == "updates":
        p = p[update_mask(len(p), aero_every, first)]
    if p.size == 0:
        raise ValueError("no step to average the power over")
    return float(np.maximum(p, 0.0).mean())


def P_plus(power_joint: np.ndarray, aero_every: int = 1, *, first: int = 0, sampling: str | None = None,
           P0: float | None = None) -> float:
    """:func:`required_power` over the reference power ``P0`` [W] (a flight's own:
    :attr:`hawksim.insect.insect.Insect.P0`; None: the default insect's, 84.2 mW), dimensionless."""
    if P0 is None:
        from hawksim.insect.folder import default_insect

        P0 = default_insect().P0
    return required_power(power_joint, aero_every, first=first, sampling=sampling) / P0
