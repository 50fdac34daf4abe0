"""The hawkmoth's numbers before and after a refactor (issue 50, item 7): run a fixed set of `hawksim` commands with
``--json``, keep their outputs (less the fields that measure the machine, not the model), and compare two such
records.

    python -m scripts.studies.behaviour_check --out /tmp/before.json           # at the base commit
    python -m scripts.studies.behaviour_check --out /tmp/after.json            # after the change
    python -m scripts.studies.behaviour_check --compare /tmp/before.json /tmp/after.json

The commands (:data:`CASES`) cover `aero` (quasi-steady and UVLM), `predict`, `trim` (a surrogate search and the
free-body orbit of the quasi-steady backend), `stability` (averaged, quasi-steady Floquet) and `fly` with every
control mode and rate on the quasi-steady backend, the UVLM's LQR and open loop and the per-step surrogate: a few
wingbeats each, so that the record takes minutes. Each command runs as ``python -m hawksim`` in the current
directory (PYTHONPATH unchanged). The comparison prints one JSON object: per case, ``identical`` (every number
equal bit for bit), else the largest absolute and relative difference and the first differing field; exit status 1
if any case differs or failed.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

from hawksim.jsonout import emit

KIN = "f=27,beta=20,phi0=5,theta0=10,alpha0=5,phi_a=55,alpha_a=45"
"""Kinematics of the `aero` and `predict` cases (Hz, deg; inside Table 2)."""

CASES = {
    "aero_qs_v1": ["aero", "--speed", "1", "--kinematics", KIN, "--aero", "quasi-steady"],
    "aero_uvlm_v1": ["aero", "--speed", "1", "--kinematics", KIN, "--aero", "uvlm", "--no-progress"],
    "predict_v1": ["predict", "--speed", "1", "--kinematics", KIN],
    "trim_surrogate_v1": ["trim", "--speed", "1", "--population", "20", "--no-progress"],
    "orbit_qs_v0": ["trim", "--speed", "0", "--free-flight", "--aero", "quasi-steady", "--no-progress"],
    "stability_qs_v1": ["stability", "--speed", "1", "--aero", "quasi-steady", "--no-progress"],
    "floquet_qs_v1": ["stability", "--speed", "1", "--aero", "quasi-steady", "--floquet", "--no-progress"],
    "fly_qs_none": ["fly", "--speed", "1", "--cycles", "4", "--control", "none", "--no-progress"],
    "fly_qs_lqr": ["fly", "--speed", "1", "--cycles", "4", "--control", "lqr", "--no-progress"],
    "fly_qs_lqr_half": ["fly", "--speed", "1", "--cycles", "4", "--control", "lqr", "--control-rate",
                        "half-stroke", "--no-progress"],
    "fly_qs_clqr": ["fly", "--speed", "1", "--cycles", "4", "--control", "clqr", "--no-progress"],
    "fly_qs_gust_profile": ["fly", "--speed", "1", "--cycles", "6", "--control", "lqr", "--gust", "0,0,0.5@1:1",
                            "--ascent-profile", "1:2,1.5:4", "--no-progress"],
    "fly_qs_perturb": ["fly", "--speed", "0.5", "--cycles", "3", "--perturb", "theta=2", "--no-progress"],
    "fly_uvlm_lqr": ["fly", "--speed", "1", "--cycles", "2", "--aero", "uvlm", "--control", "lqr",
                     "--no-progress"],
    "fly_uvlm_none": ["fly", "--speed", "1.5", "--cycles", "2", "--aero", "uvlm", "--control", "none",
                      "--no-progress"],
    "fly_step_surrogate_lqr": ["fly", "--speed", "1", "--cycles", "3", "--aero", "surrogate", "--control", "lqr",
                               "--no-progress"],
    "fly_surrogate_mean": ["fly", "--speed", "1", "--cycles", "3", "--aero", "surrogate-mean", "--no-progress"],
}
"""Case name -> `hawksim` arguments (``--json`` added)."""

MACHINE_FIELDS = ("wall", "time_s", "timings", "per_s", "elapsed", "seconds", "loadavg", "date", "host", "started",
                  "finished")
"""Fields whose names contain one of these measure the run, not the model: left out of the record."""


def strip(x):
    """``x`` (parsed JSON) without the machine fields (:data:`MACHINE_FIELDS`), recursively."""
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not any(m in k for m in MACHINE_FIELDS)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x


def record(cases: dict) -> dict:
    out = {}
    for name, args in cases.items():
        t0 = time.perf_counter()
        p = subprocess.run([sys.executable, "-m", "hawksim", *args, "--json"], capture_output=True, text=True)
        print(f"{name}: rc {p.returncode} in {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
        try:
            out[name] = {"rc": p.returncode, "json": strip(json.loads(p.stdout))}
        except json.JSONDecodeError:
            out[name] = {"rc": p.returncode, "stdout": p.stdout[-2000:], "stderr": p.stderr[-2000:]}
    return out


def leaves(x, path=""):
    """(path, value) of every leaf of parsed JSON ``x``."""
    if isinstance(x, dict):
        for k, v in x.items():
            yield from leaves(v, f"{path}.{k}")
    elif isinstance(x, list):
        for i, v in enumerate(x):
            yield from leaves(v, f"{path}[{i}]")
    else:
        yield path, x


def compare(a: dict, b: dict) -> dict:
    """Per case of ``a``: identical, or the largest differences against ``b``."""
    out = {}
    for name, ra in a.items():
        rb = b.get(name)
        if rb is None or "json" not in ra or "json" not in rb:
            out[name] = {"identical": False, "why": "missing or failed", "rc": [ra.get("rc"), (rb or {}).get("rc")]}
            continue
        la, lb = dict(leaves(strip(ra["json"]))), dict(leaves(strip(rb["json"])))
        if la.keys() != lb.keys():
            out[name] = {"identical": False, "why": "fields differ", "only_before": sorted(la.keys() - lb.keys())[:5],
                         "only_after": sorted(lb.keys() - la.keys())[:5]}
            continue
        diffs = [(k, la[k], lb[k]) for k in la if la[k] != lb[k]]
        if not diffs:
            out[name] = {"identical": True}
            continue
        num = [(k, abs(x - y), abs(x - y) / max(abs(x), abs(y), 1e-300)) for k, x, y in diffs
               if isinstance(x, (int, float)) and isinstance(y, (int, float)) and math.isfinite(x) and math.isfinite(y)]
        out[name] = {"identical": False, "fields_differing": len(diffs), "first": diffs[0][0],
                     "max_abs": max((d[1] for d in num), default=None),
                     "max_rel": max((d[2] for d in num), default=None)}
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", help="record the cases' outputs to this JSON file")
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"), help="compare two records")
    ap.add_argument("--only", nargs="+", choices=sorted(CASES), help="record only these cases")
    a = ap.parse_args()
    if a.compare:
        res = compare(*(json.loads(Path(p).read_text()) for p in a.compare))
        emit({"cases": res, "identical": all(r["identical"] for r in res.values())})
        sys.exit(0 if all(r["identical"] for r in res.values()) else 1)
    if not a.out:
        ap.error("--out or --compare")
    cases = {k: CASES[k] for k in (a.only or CASES)}
    Path(a.out).write_text(json.dumps(record(cases), indent=1))


if __name__ == "__main__":
    main()
