"""The UVLM at the quasi-steady forward trims, and the UVLM balance from them (issue 51, item 3, UVLM half): as the
paper's trims are a minimum-power search then a UVLM balance (f, beta, phi0, alpha0 adjusted until |L+ - 1|, |D+|,
|M+| <= 0.01: :func:`hawksim.trim.balance.balance_on_uvlm` at :data:`hawksim.trim.balance.TRIM_RESOLUTION`), here the
search is the quasi-steady one (results/forward_flight/qs_trims.json) and the balance the UVLM's, in forward flight
(the body's own loads counted). Prints one JSON object; writes it with --out after each speed.

    python -m scripts.studies.forward_uvlm_balance --out results/forward_flight/uvlm_balance.json
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

from hawksim import __version__
from hawksim.backends.held import run
from hawksim.insect.kinematics import Kinematics
from hawksim.trim.balance import TRIM_RESOLUTION, balance_on_uvlm

QS_TRIMS = Path("results/forward_flight/qs_trims.json")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=float, nargs="+", default=[1.0, 2.0, 3.0, 4.0], help="forward speeds U [m/s]")
    ap.add_argument("--trims", type=Path, default=QS_TRIMS, help="the quasi-steady trims to start from")
    ap.add_argument("--out", type=Path)
    a = ap.parse_args()
    qs = {r["forward_speed"]: r for r in json.loads(a.trims.read_text())["rows"]}
    data = {"command": " ".join(["python -m scripts.studies.forward_uvlm_balance", *sys.argv[1:]]),
            "hawksim_version": __version__, "created": time.strftime("%Y-%m-%d"),
            "resolution": TRIM_RESOLUTION.to_dict(), "start": str(a.trims), "rows": []}
    for U in a.speeds:
        q = qs[U]
        kin = Kinematics.from_edge(q["kinematics"])
        at_qs = run(kin, q["speed"], TRIM_RESOLUTION, forward_speed=U).averages
        b = balance_on_uvlm(kin, q["speed"], forward_speed=U)
        av = b.averages
        data["rows"].append({
            "forward_speed": U, "speed": q["speed"],
            "uvlm_at_qs_trim": {k: getattr(at_qs, k) for k in ("L_plus", "D_plus", "M_plus", "P_plus")},
            "qs_P_plus": q["P_plus"], "kinematics": b.kinematics.to_edge(), "chi_deg": math.degrees(b.kinematics.chi),
            "L_plus": av.L_plus, "D_plus": av.D_plus, "M_plus": av.M_plus, "P_plus": av.P_plus,
            "converged": b.converged, "tolerance": b.tolerance, "evaluations": b.evaluations,
            "wall_time_s": b.wall_time_s})
        print(json.dumps(data["rows"][-1]), file=sys.stderr, flush=True)
        if a.out is not None:
            a.out.write_text(json.dumps(data, indent=1))
    print(json.dumps(data))


if __name__ == "__main__":
    main()
