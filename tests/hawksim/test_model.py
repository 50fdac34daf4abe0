"""The MJCF hawkmoth equals the morphology; structure, symmetry and file errors."""

import mujoco
import numpy as np
import pytest

from hawksim.frames import quat_to_matrix
from hawksim.insect.kinematics import MIRROR, table3_kinematics, wing_rotation_body
from hawksim.insect.model import DEFAULT_MODEL_PATH, load_model, mjcf
from hawksim.insect.morphology import HAWKMOTH

TOL = 1e-8
"""Relative: a mass, inertia, position or axis in the MJCF vs the morphology's float64 value. The XML stores 9
significant digits (rounding <= 5e-9 relative); measured: exact for the masses and hinge positions, 7.2e-10 for
the wing centres of mass."""

BODY_INERTIA_ATOL = TOL * 2e-7
"""kg m^2: TOL of the body's inertia scale (principal moments ~1.9e-7 kg m^2), for entries that vanish; measured
largest difference 3.0e-16."""

WING_INERTIA_ATOL = TOL * 1e-8
"""kg m^2: TOL of the wing's inertia scale (entries up to 8.6e-9 kg m^2); measured largest difference 4.5e-18."""

POSITION_ATOL = 1e-12
"""m: absolute floor for centre-of-mass positions (~0.02 m) whose components vanish; a round-off floor, measured
largest difference 9.6e-12 on a non-zero component (passing on the TOL part)."""

FRAME_ATOL = 1e-12
"""MuJoCo's wing xmat vs hawksim.insect.kinematics' wing frames (entries of order 1). assert_allclose's default
rtol = 1e-7 also applies: measured largest difference 2.1e-10 (5.4e-9 relative), the 9 stored digits of the
joint axes, so the check passes on the rtol; the atol covers entries that vanish."""

MIRROR_ATOL = 1e-15
"""m: the posed right wing's position and centre of mass vs the left one's mirror image: MuJoCo computes the two
with the same operations on mirrored data; measured: exact (0)."""


def test_committed_xml_is_the_generated_one():
    assert DEFAULT_MODEL_PATH.read_text() == mjcf(), "regenerate with: python -m hawksim.insect.model"
    m = mujoco.MjModel.from_xml_path(str(DEFAULT_MODEL_PATH))  # plain MuJoCo loads it
    assert m.nbody == 4


def test_every_shipped_insects_mjcf_is_generated_from_its_spec():
    from hawksim.insect.folder import load_insect, shipped_insects
    from hawksim.insect.model import insect_mjcf, model_path

    for name in shipped_insects():
        insect = load_insect(name)
        assert model_path(insect).read_text() == insect_mjcf(insect), f"{name}: python -m hawksim.insect.model"


def test_one_free_joint_and_six_hinges():
    m = load_model()
    assert m.njnt == 7 and m.nq == 13 and m.nv == 12
    assert m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert all(m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE for j in range(1, 7))
    for site in ("com", "hinge_left", "hinge_right", "wing_com_left", "wing_com_right"):
        assert mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, site) >= 0


def _full_inertia(m, b):
    R = quat_to_matrix(m.body_iquat[b])
    return R @ np.diag(m.body_inertia[b]) @ R.T


