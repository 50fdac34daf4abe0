"""Time PteraSoftware 5.1.0's unsteady free-wake solver on the reference flapping case of
scripts/benchmarks/bench_uvlm.py:
one wing and its mirror image (8 x 16 panels each, the same planform), 3 wingbeats at 25 Hz in 220 steps, free
wake, no wake truncation. Creates/reuses a venv under /tmp; prints ONE JSON object {"ptera_wall_s": ..., ...}.

Set-up, through PteraSoftware's public API only (Airplane / Wing / WingCrossSection, WingMovement, Movement,
UnsteadyProblem, UnsteadyRingVortexLatticeMethodSolver):

* geometry: bench_uvlm's reference wing: span 0.05 m from a hinge 0.005 m off the symmetry plane, chord
  c(y) = 0.02 sqrt(1 - (y/0.05)^2) + 0.004 m with the quarter-chord line straight (17 cross sections,
  1 uniform spanwise panel between each, 8 uniform chordwise panels, flat NACA 0012 camber line);
  symmetric=True about the plane y = 0 with the root off it (PteraSoftware's "type 5" symmetry), which
  PteraSoftware meshes as two separate Wings, each with its own WingMovement.
* motion (the rigid-wing rotation PteraSoftware allows, angles_Gs_to_Wn_ixyz, intrinsic x-y'-z''): flap
  phi = 60 cos(2 pi f t) deg about the x axis through the root quarter-chord point (stroke amplitude of
  bench_uvlm), then pitch beta = -50 sin(2 pi f t) deg about the flapped span axis through the same point, so
  the leading edge leads on both half-strokes at 40 deg geometric incidence to the stroke at mid-stroke, as
  in bench_uvlm's kinematics; f = 25 Hz. This is bench_uvlm's motion rotated (stroke axis along x instead
  of z): PteraSoftware limits each angle to [-90, 90] deg, which rules out bench_uvlm's -90 +- 50 deg pitch
  about a vertical stroke axis, and the rotation does not change the cost.
* free stream: PteraSoftware rejects a zero speed, so 1 m/s along x (alpha = beta = 0), i.e. along the
  stroke axis (bench_uvlm runs in still air).
* time: 220 steps, delta_time = 3 / 25 / 219 s, so the 220 time levels are t = 0 ... 0.12 s, the same
  linspace(0, 3 / f, 220) that bench_uvlm uses.
* wake: run(prescribed_wake=False) (free wake), Movement(max_wake_rows=None) (no truncation).
* loads every step (UnsteadyProblem(only_final_results=False), the default); no streamlines, no progress
  bar, logging left at PteraSoftware's default (discarded).
* timing: ptera_wall_s is the wall time of solver.run() only; a 4-step run of the same problem first loads
  or compiles PteraSoftware's numba kernels (warmup_s), as bench_uvlm excludes its compilation. Numba's
  threading is left at its defaults (NUMBA_NUM_THREADS is removed from the environment).

Usage: python scripts/benchmarks/bench_pterasoftware.py [--steps N] > ptera.json   (takes a few minutes at 220 steps)
"""

import argparse
import json
import os
import subprocess
import sys
import textwrap

from hawksim.jsonout import host_info

