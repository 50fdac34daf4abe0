"""Ctrl-C and SIGTERM at any moment after a fresh install (issue 18): the trial behind tests/hawksim/test_interrupt.py.

Like ``.ci/run``: the repository at ``--rev`` is cloned into a temporary directory and installed into a fresh
virtual environment (``--install editable``: ``pip install -e ".[dev]"``, the README's second set-up command;
``wheel``: ``pip install .``, its first). Then each trial runs the installed ``hawksim`` command cold, in its own
process group, and sends the group a signal (SIGINT, as a terminal's Ctrl-C does, or SIGTERM) after a delay:

* ``--cold hawksim``: hawksim's and aero's ``__pycache__`` folders are deleted and numba's cache
  (``$XDG_CACHE_HOME``) is a new empty folder before every trial: the state of a fresh clone's first run (pip
  compiles the third-party packages' bytecode when it installs them);
* ``--cold all``: as ``hawksim``, and ``PYTHONPYCACHEPREFIX`` is a new empty folder, so that every module, numpy's
  and dask's included, is compiled from source: imports several times slower than on any fresh install, to widen
  the moments a signal can land in an import.

A trial passes when the command exits with status 130 within ``EXIT_LIMIT_S`` of the signal (its pipes closed:
no worker process holds them), prints nothing on stdout and exactly the line ``hawksim: interrupted`` on stderr,
leaves no process of its group running after ``LINGER_S``, and leaves no file but a data set holding committed rows
(no journal).

    python scripts/studies/interrupt_cold_trial.py [--rev REV] [--install editable|wheel] [--cold hawksim|all]
        [--commands dataset stability] [--delays 0.1 0.2 ...] [--repeats N] [--venv DIR] [--out FILE]

Each trial also records when the command had installed its signal handlers (``handlers_at_s``: its SIGTERM shows
in /proc/PID/status's SigCgt), so that a signal that came before (``before_handlers``: the interpreter still
starting, Python's defaults in force) is counted apart from one the command could handle.

``--venv DIR`` reuses (or first makes) the clone and environment in DIR instead of a temporary one. Prints ONE
JSON object: per trial the command, signal, delay, exit status, seconds from the signal to the exit, stderr's
lines (up to 5), the files and processes left and the reasons of a failure; per command and signal the count that
passed; the install's seconds; the host (date, load average).

Last runs (2026-12-02, 2-core development machine shared with other jobs, load average 6-9; editable installs;
results/cli/interrupt_cold/, the before runs with this script against commit e795e67):

| rev | cold | trials | pass | after the handlers | before them | exit after the signal |
|---|---|---|---|---|---|---|
| e795e67 (before) | hawksim | 96 (dataset, stability, fly, train) | 86 | 86 of 88 | 0 of 8 | <= 0.55 s |
| e795e67 (before) | all | 48 (dataset, stability) | 33 | 32 of 34 | 1 of 14 | <= 0.39 s |
| c2c9681 (after) | hawksim | 192 (the four, twice) | 180 | 180 of 180 | 0 of 12 | median 0.056 s, <= 1.2 s |
| d3aa1ee (after) | all | 48 (dataset, stability) | 34 | 34 of 34 | 0 of 14 | <= 0.12 s |

The failures before the fix, after the handlers: a worker's traceback after "hawksim: interrupted" (stability,
SIGINT at 2 s: a worker spawned while the command left), an 83-line traceback with exit 1 (fly, SIGTERM at 4.5 s),
numpy's ImportError with exit 1 (dataset SIGINT at 0.5 s, stability SIGINT at 0.7 s, all cold: the interrupt inside
numpy's import). Every failure left, before and after, is a signal that came before the command had installed its
handlers (at 0.05 s; up to 0.3 s all cold): the interpreter's own start, where Python's defaults apply
(hawksim.interrupts). A run at 1f10dd5 (before train waited for its first write to begin its work) had one more:
train, SIGTERM at 2 s, exit 130 after 3.6 s (the Ctrl-C waited for torch's import to end).
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from hawksim.jsonout import emit

ROOT = Path(__file__).resolve().parents[2]
EXIT_LIMIT_S = 3.0
"""Seconds from the signal to the exit (all pipes closed) a trial may take: tests/hawksim/test_interrupt.py's bound."""
DELAYS = (0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 4.5, 6.0)
"""Default delays [s] from the start to the signal: the interpreter's start, the imports (~0.5 s warm, several
seconds cold), the Dask LocalCluster's start-up (~3 s) and the first computations."""
COMMANDS = {
    "dataset": ["dataset", "--speed", "1", "--samples", "400", "--out", "d.sqlite", "--workers", "2", "--json",
                "--no-progress"],
    "stability": ["stability", "--speed", "1", "--workers", "2", "--json", "--no-progress"],
    "fly": ["fly", "--speed", "1", "--cycles", "2000", "--json", "--no-progress"],
    "train": ["train", "--data", "{data}", "--out", "m.safetensors", "--speed", "1", "--json", "--no-progress"],
}
"""The commands tried (argv after ``hawksim``; {data}: the clone's shipped training set)."""


