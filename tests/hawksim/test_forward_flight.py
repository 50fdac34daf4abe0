"""Forward flight (issue 51): the flight condition (U, V), the body's own loads, the quasi-steady trims and the CLI's
``--forward-speed``. Fast: quasi-steady runs of one or two beats."""

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hawksim.backends.held import body_averages, run
from hawksim.backends.resolution import Resolution
from hawksim.cli import main
from hawksim.condition import air_velocity, check_forward_speed
from hawksim.flight.points import find_operating_point
from hawksim.insect.body_aero import CD0, CD_CROSS, ETA, BodyAero, angle_of_attack
from hawksim.insect.folder import default_insect
from hawksim.insect.morphology import RHO_AIR
from hawksim.trim.model_search import BALANCE_RESOLUTION
from hawksim.trim.point import OperatingPoint
from hawksim.trim.tables import trim_kinematics

QS = Resolution(aero="quasi-steady", steps_per_cycle=40, cycles=2)
"""A cheap quasi-steady resolution (the comparisons are between runs at the same one)."""

RESULTS = Path(__file__).resolve().parents[2] / "results" / "forward_flight" / "qs_trims.json"
"""The committed quasi-steady forward-flight trims (scripts/studies/forward_trims.py)."""


# ---- the flight condition ---------------------------------------------------------------------------------------

def test_air_velocity_at_zero_forward_speed_is_the_vertical_stream():
    a = air_velocity(1.5)
    assert a.tolist() == [0.0, 0.0, -1.5] and math.copysign(1.0, a[0]) == 1.0  # +0.0, as before U existed
    assert air_velocity(0.0, 3.0).tolist() == [-3.0, 0.0, -0.0]


@pytest.mark.parametrize("bad", [-1.0, float("nan"), float("inf")])
def test_library_refuses_a_bad_forward_speed_naming_it(bad):
    with pytest.raises(ValueError, match="forward_speed"):
        check_forward_speed(bad)
    with pytest.raises(ValueError, match="forward_speed"):
        run(trim_kinematics(1.0, "quasi-steady"), 1.0, QS, forward_speed=bad)


def test_zero_forward_speed_is_the_vertical_path_bit_for_bit():
    kin = trim_kinematics(1.0, "quasi-steady")
    old = run(kin, 1.0, QS)  # the call of every vertical-ascent caller
    new = run(kin, 1.0, QS, forward_speed=0.0)
    assert old.averages == new.averages  # exact equality of every float
    assert np.array_equal(old.force_world, new.force_world) and np.array_equal(old.moment_world, new.moment_world)
    assert new.body_averages is None and not np.any(new.body_force)


def test_shipped_quasi_steady_trim_rows_reproduce():
    """The shipped quasi-steady trim table's recorded averages come back at U = 0 (the table was made by
    scripts/studies/uvlm_trim_table.py at BALANCE_RESOLUTION's settings, by an older hawksim: they differ in the
    11th digit, measured 2026-12-07; the bit-for-bit check of U = 0 is the test above)."""
    from hawksim.trim.registry import shipped_table
    from hawksim.insect.kinematics import Kinematics

    table = shipped_table("trim_table_quasi_steady.json")
    assert table["resolution"] == BALANCE_RESOLUTION.to_dict()
    row = next(r for r in table["rows"] if r["speed"] == 1.0)
    a = run(Kinematics.from_edge(row["kinematics"]), 1.0, BALANCE_RESOLUTION, forward_speed=0.0).averages
    for k in ("L_plus", "D_plus", "M_plus", "P_plus"):
        assert getattr(a, k) == pytest.approx(row["uvlm"][k], rel=1e-8, abs=1e-10), k


