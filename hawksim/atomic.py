"""All-or-nothing file writes: the bytes go to a temporary file beside the target, are fsync'ed and renamed over it,
so a full disk or an interrupt leaves the target as it was and no temporary file behind.

The target is the path the user gave (:func:`output_target`): a symbolic link is followed, and its target replaced
(the link stays a link); a path that exists and is not a regular file (a character or block device such as
``/dev/null``, a FIFO, a socket, a directory) is refused with :class:`NotRegularFileError` (a ValueError: the CLI's
exit status 2), since renaming over it would replace the device or pipe by a regular file (as root) and writing
through it would give up the all-or-nothing guarantee (docs/conventions.md, "The CLI contract")."""

from __future__ import annotations

import errno
import os
import uuid
import stat
from pathlib import Path

ENVIRONMENT_ERRNOS = frozenset({errno.ENOSPC, errno.EFBIG, errno.EDQUOT, errno.EIO, errno.EROFS})
"""errno values of a write that fails for the environment (disk full, file-size or quota limit, I/O error,
read-only file system), not for the path the user named: reported as OSError (the CLI's exit status 1)."""


class NotRegularFileError(ValueError):
    """An output path that exists and is not a regular file (a device, FIFO, socket or directory): a bad input."""


FILE_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
              (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISSOCK, "a socket"))
"""What a path that is not a regular file is, for the one-line message (by its ``st_mode``)."""


def file_kind(mode: int) -> str:
    """'a regular file', 'a directory', 'a character device', ... of an ``st_mode``."""
    if stat.S_ISREG(mode):
        return "a regular file"
    return next((name for test, name in FILE_KINDS if test(mode)), "not a regular file")


def output_target(path: str | Path, what: str = "file") -> Path:
    """The file an output to ``path`` replaces: ``path`` itself, or the end of its chain of symbolic links (a
    dangling link gives its missing target, then created). NotRegularFileError (one line: ``cannot write {what}
    {path}: it is a character device, not a regular file``) when that exists and is not a regular file."""
    path = Path(path)
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        mode = os.stat(target).st_mode
    except FileNotFoundError:
        return target
    except OSError:  # not ours to judge here (permissions, a loop): the write reports it
        return target
    if not stat.S_ISREG(mode):
        via = f" (the target of the link, {target})" if target != path else ""
        raise NotRegularFileError(f"cannot write {what} {path}: it is {file_kind(mode)}{via}, not a regular file")
    return target


def keep_mode(tmp: Path, target: Path) -> None:
    """Give ``tmp`` the permission bits of the regular file ``target`` it will replace (if that exists), so that
    replacing a file keeps its mode."""
    try:
        os.chmod(tmp, stat.S_IMODE(os.stat(target).st_mode))
    except FileNotFoundError:
        pass


def temporary_beside(path: Path) -> Path:
    """A hidden, unique temporary name in the target's directory (so the final rename stays on one file system)."""
    return path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp")


def write_bytes(path: str | Path, data: bytes, what: str = "file") -> Path:
    """Write ``data`` to ``path`` all or nothing; OSError (one line: ``cannot write {what} {path}: {reason}``, the
    errno kept) when it cannot be written; NotRegularFileError when ``path`` is (or links to) something other than a
    regular file (:func:`output_target`). Returns ``path`` (a link stays a link; its target is replaced)."""
    path = Path(path)
    target = output_target(path, what)
    tmp = temporary_beside(target)
    try:
        with open(tmp, "xb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        keep_mode(tmp, target)
        os.replace(tmp, target)
    except OSError as exc:
        raise OSError(exc.errno, f"cannot write {what} {path}: {exc.strerror or exc}") from None
    finally:
        tmp.unlink(missing_ok=True)
    return path


def write_text(path: str | Path, text: str, what: str = "file") -> Path:
    """:func:`write_bytes` of ``text`` in UTF-8 (JSON, Markdown tables)."""
    return write_bytes(path, text.encode("utf-8"), what)
