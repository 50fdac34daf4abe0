"""Issue 53's trial of bad inputs and faults against the CLI contract (docs/conventions.md, "The CLI contract"): output
paths that are not regular files, broken stdout, crafted network files, the environment, data sets without their
schema. Every case checks the exit status, that stderr is one line naming the input, and that no traceback is printed.
The device and FIFO cases use a FIFO and symbolic links in tmp_path, never the real /dev."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from hawksim import atomic
from hawksim.cli import main

ROOT = Path(__file__).resolve().parents[2]
TRAINING_DATA = ROOT / "data" / "uvlm_training_0.3.sqlite"
"""The shipped training set (only read)."""
KIN = "f=26.1,beta=4.3,phi0=9.4,theta0=-2.8,alpha0=-0.4,phi_a=58.4,alpha_a=48.8"


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert "Traceback" not in err
    return code, out, lines


def _one_line(lines, *names):
    assert len(lines) == 1, lines
    for name in names:
        assert name in lines[0], lines
    return lines[0]


# ---- defect 1: output paths replaced by rename ---------------------------------------------------------------


@pytest.fixture
def odd_paths(tmp_path):
    """A FIFO, a directory, a link to the FIFO, a link to a regular file and a dangling link, in tmp_path."""
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "adir").mkdir()
    (tmp_path / "target.bin").write_bytes(b"old")
    os.symlink(tmp_path / "fifo", tmp_path / "link_to_fifo")
    os.symlink("target.bin", tmp_path / "link_to_file")  # relative, as `ln -s` makes it
    os.symlink("missing.bin", tmp_path / "dangling")
    return tmp_path


@pytest.mark.parametrize("name,kind", [("fifo", "FIFO"), ("adir", "directory"), ("link_to_fifo", "FIFO")])
@pytest.mark.parametrize("argv", [
    ["fly", "--speed", "1", "--cycles", "1", "--rrd"],
    ["train", "--data", "d.sqlite", "--out"],
    ["dataset", "--speed", "1", "--samples", "2", "--out"],
], ids=["fly --rrd", "train --out", "dataset --out"])
def test_an_output_path_that_is_not_a_regular_file_is_refused(argv, name, kind, odd_paths, capsys):
    path = odd_paths / name
    before = sorted(p.name for p in odd_paths.iterdir())
    code, out, err = _run(argv + [path], capsys)
    assert code == 2 and out == ""
    _one_line(err, argv[-1], str(path), kind, "not a regular file")
    assert sorted(p.name for p in odd_paths.iterdir()) == before
    assert stat.S_ISFIFO(os.stat(odd_paths / "fifo").st_mode) and (odd_paths / "link_to_fifo").is_symlink()


def test_write_bytes_follows_a_link_and_keeps_it(odd_paths):
    (odd_paths / "target.bin").chmod(0o640)
    atomic.write_bytes(odd_paths / "link_to_file", b"new")
    assert (odd_paths / "link_to_file").is_symlink()
    assert (odd_paths / "target.bin").read_bytes() == b"new"
    assert stat.S_IMODE(os.stat(odd_paths / "target.bin").st_mode) == 0o640
    atomic.write_bytes(odd_paths / "dangling", b"created")
    assert (odd_paths / "dangling").is_symlink() and (odd_paths / "missing.bin").read_bytes() == b"created"
    assert not [p for p in odd_paths.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("name,kind", [("fifo", "a FIFO"), ("adir", "a directory"), ("link_to_fifo", "a FIFO")])
def test_write_bytes_refuses_what_is_not_a_regular_file(name, kind, odd_paths):
    with pytest.raises(atomic.NotRegularFileError) as info:
        atomic.write_bytes(odd_paths / name, b"x", "network")
    assert f"cannot write network {odd_paths / name}: it is {kind}" in str(info.value)
    assert "\n" not in str(info.value)
    assert stat.S_ISFIFO(os.stat(odd_paths / "fifo").st_mode)


# ---- defect 8: broken stdout ----------------------------------------------------------------------------------


class _BrokenStdout:
    """A stdout whose writes fail with ``exc`` (the reader gone: EPIPE; a full device: ENOSPC)."""

    def __init__(self, exc: OSError):
        self.exc = exc

    def write(self, text):
        raise self.exc

    def flush(self):
        raise self.exc


PREDICT = ["predict", "--speed", "1", "--kinematics", KIN]


@pytest.mark.parametrize("as_json", [True, False], ids=["json", "human"])
def test_a_reader_that_has_gone_ends_the_command_quietly(as_json, capsys, monkeypatch):
    monkeypatch.setattr("sys.stdout", _BrokenStdout(BrokenPipeError(32, "Broken pipe")))
    code = main(PREDICT + (["--json"] if as_json else []))
    err = capsys.readouterr().err
    assert code == 141 and err == ""


def test_a_full_stdout_is_one_line(capsys, monkeypatch):
    import errno

    monkeypatch.setattr("sys.stdout", _BrokenStdout(OSError(errno.ENOSPC, "No space left on device")))
    code = main(PREDICT + ["--json"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1
    _one_line(err, "stdout", "No space left on device")


def test_a_closed_pipe_is_a_quiet_exit_141(tmp_path):
    """The trial's `hawksim fly ... --json | head -c 1`, as a process: stdout a pipe whose reader has closed, so the
    write fails with EPIPE; no traceback, not even Python's "Exception ignored" at its exit."""
    import subprocess
    import sys

    r, w = os.pipe()
    os.close(r)
    try:
        proc = subprocess.run([sys.executable, "-m", "hawksim", *PREDICT, "--json"], stdout=w,
                              stderr=subprocess.PIPE, timeout=120, cwd=tmp_path,
                              env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    finally:
        os.close(w)
    assert proc.returncode == 141 and proc.stderr == b"", proc.stderr.decode()


# ---- defect 7: crafted network files; every JSON strict -------------------------------------------------------


def _strict(text: str):
    import json

    def refuse(name):
        raise ValueError(f"{name} in the CLI's JSON")

    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def crafted(tmp_path_factory):
    """The shipped 1 m/s network with its `meta` a JSON array, a string, an object with NaN; and one whose finite
    weights x 1e300 overflow."""
    import dataclasses

    from safetensors import safe_open
    from safetensors.numpy import save

    from hawksim.backends.network import load, shipped_path

    d = tmp_path_factory.mktemp("crafted")
    src = shipped_path(1.0)
    with safe_open(str(src), framework="numpy") as fh:
        md, arrays = fh.metadata(), {k: fh.get_tensor(k) for k in fh.keys()}
    for name, meta in (("array", "[1, 2]"), ("string", '"hello"'), ("nan", '{"command": NaN}')):
        (d / f"meta_{name}.safetensors").write_bytes(save(arrays, metadata={**md, "meta": meta}))
    s = load(src)
    dataclasses.replace(s, W2=s.W2 * 1e300, b2=s.b2 * 1e300, y_std=s.y_std * 1e300).save(d / "big.safetensors")
    return d


@pytest.mark.parametrize("name,says", [("meta_array", "its meta is a JSON array, not an object"),
                                       ("meta_string", "its meta is a JSON string, not an object"),
                                       ("meta_nan", "NaN is not JSON")])
@pytest.mark.parametrize("argv", [PREDICT + ["--network"], ["trim", "--speed", "1", "--population", "100", "--network"],
                                  ["train", "--data", "{data}", "--out", "{tmp}/n.safetensors", "--speed", "1",
                                   "--base"]], ids=["predict", "trim", "train --base"])
def test_a_network_whose_meta_is_not_an_object_is_named(argv, name, says, crafted, tmp_path, capsys):
    path = crafted / f"{name}.safetensors"
    argv = [a.replace("{data}", str(TRAINING_DATA)).replace("{tmp}", str(tmp_path)) for a in argv] + [path]
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == ""
    _one_line(err, str(path), says)
    assert not (tmp_path / "n.safetensors").exists()


@pytest.mark.parametrize("argv", [PREDICT + ["--json", "--network"],
                                  ["trim", "--speed", "1", "--population", "100", "--json", "--network"]],
                         ids=["predict", "trim"])
def test_a_network_that_overflows_is_a_numerical_failure(argv, crafted, capsys):
    code, out, err = _run(argv + [crafted / "big.safetensors"], capsys)
    assert code == 3 and out == ""
    _one_line(err, "numerical failure", "not finite" if argv[0] == "trim" else "big.safetensors")


def test_a_non_finite_result_is_never_printed(capsys, monkeypatch):
    """The last guard: any command's result holding NaN or Infinity exits 3 naming the key (JSON has no such
    values; Python's json.dumps wrote `Infinity`)."""
    monkeypatch.setattr("hawksim.cli.predict.cmd_predict", lambda args: {"a": {"b": [1.0, float("inf")]}})
    code, out, err = _run(PREDICT + ["--json"], capsys)
    assert code == 3 and out == ""
    _one_line(err, "numerical failure", "a.b[1]", "inf")


@pytest.mark.parametrize("argv", [PREDICT + ["--json"], PREDICT + ["--json", "--network", "reference"],
                                  ["predict", "--speed", "0.5", "--kinematics", KIN, "--json"]],
                         ids=["predict", "predict reference", "predict 0.5"])
def test_the_json_printed_parses_strictly(argv, capsys):
    code, out, err = _run(argv, capsys)
    assert code == 0, err
    obj = _strict(out)
    assert isinstance(obj, dict) and out.count("\n") == 1


# ---- defect 11: --network FILE that is not a regular file ----------------------------------------------------


@pytest.mark.parametrize("name,kind", [("fifo", "is a FIFO (named pipe), not a regular file"),
                                       ("adir", "is a directory, not a regular file"),
                                       ("link_to_fifo", "is a FIFO (named pipe) (the target of the link"),
                                       ("dangling", "does not exist (a link to the missing 'missing.bin')"),
                                       ("huge", "above the limit of 1 GiB")])
@pytest.mark.parametrize("argv", [PREDICT + ["--network"], ["trim", "--speed", "1", "--population", "100", "--network"],
                                  ["train", "--data", TRAINING_DATA, "--out", "n.safetensors", "--speed", "1",
                                   "--base"]],
                         ids=["predict", "trim", "train --base"])
def test_a_model_that_is_not_a_regular_file_is_named(argv, name, kind, odd_paths, capsys, monkeypatch):
    """A FIFO hung the read, a link to /dev/zero read without end (a FIFO stands in for the device here); each was
    "does not exist". A sparse file above the bound stands for a huge one (nothing read)."""
    monkeypatch.chdir(odd_paths)
    with open(odd_paths / "huge", "wb") as fh:
        fh.truncate((1 << 30) + 1)
    path = odd_paths / name
    code, out, err = _run(argv + [path], capsys)
    assert code == 2 and out == ""
    _one_line(err, str(path), kind)
    assert not (odd_paths / "n.safetensors").exists()


# ---- defect 10: environment variables ---------------------------------------------------------------------------


@pytest.mark.parametrize("value,says", [("0", "must be an integer from 1 to 1024"), ("abc", "is not an integer"),
                                        ("-3", "must be an integer from 1 to 1024"), ("1e3", "is not an integer"),
                                        ("100000", "must be an integer from 1 to 1024")])
def test_a_bad_numba_num_threads_is_one_line(value, says, capsys, monkeypatch):
    monkeypatch.setenv("NUMBA_NUM_THREADS", value)
    code, out, err = _run(PREDICT, capsys)
    assert code == 2 and out == ""
    _one_line(err, f"NUMBA_NUM_THREADS={value!r}", says)


def test_numba_num_threads_is_checked_before_numba_is_imported(tmp_path):
    """As the command: numba, imported with NUMBA_NUM_THREADS=0, raised a 28-line traceback from its import."""
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path), "NUMBA_NUM_THREADS": "0"}
    proc = subprocess.run([sys.executable, "-X", "importtime", "-m", "hawksim", "fly", "--speed", "1", "--cycles",
                           "1"], capture_output=True, text=True, timeout=120, cwd=tmp_path, env=env)
    lines = [ln for ln in proc.stderr.splitlines() if not ln.startswith("import time:")]
    assert proc.returncode == 2 and proc.stdout == ""
    _one_line(lines, "NUMBA_NUM_THREADS='0'")
    assert not any(ln.split("|")[-1].strip() == "numba" for ln in proc.stderr.splitlines()
                   if ln.startswith("import time:"))


