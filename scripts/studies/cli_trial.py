"""The trial of issue 18, as a new user would run it: bad inputs and faults against the CLI contract.

Each case runs the installed ``hawksim`` command in a fresh temporary directory (its working directory) and is
judged against the contract (hawksim/cli/__init__.py, docs/conventions.md): the expected exit status (2 a bad input,
1 the environment, 3 a numerical failure, 130 an interrupt, 0 success); on failure nothing on stdout and exactly one
line on stderr, naming the input, no traceback; no file left behind but those the case allows (a recording of the
steps flown, a data set's committed rows); and the case's own check (a recording that ``rerun rrd verify`` accepts,
rows intact, a bound on the seconds it takes). Faults: a full disk (RLIMIT_FSIZE with SIGXFSZ ignored, so writes
fail with EFBIG, as tests/hawksim/test_disk_full.py; or a full tmpfs, ENOSPC), a read-only file system (a tmpfs
mounted read-only), both in a private user and mount namespace (``unshare -rm``; those cases are skipped where it is
not allowed), Ctrl-C (SIGINT to the process group, as a terminal sends it) and SIGTERM at a delay, a second writer,
an unreachable scheduler.

Prints ONE JSON object: per case its name, exit status, stderr's line count, the files left, seconds, pass and the
reasons of a failure; and the count that behaves as the contract says.

    python scripts/studies/cli_trial.py [--only SUBSTRING ...] [--out results/cli/cli_trial.json]

Last run: results/cli/cli_trial.json (126 of 126 cases as the contract says, 2026-12-07 after issue 53's fixes,
the 108 earlier cases and issue 53's 18; two re-run alone and merged, their rows say why: "fly Ctrl-C controlled
rrd" took 5.2 s against its 5 s bound while a UVLM study shared the cores, and "reproduce Ctrl-C" now interrupts
at 3 s, since `reproduce --only uvlm_table4` finishes in ~5 s here, before the former 8 s). The run before:
108 of 108 (2026-12-02, load 5.4-6.2, 316 s of commands).
Issue 53's cases that this harness expresses (the "i53 " cases: non-regular output and input paths in the case's
directory, a crafted network's meta, NUMBA_NUM_THREADS, unbounded numbers, a dropped samples table, the options of
defect 14; since 2026-12-07 also defect 5: `dataset --samples 200000 --workers 1` over a copy of the shipped set,
Ctrl-C at 5 s, every shipped row intact, and `--samples 1000001`; defect 6: a numba cache in the case's directory
(NUMBA_CACHE_DIR), filled by a first `aero` run, its *.nbi files overwritten, then `aero`: exit 0 with the one
discard notice; defect 7: the shipped network with every tensor x 1e300, `predict`: exit 3; defect 8: `predict` and
`fly` with stdout's reader gone before the first write: exit 141, quiet (fly's own success summary aside), and
`predict` with stdout on /dev/full: exit 1, one line; 25 cases, not all 30 of the trial's failures):
`PYTHONPATH=. python scripts/studies/cli_trial.py --only "i53 " --out results/cli/cli_trial_issue53.json`,
25 of 25 as the contract says (2026-12-07, 18 s of commands; the 7 newer cases are not yet in the full run's
results/cli/cli_trial.json). Not expressed here (left to tests/hawksim/test_reliability.py, 2 and 4, and
test_disk_full.py, 3): a killed Dask scheduler (2: needs a real scheduler and workers started and killed
mid-run), a full disk under --kind flights (3: needs a 256 kB tmpfs sized to fill during the flights,
timing-dependent), two writers creating one file (4: needs one writer paused between creating the file and its
schema, which the CLI cannot be made to do from outside). Defect 8's `fly --cycles 300 --json | head -c 1` is
expressed as a reader that closed before the command started, which is deterministic; a reader that leaves after
one byte would depend on the pipe's buffer.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import os
import random
import resource
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from hawksim.jsonout import emit

BIN = Path(sys.executable).parent
HAWKSIM = str(BIN / "hawksim")
ROOT = Path(__file__).resolve().parents[2]
DATA = str(ROOT / "data" / "uvlm_training_0.3.sqlite")
NETWORK = str(ROOT / "hawksim" / "insects" / "hawkmoth" / "data" / "surrogates" / "uvlm_v1000.safetensors")
KIN = "f=26.1,beta=4.3,phi0=9.4,theta0=-2.8,alpha0=-0.4,phi_a=58.4,alpha_a=48.8"
TINY = ("--n-chord", "2", "--n-span", "3", "--steps-per-cycle", "20", "--cycles", "1")
FSIZE = 1 << 20
"""Bytes a file may reach in the full-disk cases (above numba's largest cache file, 126 kB)."""


@dataclass(frozen=True)
class Case:
    """One trial case. argv may hold {tmp} (the case's directory), {data} (the shipped training set) and {net} (a
    shipped network). code: the exit status the contract asks for; names: text the one stderr line must hold;
    left: files (relative to {tmp}) that may remain, must: files that must; setup(tmp) makes the inputs; fsize: the
    RLIMIT_FSIZE of a full disk; signal: (signal number, seconds after the start); mount: 'full' or 'ro' runs the
    command in {tmp}/mnt, a tmpfs that is full or read-only; rival: argv of a first writer started before this one;
    check(tmp, result) returns the reason of a failure or None; max_s bounds the seconds (from the signal, if any);
    logs: the beginnings of the progress lines a command prints on stderr before its failure (not counted: the
    failure itself is the one line left); env: variables set for the command (values may hold {tmp}); left may
    hold shell patterns (``cache/*``); stdout: 'closed' runs the command with its stdout's reader gone (a pipe
    whose read end is closed before the command starts: EPIPE on the first write; the contract asks a quiet exit,
    no stderr line) or 'full' with stdout on /dev/full (ENOSPC: one line)."""

    name: str
    argv: tuple
    code: int
    names: str = ""
    left: tuple = ()
    must: tuple = ()
    setup: Callable | None = None
    fsize: int | None = None
    signal: tuple | None = None
    mount: str | None = None
    rival: tuple | None = None
    check: Callable | None = None
    max_s: float | None = None
    env: tuple = ()
    pty: bool = False
    logs: tuple = ()
    stdout: str | None = None


@dataclass(frozen=True)
class Result:
    code: int
    stdout: str
    stderr: str
    files: tuple
    seconds: float


# ---------------------------------------------------------------------------------------------- inputs and checks
def _write(name: str, content: bytes | None):
    def setup(tmp: Path) -> None:
        p = tmp / name
        p.parent.mkdir(parents=True, exist_ok=True)
        if content is None:
            p.mkdir()
        else:
            p.write_bytes(content)
    return setup


def _copy(src: str, name: str):
    return lambda tmp: shutil.copy(src, tmp / name)


def _fifo(name: str):
    return lambda tmp: os.mkfifo(tmp / name)


def _network_meta(name: str, meta: str):
    """A copy of the shipped network whose ``meta`` is ``meta`` (issue 53, defect 7: a JSON list or string)."""
    def setup(tmp: Path) -> None:
        from safetensors import safe_open
        from safetensors.numpy import save_file

        with safe_open(NETWORK, "np") as f:
            tensors = {k: f.get_tensor(k) for k in f.keys()}
            header = dict(f.metadata())
        header["meta"] = meta
        save_file(tensors, str(tmp / name), metadata=header)
    return setup


def _dropped_samples(tmp: Path) -> None:
    """A data set whose samples table was dropped (issue 53, defect 12)."""
    _dataset_with_rows(tmp, 1)
    with sqlite3.connect(tmp / "d.sqlite") as c:
        c.execute("DROP TABLE samples")


def _verify_rrd(name: str):
    def check(tmp: Path, r: Result):
        p = subprocess.run([str(BIN / "rerun"), "rrd", "verify", str(tmp / name)], capture_output=True, text=True)
        return None if p.returncode == 0 else f"rrd verify: {p.stderr.strip()[-200:]}"
    return check


def _dataset_with_rows(tmp: Path, rows: int = 1000) -> None:
    """A data set of stand-in rows (speed 1, seed 99), written directly: the file a full disk must not spoil."""
    from hawksim.backends.resolution import Resolution
    from hawksim.surrogate.dataset import Sample, insert_sample, open_dataset

    res = Resolution(n_chord=2, n_span=3, steps_per_cycle=20, cycles=1)
    conn = open_dataset(tmp / "d.sqlite", create=True)
    conn.execute("PRAGMA synchronous=OFF")
    for i in range(rows):
        insert_sample(conn, Sample(1.0, 99, i, (26.0, 0.1, 0.2, 0.0, 0.0, 1.0, 0.8), (1.0, 0.1, 0.0, 0.9), 0.08, 0.5,
                                   peak_cf=1.5, y_prev=(1.0, 0.1, 0.0, 0.9)), res)
    conn.close()


def _rows_intact(rows: int = 1000):
    def check(tmp: Path, r: Result):
        with sqlite3.connect(tmp / "d.sqlite") as c:
            ok = c.execute("PRAGMA integrity_check").fetchone()[0]
            n = c.execute("SELECT count(*) FROM samples WHERE seed=99").fetchone()[0]
        return None if ok == "ok" and n == rows else f"integrity {ok}, {n} of {rows} rows"
    return check


def _rows_committed(tmp: Path, r: Result):
    if not (tmp / "d.sqlite").exists():
        return None
    with sqlite3.connect(tmp / "d.sqlite") as c:
        n = c.execute("SELECT count(*) FROM samples").fetchone()[0]
    return None if n > 0 else "an empty data set was left"


def _json(test: Callable[[dict], str | None]):
    def check(tmp: Path, r: Result):
        try:
            return test(json.loads(r.stdout))
        except (ValueError, KeyError, TypeError) as exc:
            return f"JSON: {exc!r}"
    return check


def _departed_without_roll(out: dict):
    if out["departed_at_beat"] is None:
        return "an open-loop flight of 30 beats did not depart"
    return None if abs(out["max_abs_roll_deg"]) < 1.0 else f"max_abs_roll_deg {out['max_abs_roll_deg']:.3g}"


def _human(*needles: str):
    def check(tmp: Path, r: Result):
        if "{" in r.stdout:
            return "raw dict in the human-readable output"
        missing = [n for n in needles if n not in r.stdout]
        return f"missing {missing}" if missing else None
    return check


def _bar_shows(text: str):
    def check(tmp: Path, r: Result):
        return None if text in r.stderr else f"the bar did not show {text!r} before the Ctrl-C"
    return check


def _network_scaled(name: str, factor: float):
    """A copy of the shipped network with every tensor times ``factor`` (issue 53, defect 7: finite weights x 1e300,
    whose outputs overflow to infinity)."""
    def setup(tmp: Path) -> None:
        from safetensors import safe_open
        from safetensors.numpy import save_file

        with safe_open(NETWORK, "np") as f:
            tensors = {k: f.get_tensor(k) * factor for k in f.keys()}
            header = dict(f.metadata())
        save_file(tensors, str(tmp / name), metadata=header)
    return setup


def _corrupt_numba_cache(argv: tuple):
    """A numba cache in {tmp}/cache, filled by running ``argv`` once, then its ``*.nbi`` index files overwritten
    with 300 fixed pseudo-random bytes (issue 53, defect 6)."""
    def setup(tmp: Path) -> None:
        env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp / "cache")}
        subprocess.run([HAWKSIM, *argv], cwd=tmp, env=env, capture_output=True, check=True, timeout=120)
        index = sorted((tmp / "cache").rglob("*.nbi"))
        if not index:
            raise RuntimeError("the cache holds no .nbi file")
        rng = random.Random(53)
        for path in index:
            path.write_bytes(rng.randbytes(300))
    return setup


