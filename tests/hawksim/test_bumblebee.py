"""The bumblebee (issue 50, item 6): its folder (hawksim/insects/bumblebee/insect.toml) loads and follows the rules
its README states, the stored hover trim balances on the quasi-steady backend, the stored orbit's Floquet multipliers
are reproduced, the 20-beat controlled hover stays within bounds, and adding the bumblebee changed nothing outside its
folder (the default insect and the hawkmoth's quasi-steady averages are as they were; the folder is self-contained).

The stored numbers are results/bumblebee_hover.json (written by the hover study named in its ``command``)."""

from __future__ import annotations

import json
import sys
import subprocess
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from hawksim.backends.held import run
from hawksim.backends.resolution import Resolution
from hawksim.insect.folder import load_insect
from hawksim.insect.insect import DEFAULT_INSECT, Insect
from hawksim.insect.kinematics import TABLE2_BOUNDS_DEG, Kinematics, table3_kinematics
from hawksim.insect.morphology import HAWKMOTH, P0_W, Morphology

ROOT = Path(__file__).resolve().parents[2]
FOLDER = ROOT / "hawksim" / "insects" / "bumblebee"
SPEC = FOLDER / "insect.toml"
RESULTS = ROOT / "results" / "bumblebee_hover.json"
QS_RES = Resolution(aero="quasi-steady", steps_per_cycle=200, cycles=2)
"""The resolution of the bumblebee's (and the hawkmoth's shipped) quasi-steady trim."""

HAWKMOTH_QS_HOVER = (1.449350783479392, -0.030200571502143458, -0.06401261483057018, 1.044475554525626,
                     0.0879448416910577)
"""The default hawkmoth's quasi-steady L+, D+, M+, P+, power [W] at Table 3's hover kinematics (QS_RES), recorded on
the sourced hawkmoth of hawksim 0.3 (regen2, 23be96a; hawksim 0.2's were 1.2561, -0.0342, -0.0587, 0.9422, 0.0793:
the feathering axis moved from 0.25 to 0.06 of the chord)."""


@pytest.fixture(scope="module")
def bee() -> Insect:
    return load_insect("bumblebee")


@pytest.fixture(scope="module")
def stored() -> dict:
    return json.loads(RESULTS.read_text())


def _kin(edge: dict) -> Kinematics:
    return Kinematics.from_edge(edge, check_bounds=False)


def test_spec_loads_with_its_quoted_numbers(bee):
    m = bee.morphology
    assert bee.name == "bumblebee"
    # Berman & Wang 2007, Table 2 (quoted)
    assert (m.total_mass, m.wing_mass, m.R, m.cbar) == (175e-6, 0.46e-6, 13.2e-3, 4.02e-3)
    assert m.wing_area == pytest.approx(53.064e-6, rel=1e-12)
    assert m.body_mass == pytest.approx(174.08e-6, rel=1e-12)


def test_spec_model_choices_follow_the_readme_rules(bee):
    """Each model choice is hawksim 0.2's hawkmoth's number times the README's scale (6 significant digits)."""
    m, h = bee.morphology, Morphology.hawksim_0_2()
    s = (m.total_mass / h.total_mass) ** (1 / 3)
    k_f = math.sqrt(m.total_mass * h.R**3 * h.cbar / (h.total_mass * m.R**3 * m.cbar))
    assert s == pytest.approx(0.480374, abs=1e-6) and k_f == pytest.approx(4.79503, abs=1e-5)
    assert (m.r2_hat, m.axis_fraction, m.wing_mass_model) == (h.r2_hat, h.axis_fraction, h.wing_mass_model)
    assert m.wing_thickness == pytest.approx(h.wing_thickness * m.R / h.R, rel=1e-5)
    seg_h = {x.name: x for x in h.segments}
    total_h = sum(x.mass for x in h.segments)
    for x in m.segments:
        assert x.mass == pytest.approx(seg_h[x.name].mass / total_h * m.body_mass, rel=1e-5)
        np.testing.assert_allclose(x.centre, s * np.array(seg_h[x.name].centre), rtol=1e-5, atol=1e-12)
        np.testing.assert_allclose(x.semi_axes, s * np.array(seg_h[x.name].semi_axes), rtol=1e-5)
    np.testing.assert_allclose(m.hinge_from_thorax, s * np.array(h.hinge_from_thorax), rtol=1e-5)
    assert bee.P0 == pytest.approx(P0_W * m.total_mass / h.total_mass, rel=1e-5)
    for k, (lo, hi) in TABLE2_BOUNDS_DEG.items():
        if k == "f":
            assert bee.bounds_deg[k] == pytest.approx((lo * k_f, hi * k_f), rel=1e-5)
            assert lo * k_f < 116 < 155 < hi * k_f  # Berman & Wang's and Sun & Xiong's measured frequencies
        else:
            assert bee.bounds_deg[k] == (lo, hi)