def test_forward_speed_tilts_the_wing_force_and_adds_the_body_loads():
    kin = trim_kinematics(0.0, "quasi-steady")
    hover = run(kin, 0.0, QS).averages
    fwd = run(kin, 0.0, QS, forward_speed=3.0)
    assert fwd.forward_speed == 3.0 and fwd.body_averages is not None
    # the hover kinematics flown at 3 m/s: a large rearward force (drag) on the wings and the body
    assert fwd.averages.D_plus > hover.D_plus + 0.3
    body = body_averages(kin, 0.0, 3.0)
    assert body == fwd.body_averages
    assert body.D_plus > 0 and body.P_plus == 0.0
    # the body's share is the difference between the runs with and without it
    from hawksim.backends import backend_for
    from hawksim.backends.held import held_flight

    bare = held_flight(kin, 0.0, backend_for(QS), cycles=QS.cycles, steps_per_cycle=QS.steps_per_cycle,
                       forward_speed=3.0, body_loads=False).averages
    assert fwd.averages.D_plus - bare.D_plus == pytest.approx(body.D_plus, rel=1e-9, abs=1e-12)
    assert fwd.averages.L_plus - bare.L_plus == pytest.approx(body.L_plus, rel=1e-9, abs=1e-12)


def test_operating_point_carries_forward_speed_and_old_json_loads():
    kin = trim_kinematics(1.0, "quasi-steady")
    p = find_operating_point(0.0, body="held", kinematics=kin, forward_speed=2.0)
    assert p.forward_speed == 2.0
    d = p.to_json()
    assert d["forward_speed"] == 2.0 and OperatingPoint.from_json(d).forward_speed == 2.0
    old = find_operating_point(1.0, body="held", kinematics=kin).to_json()
    assert "forward_speed" not in old  # vertical points write what they wrote before
    assert OperatingPoint.from_json(old).forward_speed == 0.0
    with pytest.raises(ValueError, match="forward_speed"):
        find_operating_point(0.0, forward_speed=5.0)  # no kinematics and no shipped forward trim at 5 m/s
    with pytest.raises(ValueError, match="forward_speed"):
        OperatingPoint(0.0, kin, aero="quasi-steady", body="held", forward_speed=-1.0)


# ---- the body's loads -------------------------------------------------------------------------------------------

BODY = BodyAero.of(default_insect().morphology)


def test_body_geometry_from_the_segments():
    assert BODY.length == pytest.approx(0.0425)  # the segments' 42.5 mm (morphology)
    assert BODY.s_front == pytest.approx(math.pi * 0.005 * 0.0055)  # the thorax's section
    assert abs(BODY.centre[0]) < 0.002 and BODY.centre[1] == 0.0  # near the centre of mass, in the symmetry plane


def test_body_loads_limiting_cases():
    assert not np.any(BODY.force(np.zeros(3)))  # still air: no load
    U = 3.0
    f, m = BODY.loads(np.array([-U, 0.0, 0.0]))  # head-on: axial drag only, no lift
    assert f[0] == pytest.approx(-0.5 * RHO_AIR * CD0 * BODY.s_front * U**2) and f[1] == f[2] == 0.0
    f = BODY.force(np.array([0.0, 0.0, U]))  # broadside from below: crossflow only, along the wind
    assert f[0] == 0.0 and f[2] == pytest.approx(0.5 * RHO_AIR * ETA * CD_CROSS * BODY.s_plan * U**2)
    # quadratic in the speed, odd in the wind, the pitching moment is r x F
    w = np.array([-2.0, 0.3, 0.8])
    assert np.allclose(BODY.force(2 * w), 4 * BODY.force(w)) and np.allclose(BODY.force(-w), -BODY.force(w))
    f, m = BODY.loads(w)
    assert np.allclose(m, np.cross(BODY.centre, f))
    # at incidence a the normal force is q ETA CD_CROSS S_plan sin^2 a, the axial one q CD0 S_front cos^2 a
    a = math.radians(30)
    f = BODY.force(U * np.array([-math.cos(a), 0.0, math.sin(a)]))
    q = 0.5 * RHO_AIR * U**2
    assert f[0] == pytest.approx(-q * CD0 * BODY.s_front * math.cos(a) ** 2)
    assert f[2] == pytest.approx(q * ETA * CD_CROSS * BODY.s_plan * math.sin(a) ** 2)
    assert angle_of_attack(U * np.array([-math.cos(a), 0.0, math.sin(a)])) == pytest.approx(a)


