"""Minimum-power trim searched on a held-body aerodynamic model itself (the quasi-steady one), for flight conditions
the surrogate network does not cover: forward flight (issue 51, item 3).

The search is the paper's (:mod:`hawksim.trim.search`): Eq. 3's fitness F = P+ + r (|1 - L+| + |D+| + |M+|) + s zeta
minimised by the genetic algorithm and Nelder-Mead (:func:`hawksim.trim.search.ga_nelder_mead`, the one optimiser),
on the model's held-body cycle averages (:func:`hawksim.backends.held.held_flight`, the body's own loads counted in
forward flight) instead of the network's predictions. Its population is small (:data:`SEARCH_CONFIG`: each
evaluation is a 2-beat run, ~0.02 s, against the network's microseconds), so the GA finds a basin and Nelder-Mead
its minimum; the search's resolution (:data:`SEARCH_RESOLUTION`) is coarser than the balance's. The optimum is then
balanced (:func:`hawksim.trim.balance.balance_on_uvlm`: f, beta, phi0, alpha0 adjusted, |L+ - 1|, |D+|, |M+| <= tol)
on the same model at :data:`BALANCE_RESOLUTION` (the shipped quasi-steady trim table's), so that the returned trim
meets its tolerance. The body angle is chi = 60 deg - beta (the stroke plane is fixed to the body,
:data:`hawksim.insect.morphology.STROKE_PLANE_TO_BODY`): beta sets both.

Everything random comes from ``numpy.random.default_rng(seed)``: same model, condition and seed, same trim.

Where a population search is too dear (the UVLM: ~1.5-4 s a run, hours per condition at population 80),
:func:`refine_on_model` is the local route: a minimum-power search from a given trim (trust-region sequential linear
programming on Eq. 3's form with a larger r, an exact penalty for the balance, in Table 2's box, forward-difference
gradients), then a balance where it ends outside the tolerance. It finds the minimum of the basin it starts in, not
the global one.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from hawksim.backends import backend_for
from hawksim.backends.averages import CycleAverages
from hawksim.backends.held import held_flight, run
from hawksim.backends.resolution import Resolution
from hawksim.condition import check_forward_speed
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.trim.balance import TRIM_RESOLUTION, balance_on_uvlm
from hawksim.trim.point import Trim
from hawksim.trim.search import R_PENALTY, GAConfig, fitness, ga_nelder_mead

SEARCH_RESOLUTION = Resolution(aero="quasi-steady", steps_per_cycle=100, cycles=2)
"""Resolution of the search's evaluations: 100 steps a beat, 2 beats, the last averaged (L+ within 0.4 % and P+
within 0.03 % of :data:`BALANCE_RESOLUTION` at the 1 m/s quasi-steady trim; 0.023 s a run)."""

BALANCE_RESOLUTION = Resolution(aero="quasi-steady", steps_per_cycle=200, cycles=2)
"""Resolution of the final balance: the shipped quasi-steady trim table's (``scripts/studies/uvlm_trim_table.py``)."""

SEARCH_CONFIG = GAConfig(population=80, stall_generations=6, max_generations=30, nm_tol=1e-6, nm_max_evals=1500,
                         nm_restarts=2)
"""The GA + Nelder-Mead settings of a search on a model (the paper's operators, a small population; model choice: a
search then costs ~2-4 min per condition on one core)."""


