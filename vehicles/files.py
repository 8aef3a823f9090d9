"""Opening the files a user names, safely: regular files only, and size limits.

Shared by the vehicle tables and the network reader (one definition of each rule).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import BinaryIO

from clearance.vehicles.errors import InputError

__all__ = ["env_limit", "open_regular"]


def env_limit(name: str, default: int, scale: int = 1) -> int:
    """A size limit: the environment variable ``name`` times ``scale`` if set, else
    ``default``; a value that is not a positive number is an input error.

    Examples
    --------
    >>> env_limit("CLEARANCE_NO_SUCH_VARIABLE", 7)
    7
    """
    text = os.environ.get(name, "").strip()
    if not text:
        return default
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (value > 0 and value * scale < 2**62):
        raise InputError(f"environment variable {name}={text!r}: expected a positive number")
    return int(value * scale)


def open_regular(path: str | os.PathLike[str], what: str = "file") -> BinaryIO:
    """Open ``path`` for reading bytes if, and only if, it is a regular file.

    The file is opened without blocking and checked on the descriptor itself, so a FIFO
    (which would wait for a writer), a device such as ``/dev/zero`` (endless), a
    directory, a symlink loop or a dangling link is refused before anything is read.

    Examples
    --------
    >>> open_regular("/dev/null")
    Traceback (most recent call last):
    ...
    clearance.vehicles.errors.InputError: /dev/null: is a character device, not a regular file
    """
    p = Path(path)
    try:
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InputError(f"{p}: no such {what}", file=p) from None
    except IsADirectoryError:
        raise InputError(f"{p}: is a directory, not a regular file", file=p) from None
    except OSError as exc:
        raise InputError(f"{p}: cannot be read ({exc.strerror})", file=p) from None
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise InputError(f"{p}: is {_kind(mode)}, not a regular file", file=p)
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "a special file"


