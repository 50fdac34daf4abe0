"""A trim that balances on the UVLM itself (issue 5, "beyond the paper").

Starting from given kinematics (the surrogate's optimum, or the paper's Table 3), three parameters are
adjusted until the UVLM's cycle averages satisfy the equilibrium of the paper's Sec. 3.2, |L+ - 1|, |D+|,
|M+| <= tol: the flapping frequency f (sets the lift), the stroke-plane angle beta and the mean rotation
alpha0 (tilt the mean force, set D+) and the mean sweep phi0 (moves the centre of pressure along the body,
sets M+). The other three parameters stay at the starting point, which carries the minimum-power choice.
Solver: Newton's method on the residuals (L+ - 1, D+, M+) with a forward-difference Jacobian (steps of
2 % of each parameter's Table 2 range) refreshed by Broyden's update after each step, steps clipped to
Table 2's box (the insect's ``bounds_deg``); parameters are scaled to [0, 1] by the bounds; a step wholly outside
the box ends the pass. (scipy's least_squares took steps too short to move f by the 2 Hz needed.)
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from hawksim.backends.held import CycleAverages, run
from hawksim.backends.resolution import DEFAULT, Resolution
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics
from hawksim.trim.point import Trim

FREE = ("f", "beta", "phi0", "alpha0")
"""Parameters the balance adjusts (4 unknowns for 3 equations: the minimum-norm Newton step; alpha0, the
up/down-stroke asymmetry of the angle of attack, takes over the horizontal force when beta reaches its
Table 2 bound of 0 deg, as at 0.5 m/s)."""

TRIM_RESOLUTION = replace(DEFAULT, cycles=4, average_cycles=3)
"""UVLM resolution of the balance: `hawksim aero`'s lattice and step, 4 beats with the last 3 averaged (the
hover wake is not periodic; averaging 3 beats damps its scatter)."""

DIFF_STEP = 0.02
"""Finite-difference step as a fraction of each free parameter's Table 2 range."""

RESTART_EVALS = 20
"""UVLM evaluations of a restart of the balance (from its best point, with a 4 times smaller step)."""


def balance_on_uvlm(kin0: Kinematics, speed: float, res: Resolution = TRIM_RESOLUTION, *, tol: float = 0.01,
                    max_evals: int = 30, free=FREE, diff_step: float = DIFF_STEP, restarts: int = 1,
                    insect: Insect | None = None, forward_speed: float = 0.0) -> Trim:
    """Adjust ``free`` parameters of kin0 until the UVLM balances within tol (see the module docstring), at ascent
    ``speed`` and ``forward_speed`` [m/s] (:mod:`hawksim.condition`; in forward flight the body's own loads count,
    :func:`hawksim.backends.held.held_flight`).

    ``insect`` (default :data:`hawksim.insect.insect.DEFAULT_INSECT`): the insect held (its wings, weight and P0 in
    the averages); its ``bounds_deg`` take the place of Table 2's (the scaling of the free parameters, their
    difference steps and the box the steps are clipped to).

    If ``max_evals`` evaluations do not reach tol, the balance restarts from its best point with a 4 times
    smaller difference step and RESTART_EVALS more evaluations, ``restarts`` times (the hover residual is not
    smooth in the kinematics at the scale of the first step: Broyden stalled at 0.012 there, the restart
    reaches 0.006)."""
    first = _balance(kin0, speed, res, tol, max_evals, free, diff_step, insect, forward_speed)
    if first.converged or restarts < 1:
        return first
    again = balance_on_uvlm(first.kinematics, speed, res, tol=tol, max_evals=RESTART_EVALS, free=free,
                            diff_step=diff_step / 4, restarts=restarts - 1, insect=insect,
                            forward_speed=forward_speed)
    return replace(again, start=first.start, evaluations=first.evaluations + again.evaluations,
                   wall_time_s=first.wall_time_s + again.wall_time_s)


def _balance(kin0, speed, res, tol, max_evals, free, diff_step, insect, forward_speed=0.0) -> Trim:
    """One Newton-Broyden pass of :func:`balance_on_uvlm`."""
    idx = [PARAM_NAMES.index(k) for k in free]
    lo, hi = (default_insect() if insect is None else insect).bounds_si()
    x0 = kin0.as_array()
    cache: dict[tuple, CycleAverages] = {}

    def kin_of(z):
        x = x0.copy()
        x[idx] = lo[idx] + np.clip(z, 0.0, 1.0) * (hi[idx] - lo[idx])
        return Kinematics.from_array(x)

    def averages(z):
        key = tuple(np.round(z, 12))
        if key not in cache:
            cache[key] = run(kin_of(z), speed, res, insect=insect, forward_speed=forward_speed).averages
        return cache[key]

    def residual(z):
        a = averages(z)
        return np.array([a.L_plus - 1.0, a.D_plus, a.M_plus])

    t0 = time.perf_counter()
    z = np.clip((x0[idx] - lo[idx]) / (hi[idx] - lo[idx]), 0.0, 1.0)
    start = averages(z)
    r = residual(z)
    J = None
    while np.abs(r).max() > tol and len(cache) < max_evals:
        if J is None:
            J = np.empty((3, len(idx)))  # forward differences (one evaluation per free parameter)
            for j in range(len(idx)):
                h = diff_step if z[j] + diff_step <= 1.0 else -diff_step
                zj = z.copy()
                zj[j] += h
                J[:, j] = (residual(zj) - r) / h
        dz = np.linalg.lstsq(J, -r, rcond=None)[0]
        z_new = np.clip(z + dz, 0.0, 1.0)
        step = z_new - z
        if not step @ step > 0:  # the whole step lies outside the box (e.g. f on its bound and L+ short): no
            break                # progress, and no new evaluation to end the loop (it spun forever before)
        r_new = residual(z_new)
        J = J + np.outer(r_new - r - J @ step, step) / (step @ step)  # Broyden
        z, r = z_new, r_new
    best = np.array(min(cache, key=lambda k: np.abs(np.array([cache[k].L_plus - 1, cache[k].D_plus,
                                                              cache[k].M_plus])).max()))
    a = averages(best)
    err = max(abs(a.L_plus - 1), abs(a.D_plus), abs(a.M_plus))
    model = res.aero
    start_trim = Trim(float(speed), kin0, model=model, source="start of the balance", averages=start,
                      forward_speed=forward_speed)
    return Trim(float(speed), kin_of(best), model=model, source=f"{model} balance (free: {', '.join(free)})",
                averages=a, converged=err <= tol, tolerance=tol, evaluations=len(cache),
                wall_time_s=time.perf_counter() - t0, start=start_trim, forward_speed=forward_speed)
