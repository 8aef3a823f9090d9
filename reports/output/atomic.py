"""Atomic output: a file is either the previous version or the complete new one."""

from __future__ import annotations

import io
import os
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO, TextIO

from clearance.vehicles.errors import OptionError

__all__ = ["atomic_file", "current_umask", "write_bytes_atomic", "write_stream_atomic",
           "write_text_atomic"]


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
    """Write ``data`` to ``path`` atomically (:func:`atomic_file`: temporary file, fsync,
    rename; the umask's permissions, 0644 under umask 022; ``OptionError`` naming the file
    on a failure of the file system, any previous file left as it was)."""
    with atomic_file(path) as fh:
        fh.write(data)
    return Path(path)


def write_stream_atomic(path: str | os.PathLike[str], write: Callable[[TextIO], object]
                        ) -> Path:
    """Write a text file (UTF-8, newlines as written) atomically by ``write(stream)``, for
    a file too large to hold whole in memory first (a town's DXF: 100 MB of text).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_stream_atomic(Path(d) / "a.txt", lambda f: f.write("x\\n" * 3))
    ...     p.read_bytes()
    b'x\\nx\\nx\\n'
    """
    with atomic_file(path) as fh:
        text = io.TextIOWrapper(fh, encoding="utf-8", newline="")
        try:
            write(text)
            text.flush()
        finally:
            text.detach()  # the binary file is atomic_file's to close
    return Path(path)


@contextmanager
def atomic_file(path: str | os.PathLike[str]) -> Iterator[BinaryIO]:
    """A binary file to write that replaces ``path`` once it is complete (temporary file
    in the same folder, fsync, rename); on an error or an interruption the temporary file
    is removed and any previous file at ``path`` is left as it was. The file gets the
    permissions of the user's umask. A failure of the file system (disk full, read-only,
    no such folder) raises ``OptionError`` naming the file and the cause."""
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
            yield fh
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
