"""The Floquet multipliers of your own kinematics: the free body's periodic orbit at a 1 m/s ascent from seven
wing-motion parameters of your choice (quasi-steady aerodynamics), and its stability per wingbeat.

Shows the python-control shape of the API: ``hawksim.Kinematics.from_edge`` (the one place degrees and Hz go in:
Table 2's bounds are checked) -> ``hawksim.find_operating_point(..., kinematics=...)`` (the free body's periodic
orbit: five of the parameters kept, f and phi0 solved with the body's start state) -> ``hawksim.linearize(point,
map="monodromy")`` (a :class:`hawksim.LinearModel` of the one-wingbeat map) -> its eigenvalues mu, the Floquet
multipliers. |mu| > 1 grows by that factor every beat (unstable), |mu| < 1 decays; a complex pair oscillates.
docs/guide/floquet.md explains more.
"""

import numpy as np

import hawksim
from hawksim.stability.floquet import floquet_analysis

kin = hawksim.Kinematics.from_edge({"f": 28.5, "beta": 10, "phi0": -4.5, "theta0": 15, "alpha0": 2,
                                    "phi_a": 55, "alpha_a": 65})  # Hz and degrees in, SI inside
point = hawksim.find_operating_point(1.0, aero="quasi-steady", kinematics=kin)
print(f"{point.body}-body operating point, converged: {point.converged} (residual {point.residual:.1e})")
print(f"f {kin.f:.2f} -> {point.kinematics.f:.2f} Hz, "
      f"phi0 {np.rad2deg(kin.phi0):.2f} -> {np.rad2deg(point.kinematics.phi0):.2f} deg (solved)")

lin = hawksim.linearize(point, map="monodromy")  # the one-beat map's (8, 8) Jacobian, nondimensional states
print(f"linear model: {lin.A.shape} per {'continuous time' if lin.continuous else 'wingbeat'}, "
      f"states {', '.join(lin.states)}")
floquet = floquet_analysis(lin)  # the same eigenvalues, split into the longitudinal and lateral blocks
for name, mus in (("longitudinal (u, w, q, theta)", floquet.multipliers_long),
                  ("lateral (v, p, r, phi)", floquet.multipliers_lat)):
    print(f"{name}: |mu| = " + ", ".join(f"{abs(m):.3f}" for m in sorted(mus, key=abs, reverse=True)))
print(f"largest multiplier {floquet.max_multiplier:.3f} per beat: "
      f"{'unstable' if floquet.max_multiplier > 1 else 'stable'}")
