"""The per-step surrogate's size against the flight loop's speed (issue 21, item 5): a 20-beat flight from the
shipped 1 m/s orbit with the shipped network and with other networks, best of 3 loops each, one sitting (the orbit
is the shipped network's, so only the timing compares), with each network's held-out scores from its metadata.

    python scripts/studies/step_surrogate_size.py NET.safetensors [...] [--out results/surrogate/step_size.json]

A network to compare is made with `hawksim train --kind step` (e.g. ``--layers 128,128,128 --ensemble 1``).
"""

import argparse
import json
import sys

from hawksim.backends.step_network import load, shipped_path
from hawksim.backends.step_surrogate import StepSurrogateBackend
from hawksim.flight.fly import fly
from hawksim.flight.orbit import shipped_orbit
from hawksim.jsonout import host_info
from hawksim.trim.point import Trim


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("networks", nargs="*")
    ap.add_argument("--out", default="results/surrogate/step_size.json")
    a = ap.parse_args(argv)
    o = shipped_orbit(1.0, "surrogate")
    trim = Trim(1.0, o.kinematics, model="surrogate", source="orbit")
    start = (o.launch_state.as_array(), o.chi_ref)
    res = {"host": host_info(), "flight": "20 beats from the shipped surrogate orbit at 1 m/s", "networks": {}}
    for path in [str(shipped_path()), *a.networks]:
        net = load(path)
        backend = StepSurrogateBackend(o.kinematics, network=net)
        fly(trim, backend, 1, start_state=start)  # warm-up
        wall = min(fly(trim, backend, 20, start_state=start).wall_time_s for _ in range(3))
        test = net.meta.get("test", {})
        n_weights = int(sum(W.size for W, _ in net.weights))
        res["networks"][path] = {"command": net.meta.get("command"), "weights": n_weights,
                                 "loop_wall_s": wall, "realtime_factor": 20 * o.kinematics.period / wall,
                                 "r2_body_min": test.get("r2_body_min"),
                                 "cycle_mean_abs_error": test.get("cycle_mean_abs_error")}
    text = json.dumps(res, indent=1)
    with open(a.out, "w") as fh:
        fh.write(text + "\n")
    print(text)


if __name__ == "__main__":
    sys.exit(main())