def test_stored_quasi_steady_trim_balances(bee, stored):
    """The stored minimum-power trim, re-run on the quasi-steady backend: L+ within 1 % of 1, |D+|, |M+| <= 0.01, and
    the stored averages reproduced."""
    t = stored["qs_trim"]["balanced"]
    a = run(_kin(t["kinematics"]), 0.0, QS_RES, insect=bee).averages
    assert a.L_plus == pytest.approx(1.0, abs=0.01)
    assert abs(a.D_plus) <= 0.01 and abs(a.M_plus) <= 0.01
    for k in ("L_plus", "D_plus", "M_plus", "P_plus", "power_W"):
        assert getattr(a, k) == pytest.approx(t["averages"][k], rel=1e-9, abs=1e-12)
    # inside its bounds, at a flapping frequency of a bumblebee (between Table 2 x k_f's ends)
    for k, v in t["kinematics"].items():
        lo, hi = bee.bounds_deg[k]
        assert lo <= v <= hi


def test_stored_uvlm_trim_balances(bee, stored):
    """The stored UVLM balance (from the quasi-steady balance at phi_a = 58 deg), re-run on the UVLM at the balance's
    resolution (~5 s): |L+ - 1|, |D+|, |M+| <= 0.01 and the stored averages reproduced."""
    from hawksim.trim.balance import TRIM_RESOLUTION

    t = stored["uvlm_trim"]["balanced"]
    assert t["converged"] and stored["uvlm_trim"]["resolution"] == TRIM_RESOLUTION.to_dict()
    a = run(_kin(t["kinematics"]), 0.0, TRIM_RESOLUTION, insect=bee).averages
    assert max(abs(a.L_plus - 1), abs(a.D_plus), abs(a.M_plus)) <= 0.01
    for k in ("L_plus", "D_plus", "M_plus", "P_plus"):
        assert getattr(a, k) == pytest.approx(t["averages"][k], rel=1e-6, abs=1e-9)


def test_balance_takes_the_insects_bounds(bee, stored):
    """hawksim.trim.balance.balance_on_uvlm with the bumblebee (quasi-steady, 200 steps) from the stored balance's
    start at the measured stroke amplitude: it balances in its own box (f ~126 Hz, outside Table 2's 15-40 Hz, where
    the box of the default insect would clip f to 40 Hz) and reproduces the stored result."""
    from hawksim.trim.balance import balance_on_uvlm

    want = stored["qs_measured_amplitude"]["balanced"]
    start = dict(stored["qs_trim"]["balanced"]["kinematics"], phi_a=58.0, f=155.0)
    b = balance_on_uvlm(_kin(start), 0.0, QS_RES, insect=bee)
    assert b.converged and 100 < b.kinematics.f < 150
    assert b.kinematics.to_edge() == pytest.approx(want["kinematics"], rel=1e-9)
    assert b.averages.L_plus == pytest.approx(1.0, abs=0.01) and b.averages.P_plus == pytest.approx(
        want["averages"]["P_plus"], rel=1e-9)


def test_stored_orbit_floquet_multipliers_are_reproduced(bee, stored):
    """The quasi-steady orbit from its stored kinematics and phase-0 state (Newton starts converged), and its
    monodromy's multipliers within 1e-6 of the stored ones."""
    from hawksim.flight.orbit import periodic_orbit
    from hawksim.stability.floquet import monodromy

    o = stored["qs_orbit"]
    orbit = periodic_orbit(0.0, "quasi-steady", kinematics=_kin(o["orbit"]["kinematics"]), insect=bee,
                           x0=np.array(o["orbit"]["initial_state"]))
    assert orbit.converged and orbit.kinematics.f == pytest.approx(o["orbit"]["kinematics"]["f"], rel=1e-8)
    fl = monodromy(orbit)
    for key in ("multipliers_long", "multipliers_lat"):
        want = np.array([complex(*z) for z in o["floquet"][key]])
        np.testing.assert_allclose(np.sort_complex(getattr(fl, key)), np.sort_complex(want), atol=1e-6)


def test_stored_controlled_hover_stays_within_bounds(stored):
    """The stored 20-beat LQR hover, started q = 400 deg/s off the orbit (q T = 2 deg, as the hawkmoth's 60 deg/s at
    ~30 Hz): the perturbation is felt (beat 1 sinks > 1 mm/s, pitch moves > 0.5 deg), it did not depart, from beat 5 on
    the beat-mean vertical speed is within 0.5 mm/s of 0, from beat 10 on the beat-mean pitch within 0.1 deg of the
    orbit's, and the last beat's L+ within 1e-2 of 1."""
    f, orbit = stored["qs_lqr"], stored["qs_orbit"]["orbit"]
    assert f["departed_at_beat"] is None and len(f["beats"]) == 20
    speeds = [b["mean_vertical_speed"] for b in f["beats"]]
    pitch = np.array([b["pitch_deg"] for b in f["beats"]]) - orbit["mean_pitch_deg"]
    assert abs(speeds[0]) > 1e-3 and np.abs(pitch).max() > 0.5
    assert max(abs(v) for v in speeds[4:]) < 5e-4
    assert np.abs(pitch[9:]).max() < 0.1
    assert f["last_cycle"]["L_plus"] == pytest.approx(1.0, abs=1e-2)