def trim_on_model(speed: float, *, forward_speed: float = 0.0, aero: str = "quasi-steady", seed: int = 0,
                  cfg: GAConfig = SEARCH_CONFIG, res: Resolution | None = None,
                  balance_res: Resolution | None = None, tol: float = 0.01, insect: Insect | None = None,
                  progress=None, penalty: float = R_PENALTY) -> Trim:
    """The minimum-power trim of ``insect`` (default :func:`hawksim.insect.folder.default_insect`; its
    ``bounds_deg`` are the search box and Eq. 3's zeta, P+ in its P0) at ascent ``speed`` and ``forward_speed``
    [m/s] on the held-body model ``aero`` (module docstring). ``res``/``balance_res``: the search's and the
    balance's resolutions (default :data:`SEARCH_RESOLUTION`, :data:`BALANCE_RESOLUTION` with ``aero``);
    ``penalty``: Eq. 3's r (the paper's 2 by default; where the power saved by leaving the balance exceeds r per unit
    residual, as in fast forward flight, the search's minimum is not balanced and a larger r keeps it so). Returns
    the balanced trim (``converged``: the balance met ``tol``; ``start``: the search's optimum with its averages;
    ``fitness``: Eq. 3 at that optimum; ``search``: the GA's result; ``evaluations``: the model runs of both)."""
    forward_speed = check_forward_speed(forward_speed)
    if not (np.isfinite(speed) and speed >= 0):
        raise ValueError(f"speed must be a finite ascent speed >= 0 m/s, got {speed}")
    res = replace(SEARCH_RESOLUTION if res is None else res, aero=aero)
    balance_res = replace(BALANCE_RESOLUTION if balance_res is None else balance_res, aero=aero)
    ins = default_insect() if insect is None else insect
    lo, hi = ins.bounds_si()
    backend = backend_for(res, morphology=ins.morphology)
    model = load_model(morph=ins.morphology)
    count = [0]

    def averages(x: np.ndarray):
        count[0] += 1
        return held_flight(Kinematics.from_array(x), speed, backend, cycles=res.cycles,
                           average_cycles=res.average_cycles, steps_per_cycle=res.steps_per_cycle, model=model,
                           insect=ins, forward_speed=forward_speed).averages

    def objective(u: np.ndarray) -> np.ndarray:
        x = lo + np.atleast_2d(u) * (hi - lo)
        y = np.array([averages(xi).as_tuple() for xi in x])
        f = fitness(y, x, r=penalty, lo=lo, hi=hi)
        return np.where(np.isfinite(f), f, np.inf)

    t0 = time.perf_counter()
    u, f, ga, _ = ga_nelder_mead(objective, len(lo), cfg, np.random.default_rng(seed), progress=progress)
    x = np.clip(lo + u * (hi - lo), lo, hi)  # an optimum past a bound (penalised) is moved onto it
    found = Trim(float(speed), Kinematics.from_array(x), model=aero, forward_speed=forward_speed,
                 source=f"GA + Nelder-Mead minimum of Eq. 3 on the {aero} model", averages=averages(x),
                 fitness=float(f), evaluations=count[0], search_seed=int(seed), search=ga,
                 wall_time_s=time.perf_counter() - t0)
    b = balance_on_uvlm(found.kinematics, speed, balance_res, tol=tol, insect=insect, forward_speed=forward_speed)
    return replace(b, source=f"{found.source}, balanced on it ({b.source})", start=found, fitness=found.fitness,
                   search=ga, search_seed=int(seed), evaluations=count[0] + b.evaluations,
                   wall_time_s=time.perf_counter() - t0)


REFINE_DIFF_STEP = 0.02
"""Forward-difference step of :func:`refine_on_model`'s gradients, as a fraction of each parameter's Table 2 range
(the balance's :data:`hawksim.trim.balance.DIFF_STEP`: the UVLM's averages are not smooth below it at low advance
ratio, where 1 % steps gave Jacobians whose steps the runs then contradicted)."""

REFINE_PENALTY = 10.0
"""The weight mu of the residuals in :func:`refine_on_model`'s merit P+ + mu (|L+ - 1| + |D+| + |M+|) (Eq. 3's form
with r = mu: an exact penalty once mu exceeds the balance's Lagrange multipliers, the change of P+ per unit of
residual, ~1 at these trims; the value with which the quasi-steady search kept fast forward flight balanced)."""

REFINE_MAX_EVALS = 60
"""UVLM runs of one start's search in forward flight (`hawksim trim --aero uvlm`'s default ``--max-evals``,
scripts/studies/forward_uvlm_trims.py's per start): about 6 steps of 8 runs and the rejected steps; model choice,
sized to the shared host (4-8 s a run under load, 5-15 min a search at :data:`hawksim.trim.balance.TRIM_RESOLUTION`);
on the quasi-steady model the search from these starts ends within 40-80 runs. Where no run balanced, the balance
follows (30 + 20 runs)."""

