"""Benchmark: the first `hawksim aero` after an install, against the next one, in fresh clones and fresh venvs.

Prints ONE JSON object. For each ``--variant LABEL=COMMIT[:nowarmup]`` (default: ``HEAD``), one after the
other: ``git clone`` of this repository at COMMIT into a temporary folder, ``python -m venv``, a non-editable
``pip install .`` (the README's first command), an empty user cache (``XDG_CACHE_HOME`` pointed at a new folder,
so numba's cache starts empty as for a new user), then ``hawksim warmup --json`` where the commit has it (the
README's install step; skipped with ``:nowarmup``), then ``--runs`` times ``hawksim aero`` at the default
resolution (Table 3's hover kinematics), each timed as a whole command and by its own ``wall_time_s``.

By default the venv borrows the dependencies of the interpreter running this script (a ``.pth`` line to its
site-packages, ``pip install --no-deps``), so that no multi-GB download or install runs; ``--full-install``
installs them too, as the README does. Either way hawksim itself is installed from the clone into the new
venv's site-packages, so numba sees new source paths and compiles (or loads) as after a user's install.

    python scripts/benchmarks/bench_cold_start.py --variant base=e795e67 --variant new=HEAD [--runs 2]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import sysconfig
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
TABLE3_HOVER = "f=26.5,beta=1.5,phi0=-5.5,theta0=15.8,alpha0=0.7,phi_a=60.0,alpha_a=66.9"
"""Table 3's hover kinematics (hawksim.insect.kinematics.TABLE3_DEG at 0 m/s), as bench_uvlm.py runs them."""


def _loadavg():
    try:
        return [float(v) for v in open("/proc/loadavg").read().split()[:3]]
    except OSError:
        return None


def _timed(cmd, env, cwd=None) -> tuple[float, subprocess.CompletedProcess]:
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    return time.perf_counter() - t0, proc


def variant(label: str, commit: str, warmup: bool, runs: int, full: bool, work: str) -> dict:
    clone, venv, cache = (os.path.join(work, label, d) for d in ("hawksim", "venv", "cache"))
    subprocess.run(["git", "clone", "-q", REPO, clone], check=True)
    subprocess.run(["git", "-C", clone, "checkout", "-q", commit], check=True)
    sha = subprocess.run(["git", "-C", clone, "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                         check=True).stdout.strip()
    subprocess.run([sys.executable, "-m", "venv", venv], check=True)
    py = os.path.join(venv, "bin", "python")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "PYTHON", "VIRTUAL_ENV"))}
    env["XDG_CACHE_HOME"] = cache
    if not full:
        purelib = subprocess.run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                                 capture_output=True, text=True, check=True).stdout.strip()
        with open(os.path.join(purelib, "zz_borrowed_dependencies.pth"), "w") as f:
            f.write(sysconfig.get_paths()["purelib"] + "\n")
    install = [py, "-m", "pip", "install", "-q", "."] + ([] if full else ["--no-deps"])
    install_s, proc = _timed(install, env, cwd=clone)
    if proc.returncode:
        raise RuntimeError(f"{label}: pip install failed: {proc.stderr[-2000:]}")
    hawksim = os.path.join(venv, "bin", "hawksim")
    out = {"commit": sha, "install_s": round(install_s, 1), "warmup": None, "aero": []}
    has_warmup = subprocess.run([hawksim, "warmup", "--help"], env=env, capture_output=True).returncode == 0
    if warmup and has_warmup:
        load = _loadavg()
        sec, proc = _timed([hawksim, "warmup", "--json"], env)
        if proc.returncode:
            raise RuntimeError(f"{label}: hawksim warmup failed: {proc.stderr[-2000:]}")
        w = json.loads(proc.stdout.strip().splitlines()[-1])
        out["warmup"] = {"command_s": round(sec, 2), "compiled": w["compiled"], "loadavg": load}
    for _ in range(runs):
        load = _loadavg()
        sec, proc = _timed([hawksim, "aero", "--speed", "0", "--kinematics", TABLE3_HOVER, "--json",
                            "--no-progress"], env)
        if proc.returncode:
            raise RuntimeError(f"{label}: hawksim aero failed: {proc.stderr[-2000:]}")
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        out["aero"].append({"command_s": round(sec, 2), "wall_time_s": round(r["wall_time_s"], 3),
                            "L_plus": r["L_plus"], "P_plus": r["P_plus"], "loadavg": load})
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--variant", action="append", help="LABEL=COMMIT[:nowarmup] (repeatable; default new=HEAD)")
    ap.add_argument("--runs", type=int, default=2, help="hawksim aero runs after the install (default 2)")
    ap.add_argument("--full-install", action="store_true", help="install the dependencies too (slow, large)")
    ap.add_argument("--out", help="also write the JSON here")
    args = ap.parse_args()
    variants = []
    for text in args.variant or ["new=HEAD"]:
        label, _, spec = text.partition("=")
        commit, _, flag = spec.partition(":")
        variants.append((label, commit, flag != "nowarmup"))
    start = _loadavg()
    with tempfile.TemporaryDirectory(prefix="hawksim_cold_") as work:
        results = {label: variant(label, commit, warm, args.runs, args.full_install, work)
                   for label, commit, warm in variants}
    from hawksim.jsonout import emit

    emit({"command": " ".join(["python", *sys.argv]),
          "case": "hawksim aero --speed 0 (Table 3 hover), default resolution, fresh clone + venv + user cache",
          "full_install": args.full_install, "results": results, "loadavg_start": start}, args.out, host=True)


if __name__ == "__main__":
    main()
