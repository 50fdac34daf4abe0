"""Minimum-power trims refined on a held-body model (issue 51, item 3's UVLM part:
:func:`hawksim.trim.model_search.refine_on_model`, results/forward_flight/uvlm_trims.json) and the forward flights
of the per-step surrogate's measurement (item 7: :class:`hawksim.surrogate.flights.FlightSpec`'s forward speed)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from hawksim.backends.held import run
from hawksim.backends.resolution import Resolution
from hawksim.insect.kinematics import Kinematics
from hawksim.trim.model_search import refine_on_model

ROOT = Path(__file__).resolve().parents[2]
QS = Resolution(aero="quasi-steady", steps_per_cycle=40, cycles=2)


def _residual(a) -> float:
    return max(abs(a.L_plus - 1), abs(a.D_plus), abs(a.M_plus))


def test_refine_balances_and_lowers_power_from_an_unbalanced_start():
    """On the quasi-steady model (40 steps a beat) from the committed 1 m/s trim with f raised 10 % and the sweep
    amplitude cut 10 % (L+, D+, M+ off balance): the refinement balances within 0.01 and its P+ is no higher than
    the GA + Nelder-Mead trim's own at this resolution balanced on the same model (the search is local, but starts
    in that trim's basin)."""
    from hawksim.trim.balance import balance_on_uvlm

    row = {r["forward_speed"]: r for r in json.loads((ROOT / "results/forward_flight/qs_trims.json").read_text())
           ["rows"]}[1.0]
    kin = Kinematics.from_edge(row["kinematics"])
    x = kin.as_array()
    x[0] *= 1.1
    x[5] *= 0.9
    start = Kinematics.from_array(x)
    t = refine_on_model(start, 0.0, QS, forward_speed=1.0, max_evals=90)
    assert t.converged and _residual(t.averages) <= t.tolerance == 0.01
    assert t.forward_speed == 1.0 and t.aero == "quasi-steady" and t.start.forward_speed == 1.0
    assert _residual(t.start.averages) > 0.03  # it did start off balance
    assert t.evaluations <= 90 + 30
    again = run(t.kinematics, 0.0, QS, forward_speed=1.0).averages  # the stored averages are the model's there
    assert again.P_plus == pytest.approx(t.averages.P_plus, rel=1e-12)
    ga = balance_on_uvlm(kin, 0.0, QS, forward_speed=1.0)
    assert ga.converged
    assert t.averages.P_plus <= ga.averages.P_plus + 0.005


def test_refine_from_a_balanced_minimum_stays_balanced_and_costs_little():
    """From a point that is already balanced and near a minimum, every answer is a balanced run, never one with a
    higher Eq. 3 fitness than the start's."""
    from hawksim.trim.balance import balance_on_uvlm
    from hawksim.trim.search import fitness

    row = {r["forward_speed"]: r for r in json.loads((ROOT / "results/forward_flight/qs_trims.json").read_text())
           ["rows"]}[2.0]
    b = balance_on_uvlm(Kinematics.from_edge(row["kinematics"]), 0.0, QS, forward_speed=2.0)
    t = refine_on_model(b.kinematics, 0.0, QS, forward_speed=2.0, max_evals=40)
    assert t.converged and t.evaluations <= 40

    def F(trim):
        return fitness([trim.averages.as_tuple()], [trim.kinematics.as_array()])[0]

    assert F(t) <= F(b) + 1e-12


def test_a_forward_flight_spec_carries_its_speed_and_data_sets_refuse_it():
    from hawksim.surrogate.flights import FlightSample, FlightSpec, insert_flight, sample_flight

    spec = sample_flight(0, 0)
    assert spec.forward_speed == 0.0  # the data sets' flights: vertical, as before
    fwd = FlightSpec(spec.speed, spec.kinematics, spec.x0, spec.chi_ref, spec.perturbation, spec.symmetric,
                     forward_speed=1.0)
    import numpy as np

    with pytest.raises(ValueError, match="forward_speed"):
        insert_flight(None, FlightSample(fwd, 0, 0, np.zeros((0, 1), np.float32), None, "ok", 0.0))


@pytest.mark.slow
def test_a_committed_uvlm_forward_trim_still_balances_on_the_uvlm():
    """The lowest-speed balanced row of results/forward_flight/uvlm_trims.json, run again on the UVLM at its
    resolution for the hawkmoth it was searched on (hawksim 0.2's, ``Morphology.hawksim_0_2()``: the trims wait for
    their re-run on the sourced one, docs/forward_flight.md): within its tolerance, P+ as stored (~3 s)."""
    from hawksim.insect.insect import Insect
    from hawksim.insect.morphology import Morphology

    data = json.loads((ROOT / "results/forward_flight/uvlm_trims.json").read_text())
    res = Resolution(**data["resolution"])
    r = next(r for r in data["rows"] if r["converged"])
    old = Insect(morphology=Morphology.hawksim_0_2())
    a = run(Kinematics.from_edge(r["kinematics"]), r["speed"], res, forward_speed=r["forward_speed"],
            insect=old).averages
    assert _residual(a) <= r["tolerance"]
    assert a.P_plus == pytest.approx(r["P_plus"], rel=1e-6)


@pytest.mark.slow
def test_the_sourced_hawkmoths_uvlm_forward_trims_balance_on_the_uvlm():
    """Every balanced row of results/forward_flight/uvlm_trims_sourced.json (1-4 m/s, the default hawkmoth), run
    again on the UVLM at its resolution: within its tolerance, P+ as stored (~3 s a row)."""
    data = json.loads((ROOT / "results/forward_flight/uvlm_trims_sourced.json").read_text())
    assert data["morphology"] == "sourced"
    res = Resolution(**data["resolution"])
    rows = [r for r in data["rows"] if r["converged"]]
    assert [r["forward_speed"] for r in rows] == [1.0, 2.0, 3.0, 4.0]
    for r in rows:
        a = run(Kinematics.from_edge(r["kinematics"]), r["speed"], res, forward_speed=r["forward_speed"]).averages
        assert _residual(a) <= r["tolerance"], r["forward_speed"]
        assert a.P_plus == pytest.approx(r["P_plus"], rel=1e-6), r["forward_speed"]