REFINE_RADIUS = (0.05, 0.2, 2e-3)
"""Trust region of :func:`refine_on_model` in the scaled parameters (fractions of each Table 2 range): initial,
largest, and the radius below which it stops."""


def refine_on_model(kin0: Kinematics, speed: float, res: Resolution = TRIM_RESOLUTION, *, forward_speed: float = 0.0,
                    tol: float = 0.01, max_evals: int = 80, diff_step: float = REFINE_DIFF_STEP,
                    mu: float = REFINE_PENALTY, radius: tuple[float, float, float] = REFINE_RADIUS,
                    balance_evals: int = 30, penalty: float = R_PENALTY, insect: Insect | None = None,
                    progress=None) -> Trim:
    """The local minimum-power trim near ``kin0`` on the held-body model of ``res`` (default the UVLM at
    :data:`hawksim.trim.balance.TRIM_RESOLUTION`, the paper's trims' balance) at ascent ``speed`` and
    ``forward_speed`` [m/s], all seven parameters free (scaled to [0, 1] by the insect's ``bounds_deg``, default
    :func:`hawksim.insect.folder.default_insect`), at most ``max_evals`` model runs.

    Method: sequential linear programming in a trust region on the l1 exact penalty phi = ``P+ + mu (|L+ - 1| +
    |D+| + |M+|)`` (after Fletcher & Sainz de la Maza 1989, Math. Program. 43:235; recalled, not re-read here).
    Each iteration takes the forward-difference Jacobian of (P+, L+ - 1, D+, M+) (``diff_step`` of each range: 7
    runs), solves the linear program ``min g.d + mu |c + A d|_1`` over the box and ``|d|_inf <=`` the radius
    (scipy's HiGHS), runs the step and accepts it where phi falls by at least a tenth of the predicted fall (the
    radius doubling, up to ``radius[1]``, where the step reached it and the model predicted well; else halved, the
    Jacobian corrected along the step by Broyden's update). It stops at ``max_evals`` runs or a radius below
    ``radius[2]``. A run that fails (a non-finite or blown-up UVLM) is a rejected step. (scipy's SLSQP, tried first,
    took box-wide first steps from an unbalanced start and wandered to L+ ~ 0.2.)

    The answer is the run of lowest Eq. 3 fitness with r = ``penalty`` (P+ + r times the residuals: the tolerance's
    slack is not spent on power) among those that balance within ``tol`` (``max(|L+ - 1|, |D+|, |M+|)``); if no run
    does, the run of lowest phi is balanced (:func:`hawksim.trim.balance.balance_on_uvlm`, ``balance_evals`` runs,
    its four parameters) and that is the answer. ``source`` ends with how the search stopped. ``converged``: the
    answer meets ``tol``; ``start``: the trim at kin0 (clipped to the box) with its averages; ``evaluations``: every
    run (the search's and the balance's). ``progress(n, averages)`` is called after each new run."""
    from scipy.optimize import linprog

    forward_speed = check_forward_speed(forward_speed)
    ins = default_insect() if insect is None else insect
    lo, hi = ins.bounds_si()
    n = len(lo)
    cache: dict[tuple, CycleAverages | None] = {}

    def kin_of(key):
        return Kinematics.from_array(lo + np.array(key) * (hi - lo))

    def key_of(z):
        return tuple(np.round(np.clip(z, 0.0, 1.0), 12))

    def values(key):  # (P+, L+ - 1, D+, M+), None for a failed run
        if key not in cache:
            if len(cache) >= max_evals:
                raise _Budget
            try:
                a = run(kin_of(key), speed, res, insect=insect, forward_speed=forward_speed).averages
            except (FloatingPointError, ValueError):
                a = None
            ok = a is not None and np.all(np.isfinite(a.as_tuple())) and _residual(a) < 10.0
            cache[key] = a if ok else None
            if progress is not None and a is not None:
                progress(len(cache), a)
        a = cache[key]
        return None if a is None else np.array([a.P_plus, a.L_plus - 1.0, a.D_plus, a.M_plus])

    def merit(v):
        return np.inf if v is None else v[0] + mu * np.abs(v[1:]).sum()

    t0 = time.perf_counter()
    z = key_of((kin0.as_array() - lo) / (hi - lo))
    v = values(z)
    if v is None:
        raise ValueError(f"the model run at the start kin0 failed: {kin0}")
    start = Trim(float(speed), kin_of(z), model=res.aero, source="start of the refinement", averages=cache[z],
                 forward_speed=forward_speed, insect=ins)
    delta, delta_max, delta_min = radius
    J = None
    outcome = f"evaluation budget ({max_evals} runs) spent"
    iterations = 0
    try:
        while delta >= delta_min:
            if J is None:
                J = np.empty((4, n))
                for j in range(n):
                    h = diff_step if z[j] + diff_step <= 1.0 else -diff_step
                    zj = np.array(z)
                    zj[j] += h
                    vj = values(key_of(zj))
                    if vj is None:  # a failed run beside the iterate: the other side
                        h, zj[j] = -h, z[j] - h
                        vj = values(key_of(zj))
                    if vj is None:
                        outcome = "no gradient: the runs on both sides of the iterate failed"
                        raise _Budget
                    J[:, j] = (vj - v) / h
            g, A, c = J[0], J[1:], v[1:]
            m = len(c)  # LP in (d, s+, s-): min g.d + mu sum(s+ + s-), c + A d = s+ - s-
            cost = np.concatenate([g, mu * np.ones(2 * m)])
            A_eq = np.hstack([A, -np.eye(m), np.eye(m)])
            zz = np.array(z)
            bounds = [(max(-delta, -zz[j]), min(delta, 1.0 - zz[j])) for j in range(n)] + [(0, None)] * (2 * m)
            lp = linprog(cost, A_eq=A_eq, b_eq=-c, bounds=bounds, method="highs")
            if lp.status != 0:
                outcome = f"linear program failed: {lp.message}"
                break
            d = lp.x[:n]
            predicted = merit(v) - (v[0] + g @ d + mu * np.abs(c + A @ d).sum())
            if predicted <= 1e-9:
                outcome = "no predicted descent in the trust region (a stationary point of the merit)"
                break
            iterations += 1
            z_new = key_of(zz + d)
            v_new = values(z_new)
            rho = (merit(v) - merit(v_new)) / predicted
            if rho >= 0.1:
                z, v, J = z_new, v_new, None
                if rho >= 0.75 and np.abs(d).max() >= 0.99 * delta:
                    delta = min(2 * delta, delta_max)
            else:
                if v_new is not None:  # Broyden: the model made right along the step it got wrong
                    step = np.asarray(z_new) - np.asarray(z)
                    J = J + np.outer(v_new - v - J @ step, step) / (step @ step)
                delta /= 2
        else:
            outcome = f"trust region below {delta_min:g}"
    except _Budget:
        pass
    keys = [k for k in cache if cache[k] is not None]
    err = np.array([_residual(cache[k]) for k in keys])
    ok = [k for k, e in zip(keys, err) if e <= tol]
    source = (f"{res.aero} trust-region SLP minimum of P+ + {mu:g} x residuals from the start; {outcome} after "
              f"{iterations} steps")
    if ok:
        best = min(ok, key=lambda k: fitness(np.array(cache[k].as_tuple()), kin_of(k).as_array(), penalty,
                                             lo=lo, hi=hi)[0])
        return Trim(float(speed), kin_of(best), model=res.aero, source=source, averages=cache[best], converged=True,
                    tolerance=tol, evaluations=len(cache), wall_time_s=time.perf_counter() - t0, start=start,
                    forward_speed=forward_speed, insect=ins)
    best = min(keys, key=lambda k: merit(values(k)))
    b = balance_on_uvlm(kin_of(best), speed, res, tol=tol, max_evals=balance_evals, insect=insect,
                        forward_speed=forward_speed)
    return replace(b, source=f"{source}, then balanced ({b.source})", start=start,
                   evaluations=len(cache) + b.evaluations, wall_time_s=time.perf_counter() - t0)


class _Budget(Exception):
    """Raised inside the search when the evaluation budget is spent."""


def _residual(a: CycleAverages) -> float:
    """The balance's residual max(|L+ - 1|, |D+|, |M+|)."""
    return max(abs(a.L_plus - 1.0), abs(a.D_plus), abs(a.M_plus))