def install(dest: Path, rev: str, how: str) -> tuple[Path, float]:
    """Clone ROOT at ``rev`` into ``dest/hawksim`` and install it into ``dest/hawksim/.venv``; (clone, seconds)."""
    clone = dest / "hawksim"
    t0 = time.perf_counter()
    if (clone / ".venv" / "bin" / "hawksim").exists():  # reused: an editable install follows its clone's files
        subprocess.run(["git", "-C", str(clone), "fetch", "-q", str(ROOT)], check=True)
        subprocess.run(["git", "-C", str(clone), "checkout", "-q", rev], check=True)
        if how == "wheel":
            subprocess.run([str(clone / ".venv" / "bin" / "pip"), "install", "-q", "--force-reinstall", "--no-deps",
                            "."], cwd=clone, check=True)
    else:
        shutil.rmtree(clone, ignore_errors=True)
        subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
        subprocess.run(["git", "-C", str(clone), "checkout", "-q", rev], check=True)
        subprocess.run([sys.executable, "-m", "venv", str(clone / ".venv")], check=True)
        target = "-e" if how == "editable" else None
        spec = ".[dev]" if how == "editable" else "."
        subprocess.run([str(clone / ".venv" / "bin" / "pip"), "install", "-q", *([target] if target else []), spec],
                       cwd=clone, check=True)
    return clone, time.perf_counter() - t0


def make_cold(clone: Path, how: str, scratch: Path) -> dict:
    """Delete hawksim's and aero's bytecode (in the clone and, for a wheel, in site-packages) and return the
    environment of a cold run: a new numba cache, and for ``all`` a new bytecode prefix."""
    roots = [clone / "hawksim", clone / "aero"]
    roots += list((clone / ".venv" / "lib").glob("python3*/site-packages/hawksim"))
    roots += list((clone / ".venv" / "lib").glob("python3*/site-packages/aero"))
    for root in roots:
        for d in root.rglob("__pycache__"):
            shutil.rmtree(d, ignore_errors=True)
    if scratch.exists():
        shutil.rmtree(scratch)
    scratch.mkdir()
    env = {**os.environ, "XDG_CACHE_HOME": str(scratch / "cache")}
    env.pop("NUMBA_CACHE_DIR", None)
    if how == "all":
        env["PYTHONPYCACHEPREFIX"] = str(scratch / "pyc")
    return env


LINGER_S = 3.0
"""Seconds a process of the group may outlive the command (multiprocessing's resource tracker, which removes the
workers' semaphores once the command's end closes its pipe, and then exits)."""


