"""A new insect from a file: a TOML spec of a hawkmoth with 10 % longer wings, loaded with ``hawksim.load_insect``.

Shows the spec format of docs/insects.md (each number with its unit, source class and citation; ``base`` names the
shipped insect whose values the fields left out keep), the cycle-averaged L+ and P+ of both insects at Table 3's
kinematics (the spec's reference kinematics) on the held body with the quasi-steady model, and why none of the
hawkmoth's shipped tables is the new insect's (they are keyed by the digest of the MJCF they were computed on)."""

from pathlib import Path

import hawksim
from hawksim.backends.held import run
from hawksim.backends.resolution import Resolution
from hawksim.insect.tables import mjcf_digest, table_status

Path("longwing.toml").write_text('''name = "longwing"
base = "hawkmoth"          # every field not given here is the hawkmoth's

[morphology.R]
value = 0.05335            # 1.1 x 48.50 mm
unit = "m"
source = "model choice"
citation = "the hawkmoth's wing length (Nguyen et al. 2020, Table 1) x 1.1"
''')
moth, longwing = hawksim.load_insect("hawkmoth"), hawksim.load_insect("longwing.toml")
print(f"{longwing.name}: R {longwing.morphology.R * 1e3:.2f} mm ({longwing.sources['morphology.R'][0]}), "
      f"mass {longwing.morphology.total_mass * 1e6:.2f} mg, P0 {longwing.P0 * 1e3:.1f} mW")
res = Resolution(aero="quasi-steady", cycles=2, average_cycles=1)
ref = moth.reference_deg  # Table 3: speeds [m/s] and each parameter (Hz, deg)
for i, speed in enumerate(ref["speed"][::2]):
    kin = hawksim.Kinematics.from_edge({k: ref[k][2 * i] for k in ref if k != "speed"})
    a, b = (run(kin, speed, res, insect=insect).averages for insect in (moth, longwing))
    print(f"V {speed:.1f} m/s: L+ {a.L_plus:.4f} -> {b.L_plus:.4f}, P+ {a.P_plus:.4f} -> {b.P_plus:.4f}")
print(f"model digest {mjcf_digest(moth)[:12]} -> {mjcf_digest(longwing)[:12]}; hawkmoth's quasi-steady orbits: "
      f"{table_status(moth, 'orbit', 'quasi-steady')[0].name}; {table_status(longwing, 'orbit', 'quasi-steady')[1]}")
