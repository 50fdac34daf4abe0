"""PteraSoftware's three cases: hawksim's UVLM (aero.uvlm) against PteraSoftware 5.1.0's unsteady ring VLM, the same
geometry, motion, panels and steps on both sides (issue 48, item 6).

Cases (SI; "c" the chord, q S the free-stream dynamic pressure times the planform area):

1. ``steady``: a flat rectangular wing, c = 1 m, span 8 m (AR 8), 4 x 16 uniform rings, U = 1 m/s at
   alpha = 2, 5 and 10 deg, impulsively started and run 120 steps of U dt = c / 4 (a 30-chord wake, prescribed):
   CL and CDi of the last step, against each other and against Prandtl's lifting line (Glauert's series, 2D slope
   2 pi) for context.
2. ``pitch_heave``: the AR-8 wing of tests/aero/test_uvlm_shedding.py (c = 1 m, span 8 m, 4 x 16 rings, U = 1 m/s)
   heaving h = 0.25 c sin(w t) and pitching 5 deg sin(w t + 90 deg) nose up about its quarter chord, k = w c / (2 U)
   = 0.25, 40 steps per cycle, 3 cycles, prescribed wake: CL's first harmonic over the third cycle (amplitude; phase
   of cos(w t + phase), deg) and the mean thrust coefficient CT of that cycle.
3. ``flapping``: the reference case of scripts/benchmarks/bench_pterasoftware.py (its planform, 8 x 16 rings per
   wing and its mirror image, flap 60 cos(w t) deg about the stroke axis and pitch -50 sin(w t) deg about the
   flapped span axis through the root quarter chord, 25 Hz, 1 m/s along the stroke axis, 220 steps over 3 beats,
   free wake, no truncation): cycle-mean and peak lift (both wings) of the third beat. The stroke axis is
   PteraSoftware's x (bench_uvlm's vertical z turned, as bench_pterasoftware.py explains), so the lift is the force
   along it, -x in PteraSoftware's axes (+x in hawksim's world here): the free stream, along +x in PteraSoftware's
   axes, is an axial climb at 1 m/s.

PteraSoftware runs in its own venv (created under /tmp as bench_pterasoftware.py does: PteraSoftware 5.1.0 from
PyPI), through its public API (Airplane / Wing / WingCrossSection, WingMovement, Movement, UnsteadyProblem,
UnsteadyRingVortexLatticeMethodSolver.run); this file is its driver too (``--ptera-side``, importing nothing of
hawksim). hawksim runs through aero's public API only (aero.mesh.wing_mesh, aero.uvlm.UVLM / UVLMConfig /
FreeStream), in "world" axes that are PteraSoftware's geometry axes turned 180 deg about z (x forward, z up), and
each case's panel corners are checked against PteraSoftware's at three steps (``geometry_max_diff_m``).

hawksim variants per case:

* ``default``: ``UVLMConfig()`` (rho and nu PteraSoftware's): free wake, Polhamus leading-edge suction, its cores,
  "travel" shedding, the panel's potential jump, BDF2;
* ``matched``: PteraSoftware's choices as far as the public options allow: "travel" at 0.25 of the step's travel,
  ring circulation and first-order dGamma/dt in the unsteady term (``potential_jump="ring"``,
  ``time_derivative="euler"``), no suction turned normal (``le_suction=False``), PteraSoftware's wake model
  (prescribed or free as the case), its initial cores 0.03 of the standard mean chord for the bound, wake and
  convecting vortices (``core_fraction``, ``wake_core_chords``, ``convection_core_chords``), its growth law
  (Squire's 1e-4 = ``a_prime``), and its kinematics: the velocities of the wing points are backward differences of
  their positions over the step (zero at the first step), given to hawksim as the rigid motion nearest to them;
* ``matched_issue48``: ``matched`` with issue 48's unsteady term (the panel's potential jump, BDF2): what the
  corrected term alone changes against PteraSoftware;
* ``matched_analytic``: ``matched`` with the exact (analytic) wing velocities: what PteraSoftware's finite-difference
  kinematics alone change.

What cannot be matched: PteraSoftware adds the Kutta-Joukowski force of the trailing-edge ring's rear leg (net
circulation Gamma - Gamma_previous) and hawksim does not; PteraSoftware's cores grow with each ring's own |Gamma|
per ring leg, hawksim's with each edge's net |Gamma| (and the newest wake row's age is dt in PteraSoftware, 0 at the
trailing edge in hawksim); PteraSoftware's backward-difference velocity field is affine, not rigid (hawksim takes
the rigid part); PteraSoftware's first step has the unsteady term (Gamma - 0) / dt, hawksim's zero (only step 0).

Usage: python scripts/studies/pterasoftware_cases.py [--cases steady,pitch_heave,flapping] [--force]
           [--out results/pterasoftware_cases.json]
Resumable: each (case, side) already in --out is kept unless --force.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

RHO, NU = 1.225, 1.5e-5
CORE_CHORDS = 0.03
"""PteraSoftware's initial core radius of every vortex (bound and wake), in standard mean chords."""
SQUIRE = 1.0e-4
"""PteraSoftware's Squire parameter: its core growth r_c^2 = r0^2 + 4 a_L (nu + 1e-4 |Gamma|) t, hawksim's a_prime."""