def _discard_notice(tmp: Path, r: Result):
    """Exit 0 with a result, and exactly one stderr line: the notice that a corrupt cache entry was discarded."""
    lines = r.stderr.strip().splitlines()
    if len(lines) != 1 or not lines[0].startswith("hawksim: discarded a corrupt numba cache entry"):
        return f"{len(lines)} stderr lines, not the one discard notice: {r.stderr.strip()[-200:]!r}"
    try:
        json.loads(r.stdout)
    except ValueError as exc:
        return f"JSON: {exc!r}"
    return None


def _shipped_rows_intact(name: str):
    """Every row of the shipped training set is still in the copy ``name``, which passes sqlite's integrity check
    (issue 53, defect 5: an interrupted run over a copy of it)."""
    def check(tmp: Path, r: Result):
        with sqlite3.connect(tmp / name) as c:
            ok = c.execute("PRAGMA integrity_check").fetchone()[0]
            c.execute("ATTACH DATABASE ? AS shipped", (DATA,))  # read only: nothing is written to it
            lost = c.execute("SELECT count(*) FROM (SELECT * FROM shipped.samples EXCEPT "
                             "SELECT * FROM main.samples)").fetchone()[0]
        return None if ok == "ok" and lost == 0 else f"integrity {ok}, {lost} shipped rows lost or changed"
    return check