def test_controlled_hover_is_reproduced(bee, stored):
    """The 20-beat LQR hover flown again (orbit from the stored trim, gains, flight: ~15 s): the same beats."""
    from hawksim.control.command import command_summary, fly_command
    from hawksim.control.derivatives import linearize
    from hawksim.control.schedule import operating_point_override
    from hawksim.flight.orbit import periodic_orbit

    f = stored["qs_lqr"]
    orbit = periodic_orbit(0.0, "quasi-steady", kinematics=_kin(stored["qs_trim"]["balanced"]["kinematics"]),
                           insect=bee)
    with operating_point_override(0.0, "quasi-steady", orbit, linearize(orbit)):
        cl = fly_command(0.0, 20, control="lqr", perturb={"q": 400.0}, insect=bee, aero="quasi-steady", rate="beat")
    out = command_summary(cl, 20, "lqr", "quasi-steady", "beat")
    got = [b["mean_vertical_speed"] for b in out["beats"]]
    np.testing.assert_allclose(got, [b["mean_vertical_speed"] for b in f["beats"]], atol=1e-9)


def _cli(*args):
    r = subprocess.run([sys.executable, "-m", "hawksim", *args, "--json", "--no-progress"], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_cli_flies_the_controlled_hover_from_the_folder_alone(stored):
    """`hawksim fly --insect bumblebee --control lqr`: the orbit from the spec's reference kinematics (the stored
    quasi-steady trim), its gains, the 20 beats: the stored hover's beats (flown in-process from the same trim) to
    1e-6 m/s, and the report names the insect."""
    out = _cli("fly", "--insect", "bumblebee", "--speed", "0", "--control", "lqr", "--cycles", "20",
               "--perturb", "q=400")
    assert out["insect"] == "bumblebee"
    got = [b["mean_vertical_speed"] for b in out["beats"]]
    np.testing.assert_allclose(got, [b["mean_vertical_speed"] for b in stored["qs_lqr"]["beats"]], atol=1e-6)


def test_cli_kinematics_are_checked_against_the_insects_bounds():
    """--kinematics is checked against the insect's bounds: f = 127 Hz is inside the bumblebee's [71.9, 191.8] Hz and
    outside the hawkmoth's Table 2 [15, 40] Hz (exit 2, naming it)."""
    kin = "f=127,beta=5,phi0=0,theta0=10,alpha0=0,phi_a=58,alpha_a=60"
    out = _cli("aero", "--insect", "bumblebee", "--speed", "0", "--kinematics", kin, "--aero", "quasi-steady")
    assert out["L_plus"] > 0.3
    r = subprocess.run([sys.executable, "-m", "hawksim", "aero", "--speed", "0", "--kinematics", kin],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "f=127 Hz is outside Table 2's [15, 40]" in r.stderr


# ---- adding the bumblebee changed nothing outside its folder ----------------------------------------------------

def test_default_insect_is_the_hawkmoth():
    assert DEFAULT_INSECT == Insect() and DEFAULT_INSECT.morphology == HAWKMOTH and DEFAULT_INSECT.P0 == P0_W
    assert dict(DEFAULT_INSECT.bounds_deg) == {k: tuple(map(float, v)) for k, v in TABLE2_BOUNDS_DEG.items()}
    assert (HAWKMOTH.total_mass, HAWKMOTH.R, HAWKMOTH.cbar, HAWKMOTH.name) == (1578.70e-6, 48.50e-3, 16.81e-3,
                                                                               "sourced")


def test_hawkmoth_quasi_steady_averages_unchanged():
    a = run(table3_kinematics(0.0), 0.0, QS_RES).averages
    assert (a.L_plus, a.D_plus, a.M_plus, a.P_plus, a.power_W) == pytest.approx(HAWKMOTH_QS_HOVER, rel=1e-12,
                                                                                 abs=1e-15)


def test_no_hawksim_module_names_the_bumblebee():
    """The bumblebee is data: no module of hawksim refers to it (only its own folder does)."""
    hits = [p.relative_to(ROOT) for p in (ROOT / "hawksim").rglob("*.py")
            if FOLDER not in p.parents and "bumblebee" in p.read_text().lower()]
    assert hits == []


def test_folder_is_self_contained(bee, stored, tmp_path):
    """The folder copied elsewhere loads to the same insect and gives the same quasi-steady averages."""
    copy = tmp_path / "elsewhere" / "bumblebee"
    shutil.copytree(FOLDER, copy)
    other = load_insect(copy)
    assert (other.morphology, other.P0, dict(other.bounds_deg)) == (bee.morphology, bee.P0, dict(bee.bounds_deg))
    kin = _kin(stored["qs_trim"]["balanced"]["kinematics"])
    a, b = (run(kin, 0.0, QS_RES, insect=i).averages for i in (bee, other))
    assert a == b
