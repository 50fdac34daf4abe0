"""The prescribed far wake (``UVLMConfig.free_wake_age``, ``far_wake_drift``; issue 49, item 4).

Case: a flat rectangular wing (chord 1 m, span 4 m, 3 x 8 rings) heaving h = 0.2 sin(2 pi t) m in a free stream of
1 m/s along +x, 20 steps per period, free wake. The option must (a) change nothing where no corner is old enough,
(b) move every old corner by exactly (free stream + drift) dt, the young ones by the free wake's velocity, and
(c) reject bad values with the field's name.
"""

import numpy as np
import pytest

from aero.mesh import wing_mesh
from aero.uvlm import UVLM, FreeStream, UVLMConfig

FREESTREAM = FreeStream(v0=np.array([-1.0, 0.0, 0.0]))
STEPS, DT = 30, 0.05

DRIFT_ATOL = 1e-12
"""m: an old corner's displacement in one step against (free stream + drift) dt: the same float64 sum (measured
~1e-17)."""


def _run(config: UVLMConfig, steps: int = STEPS) -> UVLM:
    span = np.linspace(-2.0, 2.0, 9)
    mesh = wing_mesh(span, np.full(9, 0.25), np.full(9, -0.75), 3)
    solver = UVLM([mesh], config)
    R = np.eye(3)[None]
    for k in range(steps):
        t = (k + 1) * DT
        h, hd = 0.2 * np.sin(2 * np.pi * t), 0.2 * 2 * np.pi * np.cos(2 * np.pi * t)
        solver.step(DT, R, np.array([[0.0, 0.0, h]]), np.array([[0.0, 0.0, hd]]), np.zeros((1, 3)),
                    freestream=FREESTREAM)
    return solver


def test_no_old_corner_changes_nothing():
    """An age limit no corner reaches gives the free wake bit for bit."""
    free = _run(UVLMConfig())
    limited = _run(UVLMConfig(free_wake_age=1e9, far_wake_drift=(0.0, 0.0, -0.5)))
    for (v0, g0), (v1, g1) in zip(free.wake, limited.wake):
        assert np.array_equal(v0, v1) and np.array_equal(g0, g1)


def test_old_corners_drift_young_ones_are_free():
    """Past the age limit a corner moves by exactly (free stream + drift) dt; below it, by the free wake's velocity
    (which differs from the free stream: the check can fail)."""
    age_limit, drift = 5.5 * DT, np.array([0.0, 0.0, -0.3])
    cfg = UVLMConfig(free_wake_age=age_limit, far_wake_drift=tuple(drift))
    solver = _run(cfg, STEPS - 1)
    before = solver.wakes[0].vertices.copy()
    age_before = solver.wakes[0].age.copy()
    _run_one = _run(cfg, STEPS)  # the same flight one step further
    after = _run_one.wakes[0].vertices
    # corner row j before the step is row j + 1 after it (a new row is shed at the trailing edge)
    moved = after[2:before.shape[0] + 1] - before[1:]
    old = age_before[1:] > age_limit
    assert old.any() and (~old).any()
    expected = (FREESTREAM.v0 + drift) * DT
    assert np.abs(moved[old] - expected).max() < DRIFT_ATOL
    assert np.abs(moved[~old] - FREESTREAM.v0 * DT).max() > 1e-4  # the free part feels the induced velocity


@pytest.mark.parametrize("kw, field", [({"free_wake_age": -1.0}, "free_wake_age"),
                                       ({"free_wake_age": float("nan")}, "free_wake_age"),
                                       ({"far_wake_drift": (0.0, 1.0)}, "far_wake_drift"),
                                       ({"far_wake_drift": (0.0, 0.0, float("inf"))}, "far_wake_drift")])
def test_bad_values_name_the_field(kw, field):
    with pytest.raises(ValueError, match=field):
        UVLMConfig(**kw)
