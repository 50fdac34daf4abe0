"""A free flight with a very heavy body reproduces the held-body cycle averages (the loop's load coupling).

With the body's mass and inertia multiplied by ``HEAVY`` = 1e4 and gravity off, the body barely moves in a few
wingbeats (its velocity changes by ~ (W / (1e4 m)) 3 T ~ 1e-4 m/s, its attitude by ~ 1e-5 rad), so the free
flight started at the held-body attitude chi and ascent speed V sees the same wing motion relative to the air
as :func:`hawksim.backends.held.held_flight`, and its cycle-mean loads must be the held ones. This checks
:meth:`hawksim.flight.simulator.Simulator.step`'s hold of the backend's loads between updates (``aero_every > 1``):
holding them in the WING frame rotates the force with the wing over the hold (a bias of about
(aero_every - 1) dt / 2 mean(omega x F), -4 % in L+ for the UVLM at 1 m/s); holding them in the WORLD frame
reproduces the held run, whose loads are a zero-order hold at the backend's own rate.

Tolerances: L+, D+ within ``REL_TOL`` = 0.5 % of max(|L+|, 1) (D+ and L+ share the scale W: D+ is near zero,
so its error is measured on the weight scale), M+ within ``M_ABS_TOL`` = 0.005 absolute (M+ is near zero at the
trim, so a relative error is meaningless; 0.005 is 0.5 % of W cbar).
"""

import mujoco
import numpy as np
import pytest

from hawksim.backends.held import held_flight
from hawksim.insect.model import load_model
from hawksim.insect.morphology import HAWKMOTH
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.frames import quat_from_matrix, rot_y
from hawksim.flight.simulator import Simulator
from hawksim.trim.tables import trim_kinematics

HEAVY = 1e4
REL_TOL = 0.005
M_ABS_TOL = 0.005
CYCLES = 3
"""Wingbeats flown; the last one is compared (the UVLM's wake develops over the first two)."""


def heavy_free_averages(kin, speed, backend, *, steps_per_cycle, aero_every, cycles=CYCLES):
    """(L+, D+, M+) of the last wingbeat of a free flight of a body ``HEAVY`` times heavier, gravity off,
    started at pitch chi moving straight up at ``speed`` [m/s]; loads as applied by the loop (world frame,
    the pitching moment about the body's centre of mass, nose up)."""
    m = load_model()
    b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "body")
    m.body_mass[b] *= HEAVY
    m.body_inertia[b] *= HEAVY
    sim = Simulator(m, kin, backend, steps_per_cycle=steps_per_cycle, gravity=False, aero_every=aero_every)
    sim.reset(velocity=np.array([0.0, 0.0, speed]), quat=quat_from_matrix(rot_y(-kin.chi)))
    L, D, M = [], [], []
    for _ in range(cycles * steps_per_cycle):
        r = sim.step()
        F = r.loads.force.sum(0)
        Mc = r.loads.moment_about(r.state, r.state.body_pos)
        L.append(F[2])
        D.append(-F[0])
        M.append(-(Mc @ r.state.body_R[:, 1]))
    last = slice(-steps_per_cycle, None)
    W = HAWKMOTH.weight
    return np.mean(L[last]) / W, np.mean(D[last]) / W, np.mean(M[last]) / (W * HAWKMOTH.cbar)


def held_averages(kin, speed, backend, *, steps_per_cycle, cycles=CYCLES):
    a = held_flight(kin, speed, backend, cycles=cycles, steps_per_cycle=steps_per_cycle).averages
    return a.L_plus, a.D_plus, a.M_plus


def _check(free, held):
    (Lf, Df, Mf), (Lh, Dh, Mh) = free, held
    scale = max(abs(Lh), 1.0)
    assert abs(Lf - Lh) <= REL_TOL * scale, (free, held)
    assert abs(Df - Dh) <= REL_TOL * scale, (free, held)
    assert abs(Mf - Mh) <= M_ABS_TOL, (free, held)


@pytest.mark.parametrize("aero_every", [1, 5])
def test_heavy_body_quasi_steady(aero_every):
    """Quasi-steady at 1 m/s: 200 integrator steps per beat, the backend every ``aero_every`` steps, against
    the held run at the backend's rate (200 / aero_every steps per beat)."""
    kin = trim_kinematics(1.0, "quasi-steady")
    free = heavy_free_averages(kin, 1.0, QuasiSteadyBackend(), steps_per_cycle=200, aero_every=aero_every)
    held = held_averages(kin, 1.0, QuasiSteadyBackend(), steps_per_cycle=200 // aero_every)
    _check(free, held)


@pytest.mark.slow
def test_heavy_body_uvlm():
    """UVLM at the 1 m/s UVLM trim, `hawksim fly`'s coupling: 6 x 12 rings, 200 steps, backend every 5."""
    from hawksim.backends.uvlm import UVLMBackend

    kin = trim_kinematics(1.0, "uvlm")
    free = heavy_free_averages(kin, 1.0, UVLMBackend(n_chord=6, n_span=12), steps_per_cycle=200, aero_every=5)
    held = held_averages(kin, 1.0, UVLMBackend(n_chord=6, n_span=12), steps_per_cycle=40)
    _check(free, held)
