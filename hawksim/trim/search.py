"""Minimum-power trim on the surrogate: the fitness of Eq. 3 and the GA + Nelder-Mead search (Nguyen et al.
2020, Sec. 2.5).

Fitness (Eq. 3), for the seven parameters x and the surrogate's cycle averages:

    F = P+ + r (|1 - L+| + |D+| + |M+|) + s sum_i |zeta_i| / (Max_i - Min_i),

r = 2, s = 5 (the paper, after Nguyen et al. 2019); zeta_i is the distance by which parameter i lies outside
Table 2's [Min_i, Max_i] (0 inside).

Search. Parameters are scaled to u in [0, 1]^7 by Table 2's bounds (a point outside the box is allowed and
penalised by Eq. 3's zeta term; operators keep u in [-0.1, 1.1]).

* Genetic algorithm (:func:`genetic`): population ``population`` (1e5 as in the paper), drawn uniformly in the
  box. Each generation keeps the best 5 % unchanged (elitism, as in the paper); the rest are children of
  parents picked by binary tournament: a fraction ``crossover_fraction`` (0.8, MATLAB ``ga``'s default) by
  blend crossover BLX-0.5 (each gene uniform in the parents' interval widened by half its length, Eshelman &
  Schaffer 1993), the others by Gaussian mutation of one parent (every gene, sigma = ``mutation_scale`` of the
  range, shrinking linearly to a tenth over ``max_generations``). Stops when the best fitness has improved by
  less than ``tol`` = 1e-6 over ``stall_generations`` generations, or after ``max_generations``.
* Nelder-Mead (scipy, adaptive) from the GA's best, in u, to xatol = fatol = 1e-10 (the paper's simplex
  tolerance), restarted from its own result (up to ``nm_restarts`` times) while that still lowers F: Eq. 3's
  absolute values make F non-smooth at balance, where a simplex can collapse before reaching the minimum.

Everything random comes from ``numpy.random.default_rng(seed)``: same surrogate and seed, same trim.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from hawksim.backends.averages import CycleAverages
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics
from hawksim.trim.point import Trim

R_PENALTY = 2.0
"""r of Eq. 3 (Nguyen et al. 2020, after Nguyen et al. 2019)."""
S_PENALTY = 5.0
"""s of Eq. 3 (Nguyen et al. 2020, after Nguyen et al. 2019)."""


def bound_violation(x: np.ndarray, lo: np.ndarray | None = None, hi: np.ndarray | None = None) -> np.ndarray:
    """Eq. 3's sum_i |zeta_i| / (Max_i - Min_i) for x (n, 7) SI (Table 2's bounds by default)."""
    if lo is None or hi is None:
        lo, hi = default_insect().bounds_si()
    x = np.atleast_2d(x)
    zeta = np.maximum(lo - x, 0.0) + np.maximum(x - hi, 0.0)
    return np.sum(zeta / (hi - lo), axis=1)


def fitness(y: np.ndarray, x: np.ndarray, r: float = R_PENALTY, s: float = S_PENALTY, *,
            lo: np.ndarray | None = None, hi: np.ndarray | None = None) -> np.ndarray:
    """Eq. 3. y (n, 4): L+, D+, M+, P+; x (n, 7) SI kinematics; ``lo``/``hi`` (7,) SI the bounds of zeta (Table 2's
    by default). Returns F (n,)."""
    y = np.atleast_2d(y)
    return (y[:, 3] + r * (np.abs(1.0 - y[:, 0]) + np.abs(y[:, 1]) + np.abs(y[:, 2]))
            + s * bound_violation(x, lo, hi))


def surrogate_insect(insect: Insect | None) -> Insect:
    """``insect`` (default :func:`hawksim.insect.folder.default_insect`) checked for a trim on the shipped surrogate:
    the network was trained on the default hawkmoth's morphology within Table 2, so the insect's morphology must be
    that one (its label aside) and its kinematic bounds inside Table 2 (a narrower envelope); its P0 may differ (P+
    is rescaled). ValueError naming the field otherwise."""
    default = default_insect()
    insect = default if insect is None else insect
    if dataclasses.replace(insect.morphology, name=default.morphology.name) != default.morphology:  # any label
        raise ValueError(f"insect {insect.name!r}: the surrogate network was trained on the default hawkmoth's "
                         "morphology; another morphology's trim is its periodic orbit (free flight)")
    for k in PARAM_NAMES:
        lo, hi = insect.bounds_deg[k]
        t_lo, t_hi = default.bounds_deg[k]
        if lo < t_lo or hi > t_hi:
            raise ValueError(f"insect field 'bounds_deg.{k}' = [{lo:g}, {hi:g}] leaves Table 2's [{t_lo:g}, "
                             f"{t_hi:g}], the surrogate network's training box")
    return insect


@dataclass(frozen=True)
class GAConfig:
    population: int = 100_000
    elite_fraction: float = 0.05
    crossover_fraction: float = 0.8
    mutation_scale: float = 0.1
    tol: float = 1e-6
    stall_generations: int = 10
    max_generations: int = 200
    nm_tol: float = 1e-10
    nm_max_evals: int = 20_000
    nm_restarts: int = 5

    def __post_init__(self):
        if self.population < 10:
            raise ValueError(f"GA population must be >= 10, got {self.population}")


@dataclass(frozen=True)
class GAResult:
    """Best point u (7,) in scaled coordinates, its fitness, per-generation (best, mean) fitness, generations."""

    u: np.ndarray
    fitness: float
    best_history: tuple
    mean_history: tuple
    generations: int


def _tournament(fit: np.ndarray, m: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of m binary-tournament winners (the fitter of two uniformly drawn individuals)."""
    a, b = rng.integers(0, fit.shape[0], m), rng.integers(0, fit.shape[0], m)
    return np.where(fit[a] <= fit[b], a, b)


