"""Export a flight and read it back: a 5-wingbeat quasi-steady flight saved with ``FlightResult.save`` to
flight.npz (the file of ``hawksim fly --out``), read with numpy alone, and loaded back into a ``FlightResult``.

Shows: the file's arrays and their units (in its JSON metadata; docs/output.md lists them), the per-beat table
written to beats.csv, and ``FlightResult.load``, which gives the saved arrays bit for bit. pandas is not a hawksim
dependency, so this reads with numpy; with pandas, ``pandas.DataFrame(table)`` of the ``table`` below is the same
per-beat table.
"""

import json

import numpy as np

import hawksim

orbit = hawksim.find_operating_point(1.0, aero="quasi-steady")  # the shipped free-body orbit
result = hawksim.fly(orbit, cycles=5)  # open loop from its launch state (the one flight loop)
result.save("flight.npz")

with np.load("flight.npz", allow_pickle=False) as z:  # numpy alone: no hawksim, no pickle
    data = {k: z[k] for k in z.files}
meta = json.loads(str(data.pop("metadata")))
print(f"{meta['format']}: {len(data)} arrays, {meta['steps']} steps of {meta['aero']} at "
      f"{meta['speed_target_m_s']:g} m/s")
for name in ("t", "body_pos", "force", "attitude"):
    print(f"  {name} {data[name].shape} [{meta['units'][name]}]")
lift = data["force"][..., 2].sum(1)  # both wings, world z [N]
print(f"mean lift {lift.mean() * 1e3:.2f} mN against a weight of {hawksim.default_insect().weight * 1e3:.2f} mN")

table = {k.removeprefix("beat_"): v for k, v in data.items() if k.startswith("beat_") and v.ndim == 1}
np.savetxt("beats.csv", np.column_stack(list(table.values())), delimiter=",", header=",".join(table), comments="")
print(f"beats.csv: {len(table['mean_vertical_speed'])} beats x {len(table)} columns ({', '.join(table)})")

back = hawksim.FlightResult.load("flight.npz")
same = all(np.array_equal(getattr(back, k), getattr(result, k)) for k in ("t", "body_pos", "force", "power_joint"))
print(f"FlightResult.load: arrays equal bit for bit: {same}; kinematics equal: {back.kinematics == result.kinematics}")
