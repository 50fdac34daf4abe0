"""Forward flight with the quasi-steady model: the hover trim's wing motion flown forward, then re-balanced.

Shows: ``forward_speed`` U [m/s] beside the ascent speed V (``hawksim.condition``: the air at (-U, 0, -V)) in a
held-body run (``hawksim.backends.held.run``); the body's own drag counted where U > 0 (``body_averages``); the
balance (f, beta, phi0, alpha0) at 1 m/s and the mean lift coefficient as Willmott & Ellington (1997) compute it.
The minimum-power trims from hover to 5 m/s are docs/forward_flight.md's (`hawksim trim --aero quasi-steady`)."""

import math

import hawksim
from hawksim.backends.held import body_averages, run
from hawksim.backends.resolution import Resolution
from hawksim.flight.lift_coefficient import mean_lift_coefficient
from hawksim.trim.balance import balance_on_uvlm

QS = Resolution(aero="quasi-steady", steps_per_cycle=100, cycles=2)
hover = hawksim.trim_kinematics(0.0, "quasi-steady")  # the shipped quasi-steady hover trim (SI)
for U in (0.0, 1.0, 2.0, 3.0):
    a = run(hover, 0.0, QS, forward_speed=U).averages
    body = body_averages(hover, 0.0, U).D_plus if U else 0.0
    print(f"U {U:.1f} m/s, hover kinematics: L+ {a.L_plus:.3f} D+ {a.D_plus:.3f} M+ {a.M_plus:.3f} "
          f"(body D+ {body:.4f})")

trim = balance_on_uvlm(hover, 0.0, QS, forward_speed=1.0)  # the body's loads count (U > 0)
k, av = trim.kinematics, trim.averages
print(f"balanced at 1 m/s (converged {trim.converged}, {trim.evaluations} runs): f {k.f:.2f} Hz, "
      f"stroke plane {math.degrees(k.beta):.2f} deg, body angle {math.degrees(k.chi):.2f} deg, "
      f"P+ {av.P_plus:.3f}, C_L {mean_lift_coefficient(k, 0.0, 1.0):.2f}")