def test_mass_and_inertia_equal_the_morphology():
    m = load_model()
    body, wl, wr = (mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n) for n in ("body", "wing_left", "wing_right"))
    assert m.body_mass[body] == pytest.approx(HAWKMOTH.body_mass, rel=TOL)
    assert m.body_mass[wl] == m.body_mass[wr] == pytest.approx(HAWKMOTH.wing_mass, rel=TOL)
    assert m.body_subtreemass[body] == pytest.approx(HAWKMOTH.total_mass, rel=TOL)
    np.testing.assert_allclose(m.body_ipos[body], 0, atol=POSITION_ATOL)
    np.testing.assert_allclose(_full_inertia(m, body), HAWKMOTH.body_inertia, rtol=TOL, atol=BODY_INERTIA_ATOL)
    np.testing.assert_allclose(m.body_ipos[wl], HAWKMOTH.wing_com, rtol=TOL, atol=POSITION_ATOL)
    np.testing.assert_allclose(m.body_ipos[wr], MIRROR @ HAWKMOTH.wing_com, rtol=TOL, atol=POSITION_ATOL)
    Iw = HAWKMOTH.wing_inertia
    np.testing.assert_allclose(_full_inertia(m, wl), Iw, rtol=TOL, atol=WING_INERTIA_ATOL)
    np.testing.assert_allclose(_full_inertia(m, wr), MIRROR @ Iw @ MIRROR, rtol=TOL, atol=WING_INERTIA_ATOL)
    np.testing.assert_allclose(m.body_pos[wl], HAWKMOTH.hinge_left, rtol=TOL)
    np.testing.assert_allclose(m.body_pos[wr], MIRROR @ HAWKMOTH.hinge_left, rtol=TOL)


def test_joint_axes_reproduce_the_kinematics_frames():
    """MuJoCo's wing frames (xmat) equal hawksim.insect.kinematics' for both wings: joint angles = (phi, theta,
    alpha)."""
    m = load_model()
    d = mujoco.MjData(m)
    kin = table3_kinematics(1.0)
    for t in np.linspace(0, kin.period, 7):
        q = kin.angles(t)
        d.qpos[:] = 0
        d.qpos[3] = 1
        d.qpos[7:10] = q
        d.qpos[10:13] = q
        mujoco.mj_kinematics(m, d)
        for side, b in (("left", 2), ("right", 3)):
            np.testing.assert_allclose(d.xmat[b].reshape(3, 3), wing_rotation_body(kin, t, side), atol=FRAME_ATOL)
        # mirror symmetry of the posed wings
        np.testing.assert_allclose(d.xpos[3], MIRROR @ d.xpos[2], atol=MIRROR_ATOL)
        np.testing.assert_allclose(d.xipos[3], MIRROR @ d.xipos[2], atol=MIRROR_ATOL)


def test_bad_model_files(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        load_model(tmp_path / "missing.xml")
    bad = tmp_path / "corrupt.xml"
    bad.write_text("<mujoco><worldbody><body")
    with pytest.raises(ValueError, match="could not be loaded") as e:
        load_model(bad)
    assert "\n" not in str(e.value)
    other = tmp_path / "other.xml"
    other.write_text('<mujoco><worldbody><body name="body"><freejoint/><geom size="0.01"/></body></worldbody></mujoco>')
    with pytest.raises(ValueError, match="wing_left"):
        load_model(other)


def test_committed_variant_xml_is_the_generated_one():
    """The default insect's MJCF is the sourced hawkmoth's (issue 49); hawksim 0.2's hawkmoth has its own committed
    MJCF; loading by morphology gives the same model."""
    from hawksim.insect.model import DEFAULT_MODEL_PATH, MODEL_PATHS
    from hawksim.insect.morphology import Morphology
    assert MODEL_PATHS["sourced"] == DEFAULT_MODEL_PATH and DEFAULT_MODEL_PATH.read_text() == mjcf(Morphology())
    old = Morphology.hawksim_0_2()
    assert MODEL_PATHS["hawksim-0.2"].read_text() == mjcf(old), "regenerate with: python -m hawksim.insect.model"
    m = load_model(morph=old)
    wl = m.body("wing_left").id
    np.testing.assert_allclose(m.body_ipos[wl], old.wing_com, rtol=TOL, atol=POSITION_ATOL)
    assert m.body_mass[wl] == pytest.approx(old.wing_mass, rel=TOL)
    with pytest.raises(ValueError, match="not both"):
        load_model(MODEL_PATHS["hawksim-0.2"], morph=old)
