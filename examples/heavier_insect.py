"""A heavier insect: the hawkmoth with 1.2x its total mass (wings unchanged) at a 1 m/s ascent, quasi-steady.

Shows: ``dataclasses.replace`` of the frozen ``Morphology`` in a ``hawksim.Insect`` (morphology, reference power P0,
kinematic bounds) that ``periodic_orbit``, ``fly`` and ``flight_backend`` take (its MJCF from it: heavier.xml).
From the default orbit the heavier body sinks; its own orbit beats faster, and ``FlightResult.summary()`` reports
L+ in units of its own weight (L+ = 1) and P+ in units of its own P0."""

from dataclasses import replace
from pathlib import Path

import hawksim
from hawksim.insect import mjcf

SPEED = 1.0  # ascent speed [m/s]
moth = hawksim.load_insect("hawkmoth")  # from its folder; its P0 (84.2 mW) and bounds are carried over
heavy = moth.with_morphology(replace(moth.morphology, total_mass=1.2 * moth.morphology.total_mass, name="heavier"))
Path("heavier.xml").write_text(mjcf(heavy.morphology))  # what fly and periodic_orbit generate from the insect
print(f"total mass {moth.morphology.total_mass * 1e3:.4f} -> {heavy.morphology.total_mass * 1e3:.4f} g; "
      f"weight {heavy.weight * 1e3:.2f} mN")


def fly(orbit, beats):  # open loop, the heavier insect, from the orbit's start state and kinematics
    trim = hawksim.Trim(SPEED, orbit.kinematics, model="quasi-steady", source="periodic orbit")
    backend = hawksim.flight_backend("quasi-steady", kinematics=orbit.kinematics, morphology=heavy.morphology)
    return hawksim.fly(trim, backend, beats, insect=heavy, start_state=(orbit.launch_state.as_array(), orbit.chi_ref))


default = hawksim.shipped_orbit(SPEED, "quasi-steady")  # the default insect's orbit
sink = fly(default, 2).beats()[-1]["mean_vertical_speed"]
print(f"default orbit (f {default.kinematics.f:.2f} Hz): beat 2 mean vertical speed {sink:.3f} m/s")

own = hawksim.periodic_orbit(SPEED, "quasi-steady", kinematics=default.kinematics, insect=heavy)
res = fly(own, 3)
lift = res.lift_drag()[0][-res.steps_per_cycle:].mean()  # last beat's mean lift [N]
print(f"own orbit (converged {own.converged}): f {own.kinematics.f:.2f} Hz, "
      f"mean vertical speed {res.beats()[-1]['mean_vertical_speed']:.4f} m/s, "
      f"L+ {res.summary()['last_cycle']['L_plus']:.4f} of its weight "
      f"(against the default hawkmoth's weight: {lift / moth.weight:.4f})")
print(f"largest Floquet multiplier {hawksim.monodromy(own).max_multiplier:.3f} per beat "  # flies own.insect
      f"(default insect: {hawksim.monodromy(default).max_multiplier:.3f})")