RECT = dict(chord=1.0, span=8.0, nc=4, ns=16, speed=1.0)
CASES = {
    "steady": dict(RECT, alphas_deg=[2.0, 5.0, 10.0], dt=0.25, steps=120, free_wake=False),
    "pitch_heave": dict(RECT, k=0.25, heave_chords=0.25, pitch_deg=5.0, pitch_phase_deg=90.0, steps_per_cycle=40,
                        cycles=3, free_wake=False),
    "flapping": dict(nc=8, ns=16, span=0.05, hinge_y=0.005, freq=25.0, cycles=3, steps=220, flap_deg=60.0,
                     pitch_deg=50.0, speed=1.0, free_wake=True),
}
CHECK_STEPS = (0, 7, 41)
"""Steps whose panel corners are compared between the two sides."""


def flapping_chord(y, span=0.05):
    """bench_uvlm's planform: c(y) = 0.02 sqrt(1 - (y / span)^2) + 0.004 m."""
    return 0.02 * np.sqrt(np.clip(1.0 - (np.asarray(y) / span) ** 2, 0.0, 1.0)) + 0.004


def case_runs(name: str) -> list[tuple[str, dict]]:
    """(run key, parameters) of a case: the steady case has one run per angle of attack."""
    p = CASES[name]
    if name == "steady":
        return [(f"steady_alpha{a:g}", dict(p, alpha_deg=a)) for a in p["alphas_deg"]]
    return [(name, p)]


def time_grid(name: str, p: dict) -> tuple[float, int]:
    """(dt [s], steps) of a run; step k is at t = k dt."""
    if name == "steady":
        return p["dt"], p["steps"]
    if name == "pitch_heave":
        omega = 2 * p["k"] * p["speed"] / p["chord"]
        return 2 * math.pi / omega / p["steps_per_cycle"], p["steps_per_cycle"] * p["cycles"]
    return p["cycles"] / p["freq"] / (p["steps"] - 1), p["steps"]   # bench's linspace(0, 3 / f, 220)


