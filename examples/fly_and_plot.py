"""Fly and plot: 12 wingbeats of open-loop free flight at a 1 m/s ascent, started on the free body's periodic
orbit (quasi-steady aerodynamics), its vertical speed and body pitch against time in fly_and_plot.png.

Shows: the shipped orbit (``hawksim.shipped_orbit``), a flight from it (``hawksim.fly`` with its start state) and
the per-step arrays of the ``FlightResult`` (SI, world frame, z up). The orbit is unstable (largest Floquet
multiplier about 1.5 per beat) but started exactly on it the flight holds for these 12 beats, its beat-mean pitch
just beginning to drift; within every beat the body oscillates at the wingbeat frequency about its 1 m/s mean.
"""

import matplotlib.pyplot as plt
import numpy as np

import hawksim

SPEED = 1.0  # ascent speed [m/s]
orbit = hawksim.shipped_orbit(SPEED, "quasi-steady")
trim = hawksim.Trim(SPEED, orbit.kinematics, model="quasi-steady", source="shipped periodic orbit")
backend = hawksim.flight_backend("quasi-steady", kinematics=orbit.kinematics)
result = hawksim.fly(trim, backend, 12, start_state=(orbit.launch_state.as_array(), orbit.chi_ref))

for b in result.beats()[::3]:
    print(f"beat mean: vertical speed {b['mean_vertical_speed']:.4f} m/s, pitch {b['pitch_deg']:.2f} deg")

fig, (ax_v, ax_p) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
ax_v.plot(result.t, result.body_v[:, 2])
ax_v.set_ylabel("vertical speed [m/s]")
ax_p.plot(result.t, np.rad2deg(result.pitch()))
ax_p.set_ylabel("body pitch [deg]")
ax_p.set_xlabel("time [s]")
fig.suptitle(f"hawkmoth, quasi-steady, {SPEED:g} m/s ascent, open loop from the periodic orbit")
fig.savefig("fly_and_plot.png", dpi=100)
print("wrote fly_and_plot.png")
