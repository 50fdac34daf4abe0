"""Regenerate the shipped artefacts on the reference UVLM and the sourced hawkmoth (issue 49, item 3), stage by
stage, resumably, with the project's own commands.

Each stage is one `hawksim` command (run as ``python -m hawksim`` in the repository given by --repo, so that a
worktree's code is the code that runs) with its outputs and seed. The data-set stages are resumable by the command
itself (``hawksim dataset`` continues a file); they run in rounds of increasing sample counts over the five speeds,
so that a stopped run leaves every speed equally covered. The manifest (--manifest, JSON) records for each finished
stage: the command, the seed, the sources digest (:func:`aero.numba_cache.sources_digest` of the code that ran),
the hawksim version, start and end (UTC), the load average and the command's JSON output; a stage whose entry is
there is skipped. Runs at the niceness given (--nice) with one worker, so that it takes only idle CPU.

    python scripts/regenerate.py --repo . --manifest results/regeneration/manifest.json --stages reference training

Stages (in the order of their dependencies; later stages are added as the issue proceeds):

* ``reference``: `hawksim dataset --resolution reference` (6 x 12 rings, 40 steps, 3 beats, the last averaged),
  seed 0, 1000 samples at each of V = 0, 0.5, 1, 1.5, 2 m/s, into data/uvlm_reference_<version>.sqlite;
* ``training``: `hawksim dataset` at the training resolution (4 x 8 rings, 30 steps), seed 0, 3000 samples a speed,
  into data/uvlm_training_<version>.sqlite.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)
DATASETS = {
    "reference": {"resolution": "reference", "rounds": (100, 200, 400, 600, 800, 1000)},
    "training": {"resolution": "training", "rounds": (500, 1000, 2000, 3000)},
}
"""Data-set stages: the ``--resolution`` name and the cumulative sample counts of each round over the speeds."""


def now() -> str:
    return datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def repo_facts(repo: Path) -> dict:
    """The version and sources digest of the code in ``repo`` (run there, so a worktree reports its own)."""
    code = ("import json, hawksim; from aero.numba_cache import sources_digest; "
            "print(json.dumps({'version': hawksim.__version__, 'sources_digest': sources_digest()}))")
    out = subprocess.run([sys.executable, "-c", code], cwd=repo, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def run_stage(name: str, repo: Path, facts: dict, manifest: dict, save, nice: int) -> None:
    spec = DATASETS[name]
    out = f"data/uvlm_{name}_{facts['version']}.sqlite"
    log = repo / f"data/uvlm_{name}_{facts['version']}.log"
    for n in spec["rounds"]:
        for v in SPEEDS:
            key = f"{name}|V={v:g}|n={n}"
            if key in manifest["stages"]:
                continue
            argv = ["hawksim", "dataset", "--speed", f"{v:g}", "--samples", str(n), "--out", out, "--seed", "0",
                    "--resolution", spec["resolution"], "--workers", "1", "--no-progress", "--json"]
            start, load = now(), os.getloadavg()
            t0 = time.perf_counter()
            env = dict(os.environ, NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
            proc = subprocess.run(["nice", "-n", str(nice), sys.executable, "-m", *argv[0:1], *argv[1:]],
                                  cwd=repo, env=env, capture_output=True, text=True)
            with log.open("a") as f:
                f.write(f"{start} {' '.join(argv)} (load {load})\n{proc.stdout}{proc.stderr}\n")
            if proc.returncode != 0:
                print(f"regenerate: {key} failed (exit {proc.returncode}); see {log}", file=sys.stderr)
                sys.exit(proc.returncode)
            manifest["stages"][key] = {"command": " ".join(argv), "seed": 0, "out": out, "start": start,
                                       "end": now(), "wall_time_s": time.perf_counter() - t0,
                                       "loadavg_start": load, **facts, "result": json.loads(proc.stdout)}
            save()
            print(f"{now()} {key} done", file=sys.stderr, flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repo", default=".", help="repository (or worktree) whose code runs")
    ap.add_argument("--manifest", required=True)
    ap.add_argument("--stages", nargs="+", choices=tuple(DATASETS), required=True)
    ap.add_argument("--nice", type=int, default=15)
    a = ap.parse_args()
    repo = Path(a.repo).resolve()
    path = Path(a.manifest)
    manifest = json.loads(path.read_text()) if path.exists() else {"stages": {}}
    facts = repo_facts(repo)
    manifest.setdefault("note", "issue 49's regeneration; each stage's command ran as `python -m hawksim ...` in "
                        "the repository whose version and sources digest it records")

    def save():
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(manifest, indent=1))
        tmp.replace(path)

    for name in a.stages:
        run_stage(name, repo, facts, manifest, save, a.nice)


if __name__ == "__main__":
    main()
