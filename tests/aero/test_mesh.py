"""Wing meshes: geometry, mirror, validation."""

import numpy as np
import pytest

from aero.mesh import WingMesh, mirror_mesh, planform_area, wing_mesh

RECTANGLE_AREA_RTOL = 1e-14
"""Planform area of the 2 x 0.5 rectangle vs 1.0, relative. Float64 round-off of a sum of 16 panel areas
(~16 eps = 4e-15); measured: exact (0)."""

TRIANGLE_AREA_RTOL = 1e-12
"""Planform area of the triangle (and of its mirror image) vs 0.5, relative. A round-off bound with a wide margin
(not derived beyond that); measured: exact (0)."""


def test_rectangle_geometry():
    m = wing_mesh(np.linspace(0, 2.0, 5), np.zeros(5), -0.5 * np.ones(5), 4)
    assert m.vertices.shape == (5, 5, 3)
    assert planform_area(m) == pytest.approx(1.0, rel=RECTANGLE_AREA_RTOL)
    assert np.allclose(m.normals, [0, 0, 1])
    assert np.allclose(m.collocation[0, 0], [-0.75 * 0.125, 0.25, 0.0])  # 3/4 of panel 1
    assert np.allclose(m.rings[-1, :, 0], -0.5 - 0.25 * 0.125)      # TE ring line a quarter panel behind the TE


def test_triangle_tip_and_mirror():
    y = np.linspace(0, 1.0, 5)
    c = 1.0 - y                       # zero chord at the tip
    m = wing_mesh(y, 0.25 * c, -0.75 * c, 3)
    assert planform_area(m) == pytest.approx(0.5, rel=TRIANGLE_AREA_RTOL)
    r = mirror_mesh(m)
    assert planform_area(r) == pytest.approx(0.5, rel=TRIANGLE_AREA_RTOL)
    assert np.allclose(r.normals, [0, 0, 1])
    assert np.all(r.vertices[..., 1] <= 0) and np.allclose(r.vertices[:, -1, 1], 0.0)


@pytest.mark.parametrize("args", [
    (np.array([0.0, 0.0, 1.0]), np.zeros(3), -np.ones(3), 2),          # repeated station
    (np.linspace(0, 1, 3), np.zeros(3), np.ones(3), 2),                 # negative chord
    (np.linspace(0, 1, 3), np.array([0, np.nan, 0]), -np.ones(3), 2),   # NaN
    (np.linspace(0, 1, 3), np.zeros(3), -np.ones(3), 0),                # nc < 1
    (np.linspace(0, 1, 1), np.zeros(1), -np.ones(1), 2),                # ns < 1
    (np.linspace(0, 1, 3), np.zeros(3), np.zeros(3), 2),                # zero area
])
def test_degenerate_meshes_raise(args):
    with pytest.raises(ValueError):
        wing_mesh(*args)


def test_wingmesh_rejects_bad_shape():
    with pytest.raises(ValueError):
        WingMesh(np.zeros((1, 3, 3)))
