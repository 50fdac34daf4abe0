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

Stages (in the order of their dependencies; ``--stages`` names them, ``--list`` prints their commands):

* ``reference``: `hawksim dataset --resolution reference` (6 x 12 rings, 40 steps, 3 beats, the last averaged),
  seed 0, 1000 samples at each of V = 0, 0.5, 1, 1.5, 2 m/s, into data/uvlm_reference_<version>.sqlite;
* ``training``: `hawksim dataset` at the training resolution (4 x 8 rings, 30 steps), seed 0, 3000 samples a speed,
  into data/uvlm_training_<version>.sqlite;
* the rest are single commands (:data:`COMMANDS`), each with the shipped file(s) it writes or the files it copies
  into hawksim/data (as insects/hawkmoth/data/surrogates/README.md and the tables' own ``command`` fields record them):
  the cycle-mean networks, the trims, the orbits, the per-step surrogate's flights and network (with the wake-age
  input, ``--wake-age``: trained on the warm-up beats too, so that a flight launched from no wake is right from its
  first beat; docs/surrogate.md, "Launch from no wake"), its orbits, the control models, and the paper's tables.
  Scripts run with PYTHONPATH set to the repository, so that its code is
  the code that runs.
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

DATA = "hawksim/insects/hawkmoth/data/"
"""The hawkmoth's folder of shipped tables and networks (:mod:`hawksim.insect.tables`), relative to the repository."""

_TRAIN = ["hawksim", "train", "--seed", "0"]
COMMANDS = {
    "networks": [
        [*_TRAIN, "--data", "data/uvlm_training_{version}.sqlite", "--out",
         DATA + f"surrogates/uvlm_v{int(round(v * 1000)):04d}.safetensors", "--hidden", "500",
         "--max-iter", "300", "--time-limit", "900", "--speed", f"{v:g}"] for v in SPEEDS] + [
        [*_TRAIN, "--data", "data/uvlm_training_{version}.sqlite", "--out",
         DATA + "surrogates/uvlm_all_speeds.safetensors", "--hidden", "500", "--max-iter", "25",
         "--time-limit", "3600", "--all-speeds"]],
    "network_reference": [
        [*_TRAIN, "--data", "data/uvlm_reference_{version}.sqlite", "--out",
         DATA + "surrogates/uvlm_reference_all_speeds.safetensors", "--hidden", "20", "--max-iter", "300",
         "--time-limit", "900", "--all-speeds", "--base", "shipped"]],
    "trim": [["hawksim", "reproduce", "--only", "trim", "--out", "results/regeneration/reproduce", "--force"],
             ["cp", "results/regeneration/reproduce/trim/trim_table.json", DATA + "trim_table.json"],
             ["python", "scripts/studies/uvlm_trim_table.py", "--aero", "quasi-steady", "--out",
              DATA + "trim_table_quasi_steady.json"],
             ["python", "scripts/studies/surrogate_trim_table.py", "--out", DATA + "trim_table_surrogate.json"]],
    "orbits": [["hawksim", "reproduce", "--only", "orbits", "--out", "results/regeneration/reproduce", "--force"],
               ["cp", "results/regeneration/reproduce/orbits/orbit_table_quasi_steady.json",
                "results/regeneration/reproduce/orbits/orbit_table_uvlm.json", DATA]],
    "flights": [["hawksim", "dataset", "--kind", "flights", "--samples", "700", "--seed", "0", "--out",
                 "data/uvlm_flights_{version}.sqlite", "--workers", "1", "--no-progress", "--json"]],
    "step_network": [[*_TRAIN, "--kind", "step", "--data", "data/uvlm_flights_{version}.sqlite", "--out",
                      DATA + "surrogates/uvlm_step.safetensors", "--layers", "192,192,192", "--lags", "0.5,1",
                      "--max-iter", "300", "--time-limit", "1500", "--weight-decay", "0", "--ensemble", "3",
                      "--wake-age", "--no-progress", "--json"]],
    "surrogate_orbits": [["python", "scripts/studies/step_surrogate_orbits.py", "--speeds", "0", "0.5", "1", "1.5",
                          "2", "--validate", "--out", "results/surrogate/step_orbits.json", "--table",
                          DATA + "orbit_table_surrogate.json"]],
    "control": [["hawksim", "reproduce", "--only", "control_uvlm", "control_surrogate", "--out",
                 "results/regeneration/reproduce", "--force"],
                ["cp", "results/regeneration/reproduce/control/control_models_uvlm.json",
                 "results/regeneration/reproduce/control/control_models_surrogate.json", DATA]],
    "paper": [["hawksim", "reproduce", "--only", "uvlm_table4", "stability", "stability_table3", "validation",
               "validation_uvlm", "backends", "--out", "results", "--force"]],
}
"""Command stages: the argument lists, run one after the other in the repository ({version} is its version).
Not yet run on the sourced hawkmoth: the first run of each may need its arguments checked against the current CLI."""


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


