"""Opening SUMO XML files safely: plain or gzip, no entities, no network, no DOCTYPE tricks.

Every failure becomes an :class:`~vehicles.errors.InputError` that names the file.
"""

from __future__ import annotations

import gzip
import os
import re
from pathlib import Path
from typing import BinaryIO

from vehicles.errors import InputError

#: How much of the prolog (decompressed) is read at most while looking for the root element.
MAX_PROLOG_BYTES = 4 * 1024 * 1024

_NAME_RE = re.compile(rb"[A-Za-z_:][-A-Za-z0-9_.:]*")


def open_binary(path: str | os.PathLike[str]) -> BinaryIO:
    """Open ``path`` for reading bytes, decompressing it when it is gzip (by its magic bytes).

    Raises
    ------
    InputError
        The file does not exist, is not a regular file or cannot be read.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(f"{p}: no such file")
    if not p.is_file():
        raise InputError(f"{p}: not a regular file")
    try:
        raw = open(p, "rb")  # noqa: SIM115 - returned to the caller
    except OSError as exc:
        raise InputError(f"{p}: cannot be read ({exc.strerror})") from exc
    magic = raw.read(2)
    raw.seek(0)
    if magic == b"\x1f\x8b":
        return gzip.GzipFile(fileobj=raw, mode="rb")  # type: ignore[return-value]
    return raw


def scan_prolog(path: str | os.PathLike[str]) -> str:
    """Check the prolog of an XML file and return the name of its root element.

    The prolog may hold an XML declaration, processing instructions, comments and a
    DOCTYPE; a DOCTYPE that declares entities is refused (entity expansion attacks), as
    is a file that is empty, not XML, or whose prolog is longer than
    :data:`MAX_PROLOG_BYTES`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "a.xml"
    >>> _ = f.write_text('<?xml version="1.0"?><!-- c --><net version="1.9"/>')
    >>> scan_prolog(f)
    'net'
    """
    p = Path(path)
    buf = b""
    with open_binary(p) as fh:
        pos = 0
        while True:
            if len(buf) - pos < 4096 and len(buf) < MAX_PROLOG_BYTES:
                try:
                    chunk = fh.read(65536)
                except (OSError, EOFError) as exc:
                    raise InputError(f"{p}: cannot be decompressed ({exc})") from exc
                buf += chunk
                if chunk:
                    continue
            # skip whitespace and a byte-order mark
            while pos < len(buf) and buf[pos : pos + 1] in (b" ", b"\t", b"\r", b"\n"):
                pos += 1
            if buf.startswith(b"\xef\xbb\xbf", pos):
                pos += 3
                continue
            if pos >= len(buf):
                if not buf.strip():
                    raise InputError(f"{p}: the file is empty")
                raise InputError(f"{p}: not XML (no root element found)")
            if buf.startswith(b"<?", pos):
                end = buf.find(b"?>", pos)
                pos = _advance(p, buf, end, 2)
            elif buf.startswith(b"<!--", pos):
                end = buf.find(b"-->", pos)
                pos = _advance(p, buf, end, 3)
            elif buf.startswith(b"<!DOCTYPE", pos) or buf.startswith(b"<!doctype", pos):
                start = pos
                end = _doctype_end(buf, pos)
                pos = _advance(p, buf, end, 1)
                if b"<!ENTITY" in buf[start:pos].upper():
                    raise InputError(
                        f"{p}: refused: the DOCTYPE declares entities (entity expansion is "
                        "never performed)"
                    )
            elif buf.startswith(b"<", pos):
                m = _NAME_RE.match(buf, pos + 1)
                if not m:
                    raise InputError(f"{p}: not XML (unexpected markup at byte {pos})")
                return m.group(0).decode("ascii", "replace")
            else:
                raise InputError(f"{p}: not XML (text before the root element)")
            if pos >= MAX_PROLOG_BYTES:
                raise InputError(f"{p}: the XML prolog is longer than {MAX_PROLOG_BYTES} bytes")


def _advance(path: Path, buf: bytes, end: int, marker_len: int) -> int:
    if end < 0:
        if len(buf) >= MAX_PROLOG_BYTES:
            raise InputError(f"{path}: the XML prolog is longer than {MAX_PROLOG_BYTES} bytes")
        raise InputError(f"{path}: not XML or truncated (unterminated markup in the prolog)")
    return end + marker_len


def _doctype_end(buf: bytes, pos: int) -> int:
    """Index of the ``>`` closing a DOCTYPE that starts at ``pos`` (-1 if not in ``buf``)."""
    depth = 0
    quote = 0
    for i in range(pos + 2, len(buf)):
        c = buf[i]
        if quote:
            if c == quote:
                quote = 0
        elif c in (0x22, 0x27):  # " '
            quote = c
        elif c == 0x5B:  # [
            depth += 1
        elif c == 0x5D:  # ]
            depth -= 1
        elif c == 0x3E and depth <= 0:  # >
            return i
    return -1
