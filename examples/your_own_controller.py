"""Your own controller: a proportional-derivative pitch controller on the mean sweep angle phi0, a plain class that
implements ``hawksim.Controller``, flown 10 wingbeats from the quasi-steady orbit at 1 m/s after a 3 deg nose-up
disturbance, beside the same flight open loop.

Shows: the protocol (``rate``, ``reset(point)``, ``update(obs)`` returning each wing's seven Eq. 1 parameters, SI,
radians), the sensed state (``obs.state``, hawksim.flight.STATE_NAMES order: theta at 7, q at 4) and ``hawksim.fly``
with ``controller=``. Open loop the unstable orbit pitches up by more than 25 deg in 10 beats; the controller holds the
beat-mean pitch within a degree of the orbit's 57.3 deg by moving phi0 (the stroke's mean position) against it.
"""

import hawksim
from hawksim.insect.kinematics import PARAM_NAMES


class PitchByPhi0:
    """phi0 = phi0_orbit - kp (theta - theta_orbit) - kq T (q - q_orbit), once per wingbeat (T = 0.04 s)."""

    rate = "beat"

    def __init__(self, kp=0.5, kq=1.0):
        self.kp, self.kq = kp, kq

    def reset(self, point):
        self.wing, self.x0 = point.kinematics.as_array(), point.initial_state.as_array()

    def update(self, obs):
        dx = obs.state - self.x0
        wing = self.wing.copy()
        wing[PARAM_NAMES.index("phi0")] -= self.kp * dx[7] + self.kq * 0.04 * dx[4]
        return wing, wing  # (left, right): both wings alike


orbit = hawksim.shipped_orbit(1.0, "quasi-steady")
for name, controller in (("open loop", None), ("PD on phi0", PitchByPhi0())):
    result = hawksim.fly(orbit, cycles=10, controller=controller, perturb={"theta": 3.0})
    pitch = [b["pitch_deg"] for b in result.beats()]
    print(f"{name}: beat-mean pitch {pitch[0]:.2f} -> {pitch[-1]:.2f} deg, departed at beat "
          f"{result.departed_at_beat()}")