# ---------------------------------------------------------------------------------------------------------------
# PteraSoftware's side (run by the PteraSoftware venv's python: no hawksim imports)
# ---------------------------------------------------------------------------------------------------------------
def ptera_side(name: str, p: dict) -> dict:
    import logging
    from importlib.metadata import version

    import pterasoftware as ps

    logging.disable(logging.CRITICAL)
    dt, steps = time_grid(name, p)
    airfoil = ps.geometry.airfoil.Airfoil(name="naca0012")        # flat camber line
    cs_mod, wing_mod = ps.geometry.wing_cross_section, ps.geometry.wing

    if name == "flapping":
        ys = np.linspace(0.0, p["span"], p["ns"] + 1)
        secs = []
        for i, y in enumerate(ys):                             # quarter-chord line straight along y (x aft)
            dx = 0.0 if i == 0 else -0.25 * (flapping_chord(y) - flapping_chord(ys[i - 1]))
            dy = 0.0 if i == 0 else y - ys[i - 1]
            tip = i == p["ns"]
            secs.append(cs_mod.WingCrossSection(
                airfoil=airfoil, num_spanwise_panels=None if tip else 1, chord=float(flapping_chord(y)),
                Lp_Wcsp_Lpp=(float(dx), float(dy), 0.0), angles_Wcsp_to_Wcs_ixyz=(0.0, 0.0, 0.0),
                control_surface_symmetry_type="symmetric", spanwise_spacing=None if tip else "uniform"))
        c0 = float(flapping_chord(0.0))
        wing = wing_mod.Wing(
            wing_cross_sections=secs, name="wing", Ler_Gs_Cgs=(-0.25 * c0, p["hinge_y"], 0.0),
            angles_Gs_to_Wn_ixyz=(0.0, 0.0, 0.0), symmetric=True, mirror_only=False,
            symmetryNormal_G=(0.0, 1.0, 0.0), symmetryPoint_G_Cg=(0.0, 0.0, 0.0), num_chordwise_panels=p["nc"],
            chordwise_spacing="uniform")
        period = 1.0 / p["freq"]
        motion = dict(ampAngles_Gs_to_Wn_ixyz=(p["flap_deg"], p["pitch_deg"], 0.0),
                      periodAngles_Gs_to_Wn_ixyz=(period, period, 0.0),
                      spacingAngles_Gs_to_Wn_ixyz=("sine", "sine", "sine"),
                      phaseAngles_Gs_to_Wn_ixyz=(90.0, 180.0, 0.0),    # flap cos(w t), pitch -sin(w t)
                      rotationPointOffset_Gs_Ler=(0.25 * c0, 0.0, 0.0))
        alpha = 0.0
    else:
        c, b = p["chord"], p["span"]
        secs = [cs_mod.WingCrossSection(airfoil=airfoil, num_spanwise_panels=p["ns"], chord=c,
                                        Lp_Wcsp_Lpp=(0.0, 0.0, 0.0), angles_Wcsp_to_Wcs_ixyz=(0.0, 0.0, 0.0),
                                        spanwise_spacing="uniform"),
                cs_mod.WingCrossSection(airfoil=airfoil, num_spanwise_panels=None, chord=c,
                                        Lp_Wcsp_Lpp=(0.0, b, 0.0), angles_Wcsp_to_Wcs_ixyz=(0.0, 0.0, 0.0))]
        wing = wing_mod.Wing(wing_cross_sections=secs, name="wing", Ler_Gs_Cgs=(0.0, -b / 2, 0.0),
                             angles_Gs_to_Wn_ixyz=(0.0, 0.0, 0.0), symmetric=False,
                             num_chordwise_panels=p["nc"], chordwise_spacing="uniform")
        motion = {}
        alpha = p.get("alpha_deg", 0.0)
        if name == "pitch_heave":
            period = 2 * math.pi / (2 * p["k"] * p["speed"] / c)
            motion = dict(ampLer_Gs_Cgs=(0.0, 0.0, p["heave_chords"] * c), periodLer_Gs_Cgs=(0.0, 0.0, period),
                          spacingLer_Gs_Cgs=("sine", "sine", "sine"), phaseLer_Gs_Cgs=(0.0, 0.0, 0.0),
                          ampAngles_Gs_to_Wn_ixyz=(0.0, p["pitch_deg"], 0.0),
                          periodAngles_Gs_to_Wn_ixyz=(0.0, period, 0.0),
                          spacingAngles_Gs_to_Wn_ixyz=("sine", "sine", "sine"),
                          phaseAngles_Gs_to_Wn_ixyz=(0.0, p["pitch_phase_deg"], 0.0),
                          rotationPointOffset_Gs_Ler=(0.25 * c, 0.0, 0.0))
    airplane = ps.geometry.airplane.Airplane(wings=[wing], name="case")
    mv = ps.movements
    wing_movements = [
        mv.wing_movement.WingMovement(
            base_wing=w, wing_cross_section_movements=[
                mv.wing_cross_section_movement.WingCrossSectionMovement(base_wing_cross_section=wcs)
                for wcs in w.wing_cross_sections], **motion)
        for w in airplane.wings]
    op = ps.operating_point.OperatingPoint(rho=RHO, vCg__E=p["speed"], alpha=alpha, beta=0.0, nu=NU)
    movement = mv.movement.Movement(
        airplane_movements=[mv.airplane_movement.AirplaneMovement(base_airplane=airplane,
                                                                  wing_movements=wing_movements)],
        operating_point_movement=mv.operating_point_movement.OperatingPointMovement(base_operating_point=op),
        delta_time=dt, num_steps=steps, max_wake_rows=None)
    problem = ps.problems.UnsteadyProblem(movement=movement, only_final_results=False)
    solver = ps.unsteady_ring_vortex_lattice_method.UnsteadyRingVortexLatticeMethodSolver(unsteady_problem=problem)
    t0 = time.perf_counter()
    solver.run(prescribed_wake=not p["free_wake"], calculate_streamlines=False, show_progress=False)
    wall = time.perf_counter() - t0
    forces, corners = [], {}
    for k, sp in enumerate(problem.steady_problems):
        ap = sp.airplanes[0]
        forces.append(np.sum([pan.forces_GP1 for w in ap.wings for pan in np.ravel(w.panels)], axis=0).tolist())
        if k in CHECK_STEPS:
            corners[str(k)] = [getattr(pan, a).tolist() for w in ap.wings for pan in np.ravel(w.panels)
                               for a in ("Flpp_GP1_CgP1", "Frpp_GP1_CgP1", "Blpp_GP1_CgP1", "Brpp_GP1_CgP1")]
    return {"force_G_N": forces, "corners_G_m": corners,
            "v_inf_G_m_s": np.asarray(problem.steady_problems[0].operating_point.vInf_GP1__E).tolist(),
            "wall_s": round(wall, 2), "version": version("pterasoftware"), "num_wings": len(airplane.wings),
            "panels": int(sum(w.num_panels for w in airplane.wings)), "dt_s": dt, "steps": steps,
            "prescribed_wake": not p["free_wake"]}


