"""A matrices (paper Eqs. 11-12, Etkin's lateral form), nondimensionalisation (Eq. 8), mode classification."""

import numpy as np
import pytest

from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import HAWKMOTH
from hawksim.stability.derivatives import mass_properties
from hawksim.stability.system import Scales, a_lat, a_long, classify, modes, nondimensional_system

D = {"Xu": -1.0, "Xw": 0.1, "Xq": 0.2, "Zu": 0.05, "Zw": -2.0, "Zq": 0.3, "Mu": 0.4, "Mw": -0.02, "Mq": -0.5,
     "Yv": -1.1, "Yp": 0.15, "Yr": 0.05, "Lv": -0.3, "Lp": -0.6, "Lr": 0.02, "Nv": 0.04, "Np": 0.03, "Nr": -0.7}

BY_HAND_RTOL = 1e-15
"""Relative: A matrix entries vs their hand-computed values (quotients of decimal inputs): one or two float64
roundings (eps 2.2e-16 each) per entry; measured 1.3e-16."""

IXZ_RTOL = 1e-13
"""Relative: the Ixz-coupled rows of a_lat satisfy Etkin's Ix p' - Ixz r' = L, Iz r' - Ixz p' = N. Round-off of a
2 x 2 solve and a product (a few tens of eps); measured 8.7e-16."""

MASS_RTOL = 1e-9
"""Relative: mass_properties' total mass vs Table 1's 1578.7 mg. Source of 1e-9 not recorded (a round-off bound
with margin); measured: exact (0)."""


def test_a_long_by_hand():
    A = a_long(D, m=10.0, Iy=4.0, g=0.5, w_e=-0.3)
    expected = [[-0.1, 0.01, 0.02 + 0.3, -0.5], [0.005, -0.2, 0.03, 0], [0.1, -0.005, -0.125, 0], [0, 0, 1, 0]]
    np.testing.assert_allclose(A, expected, rtol=BY_HAND_RTOL)


def test_a_lat_by_hand_and_ixz_coupling():
    A = a_lat(D, m=10.0, Ix=2.0, Iz=4.0, Ixz=0.0, g=0.5, w_e=-0.3)
    expected = [[-0.11, 0.015 - 0.3, 0.005, 0.5], [-0.15, -0.3, 0.01, 0], [0.01, 0.0075, -0.175, 0], [0, 1, 0, 0]]
    np.testing.assert_allclose(A, expected, rtol=BY_HAND_RTOL)
    # with Ixz: rows 2-3 solve Ix p' - Ixz r' = L, Iz r' - Ixz p' = N (Etkin 1972)
    Ix, Iz, Ixz = 2.0, 4.0, -0.5
    A = a_lat(D, m=10.0, Ix=Ix, Iz=Iz, Ixz=Ixz, g=0.5, w_e=-0.3)
    x = np.array([0.3, -0.2, 0.1, 0.0])
    pdot, rdot = (A @ x)[1:3]
    L = D["Lv"] * x[0] + D["Lp"] * x[1] + D["Lr"] * x[2]
    N = D["Nv"] * x[0] + D["Np"] * x[1] + D["Nr"] * x[2]
    assert Ix * pdot - Ixz * rdot == pytest.approx(L, rel=IXZ_RTOL)
    assert Iz * rdot - Ixz * pdot == pytest.approx(N, rel=IXZ_RTOL)


def test_classification():
    assert classify(0.1 + 0.5j) == ("oscillatory", False)
    assert classify(-0.1 - 0.5j) == ("oscillatory", True)
    assert classify(-0.3) == ("subsidence", True)
    assert classify(0.2) == ("divergence", False)
    A = np.diag([-1.0, 2.0, 0.0, 0.0])
    A[2:, 2:] = [[0.1, 1.0], [-1.0, 0.1]]
    kinds = [(m.kind, m.stable) for m in modes(A)]
    assert kinds == [("subsidence", True), ("oscillatory", False), ("oscillatory", False), ("divergence", False)]


def test_eq8_scales_and_mass_properties():
    kin = table3_kinematics(0.0)
    sc = Scales.of(kin)
    assert sc.U == pytest.approx(2 * np.radians(60) * 26.5 * 0.53 * 48.5e-3)
    assert sc.S_t == pytest.approx(2 * HAWKMOTH.wing_area)
    mp = mass_properties(kin)
    assert mp.m == pytest.approx(1578.7e-6, rel=MASS_RTOL)
    assert mp.Iy > 0 and mp.Ix > 0 and mp.Iz > 0
    assert mp.Ixz < 0  # the nose-up body's long axis runs forward-up: -int xz dm < 0 in stability axes
    # the body's own centre of mass: in the plane of symmetry, 0.43 mm below the system's (the wings sit above it;
    # 0.75 mm on hawksim 0.2's hawkmoth, whose heavier wings carried their mass further out)
    assert mp.body_cg[1] == 0.0 and mp.body_cg[2] == pytest.approx(4.3e-4, abs=0.5e-4)
    from dataclasses import replace

    d, Al, At, sca = nondimensional_system(kin, 1.0, {k: 1e-4 for k in D}, replace(mp, body_cg=(0.0, 0.0, 0.0)))
    assert sca["w_e_plus"] == pytest.approx(-1.0 / sc.U)
    assert sca["g_plus"] == pytest.approx(9.81 * sc.T / sc.U)
    assert d["Xu"] == pytest.approx(1e-4 / (0.5 * 1.225 * sc.U * sc.S_t))
    assert d["Mq"] == pytest.approx(1e-4 / (0.5 * 1.225 * sc.U**2 * sc.S_t * sc.cbar * sc.T))
    assert Al.shape == At.shape == (4, 4)


def test_derivatives_move_to_the_system_centre_of_mass_by_rigid_body_kinematics():
    """hawksim.stability.system.about_centre_of_mass against a direct evaluation: loads linear in the motion of O
    (the body's centre of mass; random 6 x 6 map), the body moved by rotations about P = O - a and moments taken
    about P with np.cross. Also: a = 0 changes nothing, and an a_y off the plane of symmetry is refused."""
    import pytest

    from hawksim.stability.system import about_centre_of_mass

    rng = np.random.default_rng(5)
    K = rng.normal(size=(6, 6))  # (X, Y, Z, L, M, N) about O per unit (u, v, w, p, q, r) of O's motion
    a = np.array([-3.4e-5, 0.0, 7.5e-4])  # O - P, the hawkmoth's (mass_properties at 1 m/s)

    def loads_about_P(v_P, w):
        F_M = K @ np.concatenate([v_P + np.cross(w, a), w])
        return np.concatenate([F_M[:3], F_M[3:] + np.cross(a, F_M[:3])])

    names = "XYZLMN"
    raw = {names[i] + "uvwpqr"[j]: K[i, j] for i in range(6) for j in range(6)}
    paper = {k: raw[k] for k in ("Xu Zu Mu Xw Zw Mw Xq Zq Mq Yv Lv Nv Yp Lp Np Yr Lr Nr".split())}
    got = about_centre_of_mass(paper, a)
    e = np.eye(3)
    for j, var in enumerate("uvwpqr"):
        col = loads_about_P(e[j], np.zeros(3)) if j < 3 else loads_about_P(np.zeros(3), e[j - 3])
        for i, f in enumerate(names):
            if f + var in got:
                assert got[f + var] == pytest.approx(col[i], rel=1e-12, abs=1e-15), f + var
    assert about_centre_of_mass(paper, (0.0, 0.0, 0.0)) == paper
    with pytest.raises(ValueError, match="plane of symmetry"):
        about_centre_of_mass(paper, (0.0, 1e-4, 0.0))
