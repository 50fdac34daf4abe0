"""All-or-nothing file writes: the bytes go to a temporary file beside the target, are fsync'ed and renamed over it,
so a full disk or an interrupt leaves the target as it was and no temporary file behind."""

from __future__ import annotations

import errno
import os
import uuid
from pathlib import Path

ENVIRONMENT_ERRNOS = frozenset({errno.ENOSPC, errno.EFBIG, errno.EDQUOT, errno.EIO, errno.EROFS})
"""errno values of a write that fails for the environment (disk full, file-size or quota limit, I/O error,
read-only file system), not for the path the user named: reported as OSError (the CLI's exit status 1)."""


def temporary_beside(path: Path) -> Path:
    """A hidden, unique temporary name in the target's directory (so the final rename stays on one file system)."""
    return path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp")


def write_bytes(path: str | Path, data: bytes, what: str = "file") -> Path:
    """Write ``data`` to ``path`` all or nothing; OSError (one line: ``cannot write {what} {path}: {reason}``, the
    errno kept) when it cannot be written."""
    path = Path(path)
    tmp = temporary_beside(path)
    try:
        with open(tmp, "xb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        raise OSError(exc.errno, f"cannot write {what} {path}: {exc.strerror or exc}") from None
    finally:
        tmp.unlink(missing_ok=True)
    return path


def write_text(path: str | Path, text: str, what: str = "file") -> Path:
    """:func:`write_bytes` of ``text`` in UTF-8 (JSON, Markdown tables)."""
    return write_bytes(path, text.encode("utf-8"), what)