def run_ptera(name: str, p: dict) -> dict:
    """PteraSoftware's side in its venv (created / installed on first use)."""
    from scripts.benchmarks.bench_pterasoftware import ensure_venv  # here: the PteraSoftware side runs this file alone

    python = ensure_venv()
    env = dict(os.environ)
    env.pop("NUMBA_NUM_THREADS", None)
    out = subprocess.run([python, os.path.abspath(__file__), "--ptera-side", name, json.dumps(p)],
                         capture_output=True, text=True, env=env)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode or not lines:
        raise RuntimeError(f"PteraSoftware run {name} failed:\n{(out.stderr or out.stdout)[-3000:]}")
    return json.loads(lines[-1])


# ---------------------------------------------------------------------------------------------------------------
# hawksim's side: world = PteraSoftware's geometry axes turned 180 deg about z (x forward, y left, z up)
# ---------------------------------------------------------------------------------------------------------------
G_TO_WORLD = np.diag([-1.0, -1.0, 1.0])


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _drx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[0.0, 0.0, 0.0], [0.0, -s, -c], [0.0, c, -s]])


def _dry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[-s, 0.0, c], [0.0, 0.0, 0.0], [-c, 0.0, -s]])


def hawksim_case(name: str, p: dict):
    """(mesh, air velocity v0 (3,) [m/s], pose(t) -> (R (3, 3), Rdot, origin (3,), origin velocity (3,)), mirror
    plane or None), world axes. The flapping case solves PteraSoftware's mirrored wing (y_G < 0, world y > 0) with
    the other as its image."""
    from aero.mesh import wing_mesh

    if name == "flapping":
        y = np.linspace(0.0, p["span"], p["ns"] + 1)
        c = flapping_chord(y, p["span"])
        mesh = wing_mesh(y, 0.25 * c, -0.75 * c, p["nc"])
        w = 2 * math.pi * p["freq"]
        P = np.diag([-1.0, 1.0, 1.0])          # world = PteraSoftware's axes mirrored, then turned: R_w = P R_G P
        origin = np.array([0.0, p["hinge_y"], 0.0])
        fa, pa = math.radians(p["flap_deg"]), math.radians(p["pitch_deg"])

        def pose(t):
            phi, dphi = fa * math.cos(w * t), -fa * w * math.sin(w * t)
            th, dth = -pa * math.sin(w * t), -pa * w * math.cos(w * t)
            R = _rx(phi) @ _ry(th)
            Rd = dphi * _drx(phi) @ _ry(th) + dth * _rx(phi) @ _dry(th)
            return P @ R @ P, P @ Rd @ P, origin, np.zeros(3)

        v0 = G_TO_WORLD @ np.array([p["speed"], 0.0, 0.0])
        return mesh, v0, pose, (np.zeros(3), np.array([0.0, 1.0, 0.0]))
    c, b = p["chord"], p["span"]
    y = np.linspace(-b / 2, b / 2, p["ns"] + 1)
    mesh = wing_mesh(y, np.full_like(y, 0.25 * c), np.full_like(y, -0.75 * c), p["nc"])  # origin: quarter chord
    qc = np.array([-0.25 * c, 0.0, 0.0])                      # leading edge at world x = 0
    a = math.radians(p.get("alpha_deg", 0.0))
    v0 = p["speed"] * np.array([-math.cos(a), 0.0, math.sin(a)])
    if name == "steady":
        def pose(t):
            return np.eye(3), np.zeros((3, 3)), qc, np.zeros(3)
        return mesh, v0, pose, None
    w = 2 * p["k"] * p["speed"] / c
    h0, pa, ph = p["heave_chords"] * c, math.radians(p["pitch_deg"]), math.radians(p["pitch_phase_deg"])

    def pose(t):                              # nose up = about -y (world)
        th, dth = pa * math.sin(w * t + ph), pa * w * math.cos(w * t + ph)
        o = qc + np.array([0.0, 0.0, h0 * math.sin(w * t)])
        return _ry(-th), -dth * _dry(-th), o, np.array([0.0, 0.0, h0 * w * math.cos(w * t)])
    return mesh, v0, pose, None


