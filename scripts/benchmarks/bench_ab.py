"""Benchmark: two commits side by side in one sitting, rounds interleaved, on the UVLM cases of the speed issue.

Prints ONE JSON object. Each ``--variant LABEL=COMMIT`` is checked out into a temporary git worktree of this
repository; then, for ``--rounds`` rounds, every variant runs once in a fresh process (``PYTHONPATH`` at its
worktree, the numba cache in a per-variant folder warmed before the first round), so that the machine's drift
(its speed swings ~2x over a day) falls on all variants alike. Each process times, after a warm-up call:

* ``aero_s``: `hawksim aero`'s solve at the default resolution (Table 3's hover kinematics), best of 2
  (``hawksim.backends.held.run``, as bench_uvlm.py's ``aero_warm_s``);
* ``reference_s``: bench_uvlm.py's reference case (two 8 x 16-ring wings by a mirror plane, 3 beats, 220 steps,
  free wake), once;

and reports the results' bits (``aero_L_plus``, ``reference_lift_N`` as float.hex), so that a change meant to keep
them can be seen to. Per variant: the median and min of each time over the rounds; ``ratio`` = the first variant's
median / each variant's (> 1: faster than the first). /proc/loadavg before and after every process.

    python -m scripts.benchmarks.bench_ab --variant base=HEAD~1 --variant new=HEAD [--rounds 3] [--threads 2]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

CHILD = r"""
import json, sys, time
import aero  # noqa: F401  (before numba)
from scripts.benchmarks.bench_uvlm import run_case  # the worktree is the working directory
from hawksim.backends.held import run
from hawksim.backends.resolution import DEFAULT
from hawksim.insect.kinematics import table3_kinematics
k = table3_kinematics(0.0)
run(k, 0.0, DEFAULT)
run_case(steps=4, cycles=4 / 220 * 3)
best, L = float("inf"), None
for _ in range(2):
    t0 = time.perf_counter()
    r = run(k, 0.0, DEFAULT)
    best = min(best, time.perf_counter() - t0)
    L = r.averages.L_plus
t0 = time.perf_counter()
res = run_case(220)
ref = time.perf_counter() - t0
lift = float(2 * res.force[-220 // 3:, 0, 2].mean())
print(json.dumps({"aero_s": best, "reference_s": ref, "aero_L_plus": float(L).hex(), "reference_lift_N": lift.hex()}))
"""


def _load():
    try:
        return [float(v) for v in open("/proc/loadavg").read().split()[:3]]
    except OSError:
        return None


def _run(tree: str, cache: str, threads: int) -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "PYTHONPATH"))}
    env.update(PYTHONPATH=tree, NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS=str(threads))
    before = _load()
    proc = subprocess.run([sys.executable, "-c", CHILD, tree], env=env, cwd=tree, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"bench_ab: the child failed in {tree}:\n{proc.stderr[-2000:]}")
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    out.update(load_before=before, load_after=_load())
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variant", action="append", required=True, help="LABEL=COMMIT (repeatable, >= 1)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out")
    a = ap.parse_args()
    variants = []
    for text in a.variant:
        label, sep, commit = text.partition("=")
        if not sep or not label or not commit:
            sys.exit(f"error: --variant must be LABEL=COMMIT, got {text!r}")
        variants.append((label, commit))
    if a.rounds < 1 or a.threads < 1:
        sys.exit("error: --rounds and --threads must be >= 1")
    from hawksim.jsonout import emit, host_info

    began = host_info()
    work = tempfile.mkdtemp(prefix="bench_ab_")
    trees = {}
    try:
        for label, commit in variants:
            tree = os.path.join(work, label)
            subprocess.run(["git", "-C", REPO, "worktree", "add", "-q", "--detach", tree, commit], check=True)
            sha = subprocess.run(["git", "-C", tree, "rev-parse", "--short", "HEAD"], capture_output=True,
                                 text=True, check=True).stdout.strip()
            trees[label] = (tree, os.path.join(work, label + "_cache"), sha)
            _run(tree, trees[label][1], a.threads)  # compile into the variant's cache
        runs = {label: [] for label, _ in variants}
        for _ in range(a.rounds):
            for label, _ in variants:
                runs[label].append(_run(*trees[label][:2], a.threads))
    finally:
        for tree, _, _ in trees.values():
            subprocess.run(["git", "-C", REPO, "worktree", "remove", "--force", tree], check=False)
        shutil.rmtree(work, ignore_errors=True)
    first = variants[0][0]
    summary = {}
    for label, commit in variants:
        r = runs[label]
        s = {"commit": commit, "sha": trees[label][2]}
        for key in ("aero_s", "reference_s"):
            vals = [x[key] for x in r]
            s[key] = {"median": round(statistics.median(vals), 4), "min": round(min(vals), 4),
                      "all": [round(v, 4) for v in vals]}
        s["bits"] = sorted({(x["aero_L_plus"], x["reference_lift_N"]) for x in r})
        summary[label] = s
    for label, _ in variants:
        summary[label]["ratio"] = {key: round(summary[first][key]["median"] / summary[label][key]["median"], 3)
                                   for key in ("aero_s", "reference_s")}
    same = len({tuple(map(tuple, s["bits"])) for s in summary.values()}) == 1
    command = " ".join(["python", "-m", "scripts.benchmarks.bench_ab", *sys.argv[1:]])
    emit({"command": command, "began": began["date"], "ended": host_info()["date"], "host": began,
          "threads": a.threads, "rounds": a.rounds, "same_bits": same, "variants": summary, "runs": runs}, a.out)


if __name__ == "__main__":
    main()