# ---- the trims --------------------------------------------------------------------------------------------------

def test_committed_forward_trims_balance_within_their_tolerance():
    """Each committed quasi-steady trim (U > 0), re-run here at the balance's resolution, meets its tolerance in
    L+, D+ and M+ (the body's loads included)."""
    from hawksim.insect.kinematics import Kinematics

    data = json.loads(RESULTS.read_text())
    rows = [r for r in data["rows"] if r["forward_speed"] > 0]
    assert sum(r["converged"] for r in rows) >= 3
    for r in rows:  # a row that did not converge says so: its residual is above the tolerance
        a = run(Kinematics.from_edge(r["kinematics"]), r["speed"], BALANCE_RESOLUTION,
                forward_speed=r["forward_speed"]).averages
        err = max(abs(a.L_plus - 1), abs(a.D_plus), abs(a.M_plus))
        assert (err <= r["tolerance"]) == r["converged"], r["forward_speed"]
        assert a.P_plus == pytest.approx(r["P_plus"], rel=1e-7)  # the kinematics are stored to 1e-10


def test_model_search_returns_a_balanced_forward_trim():
    """A tiny search (population 10, 2 generations, a short simplex) then the balance: the trim carries its
    condition and meets the tolerance or says it did not."""
    from hawksim.trim.model_search import SEARCH_CONFIG, trim_on_model

    cfg = replace(SEARCH_CONFIG, population=10, max_generations=2, nm_max_evals=20, nm_restarts=0)
    t = trim_on_model(0.0, forward_speed=2.0, cfg=cfg, res=QS, seed=1)
    assert t.forward_speed == 2.0 and t.start.forward_speed == 2.0 and t.body == "held"
    err = max(abs(t.averages.L_plus - 1), abs(t.averages.D_plus), abs(t.averages.M_plus))
    assert t.converged == (err <= t.tolerance)
    assert t.evaluations > t.start.evaluations > 10


# ---- the CLI ----------------------------------------------------------------------------------------------------

KIN = "f=27,beta=20,phi0=5,theta0=10,alpha0=5,phi_a=55,alpha_a=45"
CHEAP = ["--aero", "quasi-steady", "--steps-per-cycle", "40", "--cycles", "2"]


def test_cli_aero_forward_speed(capsys):
    assert main(["aero", "--speed", "0", "--forward-speed", "2", "--kinematics", KIN, *CHEAP, "--json",
                 "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["forward_speed"] == 2.0 and out["body"]["D_plus"] > 0
    assert main(["aero", "--speed", "0", "--kinematics", KIN, *CHEAP, "--json", "--no-progress"]) == 0
    still = json.loads(capsys.readouterr().out)
    assert "forward_speed" not in still and "body" not in still  # the vertical output as before
    assert out["D_plus"] != still["D_plus"]


@pytest.mark.parametrize("argv, needle", [
    (["aero", "--speed", "0", "--forward-speed", "-1", "--kinematics", KIN], "--forward-speed"),
    (["aero", "--speed", "0", "--forward-speed", "nan", "--kinematics", KIN], "--forward-speed"),
    (["aero", "--speed", "0", "--forward-speed", "9", "--kinematics", KIN], "--forward-speed"),
    (["trim", "--speed", "0", "--forward-speed", "-2", "--aero", "quasi-steady"], "--forward-speed"),
    (["trim", "--speed", "0", "--forward-speed", "2"], "--forward-speed"),  # the surrogate: vertical only
    # without --kinematics: no shipped balanced forward trim at 5 m/s (tests/hawksim/test_forward_cli.py: 0-4 m/s)
    (["trim", "--speed", "0", "--forward-speed", "5", "--free-flight"], "--forward-speed"),
    (["stability", "--speed", "0", "--forward-speed", "5", "--aero", "quasi-steady"], "--forward-speed"),
    (["fly", "--speed", "0", "--cycles", "2", "--forward-speed", "5"], "--forward-speed"),
])
def test_cli_bad_or_unsupported_forward_speed_exits_2_with_one_line(argv, needle, capsys):
    assert main([*argv, "--json"]) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    lines = cap.err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0]