def _vee(M):
    return np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]) / 2.0


def variant_config(variant: str, mesh, free_wake: bool):
    from aero.uvlm import UVLMConfig

    if variant == "default":
        return UVLMConfig(rho=RHO, nu=NU)
    P = mesh.vertices
    span = float(np.ptp(P[..., 1]))
    c_std = float(mesh.panel_areas.sum()) / span               # PteraSoftware's standard mean chord: S / b
    term = dict(potential_jump="panel", time_derivative="bdf2") if variant == "matched_issue48" else dict(
        potential_jump="ring", time_derivative="euler")
    return UVLMConfig(rho=RHO, nu=NU, le_suction=False, free_wake=free_wake, shed_rule="travel", shed_fraction=0.25,
                      core_fraction=CORE_CHORDS * c_std / mesh.mean_chordwise_length, wake_core_chords=CORE_CHORDS,
                      convection_core_chords=CORE_CHORDS, a_prime=SQUIRE, core_growth=True, **term)


VARIANTS = ("default", "matched", "matched_issue48", "matched_analytic", "matched_te_leg")


def te_leg_force(mesh, rho, dt, R, o, vo, omega, v0, dgamma) -> np.ndarray:
    """PteraSoftware's extra load, estimated: the Kutta-Joukowski force [N] (world) on the trailing-edge rings' rear
    legs, whose net circulation is this step's minus the last step's (dgamma (ns,) [m^2/s]); the rear leg at 0.25 of
    the step's travel behind the trailing edge ("travel" rule), the velocity there the air's minus the wing's
    (without the induced velocity, which hawksim's public API does not give at these points)."""
    te = o + mesh.vertices[-1] @ R.T
    v_rel = v0 - (vo + np.cross(omega, te - o))
    g = te + 0.25 * dt * v_rel
    mid = 0.5 * (g[1:] + g[:-1])
    v = v0 - (vo + np.cross(omega, mid - o))
    leg = g[:-1] - g[1:]                     # ring corners (i, j), (i, j+1), (i+1, j+1), (i+1, j): rear leg j+1 -> j
    return rho * (dgamma[:, None] * np.cross(v, leg)).sum(0)


