"""Issue 53's trial of bad inputs and faults against the CLI contract (docs/conventions.md, "The CLI contract"): output
paths that are not regular files, broken stdout, crafted network files, the environment, data sets without their
schema. Every case checks the exit status, that stderr is one line naming the input, and that no traceback is printed.
The device and FIFO cases use a FIFO and symbolic links in tmp_path, never the real /dev."""

from __future__ import annotations

import os
import stat

import pytest

from hawksim import atomic
from hawksim.cli import main

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
