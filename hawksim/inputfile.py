"""Checks of an input file named by the user (``--model``, ``--base``) before it is read: it must be a regular file
(or a symbolic link to one) of bounded size. A FIFO would block the read forever, a directory is not a file, a link
to ``/dev/zero`` would be read without end (issue 53, defect 11); each is named for what it is, in one line."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from hawksim.atomic import file_kind

MAX_NETWORK_FILE_BYTES = 1 << 30
"""Largest network file read [bytes], 1 GiB: ~400x the shipped per-step network (2.7 MB) and ~20 000x a cycle-mean
one (50 kB); a bound on the memory a file named by --model can take (safetensors files are read whole)."""


def check_regular_file(path: str | Path, what: str, error=ValueError, max_bytes: int = MAX_NETWORK_FILE_BYTES) -> Path:
    """``path`` if it is a regular file (links followed) of at most ``max_bytes``; else ``error`` (a ValueError
    subclass: the CLI's exit status 2) with one line: ``{what} 'path' does not exist`` / ``is a FIFO (named pipe),
    not a regular file`` / ``is 5.0 GB, above the limit of 1 GiB``. The file is opened without blocking (a FIFO
    without a writer would block an ordinary open) and checked by its open descriptor, so what is checked is what a
    reader of the path finds."""
    path = Path(path)
    name = repr(str(path))
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except FileNotFoundError:
        dangling = f" (a link to the missing {os.readlink(path)!r})" if path.is_symlink() else ""
        raise error(f"{what} {name} does not exist{dangling}") from None
    except IsADirectoryError:
        raise error(f"{what} {name} is a directory, not a regular file") from None
    except OSError as exc:
        raise error(f"{what} {name} cannot be read: {exc.strerror or exc}") from None
    try:
        st = os.fstat(fd)
    finally:
        os.close(fd)
    if not stat.S_ISREG(st.st_mode):
        via = f" (the target of the link, {os.path.realpath(path)!r})" if path.is_symlink() else ""
        raise error(f"{what} {name} is {file_kind(st.st_mode)}{via}, not a regular file")
    if st.st_size > max_bytes:
        raise error(f"{what} {name} is {st.st_size / 1e9:.3g} GB, above the limit of {max_bytes / 2**30:g} GiB")
    return path


def _no_constant(name: str):
    raise ValueError(f"{name} is not JSON")


def strict_json(text: str):
    """``json.loads`` that refuses NaN, Infinity and -Infinity (Python's json accepts them; JSON has no such
    values): ValueError."""
    import json

    return json.loads(text, parse_constant=_no_constant)


def metadata_object(text: str | None, what: str) -> dict:
    """A file's ``meta`` JSON (provenance and scores): an object, or ValueError saying what it is instead (a list or a
    string gave an AttributeError deep in the CLI before). Missing: {}."""
    if text is None:
        return {}
    meta = strict_json(text)
    if not isinstance(meta, dict):
        raise ValueError(f"its {what} is a JSON {_json_type(meta)}, not an object")
    if "command" in meta and not isinstance(meta["command"], str):
        raise ValueError(f"its {what}'s 'command' is a JSON {_json_type(meta['command'])}, not a string")
    return meta


def _json_type(value) -> str:
    """JSON's name of a parsed value's type."""
    names = {dict: "object", list: "array", str: "string", bool: "boolean", int: "number", float: "number"}
    return "null" if value is None else names.get(type(value), type(value).__name__)
