"""The shipped orbit tables (insects/hawkmoth/data/orbit_table_*.json, `hawksim reproduce --only orbits`) are periodic
orbits of the current code: re-flying a row's periodic beat from its launch state reproduces the recorded residual,
and `hawksim fly` starts from them."""

import json
from pathlib import Path

import numpy as np
import pytest

from hawksim.backends.registry import descriptor
from hawksim.flight.orbit import (ORBIT_TOL, Orbit, OrbitFlight, orbit_residual,
                                  orbit_within_uvlm_tolerance)
from hawksim.trim.registry import shipped_table

REPRODUCE_TOL = 1e-9
"""Normalized residual: the re-flown quasi-steady orbit's residual may differ from the recorded one by this much
(the flight is bitwise deterministic on one machine; the margin covers another BLAS or CPU's last bits, amplified
by at most the largest multiplier 2.4 over one beat from a 1e-15 round-off)."""


def _rows(aero):
    table = shipped_table(descriptor(aero).orbit_table)
    return [Orbit.from_json(r) for r in table["rows"]] if table is not None else []


def _refly(o: Orbit) -> np.ndarray:
    b = OrbitFlight(o.aero).fly(o.kinematics, o.launch_state.as_array(), o.warm_beats + 1, o.chi_ref)
    return orbit_residual(o.kinematics, o.speed, b, o.warm_beats)


def test_the_quasi_steady_table_has_five_converged_orbits():
    rows = _rows("quasi-steady")
    assert [o.speed for o in rows] == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert all(o.converged and o.residual <= ORBIT_TOL for o in rows)


@pytest.mark.parametrize("speed", [0.0, 1.0, 2.0])
def test_quasi_steady_rows_are_orbits_of_this_code(speed):
    o = next(o for o in _rows("quasi-steady") if o.speed == speed)
    r = _refly(o)
    assert np.abs(r).max() <= ORBIT_TOL
    np.testing.assert_allclose(r, o.residuals, atol=REPRODUCE_TOL)


def test_fly_starts_from_the_shipped_orbit():
    from hawksim.cli.fly import fly_named

    r = fly_named(1.0, 2)
    assert r.trim_source.startswith("shipped periodic orbit")
    o = next(o for o in _rows("quasi-steady") if o.speed == 1.0)
    assert r.kinematics == o.kinematics


@pytest.mark.slow
def test_uvlm_rows_are_orbits_of_this_code():
    """The UVLM rows (where shipped) meet the UVLM tolerance (1e-3 m/s, 1e-2 rad/s) when re-flown."""
    rows = _rows("uvlm")
    if not rows:
        pytest.skip("no shipped UVLM orbit table")
    o = next((o for o in rows if o.speed == 1.0), rows[0])
    r = _refly(o)
    assert orbit_within_uvlm_tolerance(r, o.kinematics) == o.converged
    np.testing.assert_allclose(r, o.residuals, atol=1e-6)


UVLM_HOLD_BEATS = 3
"""Beats from the UVLM orbit's periodic beat on that the open-loop flight holds (issue 19 asks for 5, which this
free wake does not allow). The flight's beat-to-beat change (the orbit's ``floor``, 7.3e-3 normalized at 1 m/s on
the sourced hawkmoth, 2.6e-3 on hawksim 0.2's) drives the unstable mode (|mu| 1.62 a beat; 0.2: 1.44). Measured
(hawksim 0.3, `hawksim fly --speed 1 --cycles 10 --aero uvlm`): beats 3-8 (beat 3 the periodic one) 1.00001,
0.99881, 0.99664, 0.99299, 0.98842, 0.98333 m/s; pitch 60.28, 60.30, 60.65, 61.71, 63.36, 65.75 deg. So 3 beats
stay within UVLM_PITCH_TOL_DEG (worst 0.37 deg), 4 do not (1.42), though 4 stay within UVLM_SPEED_TOL (0.0070).
hawksim 0.2 held 4 (speed 0.99983 .. 0.99185, pitch 60.62-60.81). The floor is not the wake's growth past the
measured beat (0.2's study: `python scripts/studies/uvlm_orbit_floor.py --speed 1 --wake-beats 2 --resolve`)."""
UVLM_SPEED_TOL = 0.01
"""m/s: issue 19's tolerance on the cycle-mean vertical speed."""
UVLM_PITCH_TOL_DEG = 1.0
"""deg: issue 19's tolerance on the cycle-mean pitch (measured drift 0.37 deg over the 3 beats)."""


@pytest.mark.slow
def test_uvlm_trim_holds_from_the_shipped_orbit():
    from hawksim.cli.fly import fly_named

    o = next((o for o in _rows("uvlm") if o.speed == 1.0), None)
    if o is None:
        pytest.skip("no shipped UVLM orbit at 1 m/s")
    r = fly_named(1.0, o.warm_beats + UVLM_HOLD_BEATS, "uvlm")
    assert r.trim_source.startswith("shipped periodic orbit")
    beats = r.beats()[o.warm_beats:]
    ref = beats[0]["pitch_deg"]
    for b in beats:
        assert b["mean_vertical_speed"] == pytest.approx(1.0, abs=UVLM_SPEED_TOL)
        assert b["pitch_deg"] == pytest.approx(ref, abs=UVLM_PITCH_TOL_DEG)


FLOQUET_EXPONENT_TOL = 1e-6
"""Per wingbeat: the CLI's longitudinal exponents at 1 m/s against the quasi-steady Floquet exponents of the committed
validation (results/free_flight/validation.json, `hawksim reproduce --only validation`: 0.4356 +- 0.2515i, -0.1209,
-1.0794 on hawksim 0.3's hawkmoth; 0.389 +- 0.230i, -0.112, -1.013 on 0.2's). The same orbit and monodromy in
another process: agreement to the orbit's convergence, far inside this tolerance."""


def _validation_exponents(speed: float, aero: str, system: str) -> list[complex]:
    p = Path(__file__).resolve().parents[2] / "results" / "free_flight" / "validation.json"
    rows = json.loads(p.read_text())["entries"]
    return [complex(*r["floquet"]) for r in rows if (r["speed"], r["aero"], r["system"]) == (speed, aero, system)]


def test_stability_floquet_cli_contract(capsys):

    from hawksim.cli import main

    assert main(["stability", "--speed", "1", "--floquet", "--aero", "quasi-steady", "--json", "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("longitudinal", "lateral", "floquet", "orbit", "control_derivatives"):
        assert key in out
    for system in ("longitudinal", "lateral"):
        f = out["floquet"][system]
        assert len(f["multipliers"]) == len(f["exponents"]) == len(f["modes"]) == 4
        assert len(out[system]["eigenvalues"]) == 4 and len(out[system]["derivatives"]) == 9
    ex = sorted(out["floquet"]["longitudinal"]["exponents"], key=lambda z: -z[0])
    ref = sorted(_validation_exponents(1.0, "quasi-steady", "longitudinal"), key=lambda z: -z.real)
    assert len(ref) >= 3  # the pair once, the two subsidences
    assert ex[0][0] == pytest.approx(ref[0].real, abs=FLOQUET_EXPONENT_TOL)
    assert abs(ex[0][1]) == pytest.approx(abs(ref[0].imag), abs=FLOQUET_EXPONENT_TOL)
    assert ex[-1][0] == pytest.approx(ref[-1].real, abs=FLOQUET_EXPONENT_TOL)
    assert len(out["control_derivatives"]["B1"][0]) == len(out["control_derivatives"]["inputs"])
