"""Opening SUMO XML files safely: plain or gzip, no entities, no network, no DOCTYPE tricks.

Only the named file is opened: never a DTD it names (``<!DOCTYPE net SYSTEM "...">``),
never anything on the network. Only a regular file is read (a FIFO, a device, a directory
or a symlink loop is refused before a byte is read), and no more than
:func:`max_bytes` of it, decompressed. Every failure becomes an
:class:`~clearance.vehicles.errors.NetworkError` that names the file.
"""

from __future__ import annotations

import gzip
import os
import re
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

from clearance.vehicles.errors import InputError, LimitError, NetworkError
from clearance.vehicles.files import env_limit, open_regular

__all__ = ["DEFAULT_MAX_BYTES", "DEFAULT_MAX_ELEMENTS", "MAX_ELEMENTS_ENV", "MAX_MB_ENV",
           "MAX_PROLOG_BYTES", "max_bytes", "max_elements", "open_binary", "read_chunks",
           "scan_prolog", "too_big"]

#: How much of the prolog (decompressed) is read at most while looking for the root element.
MAX_PROLOG_BYTES = 4 * 1024 * 1024

_NAME_RE = re.compile(rb"[A-Za-z_:][-A-Za-z0-9_.:]*")

#: Default of :func:`max_bytes`: 1 GB of XML, decompressed. The largest network this tool
#: is measured on (a 10,000-junction netgenerate grid, about 430,000 connections) is 132 MB;
#: a network 8 times its size would need about 9 GB to extract its curves.
DEFAULT_MAX_BYTES = 1_000_000_000

#: Default of :func:`max_elements`: 5 million lanes, edges, connections, junctions and
#: roundabouts, about 5 times the grid above (about a million of them); 28 million
#: connections took 5.9 GB to read.
DEFAULT_MAX_ELEMENTS = 5_000_000

#: The environment variables that raise (or lower) the two caps.
MAX_MB_ENV = "CLEARANCE_MAX_MB"
MAX_ELEMENTS_ENV = "CLEARANCE_MAX_ELEMENTS"


def max_bytes() -> int:
    """How many bytes of XML (decompressed) a network may have: ``CLEARANCE_MAX_MB``
    megabytes (10**6 bytes) if set, else :data:`DEFAULT_MAX_BYTES`.

    Examples
    --------
    >>> max_bytes() == DEFAULT_MAX_BYTES or MAX_MB_ENV in os.environ
    True
    """
    return env_limit(MAX_MB_ENV, DEFAULT_MAX_BYTES, 10**6)


def max_elements() -> int:
    """How many elements a network may have: ``CLEARANCE_MAX_ELEMENTS`` if set, else
    :data:`DEFAULT_MAX_ELEMENTS`."""
    return env_limit(MAX_ELEMENTS_ENV, DEFAULT_MAX_ELEMENTS)


def too_big(path: str | os.PathLike[str], what: str, limit: int, env: str) -> LimitError:
    """The error for a file over one of the caps: what was exceeded, and how to raise it."""
    shown = f"{limit / 1e6:g} MB" if env == MAX_MB_ENV else f"{limit:,} elements"
    return LimitError(
        f"{path}: refused: {what} exceeds the limit of {shown}, far more than a plausible "
        f"network needs (a corrupt file or a decompression bomb?); to read it anyway, set "
        f"the environment variable {env} higher"
    )


def open_binary(path: str | os.PathLike[str],
                error: type[InputError] = NetworkError) -> BinaryIO:
    """Open ``path`` for reading bytes, decompressing it when it is gzip (by its magic bytes).

    Raises
    ------
    NetworkError
        (or ``error``, for files other than networks) The file does not exist, is not a
        regular file, cannot be read, or is a plain file
        larger than :func:`max_bytes`.
    """
    p = Path(path)
    raw = open_regular(p)
    try:
        magic = raw.read(2)
        raw.seek(0)
    except OSError as exc:
        raw.close()
        raise error(f"{p}: cannot be read ({exc.strerror})", file=p) from None
    if magic == b"\x1f\x8b":
        return gzip.GzipFile(fileobj=raw, mode="rb")  # type: ignore[return-value]
    limit = max_bytes()
    if os.fstat(raw.fileno()).st_size > limit:
        raw.close()
        raise too_big(p, "the file's size", limit, MAX_MB_ENV)
    return raw


def read_chunks(fh: BinaryIO, path: str | os.PathLike[str], size: int) -> Iterator[bytes]:
    """The bytes of an opened file in chunks of ``size``, refusing more than
    :func:`max_bytes` of them in all (a gzip file is counted decompressed).

    Examples
    --------
    >>> import io
    >>> [len(c) for c in read_chunks(io.BytesIO(b"abcde"), "x", 2)]
    [2, 2, 1]
    """
    limit = max_bytes()
    total = 0
    while chunk := fh.read(size):
        total += len(chunk)
        if total > limit:
            raise too_big(path, "its decompressed size", limit, MAX_MB_ENV)
        yield chunk


def scan_prolog(path: str | os.PathLike[str], error: type[InputError] = NetworkError) -> str:
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
    with open_binary(p, error) as fh:
        pos = 0
        while True:
            if len(buf) - pos < 4096 and len(buf) < MAX_PROLOG_BYTES:
                try:
                    chunk = fh.read(65536)
                except (OSError, EOFError) as exc:
                    raise error(f"{p}: cannot be decompressed ({exc})", file=p) from exc
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
                    raise error(f"{p}: the file is empty", file=p)
                raise error(f"{p}: not XML (no root element found)", file=p)
            if buf.startswith(b"<?", pos):
                end = buf.find(b"?>", pos)
                pos = _advance(p, buf, end, 2, error)
            elif buf.startswith(b"<!--", pos):
                end = buf.find(b"-->", pos)
                pos = _advance(p, buf, end, 3, error)
            elif buf.startswith(b"<!DOCTYPE", pos) or buf.startswith(b"<!doctype", pos):
                start = pos
                end = _doctype_end(buf, pos)
                pos = _advance(p, buf, end, 1, error)
                if b"<!ENTITY" in buf[start:pos].upper():
                    raise error(
                        f"{p}: refused: the DOCTYPE declares entities (entity expansion is "
                        "never performed)"
                    )
            elif buf.startswith(b"<", pos):
                m = _NAME_RE.match(buf, pos + 1)
                if not m:
                    raise error(f"{p}: not XML (unexpected markup at byte {pos})", file=p)
                return m.group(0).decode("ascii", "replace")
            else:
                raise error(f"{p}: not XML (text before the root element)", file=p)
            if pos >= MAX_PROLOG_BYTES:
                raise error(f"{p}: the XML prolog is longer than {MAX_PROLOG_BYTES} bytes",
                                 file=p)


def _advance(path: Path, buf: bytes, end: int, marker_len: int,
             error: type[InputError] = NetworkError) -> int:
    if end < 0:
        if len(buf) >= MAX_PROLOG_BYTES:
            raise error(f"{path}: the XML prolog is longer than {MAX_PROLOG_BYTES} bytes")
        raise error(f"{path}: not XML or truncated (unterminated markup in the prolog)")
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
