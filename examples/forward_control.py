"""Control in forward flight: the LQR on the forward-flight schedule holds 3 m/s through a side gust, then speeds up.

Shows: ``Schedule(u_lo, u_hi, axis="forward")`` (periodic orbits of the free body every 0.5 m/s from the shipped
quasi-steady forward trims, linearized, LQR gains interpolated in the forward speed U); ``LQR(schedule, U,
profile=...)`` whose hold point moves forward at its speed reference; a ``Gust`` of 0.5 m/s from the side for one
wingbeat; ``FlightResult.beat_log`` per beat (forward speed, pitch error against the reference, roll). The hover ->
4 m/s -> hover profile and its figure are docs/forward_flight.md's (`hawksim fly --forward-profile 4:100,0:120`)."""

import numpy as np

import hawksim
from hawksim.control import LQR, Schedule

schedule = Schedule(3.0, 3.5, axis="forward")  # the orbits at 3 and 3.5 m/s (seconds)
ctl = LQR(schedule, 3.0, profile=[(3.0, 20), (3.5, 20)])  # hold 3 m/s, then 3.5 (0.05 m/s per beat)
gust = hawksim.Gust(np.array([0.0, 0.5, 0.0]), 5, 1)  # from the side (world y), beat 5 only
r = hawksim.fly(ctl.point, cycles=40, controller=ctl, gusts=[gust])
for b in r.beat_log[3:9] + r.beat_log[-1:]:
    print(f"beat {b['beat']:2d}: forward speed {b['mean_forward_speed']:.4f} m/s (reference {b['speed_reference']:.2f})"
          f", pitch error {b['pitch_error_deg']:+.3f} deg, roll {b['roll_deg']:+.3f} deg")
print(f"departed at beat {r.departed_at_beat()}")
