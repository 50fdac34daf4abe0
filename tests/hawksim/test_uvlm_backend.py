"""The UVLM as a hawksim backend: mirror images vs explicit wings, the paper's Table 4, `hawksim aero`."""

import json

import numpy as np
import pytest

from hawksim.backends.held import held_flight, run
from hawksim.backends.resolution import Resolution
from hawksim.backends.uvlm import UVLMBackend, hawkmoth_meshes
from hawksim.cli import main
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import HAWKMOTH

COARSE = Resolution(n_chord=4, n_span=8, steps_per_cycle=30, cycles=3)

AREA_RTOL = 1e-12
"""Relative: summed panel areas of the hawkmoth mesh vs the planform's wing area: round-off; measured 1.3e-16."""

MIRROR_RTOL = 1e-8
"""Relative: mirrored (symmetric=True) vs two-wing UVLM forces and moments over the 0.4 beat before the wing meets
its own wake. Mathematically identical: round-off, grown through the solves; measured: the only differences are
on components that vanish (below the atol)."""

MIRROR_FORCE_ATOL = 1e-10
"""N: absolute floor of the same force comparison (forces ~0.04 N); measured largest difference 2.1e-17 N."""

MIRROR_MOMENT_ATOL = 1e-12
"""N m: absolute floor of the same moment comparison (moments ~1e-3 N m); measured largest difference 5.4e-19."""

SYMMETRY_TOL = 1e-9
"""Side force of the explicit symmetric pair as a fraction of the peak |Fz|; roll and yaw moment as a fraction of
peak |Fz| x R. Round-off; measured 1.4e-16 (force), 2.6e-16 (moments)."""

TABLE4_RTOL = 0.04
"""Relative: L+ and P+ at Table 3's kinematics vs Nguyen et al. (2020) Table 4 at the 6 x 12 x 40 lattice (3 beats).
L+ is calibrated there (the feathering axis, issue 49: within 3 % at 0, 1, 2 m/s by the calibration's rule); P+
is a prediction. Measured L+ -2.3 % / +2.8 %, P+ -0.8 % / +1.1 % at 1 / 2 m/s (hawksim 0.2: 12.5 %, 10.6 %)."""

TABLE4_DM_TOL = 0.08
"""|D+| and |M+| at the same runs ('near 0'; the paper's trim balances them on its model, not on ours): a round
bound; measured D+ 0.066 / 0.044 and M+ 0.039 / -0.008 at 1 / 2 m/s on the sourced hawkmoth (its hinges and
feathering axis moved the horizontal force; hawksim 0.2: at most 0.022)."""

POWER_RISE = 1.1
"""P+(1.5 m/s) must exceed this multiple of P+(0.5 m/s). Table 4: 0.96 -> 1.21 (x 1.26); measured x 1.34 at the
coarse lattice."""

ROLL_TOL_DEG = 1e-6
"""deg: largest roll of a symmetric UVLM free flight over one beat: round-off; not measured separately."""

LATERAL_DRIFT_TOL_M = 1e-9
"""m: largest lateral body position in the same flight: round-off; not measured separately."""

ONE_BEAT_SPEED_RANGE = (0.5, 1.5)
"""m/s: mean vertical speed after one free beat started at 1 m/s: one beat cannot change it by more than a few
tenths (a plausibility band, not derived)."""

HOLD_SPEED_TOL = 0.1
"""m/s: beat-mean ascent speed vs 1 m/s over 2 free beats with the UVLM from the shipped UVLM trim. Measured with
hawksim 0.2: 1.007, 0.954 m/s (0.1: 1.007, 0.950); largest deviation now 0.033 m/s."""

HOLD_PITCH_TOL_DEG = 2.0
"""deg: beat-mean body angle vs chi over the same 2 beats; measured largest deviation 1.0 deg."""


def test_meshes_have_the_wing_area_and_mirror():
    left, right = hawkmoth_meshes(n_chord=6, n_span=12)
    assert left.panel_areas.sum() == pytest.approx(HAWKMOTH.wing_area, rel=AREA_RTOL)
    np.testing.assert_allclose(right.vertices[:, ::-1] * [1, -1, 1], left.vertices)