VENV = "/tmp/ptera-venv"
VERSION = "5.1.0"
CASE = textwrap.dedent("""
    import json, math, os, sys, time
    from importlib.metadata import version
    import numpy as np
    import numba
    import pterasoftware as ps

    STEPS = int(sys.argv[1])
    FREQ, CYCLES, STEPS_REF = 25.0, 3, 220
    DT = CYCLES / FREQ / (STEPS_REF - 1)      # 220 time levels t = 0 ... 3 / FREQ
    PHI_A, THETA_A, U = 60.0, 50.0, 1.0       # flap and pitch amplitudes [deg], free stream [m/s]
    NC, NS, SPAN, HINGE_Y = 8, 16, 0.05, 0.005


    def chord(y):
        return 0.02 * math.sqrt(max(1.0 - (y / SPAN) ** 2, 0.0)) + 0.004


    def make_wing():
        ys = np.linspace(0.0, SPAN, NS + 1)
        sections = []
        for i, y in enumerate(ys):
            # leading edge at -c/4 (x aft), so that the quarter-chord line is straight along y
            dx = 0.0 if i == 0 else -0.25 * (chord(y) - chord(ys[i - 1]))
            dy = 0.0 if i == 0 else y - ys[i - 1]
            tip = i == NS
            sections.append(ps.geometry.wing_cross_section.WingCrossSection(
                airfoil=ps.geometry.airfoil.Airfoil(name="naca0012"),
                num_spanwise_panels=None if tip else 1, chord=chord(y),
                Lp_Wcsp_Lpp=(dx, dy, 0.0), angles_Wcsp_to_Wcs_ixyz=(0.0, 0.0, 0.0),
                control_surface_symmetry_type="symmetric",
                spanwise_spacing=None if tip else "uniform"))
        return ps.geometry.wing.Wing(
            wing_cross_sections=sections, name="wing",
            Ler_Gs_Cgs=(-0.25 * chord(0.0), HINGE_Y, 0.0), angles_Gs_to_Wn_ixyz=(0.0, 0.0, 0.0),
            symmetric=True, mirror_only=False, symmetryNormal_G=(0.0, 1.0, 0.0),
            symmetryPoint_G_Cg=(0.0, 0.0, 0.0), num_chordwise_panels=NC, chordwise_spacing="uniform")


    def make_solver(num_steps):
        airplane = ps.geometry.airplane.Airplane(wings=[make_wing()], name="flapper")
        period = 1.0 / FREQ
        wing_movements = [
            ps.movements.wing_movement.WingMovement(
                base_wing=wing,
                wing_cross_section_movements=[
                    ps.movements.wing_cross_section_movement.WingCrossSectionMovement(base_wing_cross_section=wcs)
                    for wcs in wing.wing_cross_sections],
                ampAngles_Gs_to_Wn_ixyz=(PHI_A, THETA_A, 0.0),
                periodAngles_Gs_to_Wn_ixyz=(period, period, 0.0),
                spacingAngles_Gs_to_Wn_ixyz=("sine", "sine", "sine"),
                phaseAngles_Gs_to_Wn_ixyz=(90.0, 180.0, 0.0),   # 60 cos(wt), -50 sin(wt)
                rotationPointOffset_Gs_Ler=(0.25 * chord(0.0), 0.0, 0.0))
            for wing in airplane.wings]                          # the wing and its reflection
        airplane_movement = ps.movements.airplane_movement.AirplaneMovement(
            base_airplane=airplane, wing_movements=wing_movements)
        operating_point = ps.operating_point.OperatingPoint(rho=1.225, vCg__E=U, alpha=0.0, beta=0.0,
                                                            nu=15.06e-6)
        movement = ps.movements.movement.Movement(
            airplane_movements=[airplane_movement],
            operating_point_movement=ps.movements.operating_point_movement.OperatingPointMovement(
                base_operating_point=operating_point),
            delta_time=DT, num_steps=num_steps, max_wake_rows=None)
        problem = ps.problems.UnsteadyProblem(movement=movement, only_final_results=False)
        return ps.unsteady_ring_vortex_lattice_method.UnsteadyRingVortexLatticeMethodSolver(
            unsteady_problem=problem), airplane


    def run(solver):
        t0 = time.perf_counter()
        solver.run(prescribed_wake=False, calculate_streamlines=False, show_progress=False)
        return time.perf_counter() - t0


    t0 = time.perf_counter()
    warm, _ = make_solver(4)
    run(warm)
    warmup_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    solver, airplane = make_solver(STEPS)
    setup_s = time.perf_counter() - t0
    wall = run(solver)
    wings = airplane.wings
    print(json.dumps({
        "ptera_wall_s": round(wall, 2), "steps": STEPS, "panels_per_wing": f"{NC}x{NS}", "cycles": CYCLES,
        "version": version("pterasoftware"), "free_wake": True, "wake_truncation": None,
        "num_wings": len(wings), "panels_total": int(sum(w.num_panels for w in wings)),
        "final_wake_vortices": int(solver.list_num_wake_vortices[-1]),
        "delta_time_s": DT, "sim_time_s": round((STEPS - 1) * DT, 6), "freq_hz": FREQ,
        "motion": f"flap {PHI_A:g}cos(wt) deg about x + pitch -{THETA_A:g}sin(wt) deg about span axis, "
                  "both through the root quarter chord; wing + mirror image (type 5 symmetry)",
        "freestream_m_s": U,
        "freestream_note": "PteraSoftware rejects a zero free stream; bench_uvlm runs in still air",
        "loads_every_step": True, "setup_s": round(setup_s, 2), "warmup_s": round(warmup_s, 2),
        "numba_threading_layer": numba.threading_layer(), "numba_num_threads": numba.get_num_threads(),
        "cpus": os.cpu_count()}))
""")


def ensure_venv() -> str:
    """The python of a venv under /tmp with PteraSoftware :data:`VERSION` (created and installed on first use)."""
    if not os.path.exists(f"{VENV}/bin/python"):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
    chk = subprocess.run([f"{VENV}/bin/python", "-c", "from importlib.metadata import version as v;"
                          "print(v('pterasoftware'))"], capture_output=True, text=True)
    if chk.stdout.strip() != VERSION:
        subprocess.run([f"{VENV}/bin/python", "-m", "pip", "install", "-q", f"pterasoftware=={VERSION}"],
                       check=True)
    return f"{VENV}/bin/python"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=220, help="time steps (220: the reference case)")
    args = ap.parse_args()
    ensure_venv()
    env = dict(os.environ)
    env.pop("NUMBA_NUM_THREADS", None)        # numba's default thread pool
    out = subprocess.run([f"{VENV}/bin/python", "-c", CASE, str(args.steps)], capture_output=True, text=True,
                         env=env)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode or not lines:
        print(json.dumps({"error": (out.stderr or out.stdout)[-2000:]}))
        sys.exit(1)
    print(json.dumps({**json.loads(lines[-1]), "host": host_info()}))


if __name__ == "__main__":
    main()
