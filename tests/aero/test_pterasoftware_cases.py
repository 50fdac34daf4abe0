"""hawksim's UVLM against PteraSoftware 5.1.0 on the two small cases of scripts/studies/pterasoftware_cases.py, with
PteraSoftware's choices (the study's "matched" variant), against the PteraSoftware numbers the study stored in
results/pterasoftware_cases.json (PteraSoftware itself does not run here).

Both cases: a flat rectangular wing, chord 1 m, span 8 m, 4 x 16 uniform rings, U = 1 m/s, prescribed wake; the
matched settings: "travel" shedding at 0.25 of the step's travel, ring circulation and first-order dGamma/dt in the
unsteady term, no suction turned normal, PteraSoftware's cores (0.03 of the mean chord, bound and wake) and growth
(a' = 1e-4), and its kinematics: backward differences of the positions (zero at the first step).
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from aero.mesh import wing_mesh
from aero.uvlm import UVLM, FreeStream, UVLMConfig

RESULTS = Path(__file__).resolve().parents[2] / "results" / "pterasoftware_cases.json"
RHO, NU, CHORD, SPAN, SPEED, NC, NS = 1.225, 1.5e-5, 1.0, 8.0, 1.0, 4, 16

STEADY_CL_RTOL = 0.01
"""CL at alpha = 5 deg after 120 steps: measured +0.51 % against PteraSoftware. The remainder is PteraSoftware's
core growth, which grows each wake ring's four legs with that ring's |Gamma| and age (c + 1) dt where hawksim grows
each edge's net |Gamma| from age 0: with fixed cores, the normal velocity PteraSoftware's wake induces at the
trailing-edge collocation points changes by 0.25 %, the order of the circulation difference there (0.16-0.55 %,
the most at the trailing edge); hawksim's options cannot reproduce a per-ring growth. Twice the measured
difference."""

STEADY_CDI_RTOL = 0.02
"""CDi: measured +0.90 % (about twice CL's, CDi ~ CL^2). Twice the measured difference."""

AMPLITUDE_RTOL = 0.01
"""Pitch-heave, k = 0.25: CL's first-harmonic amplitude with PteraSoftware's extra trailing-edge force added (the
Kutta-Joukowski force on the trailing-edge ring's rear leg, net circulation Gamma - Gamma_previous, which
PteraSoftware counts and hawksim does not; estimated here with the air's minus the wing's velocity, without the
induced velocity). Measured +0.2 % (without that force: +6.1 %, and the phase 8.1 deg late)."""

PHASE_ATOL_DEG = 0.5
"""The same harmonic's phase [deg]: measured -0.07 deg."""


def _stored(key: str) -> dict:
    if not RESULTS.exists():
        pytest.skip(f"{RESULTS} missing (the PteraSoftware study writes it: docs/validation.md, section 6)")
    return json.loads(RESULTS.read_text())["runs"][key]["ptera"]


def _mesh():
    y = np.linspace(-SPAN / 2, SPAN / 2, NS + 1)
    return wing_mesh(y, np.full_like(y, 0.25 * CHORD), np.full_like(y, -0.75 * CHORD), NC)


def _matched(mesh) -> UVLMConfig:
    return UVLMConfig(rho=RHO, nu=NU, le_suction=False, free_wake=False, shed_rule="travel", shed_fraction=0.25,
                      potential_jump="ring", time_derivative="euler",
                      core_fraction=0.03 * CHORD / mesh.mean_chordwise_length, wake_core_chords=0.03,
                      convection_core_chords=0.03, a_prime=1e-4)


def _lift_drag(force, v_air):
    d = v_air / np.linalg.norm(v_air)
    up = np.array([0.0, 0.0, 1.0]) - d[2] * d
    return force @ (up / np.linalg.norm(up)), force @ d


def test_steady_wing_matches_pterasoftware():
    ref = _stored("steady_alpha5")
    mesh = _mesh()
    solver = UVLM([mesh], _matched(mesh))
    a = math.radians(5.0)
    fs = FreeStream(v0=SPEED * np.array([-math.cos(a), 0.0, math.sin(a)]))
    pose = (np.eye(3)[None], np.array([[-0.25 * CHORD, 0.0, 0.0]]), np.zeros((1, 3)), np.zeros((1, 3)))
    for _ in range(120):
        r = solver.step(0.25 * CHORD / SPEED, *pose, fs)
    lift, drag = _lift_drag(r.force[0], fs.v0)
    qs = 0.5 * RHO * SPEED**2 * CHORD * SPAN
    assert lift / qs == pytest.approx(ref["CL"], rel=STEADY_CL_RTOL)
    assert drag / qs == pytest.approx(ref["CDi"], rel=STEADY_CDI_RTOL)
    assert lift / qs != pytest.approx(ref["CL"], rel=1e-3)  # the known remainder is there (else: update the note)


def _ry(t):
    return np.array([[math.cos(t), 0.0, math.sin(t)], [0.0, 1.0, 0.0], [-math.sin(t), 0.0, math.cos(t)]])


def test_pitch_heave_matches_pterasoftware_with_its_trailing_edge_force():
    ref = _stored("pitch_heave")
    mesh = _mesh()
    solver = UVLM([mesh], _matched(mesh))
    omega, n, cycles = 2 * 0.25 * SPEED / CHORD, 40, 3
    dt = 2 * math.pi / omega / n
    fs = FreeStream(v0=np.array([-SPEED, 0.0, 0.0]))
    lift, prev, g_prev = [], None, None
    for k in range(n * cycles):
        t = k * dt
        R = _ry(-math.radians(5.0) * math.sin(omega * t + math.pi / 2))  # nose up about -y
        o = np.array([-0.25 * CHORD, 0.0, 0.25 * CHORD * math.sin(omega * t)])
        if prev is None:
            v, w = np.zeros(3), np.zeros(3)
        else:  # the rigid part of the backward-difference velocity field
            M = (np.eye(3) - prev[0] @ R.T) / dt
            v, w = (o - prev[1]) / dt, 0.5 * np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]])
        prev = (R, o)
        r = solver.step(dt, R[None], o[None], v[None], w[None], fs)
        f = r.force[0].copy()
        if g_prev is not None:  # PteraSoftware's rear-leg force on the trailing-edge rings
            te = o + mesh.vertices[-1] @ R.T
            g = te + 0.25 * dt * (fs.v0 - (v + np.cross(w, te - o)))
            mid = 0.5 * (g[1:] + g[:-1])
            f += RHO * ((r.gamma[0, -1] - g_prev)[:, None]
                        * np.cross(fs.v0 - (v + np.cross(w, mid - o)), g[:-1] - g[1:])).sum(0)
        g_prev = r.gamma[0, -1].copy()
        lift.append(f[2])
    t = np.arange(n * cycles)[-n:] * dt
    cl = np.array(lift[-n:]) / (0.5 * RHO * SPEED**2 * CHORD * SPAN)
    _, ac, as_ = np.linalg.lstsq(np.column_stack([np.ones_like(t), np.cos(omega * t), np.sin(omega * t)]), cl,
                                 rcond=None)[0]
    assert np.hypot(ac, as_) == pytest.approx(ref["CL_amplitude"], rel=AMPLITUDE_RTOL)
    assert abs(np.degrees(np.arctan2(-as_, ac)) - ref["CL_phase_deg"]) < PHASE_ATOL_DEG