def test_mirror_images_equal_two_explicit_wings():
    """Before the wing meets its own wake (0.4 beat), the mirrored solve equals the two-wing solve."""
    kin = table3_kinematics(1.0)
    kw = dict(cycles=1, steps_per_cycle=30)
    n = 12
    sym = UVLMBackend(n_chord=4, n_span=8, symmetric=True)
    full = UVLMBackend(n_chord=4, n_span=8, symmetric=False)
    a = held_flight(kin, 1.0, sym, **kw)
    b = held_flight(kin, 1.0, full, **kw)
    np.testing.assert_allclose(a.force_world[:n], b.force_world[:n], rtol=MIRROR_RTOL, atol=MIRROR_FORCE_ATOL)
    np.testing.assert_allclose(a.moment_world[:n], b.moment_world[:n], rtol=MIRROR_RTOL, atol=MIRROR_MOMENT_ATOL)
    # symmetric flapping: no side force, roll or yaw moment (explicit two wings, all steps)
    scale = np.abs(b.force_world[:, 2]).max()
    assert np.abs(b.force_world[:n, 1]).max() < SYMMETRY_TOL * scale
    assert np.abs(b.moment_world[:n, [0, 2]]).max() < SYMMETRY_TOL * scale * HAWKMOTH.R


@pytest.mark.parametrize("speed, L_paper, P_paper", [(1.0, 0.99, 1.09), (2.0, 0.99, 1.34)])
def test_table3_kinematics_reproduce_table4(speed, L_paper, P_paper):
    """Nguyen et al. (2020) Table 4: the UVLM gives L+ and P+ at Table 3's kinematics. Our UVLM, morphology and
    hinge differ from theirs (see docs/uvlm.md); L+ is calibrated to it (the feathering axis), P+ predicted."""
    a = run(table3_kinematics(speed), speed, Resolution(n_chord=6, n_span=12, steps_per_cycle=40, cycles=3)).averages
    assert a.L_plus == pytest.approx(L_paper, rel=TABLE4_RTOL)
    assert a.P_plus == pytest.approx(P_paper, rel=TABLE4_RTOL)
    assert abs(a.D_plus) < TABLE4_DM_TOL and abs(a.M_plus) < TABLE4_DM_TOL


def test_power_rises_with_ascent_speed():
    P = [run(table3_kinematics(v), v, COARSE).averages.P_plus for v in (0.5, 1.5)]
    assert P[1] > P[0] * POWER_RISE