# ---------------------------------------------------------------------------------------------- the cases
def cases() -> list[Case]:
    fly = ("fly", "--speed", "1", "--cycles", "2")
    ds = ("dataset", "--speed", "1", "--samples", "400", "--out", "d.sqlite", "--workers", "2", "--json",
          "--no-progress")
    xml = b"<mujoco><worldbody></mujoco>"
    step_files = ("--data", "{tmp}/f.sqlite", "--out", "n.safetensors")  # (after the bad option: parsed first)
    aero1 = ("aero", "--speed", "1", "--kinematics", KIN, "--cycles", "1", "--json", "--no-progress")
    out = [
        # fly: bad values, resource limits, files
        Case("fly speed negative", ("fly", "--speed", "-1", "--cycles", "2"), 2, "--speed"),
        Case("fly speed nan", ("fly", "--speed", "nan", "--cycles", "2"), 2, "--speed"),
        Case("fly speed above range", ("fly", "--speed", "3", "--cycles", "2"), 2, "--speed"),
        Case("fly cycles 0", ("fly", "--speed", "1", "--cycles", "0"), 2, "--cycles"),
        Case("fly cycles 1.5", ("fly", "--speed", "1", "--cycles", "1.5"), 2, "--cycles"),
        Case("fly cycles 1e9", ("fly", "--speed", "1", "--cycles", "1e9"), 2, "--cycles", max_s=10),
        Case("fly steps-per-cycle 1e8", (*fly, "--steps-per-cycle", "100000000"), 2, "--steps-per-cycle", max_s=10),
        Case("fly steps-per-cycle 3", (*fly, "--steps-per-cycle", "3"), 2, "--steps-per-cycle"),
        Case("fly kinematics f out of Table 2", (*fly, "--kinematics", KIN.replace("f=26.1", "f=50")), 2, "f"),
        Case("fly kinematics unknown key", (*fly, "--kinematics", KIN + ",gamma=3"), 2, "gamma"),
        Case("fly kinematics not a number", (*fly, "--kinematics", KIN.replace("alpha_a=48.8", "alpha_a=x")), 2,
             "alpha_a"),
        Case("fly kinematics nan", (*fly, "--kinematics", KIN.replace("f=26.1", "f=nan")), 2, "--kinematics"),
        Case("fly model missing", (*fly, "--model", "/nonexistent/h.xml"), 2, "/nonexistent/h.xml"),
        Case("fly model empty file", (*fly, "--model", "{tmp}/m.xml"), 2, "m.xml", left=("m.xml",),
             setup=_write("m.xml", b"")),
        Case("fly model a directory", (*fly, "--model", "{tmp}/m.xml"), 2, "m.xml", left=("m.xml",),
             setup=_write("m.xml", None)),
        Case("fly model a safetensors file", (*fly, "--model", "{tmp}/m.safetensors"), 2, "m.safetensors",
             left=("m.safetensors",), setup=_copy(NETWORK, "m.safetensors")),
        Case("fly model a pickle", (*fly, "--model", "{tmp}/m.pkl"), 2, "m.pkl", left=("m.pkl",),
             setup=_write("m.pkl", b"\x80\x04\x95\x05\x00\x00\x00\x00\x00\x00\x00K\x01.")),
        Case("fly model broken MJCF", (*fly, "--model", "{tmp}/m.xml"), 2, "m.xml", left=("m.xml",),
             setup=_write("m.xml", xml)),
        Case("fly perturb unknown", (*fly, "--perturb", "zz=1"), 2, "zz"),
        Case("fly perturb twice", (*fly, "--perturb", "u=1", "--perturb", "u=2"), 2, "--perturb"),
        Case("fly perturb nan", (*fly, "--perturb", "u=nan"), 2, "--perturb"),
        Case("fly rrd empty name", (*fly, "--rrd", ""), 2, "--rrd"),
        Case("fly rrd missing directory", (*fly, "--rrd", "/nonexistent/dir/o.rrd"), 2, "o.rrd"),
        Case("fly rrd a directory", (*fly, "--rrd", "{tmp}/r"), 2, "--rrd", left=("r",), setup=_write("r", None)),
        Case("fly aero unknown", (*fly, "--aero", "cfd"), 2, "--aero"),
        Case("fly gust malformed", (*fly, "--gust", "1,2@3"), 2, "--gust"),
        Case("fly ascent-profile zero beats", (*fly, "--ascent-profile", "1:0"), 2, "--ascent-profile"),
        Case("fly sensing-delay negative", (*fly, "--sensing-delay", "-1"), 2, "--sensing-delay"),
        Case("fly control lqr with uvlm off its schedule", ("fly", "--speed", "0.5", "--cycles", "2", "--aero", "uvlm",
                                                           "--control", "lqr"), 2, "--speed 0.5"),
        # fly: numerical failure, honest results, human output
        Case("fly perturb q=1e9 blows up", (*fly, "--perturb", "q=1e9", "--json", "--no-progress"), 3, "BADQACC"),
        Case("fly open loop departs without roll", ("fly", "--speed", "1", "--cycles", "30", "--control", "none",
                                                   "--json", "--no-progress"), 0,
             check=_json(_departed_without_roll)),
        Case("fly human-readable output", (*fly, "--no-progress"), 0, check=_human("m/s", "vertical speed")),
        # fly: full disk, interrupts
        Case("fly uvlm rrd full disk", (*fly, "--aero", "uvlm", "--rrd", "f.rrd", "--no-progress"), 1, "f.rrd",
             fsize=FSIZE),
        Case("fly lqr rrd full disk", ("fly", "--speed", "1", "--cycles", "12", "--rrd", "f.rrd", "--no-progress"),
             1, "f.rrd", fsize=FSIZE),
        Case("fly open-loop rrd full disk", ("fly", "--speed", "1", "--cycles", "12", "--control", "none", "--rrd",
                                             "f.rrd", "--no-progress"), 1, "f.rrd", fsize=FSIZE),
        Case("fly rrd on a full tmpfs", (*fly, "--rrd", "mnt/f.rrd", "--no-progress"), 1, "f.rrd", mount="full"),
        Case("fly Ctrl-C open loop rrd", ("fly", "--speed", "1", "--cycles", "2000", "--control", "none", "--rrd",
                                          "f.rrd", "--no-progress"), 130, must=("f.rrd",), left=("f.rrd",),
             signal=(signal.SIGINT, 5.0), check=_verify_rrd("f.rrd"), max_s=5),
        Case("fly Ctrl-C controlled rrd", ("fly", "--speed", "1", "--cycles", "2000", "--rrd", "f.rrd",
                                           "--no-progress"), 130, must=("f.rrd",), left=("f.rrd",),
             signal=(signal.SIGINT, 20.0), check=_verify_rrd("f.rrd"), max_s=5),
        Case("fly SIGTERM controlled rrd", ("fly", "--speed", "1", "--cycles", "2000", "--rrd", "f.rrd",
                                            "--no-progress"), 130, must=("f.rrd",), left=("f.rrd",),
             signal=(signal.SIGTERM, 20.0), check=_verify_rrd("f.rrd"), max_s=5),
        Case("fly SIGTERM before the flight", ("fly", "--speed", "1", "--cycles", "2000", "--rrd", "f.rrd",
                                               "--no-progress"), 130, signal=(signal.SIGTERM, 1.0), max_s=3),
        Case("fly Ctrl-C without rrd", ("fly", "--speed", "1", "--cycles", "2000", "--no-progress"), 130,
             signal=(signal.SIGINT, 4.0), max_s=3),
        # aero
        Case("aero cycles 1e9", ("aero", "--speed", "0", "--kinematics", KIN, "--cycles", "1000000000"), 2,
             "--cycles", max_s=10),
        Case("aero n-chord 1e6", ("aero", "--speed", "0", "--kinematics", KIN, "--n-chord", "1000000"), 2,
             "--n-chord", max_s=10),
        Case("aero n-span 0", ("aero", "--speed", "0", "--kinematics", KIN, "--n-span", "0"), 2, "--n-span"),
        Case("aero kinematics nan", ("aero", "--speed", "0", "--kinematics", KIN.replace("f=26.1", "f=nan")), 2,
             "--kinematics"),
        Case("aero kinematics missing", ("aero", "--speed", "0"), 2, "--kinematics"),
        Case("aero Ctrl-C", ("aero", "--speed", "0", "--kinematics", KIN, "--cycles", "20", "--no-progress"), 130,
             signal=(signal.SIGINT, 3.0), max_s=3),
        # stability
        Case("stability speed 5", ("stability", "--speed", "5"), 2, "--speed"),
        Case("stability workers 0", ("stability", "--speed", "1", "--workers", "0"), 2, "--workers"),
        Case("stability unreachable scheduler", ("stability", "--speed", "1", "--scheduler", "tcp://127.0.0.1:1",
                                                 "--no-progress"), 1, "tcp://127.0.0.1:1", max_s=20),
        Case("stability Ctrl-C in the start-up", ("stability", "--speed", "1", "--workers", "2", "--no-progress"),
             130, signal=(signal.SIGINT, 2.5), max_s=3),
        Case("stability Ctrl-C while computing", ("stability", "--speed", "1", "--workers", "2", "--no-progress"),
             130, signal=(signal.SIGINT, 9.0), max_s=3),
        Case("stability has a progress bar", ("stability", "--speed", "1", "--workers", "2"), 130,
             signal=(signal.SIGINT, 12.0), pty=True, check=_bar_shows("disturbed UVLM runs"), max_s=3),
        Case("stability SIGTERM", ("stability", "--speed", "1", "--workers", "2", "--no-progress"), 130,
             signal=(signal.SIGTERM, 4.0), max_s=3),
        # dataset
        Case("dataset seed 2^70", (*ds, "--seed", "1180591620717411303424"), 2, "--seed"),
        Case("dataset seed negative", (*ds, "--seed", "-1"), 2, "--seed"),
        Case("dataset samples 0", ("dataset", "--speed", "1", "--samples", "0", "--out", "d.sqlite"), 2,
             "--samples"),
        Case("dataset workers 0", (*ds, "--workers", "0"), 2, "--workers"),
        Case("dataset out a directory", ("dataset", "--speed", "1", "--samples", "2", "--out", "{tmp}/r"), 2, "r",
             left=("r",), setup=_write("r", None)),
        Case("dataset out missing directory", ("dataset", "--speed", "1", "--samples", "2", "--out",
                                               "/nonexistent/d.sqlite"), 2, "d.sqlite"),
        Case("dataset out a foreign file", ("dataset", "--speed", "1", "--samples", "2", "--out", "d.sqlite",
                                            "--workers", "1", "--no-progress"), 2, "d.sqlite", left=("d.sqlite",),
             setup=_write("d.sqlite", b"not a data set\n"),
             check=lambda tmp, r: None if (tmp / "d.sqlite").read_bytes() == b"not a data set\n" else "file changed"),
        Case("dataset unreachable scheduler", (*ds, "--scheduler", "tcp://127.0.0.1:1"), 1, "tcp://127.0.0.1:1",
             max_s=20),
        Case("dataset second writer", (*ds, "--workers", "1"), 2, "another hawksim dataset", left=("d.sqlite",),
             rival=ds),
        Case("dataset full disk, new file", (*ds, "--workers", "1", *TINY), 1, "d.sqlite", fsize=4096),
        Case("dataset full disk, existing file", (*ds, "--workers", "1", *TINY), 1, "d.sqlite", left=("d.sqlite",),
             setup=_dataset_with_rows, fsize=-1, check=_rows_intact()),
        Case("dataset on a full tmpfs", ("dataset", "--speed", "1", "--samples", "400", "--out", "mnt/d.sqlite",
                                         "--workers", "1", "--json", "--no-progress", *TINY), 1, "d.sqlite",
             mount="full"),
        Case("dataset on a read-only file system", ("dataset", "--speed", "1", "--samples", "2", "--out",
                                                    "mnt/d.sqlite"), 2, "d.sqlite", mount="ro"),
        *[Case(f"dataset Ctrl-C at {d:g} s", ds, 130, left=("d.sqlite",), signal=(signal.SIGINT, d),
               check=_rows_committed, max_s=3) for d in (0.3, 1.5, 3.0, 6.0)],
        Case("dataset SIGTERM at 2 s", ds, 130, left=("d.sqlite",), signal=(signal.SIGTERM, 2.0),
             check=_rows_committed, max_s=3),
        # train
        Case("train data missing", ("train", "--data", "none.sqlite", "--out", "m.safetensors"), 2, "none.sqlite"),
        Case("train data a foreign file", ("train", "--data", "d.sqlite", "--out", "m.safetensors"), 2, "d.sqlite",
             left=("d.sqlite",), setup=_write("d.sqlite", b"not a data set\n")),
        Case("train data empty", ("train", "--data", "d.sqlite", "--out", "m.safetensors"), 2, "d.sqlite",
             left=("d.sqlite",), setup=_write("d.sqlite", b"")),
        Case("train speed with all-speeds", ("train", "--data", "{data}", "--out", "m.safetensors", "--speed", "1",
                                             "--all-speeds"), 2, "--all-speeds"),
        Case("train speed not in the data", ("train", "--data", "{data}", "--out", "m.safetensors", "--speed",
                                             "0.3"), 2, "--speed"),
        Case("train out missing directory", ("train", "--data", "{data}", "--out", "/nonexistent/m.safetensors"),
             2, "m.safetensors"),
        Case("train hidden 0", ("train", "--data", "{data}", "--out", "m.safetensors", "--hidden", "0"), 2,
             "--hidden"),
        Case("train out full disk", ("train", "--data", "d.sqlite", "--out", "m.safetensors", "--speed", "1",
                                     "--hidden", "300", "--max-iter", "1", "--no-progress"), 1, "m.safetensors",
             left=("d.sqlite",), setup=_copy(DATA, "d.sqlite"), fsize=16000),
        Case("train validation-png full disk", ("train", "--data", "d.sqlite", "--out", "m.safetensors", "--speed",
                                                "1", "--hidden", "300", "--max-iter", "1", "--validation-png",
                                                "v.png", "--no-progress"), 1, "v.p",
             left=("d.sqlite", "m.safetensors", "v.pdf"), setup=_copy(DATA, "d.sqlite"), fsize=60000),
        Case("train data on a read-only file system", ("train", "--data", "mnt/d.sqlite", "--out", "m.safetensors",
                                                       "--speed", "1", "--hidden", "300", "--max-iter", "1",
                                                       "--no-progress"), 0, left=("m.safetensors",), mount="ro-data"),
        Case("train Ctrl-C", ("train", "--data", "{data}", "--out", "m.safetensors", "--speed", "1",
                              "--no-progress"), 130, signal=(signal.SIGINT, 8.0), max_s=10),
        Case("train bar shows its stage", ("train", "--data", "{data}", "--out", "m.safetensors", "--speed", "1"),
             130, signal=(signal.SIGINT, 6.0), pty=True, check=_bar_shows("stage="), max_s=10),
        # predict
        Case("predict kinematics bad", ("predict", "--speed", "1", "--kinematics", "f=1"), 2, "--kinematics"),
        Case("predict speed 3", ("predict", "--speed", "3", "--kinematics", KIN), 2, "--speed"),
        Case("predict model missing", ("predict", "--speed", "1", "--kinematics", KIN, "--model", "none.st"), 2,
             "none.st"),
        Case("predict model a text file", ("predict", "--speed", "1", "--kinematics", KIN, "--model", "m.st"), 2,
             "m.st", left=("m.st",), setup=_write("m.st", b"hello\n")),
        Case("predict human-readable output", ("predict", "--speed", "1", "--kinematics", KIN), 0,
             check=_human("L_plus", "P_plus")),
        # trim
        Case("trim population 1e9", ("trim", "--speed", "1", "--population", "1000000000"), 2, "--population"),
        Case("trim population 1.5", ("trim", "--speed", "1", "--population", "1.5"), 2, "--population"),
        Case("trim population 1e5 as its help writes it", ("trim", "--population", "1e5", "--speed", "3"), 2,
             "--speed"),
        Case("trim seed negative", ("trim", "--speed", "1", "--seed", "-1"), 2, "--seed"),
        Case("trim model missing", ("trim", "--speed", "1", "--model", "none.st"), 2, "none.st"),
        Case("trim free-flight aero unknown", ("trim", "--speed", "1", "--free-flight", "--aero", "cfd"), 2,
             "--aero"),
        Case("trim Ctrl-C", ("trim", "--speed", "1", "--no-progress"), 130, signal=(signal.SIGINT, 4.0), max_s=3),
        # reproduce
        Case("reproduce out missing parent", ("reproduce", "--out", "/nonexistent/r"), 2, "--out",
             check=lambda tmp, r: "created /nonexistent" if os.path.exists("/nonexistent") else None),
        Case("reproduce out a file", ("reproduce", "--out", "a_file"), 2, "--out", left=("a_file",),
             setup=_write("a_file", b"x")),
        Case("reproduce out not empty", ("reproduce", "--out", "full"), 2, "--force", left=("full", "full/old.json"),
             setup=_write("full/old.json", b"{}")),
        Case("reproduce default results not empty", ("reproduce",), 2, "--force",
             left=("results", "results/old.json"), setup=_write("results/old.json", b"{}")),
        Case("reproduce on a read-only file system", ("reproduce", "--out", "mnt/r"), 2, "--out", mount="ro"),
        Case("reproduce on a full tmpfs", ("reproduce", "--only", "uvlm_table4", "--out", "mnt/r"), 1,
             "uvlm_table4.json", mount="full", logs=("hawksim reproduce:", "uvlm_table4 ...")),
        Case("reproduce on a full tmpfs, existing results", ("reproduce", "--only", "uvlm_table4", "--out", "mnt/r",
                                                              "--force"), 1, "uvlm_table4.json", mount="full-keep",
             logs=("hawksim reproduce:", "uvlm_table4 ...")),
        Case("reproduce Ctrl-C", ("reproduce", "--only", "uvlm_table4", "--out", "r"), 130,
             signal=(signal.SIGINT, 3.0), max_s=3, logs=("hawksim reproduce:", "uvlm_table4 ...")),
        Case("reproduce only unknown", ("reproduce", "--only", "figure99"), 2, "--only"),
        # issue 53 (defects 1, 7, 9-14), the cases this harness can express: paths in {tmp}, never the real /dev
        Case("i53 fly rrd a FIFO", ("fly", "--speed", "1", "--cycles", "1", "--rrd", "{tmp}/p"), 2, "FIFO",
             setup=_fifo("p"), left=("p",), max_s=30),
        Case("i53 fly rrd a directory", ("fly", "--speed", "1", "--cycles", "1", "--rrd", "{tmp}/d"), 2, "directory",
             setup=_write("d", None), left=("d",)),
        Case("i53 predict model a FIFO", ("predict", "--speed", "1", "--kinematics", KIN, "--model", "{tmp}/p"), 2,
             "FIFO", setup=_fifo("p"), left=("p",), max_s=30),
        Case("i53 predict model meta a list", ("predict", "--speed", "1", "--kinematics", KIN, "--model",
                                               "{tmp}/n.safetensors"), 2, "JSON array",
             setup=_network_meta("n.safetensors", "[1, 2]"), left=("n.safetensors",)),
        Case("i53 NUMBA_NUM_THREADS 0", ("fly", "--speed", "1", "--cycles", "1"), 2, "NUMBA_NUM_THREADS",
             env=(("NUMBA_NUM_THREADS", "0"),)),
        Case("i53 NUMBA_NUM_THREADS abc", ("fly", "--speed", "1", "--cycles", "1"), 2, "NUMBA_NUM_THREADS",
             env=(("NUMBA_NUM_THREADS", "abc"),)),
        Case("i53 fly sensing-delay 1e9", ("fly", "--speed", "1", "--cycles", "1", "--control", "lqr",
                                           "--sensing-delay", "1000000000"), 2, "--sensing-delay"),
        Case("i53 train step weight-decay inf", ("train", "--kind", "step", "--weight-decay", "inf", *step_files), 2,
             "--weight-decay"),
        Case("i53 train step lags 1e308", ("train", "--kind", "step", "--lags", "1e308", *step_files), 2, "--lags"),
        Case("i53 train step layers 200000", ("train", "--kind", "step", "--layers", "200000,200000", *step_files),
             2, "--layers"),
        Case("i53 dataset samples table dropped", ds, 2, "samples table",
             setup=_dropped_samples, left=("d.sqlite",)),
        Case("i53 dataset samples 2e6", ("dataset", "--speed", "1", "--samples", "2000000", "--out", "d.sqlite"), 2,
             "--samples"),
        Case("i53 dataset flights with --speed", ("dataset", "--kind", "flights", "--speed", "1", "--samples", "2",
                                                  "--out", "d.sqlite"), 2, "--speed"),
        Case("i53 dataset flights with --n-chord", ("dataset", "--kind", "flights", "--n-chord", "4", "--samples",
                                                    "2", "--out", "d.sqlite"), 2, "--n-chord"),
        Case("i53 trim free-flight with --model", ("trim", "--speed", "1", "--free-flight", "--model", "{net}"), 2,
             "--model"),
        Case("i53 trim free-flight with --population", ("trim", "--speed", "1", "--free-flight", "--population",
                                                        "10"), 2, "--population"),
        Case("i53 fly sensing-delay with control none", ("fly", "--speed", "1", "--cycles", "1", "--control", "none",
                                                         "--sensing-delay", "1"), 2, "--sensing-delay"),
        Case("i53 dataset samples 200000 over the shipped set, Ctrl-C", ("dataset", "--speed", "1", "--samples",
             "200000", "--workers", "1", "--out", "x.sqlite", "--no-progress"), 130, setup=_copy(DATA, "x.sqlite"),
             left=("x.sqlite",), signal=(signal.SIGINT, 5.0), check=_shipped_rows_intact("x.sqlite"), max_s=3),
        Case("i53 dataset samples 1000001", ("dataset", "--speed", "1", "--samples", "1000001", "--out", "d.sqlite"),
             2, "--samples"),
        Case("i53 predict network weights x 1e300", ("predict", "--speed", "1", "--kinematics", KIN, "--model",
                                                     "{tmp}/n.safetensors", "--json"), 3, "n.safetensors",
             setup=_network_scaled("n.safetensors", 1e300), left=("n.safetensors",)),
        Case("i53 aero corrupt numba cache", aero1, 0, env=(("NUMBA_CACHE_DIR", "{tmp}/cache"),),
             setup=_corrupt_numba_cache(aero1), left=("cache", "cache/*"), check=_discard_notice, max_s=30),
        Case("i53 predict stdout reader gone", ("predict", "--speed", "1", "--kinematics", KIN, "--json"), 141,
             stdout="closed"),
        Case("i53 fly stdout reader gone", ("fly", "--speed", "1", "--cycles", "1", "--json", "--no-progress"), 141,
             stdout="closed", logs=("fly: held under",)),  # (its summary line on success, not the failure's)
        Case("i53 predict stdout /dev/full", ("predict", "--speed", "1", "--kinematics", KIN, "--json"), 1,
             "stdout", stdout="full"),
        Case("i53 aero steps-per-cycle 1e9", ("aero", "--speed", "1", "--kinematics", KIN, "--steps-per-cycle",
                                              "1000000000"), 2, "--steps-per-cycle", max_s=10),
        # the command itself
        Case("no subcommand", (), 2, "command"),
        Case("unknown subcommand", ("fry",), 2, "fry"),
        Case("bad HAWKSIM_VECTOR_WIDTH", ("predict", "--speed", "1", "--kinematics", KIN), 2,
             "HAWKSIM_VECTOR_WIDTH", env=(("HAWKSIM_VECTOR_WIDTH", "3"),)),
    ]
    return out