def genetic(objective, dim: int, cfg: GAConfig, rng: np.random.Generator, progress=None) -> GAResult:
    """Minimise ``objective`` (m, dim) -> (m,) over u in [0, 1]^dim (see the module docstring)."""
    n = cfg.population
    n_elite = max(1, int(round(cfg.elite_fraction * n)))
    n_cross = int(round(cfg.crossover_fraction * (n - n_elite)))
    n_mut = n - n_elite - n_cross
    pop = rng.random((n, dim))
    fit = objective(pop)
    best_hist, mean_hist = [], []
    gen = 0
    for gen in range(1, cfg.max_generations + 1):
        order = np.argsort(fit, kind="stable")
        elite = pop[order[:n_elite]]
        pa, pb = pop[_tournament(fit, n_cross, rng)], pop[_tournament(fit, n_cross, rng)]
        lo_, hi_ = np.minimum(pa, pb), np.maximum(pa, pb)
        span = hi_ - lo_
        children = lo_ - 0.5 * span + rng.random(pa.shape) * 2.0 * span
        sigma = cfg.mutation_scale * (1.0 - 0.9 * (gen - 1) / max(1, cfg.max_generations - 1))
        mutants = pop[_tournament(fit, n_mut, rng)] + sigma * rng.standard_normal((n_mut, dim))
        new = np.clip(np.concatenate([children, mutants]), -0.1, 1.1)
        pop = np.concatenate([elite, new])
        fit = np.concatenate([fit[order[:n_elite]], objective(new)])
        best_hist.append(float(fit.min()))
        mean_hist.append(float(np.mean(fit[np.isfinite(fit)])))
        if progress:
            progress(gen, cfg.max_generations, best_hist[-1])
        if gen > cfg.stall_generations and best_hist[-cfg.stall_generations - 1] - best_hist[-1] < cfg.tol:
            break
    i = int(np.argmin(fit))
    return GAResult(pop[i].copy(), float(fit[i]), tuple(best_hist), tuple(mean_hist), gen)


