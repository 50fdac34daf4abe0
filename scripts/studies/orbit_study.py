"""Orbit + Floquet study (quasi-steady): residuals, iterations, f/phi0 vs the held trim, P+, multipliers vs A-matrix
eigenvalues at the Table 3 speeds. Usage: python scripts/orbit_study.py (about 10 s)."""
import time
import numpy as np
from hawksim.flight.orbit import periodic_orbit
from hawksim.stability.floquet import monodromy, quasi_steady_system
from hawksim.trim.tables import trim_kinematics
from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
np.set_printoptions(precision=4, suppress=False, linewidth=150)
for V in (0.0, 0.5, 1.0, 1.5, 2.0):
    t = time.perf_counter()
    o = periodic_orbit(V)
    k = trim_kinematics(V, "quasi-steady")
    h = held_flight(k, V, QuasiSteadyBackend(), cycles=2, steps_per_cycle=200).averages
    ho = held_flight(o.kinematics, V, QuasiSteadyBackend(), cycles=2, steps_per_cycle=200).averages
    print(f"V={V} res={o.residual:.2e} it={o.iterations} wall={o.wall_time_s:.1f}s f {k.f:.4f}->{o.kinematics.f:.4f} phi0 {np.degrees(k.phi0):.4f}->{np.degrees(o.kinematics.phi0):.4f} deg; P+ held {h.P_plus:.4f} orbit {o.P_plus:.4f}; held L+ at orbit kin {ho.L_plus:.4f} M+ {ho.M_plus:.4f}; mean pitch {np.degrees(o.mean_pitch):.3f} chi {np.degrees(k.chi):.3f}; x0 {o.initial_state}")  # noqa: E501
    fq = monodromy(o)
    av = quasi_steady_system(o.kinematics, V)
    print("  coupling", f"{fq.coupling:.2e}", "max|mu|", f"{fq.max_multiplier:.4f}", "wall", f"{fq.wall_time_s:.1f}")
    print("  mu_long", fq.multipliers_long, "\n  ln mu_long", fq.exponents_long, "\n  eig A_long", av.eig_long)
    print("  mu_lat", fq.multipliers_lat, "\n  ln mu_lat", fq.exponents_lat, "\n  eig A_lat", av.eig_lat)
