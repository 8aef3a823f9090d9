"""Atomic output: a file is either the previous version or the complete new one."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from clearance.vehicles.errors import OptionError

__all__ = ["current_umask", "write_bytes_atomic", "write_text_atomic"]


def current_umask() -> int:
    """The process's umask (read by setting it and putting it back).

    >>> 0 <= current_umask() <= 0o777
    True
    """
    umask = os.umask(0o022)
    os.umask(umask)
    return umask


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in the same folder.

    An interrupted run leaves any previous file intact; never a half-written one.
    """
    return write_bytes_atomic(path, text.encode("utf-8"))


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file, fsync, rename).

    The file gets the permissions of the user's umask (0644 under umask 022). A failure of
    the file system (disk full, read-only, no such folder) raises ``InputError`` naming the
    file and the cause; any previous file at ``path`` is left as it was.
    """
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OptionError(f"{folder}: cannot create output folder: {exc.strerror}") from None
    if target.is_dir():
        raise OptionError(f"{target}: is a directory, expected a file name")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise OptionError(f"{folder}: cannot write here: {exc.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            os.fchmod(fh.fileno(), 0o666 & ~current_umask())
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise OptionError(f"{target}: cannot write: {exc.strerror}; any previous file is "
                         "unchanged") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target