# ---------------------------------------------------------------------------------------------- running
def _files(tmp: Path) -> tuple:
    return tuple(sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*")))


def _argv(case: Case, tmp: Path) -> list[str]:
    return [a.replace("{tmp}", str(tmp)).replace("{data}", DATA).replace("{net}", NETWORK) for a in case.argv]


def _preexec(fsize: int | None):
    def pre():
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        if fsize is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    return pre


def _run_plain(case: Case, tmp: Path) -> Result:
    env = {**os.environ, **{k: v.replace("{tmp}", str(tmp)) for k, v in case.env}}
    fsize = case.fsize
    if fsize == -1:  # no room to grow: the limit is the existing data set's size
        fsize = (tmp / "d.sqlite").stat().st_size
    rival = None
    if case.rival:
        rival = subprocess.Popen([HAWKSIM, *case.rival], cwd=tmp, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL, start_new_session=True, preexec_fn=_preexec(None))
        deadline = time.time() + 30
        while time.time() < deadline and not (tmp / "d.sqlite").exists():
            time.sleep(0.2)
        time.sleep(0.5)
    master = None
    stderr = subprocess.PIPE
    if case.pty:
        import fcntl
        import struct
        import termios

        master, slave = os.openpty()
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 200, 0, 0))
        stderr = slave
    stdout, gone = subprocess.PIPE, None
    if case.stdout == "closed":  # the reader has gone before the command writes: EPIPE
        gone, stdout = os.pipe()
        os.close(gone)
    elif case.stdout == "full":
        stdout = os.open("/dev/full", os.O_WRONLY)
    t0 = time.perf_counter()
    p = subprocess.Popen([HAWKSIM, *_argv(case, tmp)], cwd=tmp, env=env, stdout=stdout, stderr=stderr,
                         stdin=subprocess.DEVNULL, start_new_session=True, preexec_fn=_preexec(fsize))
    if case.stdout:
        os.close(stdout)
    err_pty = b""
    if case.pty:
        os.close(stderr)
    if case.signal:
        signum, delay = case.signal
        end = t0 + delay
        while time.perf_counter() < end and p.poll() is None:
            err_pty += _drain(master, 0.1) if master is not None else b""
            time.sleep(0.0 if master is not None else 0.05)
        t0 = time.perf_counter()
        if p.poll() is None:
            os.killpg(p.pid, signum)
    while master is not None and p.poll() is None:
        err_pty += _drain(master, 0.2)
    try:
        out, err = p.communicate(timeout=600)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
    seconds = time.perf_counter() - t0
    if master is not None:
        err_pty += _drain(master, 0.2)
        os.close(master)
        err = err_pty.replace(b"\r", b"\n")
    if rival is not None:
        os.killpg(rival.pid, signal.SIGINT)
        rival.wait(60)
    return Result(p.returncode, (out or b"").decode(errors="replace"), (err or b"").decode(errors="replace"),
                  _files(tmp), seconds)


