"""A heavier insect: the hawkmoth with 1.2x its total mass (wings unchanged) at a 1 m/s ascent, quasi-steady.

Shows: ``dataclasses.replace`` of the frozen ``Morphology``, its MuJoCo model written by ``hawksim.insect.mjcf``
(heavier.xml) and loaded by ``hawksim.load_model``; ``hawksim.fly`` and ``hawksim.periodic_orbit`` take that model.
With the default insect's orbit the heavier body sinks; its own orbit beats faster and its mean lift is its weight
(L+ computed here: ``FlightResult.summary()`` divides by the default hawkmoth's weight until issue 50, item 1).
"""

import dataclasses
from pathlib import Path

import hawksim
from hawksim.insect import mjcf

SPEED = 1.0  # ascent speed [m/s]
heavy = dataclasses.replace(hawksim.HAWKMOTH, total_mass=1.2 * hawksim.HAWKMOTH.total_mass, name="heavier")
Path("heavier.xml").write_text(mjcf(heavy))
model = hawksim.load_model("heavier.xml")
print(f"total mass {hawksim.HAWKMOTH.total_mass * 1e3:.4f} -> {heavy.total_mass * 1e3:.4f} g; "
      f"weight {heavy.weight * 1e3:.2f} mN")


def fly(orbit, beats):  # open loop, the heavier insect, from the orbit's start state and kinematics
    trim = hawksim.Trim(SPEED, orbit.kinematics, model="quasi-steady", source="periodic orbit")
    backend = hawksim.flight_backend("quasi-steady", kinematics=orbit.kinematics)
    return hawksim.fly(trim, backend, beats, model=model, start_state=(orbit.launch_state.as_array(), orbit.chi_ref))


default = hawksim.shipped_orbit(SPEED, "quasi-steady")  # the default insect's orbit
sink = fly(default, 2).beats()[-1]["mean_vertical_speed"]
print(f"default orbit (f {default.kinematics.f:.2f} Hz): beat 2 mean vertical speed {sink:.3f} m/s")

own = hawksim.periodic_orbit(SPEED, "quasi-steady", kinematics=default.kinematics, model=model)
res = fly(own, 3)
print(f"own orbit (converged {own.converged}): f {own.kinematics.f:.2f} Hz, "
      f"mean vertical speed {res.beats()[-1]['mean_vertical_speed']:.4f} m/s, "
      f"L+ {res.lift_drag()[0].mean() / heavy.weight:.4f} of its weight "
      f"(summary()'s L_plus: {res.summary()['last_cycle']['L_plus']:.4f}, against the default weight)")
print(f"largest Floquet multiplier {hawksim.monodromy(own, model=model).max_multiplier:.3f} per beat "
      f"(default insect: {hawksim.monodromy(default).max_multiplier:.3f})")
