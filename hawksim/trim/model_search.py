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
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from hawksim.backends import backend_for
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import Resolution
from hawksim.condition import check_forward_speed
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.model import load_model
from hawksim.trim.balance import balance_on_uvlm
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