def _drain(fd: int, timeout: float) -> bytes:
    import select

    got = b""
    while select.select([fd], [], [], timeout)[0]:
        try:
            chunk = os.read(fd, 65536)
        except OSError:
            break
        if not chunk:
            break
        got += chunk
        timeout = 0.0
    return got


_INNER = r"""
import json, os, shutil, subprocess, sys, time
mnt, how, argv, cwd, data = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), sys.argv[4], sys.argv[5]
opts = {"full": "size=1m", "full-keep": "size=1m", "ro": "ro,size=1m", "ro-data": "size=16m"}[how]
subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", mnt], check=True)
if how == "ro-data":  # the shipped data set on a read-only disk
    shutil.copy(data, os.path.join(mnt, "d.sqlite"))
    subprocess.run(["mount", "-o", "remount,ro", mnt], check=True)
if how == "full-keep":  # an earlier result, which a failed rerun must leave as it was
    os.makedirs(os.path.join(mnt, "r"))
    with open(os.path.join(mnt, "r", "uvlm_table4.json"), "w") as fh:
        fh.write('{"old": 1}')
if how in ("full", "full-keep"):
    try:
        with open(os.path.join(mnt, "filler"), "wb") as fh:
            while True:
                fh.write(b"x" * 4096)
                fh.flush()
    except OSError:
        pass
t0 = time.perf_counter()
p = subprocess.run(argv, cwd=cwd, capture_output=True, text=True)
files = sorted(os.path.relpath(os.path.join(d, f), cwd) for d, ds, fs in os.walk(cwd) for f in ds + fs)
files = [f for f in files if f != os.path.join("mnt", "filler")]
kept = None
if how == "full-keep":
    with open(os.path.join(mnt, "r", "uvlm_table4.json")) as fh:
        kept = fh.read()
print(json.dumps({"code": p.returncode, "stdout": p.stdout, "stderr": p.stderr, "files": files,
                  "seconds": time.perf_counter() - t0, "kept": kept}))
"""