def restamp_written(repo: Path, since: float, env: dict, log: Path) -> None:
    """Restamp (:func:`hawksim.insect.tables.restamp`, in the repository's own code) the hawkmoth's manifest entries
    whose files were written at or after ``since`` (epoch seconds): they were computed on the repository's MJCF."""
    code = ("import json, sys, time; from pathlib import Path; from hawksim.insect.folder import default_insect; "
            "from hawksim.insect.tables import manifest, restamp; ins = default_insect(); "
            "data = Path(ins.folder) / 'data'; since = float(sys.argv[1]); "
            "names = [str(e.path.relative_to(data)) for e in manifest(ins) if e.path.is_file() "
            "and e.path.stat().st_mtime >= since]; print(json.dumps(restamp(ins, names)))")
    proc = subprocess.run([sys.executable, "-c", code, repr(since - 1.0)], cwd=repo, env=env, capture_output=True,
                          text=True, check=True)
    with log.open("a") as f:
        f.write(f"{now()} restamped in the manifest: {proc.stdout.strip()}\n")


def run_commands(name: str, repo: Path, facts: dict, manifest: dict, save, nice: int) -> None:
    """A command stage (:data:`COMMANDS`): each command once, in order, recorded in the manifest when it succeeds."""
    env = dict(os.environ, NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1", PYTHONPATH=str(repo))
    log = repo / "results/regeneration/commands.log"
    log.parent.mkdir(parents=True, exist_ok=True)
    for k, argv in enumerate(COMMANDS[name]):
        argv = [a.format(version=facts["version"]) for a in argv]
        key = f"{name}|{k}"
        if key in manifest["stages"]:
            continue
        if argv[0] == "hawksim":
            cmd = ["nice", "-n", str(nice), sys.executable, "-m", *argv]
        elif argv[0] == "python":
            cmd = ["nice", "-n", str(nice), sys.executable, *argv[1:]]
        else:
            cmd = argv
        start, load = now(), os.getloadavg()
        t0, wall0 = time.perf_counter(), time.time()
        proc = subprocess.run(cmd, cwd=repo, env=env, capture_output=True, text=True)
        with log.open("a") as f:
            f.write(f"{start} {' '.join(argv)} (load {load})\n{proc.stdout[-20000:]}{proc.stderr[-20000:]}\n")
        if proc.returncode != 0:
            print(f"regenerate: {key} ({' '.join(argv)}) failed (exit {proc.returncode}); see {log}", file=sys.stderr)
            sys.exit(proc.returncode)
        restamp_written(repo, wall0, env, log)
        manifest["stages"][key] = {"command": " ".join(argv), "seed": 0, "start": start, "end": now(),
                                   "wall_time_s": time.perf_counter() - t0, "loadavg_start": load, **facts}
        save()
        print(f"{now()} {key} done", file=sys.stderr, flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repo", default=".", help="repository (or worktree) whose code runs")
    ap.add_argument("--manifest", required=True)
    ap.add_argument("--stages", nargs="+", choices=(*DATASETS, *COMMANDS), required=True)
    ap.add_argument("--nice", type=int, default=15)
    ap.add_argument("--list", action="store_true", help="print the stages' commands and exit")
    a = ap.parse_args()
    if a.list:
        for name in a.stages:
            cmds = ([f"hawksim dataset ... --resolution {DATASETS[name]['resolution']} (rounds "
                     f"{DATASETS[name]['rounds']})"] if name in DATASETS else [" ".join(c) for c in COMMANDS[name]])
            print(f"{name}:", *cmds, sep="\n  ")
        return
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
        if name in DATASETS:
            run_stage(name, repo, facts, manifest, save, a.nice)
        else:
            run_commands(name, repo, facts, manifest, save, a.nice)


if __name__ == "__main__":
    main()
