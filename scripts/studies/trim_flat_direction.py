"""How flat is the minimum-power trim along one kinematic parameter? (issue 49, Table 3 target "off its bound, or
the reason measured").

The GA + Nelder-Mead minimum of Eq. 3 (:func:`hawksim.trim.search.trim_on_surrogate`, the trim stage of
`hawksim reproduce`) is searched again with one parameter's upper bound lowered to each of ``--caps`` (degrees; the
other bounds Table 2's), on the network ``--network`` (a safetensors file; default the shipped network of the speed).
Where P+ of the capped trims differs by less than the network's own error (docs/surrogate.md), the minimum does not
determine that parameter: it lands on whichever bound the network's error tilts it to. Prints ONE JSON object: per
cap, the trim's kinematics [deg, Hz], body angle chi = 60 deg - beta [deg], L+, D+, M+, P+ and Eq. 3's fitness.

    python -m scripts.studies.trim_flat_direction --speed 0 --param beta --caps 5 15 30 50 \\
        --out results/trim/flat_beta_v0.json
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import os
import shlex
import sys

from hawksim.backends.network import load, shipped_path
from hawksim.insect.kinematics import PARAM_NAMES
from hawksim.jsonout import emit
from hawksim.trim.search import GAConfig, surrogate_insect, trim_on_surrogate


def capped_trim(net, speed: float, param: str, cap_deg: float, *, seed: int, population: int) -> dict:
    """The minimum-power trim with ``param``'s upper bound at ``cap_deg`` (its unit: Hz for f, else deg)."""
    ins = surrogate_insect(None)
    lo, hi = ins.bounds_deg[param]
    if not lo < cap_deg <= hi:
        raise ValueError(f"cap {cap_deg:g} for {param!r} must lie in ({lo:g}, {hi:g}]")
    ins = dataclasses.replace(ins, bounds_deg={**ins.bounds_deg, param: (lo, float(cap_deg))})
    t = trim_on_surrogate(net, speed, seed=seed, cfg=dataclasses.replace(GAConfig(), population=population),
                          insect=ins)
    kin = t.kinematics.to_edge()
    return {"cap": float(cap_deg), "kinematics": {k: float(kin[k]) for k in PARAM_NAMES},
            "chi_deg": 60.0 - float(kin["beta"]), "averages": t.averages.to_dict(), "fitness": float(t.fitness)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--speed", type=float, default=0.0)
    ap.add_argument("--param", default="beta", choices=PARAM_NAMES)
    ap.add_argument("--caps", type=float, nargs="+", default=[5.0, 15.0, 30.0, 50.0])
    ap.add_argument("--network", help="safetensors file (default: the shipped network of --speed)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--population", type=int, default=100_000)
    ap.add_argument("--out")
    a = ap.parse_args(argv)
    path = a.network or shipped_path(a.speed)
    net = load(path)
    rows = [capped_trim(net, a.speed, a.param, c, seed=a.seed, population=a.population) for c in a.caps]
    p = [r["averages"]["P_plus"] for r in rows]
    out = {"command": shlex.join(["python", "-m", "scripts.studies.trim_flat_direction", *(argv or sys.argv[1:])]),
           "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "loadavg": list(os.getloadavg()), "network": str(path), "speed": a.speed, "param": a.param,
           "seed": a.seed, "population": a.population, "rows": rows,
           "P_plus_spread": max(p) - min(p)}
    emit(out, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