# ---- defects 9 and 13: unbounded numbers of train --kind step and fly ---------------------------------------------

STEP = ["train", "--kind", "step", "--data", "flights.sqlite", "--out", "n.safetensors"]


@pytest.mark.parametrize("argv,names", [
    (STEP + ["--weight-decay", "inf"], ("--weight-decay", "inf")),
    (STEP + ["--weight-decay", "nan"], ("--weight-decay", "nan")),
    (STEP + ["--weight-decay", "-1"], ("--weight-decay", "-1")),
    (STEP + ["--lags", "inf"], ("--lags", "'inf'")),
    (STEP + ["--lags", "1e308"], ("--lags", "'1e308'")),
    (STEP + ["--lags", "0.5,x"], ("--lags", "'0.5,x'", "not a comma-separated list")),
    (STEP + ["--layers", "200000,200000"], ("--layers", "'200000,200000'", "from 1 to 4096")),
    (STEP + ["--layers", "a,b"], ("--layers", "'a,b'", "not a comma-separated list")),
    (STEP + ["--layers", ",".join(["8"] * 17)], ("--layers", "at most 16")),
    (["fly", "--speed", "1", "--cycles", "1", "--control", "lqr", "--sensing-delay", "1000000000"],
     ("--sensing-delay", "1000000000", "limit of 20")),
], ids=lambda a: " ".join(a[7:]) if isinstance(a, list) and a[0] == "train" else None)
def test_unbounded_numbers_are_refused_naming_the_option(argv, names, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == ""
    _one_line(err, *names)
    assert "invalid" not in err[0]  # argparse's "invalid _floats value" named no input
    assert list(tmp_path.iterdir()) == []


def test_the_lag_bound_is_a_flights_length():
    from hawksim.cli.train import MAX_LAG_BEATS
    from hawksim.surrogate.flights import FLIGHT_BEATS

    assert MAX_LAG_BEATS == FLIGHT_BEATS


# ---- defect 12: a data set without its samples table ------------------------------------------------------------


@pytest.mark.parametrize("damage,says", [("DROP TABLE samples", "has no samples table"),
                                         ("ALTER TABLE samples DROP COLUMN version", "lacks the column(s) version")])
@pytest.mark.parametrize("argv", [["dataset", "--speed", "1", "--samples", "2", "--out"],
                                  ["dataset", "--kind", "flights", "--samples", "2", "--out"],
                                  ["train", "--out", "n.safetensors", "--speed", "1", "--data"],
                                  ["train", "--kind", "step", "--out", "n.safetensors", "--data"]],
                         ids=["dataset", "dataset flights", "train", "train step"])
def test_a_data_set_with_a_damaged_schema_is_named(argv, damage, says, tmp_path, capsys, monkeypatch):
    import sqlite3

    from hawksim.surrogate.dataset import open_dataset

    monkeypatch.chdir(tmp_path)
    path = tmp_path / "d.sqlite"
    open_dataset(path, create=True).close()
    with sqlite3.connect(path) as conn:
        conn.execute(damage)
    conn.close()
    code, out, err = _run(argv + [path], capsys)
    assert code == 2 and out == ""
    _one_line(err, str(path), says)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.sqlite"]


# ---- defect 2: the Dask scheduler lost mid-run -------------------------------------------------------------------


class _LostClient:
    """A dask Client whose scheduler is gone once work is submitted: what `kill -9` of the scheduler did to a run
    (FutureCancelledError, reason scheduler-connection-lost, out of the first result)."""

    def __init__(self, address, timeout=None):
        self.address = address

    def scheduler_info(self):
        return {"workers": {"tcp://w1": {}, "tcp://w2": {}}}

    def submit(self, fn, *args, **kwargs):
        from distributed.client import FutureCancelledError

        raise FutureCancelledError("evaluate_sample-0", "scheduler-connection-lost")

    def close(self, timeout=None):
        raise OSError("the scheduler is gone")  # closing a client of a lost scheduler fails too


@pytest.mark.parametrize("kind", ["samples", "flights"])
def test_a_lost_scheduler_is_one_line_saying_the_rows_are_kept(kind, tmp_path, capsys, monkeypatch):
    import dask.distributed

    monkeypatch.setattr(dask.distributed, "Client", _LostClient)
    out = tmp_path / "c.sqlite"
    argv = ["dataset", "--kind", kind, "--samples", "6", "--seed", "7", "--scheduler", "tcp://127.0.0.1:8786",
            "--out", out, "--no-progress"] + (["--speed", "1"] if kind == "samples" else [])
    code, stdout, err = _run(argv, capsys)
    assert code == 1 and stdout == ""
    _one_line(err, "the Dask scheduler tcp://127.0.0.1:8786 was lost mid-run (scheduler-connection-lost)",
              "every result committed before is kept", "rerun the same command")
    assert list(tmp_path.iterdir()) == []  # the file this run made holds nothing: removed


# ---- defect 5: a large --samples against an existing data set ------------------------------------------------


def test_a_large_samples_count_looks_the_stored_indices_up_once(tmp_path, capsys, monkeypatch):
    """The trial's case (`--samples 200000` on a copy of the shipped training set) ran the stored-index query once
    per index: nothing in 150 s. One query now, and the progress starts before any sample is computed."""
    import shutil

    from hawksim.surrogate import dataset

    path = tmp_path / "x.sqlite"
    shutil.copyfile(TRAINING_DATA, path)
    queries, events = [], []
    lookup = dataset.stored_indices

    def counted(conn, speed, seed):
        queries.append((speed, seed))
        return lookup(conn, speed, seed)

    def compute(todo, evaluate, scheduler, workers):  # no UVLM: the lookup is what is measured
        events.append(("compute", len(todo)))
        return iter(())

    monkeypatch.setattr(dataset, "stored_indices", counted)
    monkeypatch.setattr(dataset, "_compute", compute)
    conn = dataset.open_dataset(path)
    resolution = dataset.stored_resolution(conn, 1.0, 0)
    (version,) = dataset.stored_versions(conn, 1.0, 0)
    conn.close()
    # the shipped set was made by another version, which `generate` refuses to continue (tested in
    # test_dataset.py); this test measures the index lookup, so it continues the file as that version
    monkeypatch.setattr(dataset, "__version__", version)
    r = dataset.generate(path, 1.0, 100_000, seed=0, resolution=resolution, workers=1,
                         progress=lambda done, n: events.append(("progress", done, n)))
    assert len(queries) == 2  # the indices to do, and the count stored at the end
    stored = r.samples
    assert 0 < stored < 100_000
    assert events == [("progress", stored, 100_000), ("compute", 100_000 - stored)]


@pytest.mark.parametrize("kind", ["samples", "flights"])
def test_samples_above_the_bound_are_refused_naming_the_option(kind, tmp_path, capsys, monkeypatch):
    from hawksim.cli.args import MAX_DATASET_SAMPLES

    monkeypatch.chdir(tmp_path)
    too_many = str(MAX_DATASET_SAMPLES + 1)
    code, out, err = _run(["dataset", "--kind", kind, "--speed", "1", "--samples", too_many, "--out", "x.sqlite"],
                          capsys)
    assert code == 2 and out == ""
    _one_line(err, "--samples", too_many, "exceeds the limit", "MAX_DATASET_SAMPLES")
    assert list(tmp_path.iterdir()) == []
    assert MAX_DATASET_SAMPLES >= 3000  # the shipped runs (3000 samples per speed) stay within it


# ---- defect 4: two writers creating the same data set ------------------------------------------------------------


def _fake_compute(todo, evaluate, scheduler, workers):
    """Samples without the UVLM: what the writer stores is what is tested."""
    from hawksim.surrogate.dataset import Sample

    for i in todo:
        seed, speed = evaluate.args
        yield Sample(speed, seed, i, (26.0,) * 7, (1.0, 0.0, 0.0, 1.0), 0.08, 0.01, peak_cf=1.0)


def test_a_second_writer_of_a_file_being_created_is_refused_and_deletes_nothing(tmp_path, capsys, monkeypatch):
    """The trial paused writer A between creating the file and writing its schema: writer B wrote the schema, A
    failed (`table samples already exists`) and deleted the file, and both runs were lost. Now A creates the file
    under its lock; B is refused in one line, and A's run completes."""
    import sqlite3
    import threading

    from hawksim.backends.resolution import TRAINING
    from hawksim.surrogate import dataset

    path = tmp_path / "c.sqlite"
    paused, resume = threading.Event(), threading.Event()
    connect = sqlite3.connect

    def pausing_connect(*args, **kwargs):  # A stops once SQLite has the (still empty) file open
        conn = connect(*args, **kwargs)
        if threading.current_thread().name == "writer A":
            paused.set()
            assert resume.wait(60)
        return conn

    monkeypatch.setattr(dataset, "_compute", _fake_compute)
    monkeypatch.setattr(dataset.sqlite3, "connect", pausing_connect)
    result = {}

    def writer_a():
        try:
            result["a"] = dataset.generate(path, 1.0, 5, seed=3, resolution=TRAINING)
        except BaseException as exc:  # noqa: BLE001 - reported by the assertion below
            result["a"] = exc

    a = threading.Thread(target=writer_a, name="writer A")
    a.start()
    try:
        while not paused.wait(0.1):
            assert a.is_alive(), result
        assert path.exists() and path.stat().st_size == 0  # created, no schema yet
        code, out, err = _run(["dataset", "--speed", "1", "--samples", "5", "--seed", "3", "--out", path,
                               "--no-progress"], capsys)
        assert code == 2 and out == ""
        _one_line(err, str(path), "is being written by another hawksim dataset")
        assert path.exists()  # B deleted nothing
    finally:
        resume.set()
        a.join(60)
    assert not isinstance(result["a"], BaseException), result["a"]
    assert (result["a"].samples, result["a"].new) == (5, 5)
    conn = dataset.open_dataset(path)
    assert dataset.stored_indices(conn, 1.0, 3) == set(range(5))
    conn.close()


# ---- defect 14: options silently ignored, an unbounded step, half-done outputs -------------------------------

def _no_work(*args, **kwargs):
    raise AssertionError("the command began its work: the option was not refused")


@pytest.mark.parametrize("argv, option", [
    (["dataset", "--kind", "flights", "--speed", "1"], "--speed"),
    (["dataset", "--kind", "flights", "--n-chord", "4"], "--n-chord"),
    (["dataset", "--kind", "flights", "--steps-per-cycle", "30"], "--steps-per-cycle"),
    (["dataset", "--kind", "flights", "--resolution", "reference"], "--resolution"),
    (["dataset", "--speed", "1", "--family", "wide"], "--family"),
    (["trim", "--speed", "1", "--free-flight", "--model", "m.safetensors"], "--model"),
    (["trim", "--speed", "1", "--free-flight", "--population", "10"], "--population"),
    (["trim", "--speed", "1", "--free-flight", "--seed", "3"], "--seed"),
    (["trim", "--speed", "1", "--free-flight", "--verify"], "--verify"),
    (["trim", "--speed", "1", "--aero", "uvlm", "--population", "10"], "--aero"),
    (["fly", "--speed", "1", "--cycles", "1", "--control", "none", "--sensing-delay", "1"], "--sensing-delay"),
    (["fly", "--speed", "1", "--cycles", "1", "--aero", "surrogate", "--control", "none", "--sensing-delay", "0"],
     "--sensing-delay"),
])
def test_an_option_that_does_not_apply_is_refused_naming_it(argv, option, tmp_path, capsys, monkeypatch):
    import hawksim.flight.orbit
    import hawksim.surrogate.dataset
    import hawksim.surrogate.flights

    monkeypatch.setattr(hawksim.surrogate.flights, "generate_flights", _no_work)
    monkeypatch.setattr(hawksim.surrogate.dataset, "generate", _no_work)
    monkeypatch.setattr(hawksim.flight.orbit, "periodic_orbit", _no_work)
    if argv[0] == "dataset":
        argv = [*argv, "--samples", "2", "--out", tmp_path / "d.sqlite", "--no-progress"]
    code, out, lines = _run(argv, capsys)
    assert code == 2 and out == ""
    assert "does not apply" in _one_line(lines, option) or "applies to" in lines[0]
    assert not (tmp_path / "d.sqlite").exists()


def test_steps_per_cycle_of_a_uvlm_run_is_bounded(capsys):
    from hawksim.cli import build_parser
    from hawksim.cli.args import MAX_UVLM_STEPS_PER_CYCLE

    code, out, lines = _run(["aero", "--speed", "1", "--kinematics", KIN, "--steps-per-cycle",
                             MAX_UVLM_STEPS_PER_CYCLE + 1], capsys)
    assert code == 2 and out == ""
    _one_line(lines, "--steps-per-cycle", str(MAX_UVLM_STEPS_PER_CYCLE + 1), str(MAX_UVLM_STEPS_PER_CYCLE))
    args = build_parser().parse_args(["aero", "--speed", "1", "--kinematics", KIN, "--steps-per-cycle",
                                      str(MAX_UVLM_STEPS_PER_CYCLE)])
    assert args.steps_per_cycle == MAX_UVLM_STEPS_PER_CYCLE


TRAIN = ["train", "--data", TRAINING_DATA, "--speed", "1", "--hidden", "2", "--max-iter", "1", "--no-progress"]


def test_a_failed_validation_figure_leaves_no_network(tmp_path, capsys, monkeypatch):
    import errno

    import hawksim.surrogate.plots

    def full_disk(result, path, *a, **k):
        Path(path).with_suffix(".png").write_bytes(b"half")  # the PNG written, then its PDF fails
        raise OSError(errno.ENOSPC, f"cannot write figure {Path(path).with_suffix('.pdf')}: No space left on device")

    monkeypatch.setattr(hawksim.surrogate.plots, "validation_figure", full_disk)
    code, out, lines = _run([*TRAIN, "--out", tmp_path / "n.safetensors", "--validation-png", tmp_path / "v.png"],
                            capsys)
    assert code == 1 and out == ""
    _one_line(lines, "No space left on device", "v.pdf")
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no network, no temporary, no half figure


def test_a_network_with_its_validation_figure_is_written_whole(tmp_path, capsys):
    (tmp_path / "n.safetensors").symlink_to("target.safetensors")  # a link keeps being one
    code, out, lines = _run([*TRAIN, "--out", tmp_path / "n.safetensors", "--validation-png", tmp_path / "v.png"],
                            capsys)
    assert code == 0, lines
    assert sorted(p.name for p in tmp_path.iterdir()) == ["n.safetensors", "target.safetensors", "v.pdf", "v.png"]
    assert (tmp_path / "n.safetensors").is_symlink() and (tmp_path / "target.safetensors").stat().st_size > 0


def test_validation_png_does_not_apply_to_the_step_network(tmp_path, capsys):
    code, out, lines = _run(["train", "--kind", "step", "--data", tmp_path / "f.sqlite", "--out",
                             tmp_path / "n.safetensors", "--validation-png", tmp_path / "v.png"], capsys)
    assert code == 2
    _one_line(lines, "--validation-png", "--kind step")


def test_an_interrupted_table_is_not_under_its_final_name(tmp_path, monkeypatch):
    import json

    import hawksim.flight.orbit as orbit
    from hawksim.paper.reproduce import orbits_all, partial_path

    solved = []

    def interrupted_at(stop):
        def solve(v, aero, log=None):
            if v == stop:
                raise KeyboardInterrupt
            solved.append(v)
            return orbit.shipped_orbit(v, aero)
        return solve

    from hawksim.backends.registry import descriptor

    final = tmp_path / descriptor("quasi-steady").orbit_table
    monkeypatch.setattr(orbit, "periodic_orbit", interrupted_at(1.0))
    with pytest.raises(KeyboardInterrupt):
        orbits_all(tmp_path, log=lambda m: None, aeros=("quasi-steady",), speeds=(0.5, 1.0, 1.5))
    assert not final.exists()
    assert [r["speed"] for r in json.loads(partial_path(final).read_text())["rows"]] == [0.5]
    monkeypatch.setattr(orbit, "periodic_orbit", interrupted_at(None))
    orbits_all(tmp_path, log=lambda m: None, aeros=("quasi-steady",), speeds=(0.5, 1.0, 1.5))
    assert solved == [0.5, 1.0, 1.5]  # 0.5 solved once: the run resumed
    assert [r["speed"] for r in json.loads(final.read_text())["rows"]] == [0.5, 1.0, 1.5]
    assert not partial_path(final).exists()