def ga_nelder_mead(objective, dim: int, cfg: GAConfig, rng: np.random.Generator, *, objective_one=None,
                   progress=None) -> tuple[np.ndarray, float, GAResult, int]:
    """The paper's two-stage search: :func:`genetic` on the batched ``objective`` (m, dim) -> (m,), then scipy's
    Nelder-Mead (adaptive) from its best point to ``cfg.nm_tol`` on ``objective_one`` (dim,) -> float (default: the
    batched objective on one point). Returns (u, F(u), the GA result, Nelder-Mead's function evaluations)."""
    from scipy.optimize import minimize

    if objective_one is None:
        def objective_one(u):
            return float(objective(np.asarray(u)[None, :])[0])

    ga = genetic(objective, dim, cfg, rng, progress=progress)
    u, f, nfev = np.asarray(ga.u, dtype=float), objective_one(ga.u), 0
    for _ in range(cfg.nm_restarts + 1):  # a fresh simplex re-opens a search collapsed on a kink of |.|
        nm = minimize(objective_one, u, method="Nelder-Mead",
                      options={"xatol": cfg.nm_tol, "fatol": cfg.nm_tol, "maxfev": cfg.nm_max_evals, "adaptive": True})
        nfev += int(nm.nfev)
        if not nm.fun < f - cfg.nm_tol:
            break
        u, f = np.asarray(nm.x), float(nm.fun)
    return u, f, ga, nfev


def trim_on_surrogate(surrogate, speed: float, *, seed: int = 0, cfg: GAConfig = GAConfig(),
                      progress=None, insect: Insect | None = None) -> Trim:
    """GA + Nelder-Mead minimum of Eq. 3 on ``surrogate`` (a :class:`hawksim.backends.network.Surrogate`) at ``speed``.
    The Trim's ``evaluations`` are Nelder-Mead's, ``search`` the GA's result. ``insect``
    (:func:`surrogate_insect`: the default hawkmoth's morphology): the search box and Eq. 3's zeta are its
    ``bounds_deg``, and P+ is in its P0."""
    t0 = time.perf_counter()
    insect = surrogate_insect(insect)
    lo, hi = insect.bounds_si()
    p_scale = default_insect().P0 / insect.P0
    surrogate.features(np.zeros((1, 7)), speed)  # a per-speed network refuses another speed here

    def own(y):  # the network's P+ is in the default insect's P0
        if p_scale == 1.0:
            return y
        y = np.array(y, dtype=float)
        y[:, 3] *= p_scale
        return y

    def objective_batch(u):
        x = lo + u * (hi - lo)
        f = fitness(own(surrogate.predict_torch(x, speed)), x, lo=lo, hi=hi)
        if not np.any(np.isfinite(f)):  # a network whose weights overflow (issue 53): the search would never stall
            raise FloatingPointError(f"the surrogate's fitness is not finite at any of {len(f)} kinematics of the "
                                     "search (its outputs overflow)")
        return f

    def objective_one(u):
        x = lo + np.asarray(u)[None, :] * (hi - lo)
        return float(fitness(own(surrogate.predict(x, speed)), x, lo=lo, hi=hi)[0])

    u, _, ga, nfev = ga_nelder_mead(objective_batch, len(lo), cfg, np.random.default_rng(seed),
                                    objective_one=objective_one, progress=progress)
    x = np.clip(lo + u * (hi - lo), lo, hi)  # an optimum past a bound (penalised, rare) is moved onto it
    kin = Kinematics.from_array(x)
    y = own(surrogate.predict(x[None, :], speed))[0]
    return Trim(float(speed), kin, model="surrogate", source="GA + Nelder-Mead minimum of Eq. 3 on the surrogate",
                averages=CycleAverages.from_plus(y),
                fitness=float(fitness(y[None], x[None], lo=lo, hi=hi)[0]), evaluations=nfev,
                wall_time_s=time.perf_counter() - t0,
                search_seed=int(seed), search=ga)
