"""The Floquet multipliers of your own kinematics: the free body's periodic orbit at a 1 m/s ascent from seven
wing-motion parameters of your choice (quasi-steady aerodynamics), and its stability per wingbeat.

Shows: ``hawksim.Kinematics.from_edge`` (the one place degrees and Hz go in: Table 2's bounds are checked),
``hawksim.periodic_orbit(..., kinematics=...)``, which keeps five of the parameters and solves f and phi0 with the
body's start state, and ``hawksim.monodromy``: the eigenvalues mu of the one-wingbeat map. |mu| > 1 grows by that
factor every beat (unstable), |mu| < 1 decays; a complex pair oscillates. docs/guide/floquet.md explains more.
"""

import numpy as np

import hawksim

kin = hawksim.Kinematics.from_edge({"f": 28.5, "beta": 10, "phi0": -4.5, "theta0": 15, "alpha0": 2,
                                    "phi_a": 55, "alpha_a": 65})  # Hz and degrees in, SI inside
orbit = hawksim.periodic_orbit(1.0, "quasi-steady", kinematics=kin)
print(f"orbit converged: {orbit.converged} (residual {orbit.residual:.1e})")
print(f"f {kin.f:.2f} -> {orbit.kinematics.f:.2f} Hz, "
      f"phi0 {np.rad2deg(kin.phi0):.2f} -> {np.rad2deg(orbit.kinematics.phi0):.2f} deg (solved)")

floquet = hawksim.monodromy(orbit)
for name, mus in (("longitudinal (u, w, q, theta)", floquet.multipliers_long),
                  ("lateral (v, p, r, phi)", floquet.multipliers_lat)):
    print(f"{name}: |mu| = " + ", ".join(f"{abs(m):.3f}" for m in sorted(mus, key=abs, reverse=True)))
print(f"largest multiplier {floquet.max_multiplier:.3f} per beat: "
      f"{'unstable' if floquet.max_multiplier > 1 else 'stable'}")