def namespaces() -> bool:
    return shutil.which("unshare") is not None and subprocess.run(["unshare", "-rm", "true"],
                                                                  capture_output=True).returncode == 0


def _run_mounted(case: Case, tmp: Path) -> Result:
    (tmp / "mnt").mkdir()
    p = subprocess.run(["unshare", "-rm", sys.executable, "-c", _INNER, str(tmp / "mnt"), case.mount,
                        json.dumps([HAWKSIM, *_argv(case, tmp)]), str(tmp), DATA], capture_output=True, text=True)
    r = json.loads(p.stdout)
    files = tuple(f for f in r["files"] if f != "mnt")
    if case.mount == "ro-data":
        files = tuple(f for f in files if f != os.path.join("mnt", "d.sqlite"))
    if case.mount == "full-keep":  # the earlier result stays, as it was
        kept = ("mnt/r", "mnt/r/uvlm_table4.json")
        files = tuple(f for f in files if f not in kept) + (() if r["kept"] == '{"old": 1}' else ("CHANGED r",))
    return Result(r["code"], r["stdout"], r["stderr"], files, r["seconds"])


def judge(case: Case, r: Result, tmp: Path) -> list[str]:
    """The ways ``r`` breaks the contract for ``case`` (empty: it behaves)."""
    why = []
    lines = [ln for ln in r.stderr.strip().splitlines() if not (case.logs and ln.startswith(case.logs))]
    if r.code != case.code:
        why.append(f"exit {r.code}, not {case.code}")
    if "Traceback" in r.stderr:
        why.append("a traceback")
    if case.code != 0 and not case.pty:
        if r.stdout:
            why.append("output on stdout")
        if case.stdout == "closed":  # a reader that has gone: a quiet exit, like a Unix tool
            if lines:
                why.append(f"{len(lines)} stderr lines, not 0")
        elif len(lines) != 1:
            why.append(f"{len(lines)} stderr lines, not 1")
        elif case.names and case.names not in lines[0]:
            why.append(f"the line does not name {case.names!r}")
    left = [f for f in r.files if not any(fnmatch.fnmatchcase(f, pattern) for pattern in case.left)]
    if left:
        why.append(f"left {left}")
    missing = [f for f in case.must if f not in r.files]
    if missing:
        why.append(f"did not write {missing}")
    if case.max_s is not None and r.seconds > case.max_s:
        why.append(f"took {r.seconds:.1f} s (bound {case.max_s:g} s)")
    if case.check is not None and not why:
        reason = case.check(tmp, r)
        if reason:
            why.append(reason)
    return why


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", nargs="+", help="run the cases whose name holds one of these")
    ap.add_argument("--out")
    a = ap.parse_args()
    chosen = [c for c in cases() if not a.only or any(s in c.name for s in a.only)]
    can_mount = namespaces()
    rows = []
    for case in chosen:
        if case.mount and not can_mount:
            rows.append({"case": case.name, "skipped": "unshare -rm is not allowed here"})
            continue
        with tempfile.TemporaryDirectory(prefix="hawksim-trial-") as d:
            tmp = Path(d)
            if case.setup:
                case.setup(tmp)
            r = (_run_mounted if case.mount else _run_plain)(case, tmp)
            why = judge(case, r, tmp)
        row = {"case": case.name, "argv": list(case.argv), "exit": r.code, "expected": case.code,
               "stderr_lines": len(r.stderr.strip().splitlines()), "files_left": list(r.files),
               "seconds": round(r.seconds, 2), "pass": not why, "why": why}
        if why:
            row["stderr_tail"] = r.stderr.strip()[-400:]
        rows.append(row)
        print(f"{'pass' if not why else 'FAIL'}  {case.name}: exit {r.code} {'; '.join(why)}", file=sys.stderr)
    ran = [r for r in rows if "skipped" not in r]
    emit({"cases": rows, "ran": len(ran), "passed": sum(r["pass"] for r in ran),
          "failed": [r["case"] for r in ran if not r["pass"]],
          "skipped": [r["case"] for r in rows if "skipped" in r]}, a.out, host=True)


if __name__ == "__main__":
    main()