def run_hawksim(name: str, p: dict, variant: str) -> dict:
    """hawksim's side of one run: world-axes force (steps, 3) of the wing and its image [N], panel corners at
    CHECK_STEPS (wing and image) [m], the air velocity and the wall time."""
    from aero.uvlm import UVLM, FreeStream

    mesh, v0, pose, mirror = hawksim_case(name, p)
    dt, steps = time_grid(name, p)
    cfg = variant_config(variant, mesh, p["free_wake"])
    solver = UVLM([mesh], cfg)
    fs = FreeStream(v0=v0)
    backward = variant in ("matched", "matched_issue48", "matched_te_leg")
    forces, corners = [], {}
    prev, gamma_te = None, None
    t0 = time.perf_counter()
    for k in range(steps):
        R, Rd, o, od = pose(k * dt)
        if not backward:
            omega, vo = _vee(Rd @ R.T), od
        elif prev is None:                     # PteraSoftware: no motion velocity at the first step
            omega, vo = np.zeros(3), np.zeros(3)
        else:                                  # v(x) = (x_k - x_{k-1}) / dt, its rigid part about o_k
            omega, vo = _vee((np.eye(3) - prev[0] @ R.T) / dt), (o - prev[1]) / dt
        prev = (R, o)
        r = solver.step(dt, R[None], o[None], vo[None], omega[None], fs, mirror)
        f = r.force[0]
        if variant == "matched_te_leg" and gamma_te is not None:
            f = f + te_leg_force(mesh, cfg.rho, dt, R, o, vo, omega, v0, r.gamma[0, -1] - gamma_te)
        gamma_te = r.gamma[0, -1].copy()
        if mirror is not None:                 # the image's force: reflected across y = 0
            f = f + f * np.array([1.0, -1.0, 1.0])
        forces.append(f.tolist())
        if k in CHECK_STEPS:
            x = o + mesh.vertices.reshape(-1, 3) @ R.T
            if mirror is not None:
                x = np.concatenate([x, x * np.array([1.0, -1.0, 1.0])])
            corners[str(k)] = x
    return {"force_N": forces, "corners_m": corners, "v0_m_s": v0, "wall_s": round(time.perf_counter() - t0, 2)}