def group_members(pgid: int) -> list[str]:
    """The command lines (first 100 characters) of the live processes of process group ``pgid`` (Linux /proc)."""
    out = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
            fields = stat[stat.rindex(")") + 2:].split()
            if int(fields[2]) != pgid or fields[0] == "Z":
                continue
            out.append((d / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()[:100])
        except (OSError, ValueError, IndexError):
            continue
    return out


def handlers_installed(pid: int) -> bool:
    """Whether ``pid`` catches SIGTERM: hawksim.interrupts.install has run (Python's defaults leave it alone)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    return bool(int(status.split("SigCgt:")[1].split()[0], 16) & (1 << (signal.SIGTERM - 1)))


def trial(clone: Path, argv: list[str], signum: int, delay: float, env: dict) -> dict:
    """One run: the signal to the process group after ``delay`` s; the row of the output."""
    exe = str(clone / ".venv" / "bin" / "hawksim")
    argv = [a.replace("{data}", str(clone / "data" / "uvlm_training_0.3.sqlite")) for a in argv]
    with tempfile.TemporaryDirectory(prefix="hawksim-cold-") as d:
        cwd = Path(d)
        p = subprocess.Popen([exe, *argv], cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             stdin=subprocess.DEVNULL, start_new_session=True,
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        started = time.perf_counter()
        installed = None
        while time.perf_counter() < started + delay:
            if installed is None and handlers_installed(p.pid):
                installed = time.perf_counter() - started
            time.sleep(0.002)
        early = p.poll()
        t0 = time.perf_counter()
        if early is None:
            os.killpg(p.pid, signum)
        try:
            out, err = p.communicate(timeout=60)
            hung = False
        except subprocess.TimeoutExpired:
            hung = True
            os.killpg(p.pid, signal.SIGKILL)
            out, err = p.communicate()
        took = time.perf_counter() - t0
        t_exit = time.perf_counter()
        first_left = group_members(p.pid)
        while (left_procs := group_members(p.pid)) and time.perf_counter() < t_exit + LINGER_S:
            time.sleep(0.05)
        linger = time.perf_counter() - t_exit
        if left_procs:
            os.killpg(p.pid, signal.SIGKILL)
        files = sorted(str(f.relative_to(cwd)) for f in cwd.rglob("*"))
        rows = None
        if files == ["d.sqlite"]:
            with sqlite3.connect(cwd / "d.sqlite") as c:
                rows = c.execute("SELECT count(*) FROM samples").fetchone()[0]
    lines = err.decode(errors="replace").strip().splitlines()
    why = []
    if early is not None:
        why.append(f"ended before the signal (exit {early})")
    if hung:
        why.append("still running 60 s after the signal")
    if p.returncode != 130:
        why.append(f"exit {p.returncode}")
    if out:
        why.append("output on stdout")
    if lines != ["hawksim: interrupted"]:
        why.append(f"{len(lines)} stderr lines" if len(lines) != 1 else f"stderr {lines[0][:80]!r}")
    if took > EXIT_LIMIT_S and not hung:
        why.append(f"took {took:.2f} s")
    if left_procs:
        why.append(f"{len(left_procs)} processes of its group running {LINGER_S:g} s after: {left_procs[0][:60]}")
    if files not in ([], ["d.sqlite"]) or (files == ["d.sqlite"] and not rows):
        why.append(f"left {files} ({rows} rows)" if files == ["d.sqlite"] else f"left {files}")
    return {"command": argv[0], "signal": signal.Signals(signum).name, "delay_s": delay,
            "handlers_at_s": None if installed is None else round(installed, 3),
            "before_handlers": installed is None, "exit": p.returncode,
            "seconds": round(took, 3), "stderr": lines[:3] + (["..."] if len(lines) > 5 else lines[3:5]),
            "stderr_lines": len(lines), "files_left": files, "rows": rows, "processes_at_exit": first_left,
            "linger_s": round(linger, 2), "processes_left": left_procs,
            "pass": not why, "why": why, **({"stderr_tail": lines[-8:]} if why and len(lines) > 5 else {})}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rev", default="HEAD", help="commit of this repository to clone (default HEAD)")
    ap.add_argument("--install", choices=("editable", "wheel"), default="editable")
    ap.add_argument("--cold", choices=("hawksim", "all"), default="hawksim")
    ap.add_argument("--commands", nargs="+", choices=tuple(COMMANDS), default=["dataset", "stability"])
    ap.add_argument("--signals", nargs="+", choices=("SIGINT", "SIGTERM"), default=["SIGINT", "SIGTERM"])
    ap.add_argument("--delays", nargs="+", type=float, default=list(DELAYS))
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--venv", help="keep the clone and its environment in this folder (made if absent)")
    ap.add_argument("--out")
    a = ap.parse_args()
    rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", a.rev], capture_output=True, text=True,
                         check=True).stdout.strip()
    keep = Path(a.venv) if a.venv else None
    work = keep or Path(tempfile.mkdtemp(prefix="hawksim-cold-install-"))
    work.mkdir(parents=True, exist_ok=True)
    try:
        clone, install_s = install(work, rev, a.install)
        rows = []
        t_start = time.perf_counter()
        for rep in range(a.repeats):
            for name in a.commands:
                for sig in a.signals:
                    for delay in a.delays:
                        env = make_cold(clone, a.cold, work / "scratch")
                        row = trial(clone, COMMANDS[name], getattr(signal, sig), delay, env)
                        row["repeat"] = rep
                        rows.append(row)
                        print(f"{'pass' if row['pass'] else 'FAIL'}  {name} {sig} at {delay:g} s: exit "
                              f"{row['exit']} in {row['seconds']:.2f} s {'; '.join(row['why'])}", file=sys.stderr)
        summary = {}
        early = [r for r in rows if r["before_handlers"]]
        at = [r["handlers_at_s"] for r in rows if r["handlers_at_s"] is not None]
        for r in rows:
            key = f"{r['command']} {r['signal']}"
            s = summary.setdefault(key, {"passed": 0, "ran": 0})
            s["ran"] += 1
            s["passed"] += r["pass"]
        emit({"rev": rev, "install": a.install, "cold": a.cold, "install_s": round(install_s, 1),
              "trials_s": round(time.perf_counter() - t_start, 1), "ran": len(rows),
              "passed": sum(r["pass"] for r in rows), "by_command": summary,
              "before_handlers": {"ran": len(early), "passed": sum(r["pass"] for r in early)},
              "after_handlers": {"ran": len(rows) - len(early), "passed": sum(r["pass"] for r in rows
                                                                               if not r["before_handlers"])},
              "handlers_at_s": {"min": min(at), "max": max(at)} if at else None,
              "failed": [f"{r['command']} {r['signal']} {r['delay_s']:g} s: {'; '.join(r['why'])}"
                         for r in rows if not r["pass"]],
              "exit_limit_s": EXIT_LIMIT_S, "trials": rows}, a.out, host=True)
    finally:
        if keep is None:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