def test_aero_cli_contract(capsys):
    kin = "f=29.4,beta=2.8,phi0=-4.7,theta0=15,alpha0=1.2,phi_a=60,alpha_a=65"
    assert main(["aero", "--speed", "1", "--kinematics", kin, "--n-chord", "4", "--n-span", "8",
                 "--steps-per-cycle", "30", "--json", "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    for k in ("L_plus", "D_plus", "M_plus", "P_plus", "power_W", "wall_time_s"):
        assert np.isfinite(out[k])
    assert out["power_W"] == pytest.approx(out["P_plus"] * 84.2e-3)
    # a healthy run's verdict: periodic, and its peak force coefficient where a revolving wing's lies (0.6-2.9
    # across 100 hover samples, hawksim.surrogate.dataset.PEAK_FORCE_CEILING)
    assert out["status"] == "ok" and 0.3 < out["peak_force_coefficient"] < 3.0
    assert main(["aero", "--speed", "1", "--kinematics", kin.replace("f=29.4", "f=inf"), "--json"]) == 2
    assert "f" in capsys.readouterr().err


SPIKE_KIN = "f=31.7254,beta=19.8123,phi0=18.288,theta0=-12.5012,alpha0=2.45871,phi_a=40.2715,alpha_a=68.2367"
"""Kinematics inside Table 2 at which the default lattice's run blows up without going non-finite (a wake vortex
crossing the lattice): per-beat L+ -685, -233, -5.0, peak force coefficient 1.2e4 (2026-12-03; found 5 % of the
ranges from a held-out sample by scripts/studies/reference_label_roughness.py). Before, `hawksim aero` printed
L+ -5.0 as a result."""


def test_aero_refuses_a_blown_up_run(capsys):
    """A run whose peak force coefficient is above the data set's ceiling is a numerical failure (exit 3, one line
    naming the peak and the ceiling, nothing on stdout), as a data set would store it as 'diverged'."""
    code = main(["aero", "--speed", "1.5", "--kinematics", SPIKE_KIN, "--json", "--no-progress"])
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert code == 3 and cap.out == "" and len(err) == 1
    assert "peak force coefficient" in err[0] and "above the credible 4" in err[0]


def test_label_status_rule():
    """The data set's verdict (hawksim.surrogate.dataset.label_status): diverged above the peak ceiling or without
    a label, unsettled past SETTLE_TOL from the wingbeat before, else ok; each boundary crossed once."""
    from hawksim.surrogate.dataset import PEAK_FORCE_CEILING, SETTLE_TOL, label_status

    y = (1.0, 0.1, 0.1, 1.0)
    assert label_status(y, 1.0, None) == "ok"
    assert label_status(None, None, None) == "diverged"
    assert label_status(y, PEAK_FORCE_CEILING * 1.01, None) == "diverged"
    assert label_status(y, PEAK_FORCE_CEILING * 0.99, None) == "ok"
    assert label_status(y, 1.0, (1.0 + 1.01 * SETTLE_TOL, 0.1, 0.1, 1.0)) == "unsettled"
    assert label_status(y, 1.0, (1.0 + 0.99 * SETTLE_TOL, 0.1, 0.1, 1.0)) == "ok"


def test_uvlm_flight_stays_symmetric():
    from hawksim.cli.fly import fly_named

    r = fly_named(1.0, 1, "uvlm", steps_per_cycle=80, periodic_start=False)
    s = r.summary()
    assert s["max_abs_roll_deg"] < ROLL_TOL_DEG and abs(r.body_pos[:, 1]).max() < LATERAL_DRIFT_TOL_M
    assert ONE_BEAT_SPEED_RANGE[0] < s["mean_vertical_speed"] < ONE_BEAT_SPEED_RANGE[1]


def test_uvlm_trim_holds_over_two_wingbeats():
    """From the shipped UVLM-balanced minimum-power trim at 1 m/s (insects/hawkmoth/data/trim_table.json), the free
    6-DOF flight with the UVLM in the loop keeps its ascent speed within 0.1 m/s and its cycle-mean body angle within
    2 deg of chi for 2 beats (measured with hawksim 0.2: 1.007, 0.954 m/s; 0.1: 1.007, 0.950). It then keeps
    slowing, 0.89 m/s in beat 3: the held-body balance credits the wings with ~15 % more lift than the recoiling
    free body gets (docs/results.md), and the longitudinal mode is unstable (docs/stability.md)."""
    from hawksim.cli.fly import fly_named
    from hawksim.trim.tables import trim_source

    assert "uvlm balance" in trim_source().lower()
    r = fly_named(1.0, 2, "uvlm")
    n = r.steps_per_cycle
    z, pitch = r.body_pos[:, 2], np.degrees(r.pitch())
    for c in range(2):
        s = slice(c * n, (c + 1) * n)
        vz = (z[s][-1] - z[s][0]) / (r.t[s][-1] - r.t[s][0])
        assert vz == pytest.approx(1.0, abs=HOLD_SPEED_TOL)
        assert pitch[s].mean() == pytest.approx(np.degrees(r.kinematics.chi), abs=HOLD_PITCH_TOL_DEG)


def test_uvlm_flight_recording_has_pressure_panels_and_wake(tmp_path):
    """`hawksim fly --aero uvlm --rrd` records panels coloured by pressure and wake lines for both wings."""
    from rerun.chunk import RrdReader

    from hawksim.cli.fly import fly_named
    from hawksim.flight.recording import write_rrd

    r = fly_named(1.0, 1, "uvlm", steps_per_cycle=80, keep_extras_every=8, periodic_start=False)
    assert r.extras and r.extras[0][1]["panels"].shape[0] == 2  # left + mirrored right
    path = write_rrd(tmp_path / "u.rrd", r)
    entities = {ch.entity_path for ch in RrdReader(path).stream().to_chunks()}
    for side in ("left", "right"):
        assert f"/world/uvlm/panels/{side}" in entities and f"/world/uvlm/wake/{side}" in entities


def test_uvlm_is_deterministic():
    kin = table3_kinematics(1.0)
    a = run(kin, 1.0, COARSE).averages
    b = run(kin, 1.0, COARSE).averages
    assert a == b