# ---------------------------------------------------------------------------------------------------------------
# the measures
# ---------------------------------------------------------------------------------------------------------------
def lift_drag(force: np.ndarray, v_air: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lift (perpendicular to the air's velocity, upward) and drag (along it) [N] of forces (n, 3), z up."""
    d = v_air / np.linalg.norm(v_air)
    up = np.array([0.0, 0.0, 1.0]) - d[2] * d
    up /= np.linalg.norm(up)
    return force @ up, force @ d


def measures(name: str, p: dict, force: np.ndarray, v_air: np.ndarray) -> dict:
    """The case's measures from world-axes forces (steps, 3) [N] and the air velocity (3,) [m/s]."""
    dt, steps = time_grid(name, p)
    lift, drag = lift_drag(force, v_air)
    if name == "steady":
        qs = 0.5 * RHO * p["speed"] ** 2 * p["chord"] * p["span"]
        return {"CL": float(lift[-1] / qs), "CDi": float(drag[-1] / qs)}
    if name == "pitch_heave":
        qs = 0.5 * RHO * p["speed"] ** 2 * p["chord"] * p["span"]
        n = p["steps_per_cycle"]
        w = 2 * p["k"] * p["speed"] / p["chord"]
        t = np.arange(steps)[-n:] * dt
        cl = lift[-n:] / qs
        a0, ac, as_ = np.linalg.lstsq(np.column_stack([np.ones_like(t), np.cos(w * t), np.sin(w * t)]), cl,
                                      rcond=None)[0]
        return {"CL_amplitude": float(np.hypot(ac, as_)), "CL_phase_deg": float(np.degrees(np.arctan2(-as_, ac))),
                "CL_mean": float(a0), "CT_mean": float(np.mean(-drag[-n:]) / qs)}
    per = (steps - 1) // p["cycles"]                          # third beat: t in [2 T, 3 T)
    fl = force[-per - 1:-1, 0]                                # along the stroke axis (bench_uvlm's lift)
    return {"lift_mean_N": float(fl.mean()), "lift_peak_N": float(fl.max())}


def lifting_line(aspect: float, alphas_deg, terms: int = 40) -> list[dict]:
    """Prandtl's lifting line for a rectangular wing (2D slope 2 pi), Glauert's odd sine series collocated at
    ``terms`` stations: CL = pi AR A1, CDi = pi AR sum n A_n^2 (Anderson, Fundamentals of Aerodynamics, Sec. 5.3)."""
    th = (np.arange(terms) + 0.5) * np.pi / (2 * terms)        # 0 < theta < pi/2 (symmetric wing)
    n = 2 * np.arange(terms) + 1
    mu = 2 * np.pi / (4 * aspect)                            # a0 c / (4 b) for a rectangular wing, c / b = 1 / AR
    M = np.sin(np.outer(th, n)) * (mu * n[None, :] + np.sin(th)[:, None])
    out = []
    for a in alphas_deg:
        A = np.linalg.solve(M, mu * math.radians(a) * np.sin(th))
        out.append({"alpha_deg": a, "CL": float(np.pi * aspect * A[0]),
                    "CDi": float(np.pi * aspect * np.sum(n * A**2))})
    return out


def compare(name: str, p: dict, ptera: dict, hawk: dict) -> dict:
    """Measures of both sides, geometry and air-velocity agreement."""
    fg = np.asarray(ptera["force_G_N"])
    vg = np.asarray(ptera["v_inf_G_m_s"])
    mp = measures(name, p, fg @ G_TO_WORLD.T, G_TO_WORLD @ vg)
    geo = 0.0
    for k, pts in ptera["corners_G_m"].items():
        xp = np.asarray(pts) @ G_TO_WORLD.T
        xh = hawk["corners_m"][k]
        geo = max(geo, float(np.sqrt(((xp[:, None, :] - xh[None, :, :]) ** 2).sum(-1)).min(1).max()))
    return {"ptera": mp, "geometry_max_diff_m": geo,
            "air_velocity_diff_m_s": float(np.abs(G_TO_WORLD @ vg - hawk["v0_m_s"]).max())}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated: " + ", ".join(CASES))
    ap.add_argument("--out", default="results/pterasoftware_cases.json")
    ap.add_argument("--force", action="store_true", help="rerun runs already in --out")
    args = ap.parse_args()
    names = [s.strip() for s in args.cases.split(",") if s.strip()]
    bad = [s for s in names if s not in CASES]
    if bad:
        print(f"pterasoftware_cases: unknown case {bad[0]!r} (known: {', '.join(CASES)})", file=sys.stderr)
        sys.exit(2)
    from hawksim.jsonout import host_info

    doc = {}
    if os.path.exists(args.out):
        with open(args.out) as f:
            doc = json.load(f)
    doc.setdefault("runs", {})
    doc["cases"] = CASES
    from scripts.benchmarks.bench_pterasoftware import VERSION

    doc["ptera_version"] = VERSION
    doc.pop("command", None)
    doc.setdefault("commands", []).append("python " + " ".join(sys.argv))   # every invocation that wrote the file

    def save():
        os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
        tmp = args.out + ".tmp"
        with open(tmp, "w") as f:
            json.dump(doc, f, indent=1)
        os.replace(tmp, args.out)

    for name in names:
        for key, p in case_runs(name):
            run = doc["runs"].get(key, {})
            if "ptera_raw" not in run or args.force:
                print(f"{key}: PteraSoftware ...", file=sys.stderr, flush=True)
                pr = run_ptera(name, p)
                run = {"ptera_version": pr["version"], "ptera_wall_s": pr["wall_s"], "ptera_panels": pr["panels"],
                       "ptera_wings": pr["num_wings"], "dt_s": pr["dt_s"], "steps": pr["steps"],
                       "prescribed_wake": pr["prescribed_wake"], "host": host_info(),
                       "ptera_raw": {k: pr[k] for k in ("force_G_N", "corners_G_m", "v_inf_G_m_s")}}
                doc["runs"][key] = run
                save()
            hs = run.setdefault("hawksim", {})
            for variant in VARIANTS:
                if variant in hs and not args.force:
                    continue
                print(f"{key}: hawksim {variant} ...", file=sys.stderr, flush=True)
                h = run_hawksim(name, p, variant)
                cmp_ = compare(name, p, run["ptera_raw"], h)
                run.update(ptera=cmp_["ptera"], geometry_max_diff_m=cmp_["geometry_max_diff_m"],
                           air_velocity_diff_m_s=cmp_["air_velocity_diff_m_s"])
                mh = measures(name, p, np.asarray(h["force_N"]), h["v0_m_s"])
                hs[variant] = dict(mh, wall_s=h["wall_s"], diff_vs_ptera={
                    m: (v - run["ptera"][m] if m.endswith("_deg") else v / run["ptera"][m] - 1.0)
                    for m, v in mh.items() if m.endswith("_deg") or abs(run["ptera"][m]) > 1e-4})
                save()
    if "steady" in names:
        doc["lifting_line"] = lifting_line(RECT["span"] / RECT["chord"], CASES["steady"]["alphas_deg"])
    doc["host"] = host_info()
    save()
    summary = {k: {"ptera": r["ptera"], **{v: {m: round(x, 5) for m, x in r["hawksim"][v].items()
                                               if m not in ("diff_vs_ptera", "wall_s")} for v in r["hawksim"]}}
               for k, r in doc["runs"].items()}
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--ptera-side":
        print(json.dumps(ptera_side(sys.argv[2], json.loads(sys.argv[3]))))
    else:
        main()
