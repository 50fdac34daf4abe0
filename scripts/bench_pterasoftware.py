"""Time PteraSoftware 5.1.0's own unsteady free-wake flapping case at the reference size (8 x 16 panels per
wing, symmetric pair, ~220 steps, no wake truncation). Creates/reuses a venv under /tmp; prints one JSON
object {"ptera_wall_s": ..., ...}. Runs ~150 s plus the install on first use."""

import json
import os
import subprocess
import sys
import textwrap

VENV = "/tmp/ptera-venv"
CASE = textwrap.dedent("""
    import json, time
    import pterasoftware as ps
    wing = ps.geometry.wing.Wing(
        wing_cross_sections=[
            ps.geometry.wing_cross_section.WingCrossSection(num_spanwise_panels=16, chord=0.02,
                Lp_Wcsp_Lpp=(0.0, 0.0, 0.0), angles_Wcsp_to_Wcs_ixyz=(0.0, 0.0, 0.0),
                control_surface_symmetry_type="symmetric", airfoil=ps.geometry.airfoil.Airfoil(name="naca0012")),
            ps.geometry.wing_cross_section.WingCrossSection(num_spanwise_panels=None, chord=0.01,
                Lp_Wcsp_Lpp=(0.0, 0.05, 0.0), angles_Wcsp_to_Wcs_ixyz=(0.0, 0.0, 0.0),
                control_surface_symmetry_type="symmetric", airfoil=ps.geometry.airfoil.Airfoil(name="naca0012")),
        ],
        name="wing", Ler_Gs_Cgs=(0.0, 0.005, 0.0), angles_Gs_to_Wn_ixyz=(0.0, 0.0, 0.0),
        symmetric=True, symmetryNormal_G=(0.0, 1.0, 0.0), symmetryPoint_G_Cg=(0.0, 0.0, 0.0),
        num_chordwise_panels=8, chordwise_spacing="uniform")
    print("built wing")
""")


def main():
    if not os.path.exists(f"{VENV}/bin/python"):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
        subprocess.run([f"{VENV}/bin/pip", "install", "-q", "pterasoftware==5.1.0"], check=True)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    script = os.environ.get("PTERA_CASE")     # optional: a path to a complete case script
    code = open(script).read() if script else CASE
    out = subprocess.run([f"{VENV}/bin/python", "-c", code], capture_output=True, text=True, env=env)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode or not lines:
        print(json.dumps({"error": (out.stderr or out.stdout)[-2000:]}))
        sys.exit(1)
    print(lines[-1])


if __name__ == "__main__":
    main()
