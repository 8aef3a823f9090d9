"""File names made from ids: readable, within file-system limits, stable and unique.

Curve ids, vehicle and network names can be long (an OpenStreetMap curve id of 250
characters) and hold characters a file name should not (``/``, ``:``, ``#``, ``>``,
spaces). :func:`file_name` keeps letters, digits, ``.``, ``-`` and ``_`` and turns
anything else into ``_``. When that changed anything, or the name would be longer than
:data:`MAX_NAME_BYTES`, it cuts the readable part and appends ``~`` and 16 hex digits of
the SHA-256 of the exact parts. So:

* every name is at most :data:`MAX_NAME_BYTES` bytes (ASCII), which leaves room under the
  255-byte limit of common file systems for the atomic writer's temporary name
  (``.<name>.<8 characters>.tmp``);
* a name depends only on its own parts (the same id gives the same name in every run,
  whatever else is in the study);
* two different lists of parts give different names: a name without ``~`` is the parts
  themselves, joined so that they can be read back, and ``~`` is never kept from a part,
  so it marks a name with a hash (16 hex digits, 64 bits: a clash among a million names
  has a chance of about 3e-8).
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Sequence

__all__ = ["MAX_NAME_BYTES", "file_name"]

#: Longest generated file name in bytes, suffix included.
MAX_NAME_BYTES = 200

_UNSAFE = re.compile(r"[^A-Za-z0-9._-]")
_HASH_DIGITS = 16
_SEP = "__"


def file_name(parts: Sequence[str], suffix: str = "", room: int = 0) -> str:
    """A file name for ``parts`` (ids, names) joined by ``__``, ending in ``suffix``.

    Parameters
    ----------
    parts
        The ids the file stands for, e.g. ``(vehicle, curve_id)``.
    suffix
        Appended as is (``".csv"``); it must itself be a safe name.
    room
        Bytes to leave for a suffix the caller appends later (a figure stem's ``.png``).

    Returns
    -------
    str
        At most :data:`MAX_NAME_BYTES` bytes less ``room``, only ``[A-Za-z0-9._~-]``,
        never starting with ``.``.

    Examples
    --------
    >>> file_name(["P", "bend3"], ".csv")
    'P__bend3.csv'
    >>> file_name(["P", "turn:X:XN_in_0->XW_out_0"], ".csv")
    'P__turn_X_XN_in_0-_XW_out_0~dcaa41e1a86e8078.csv'
    >>> len(file_name(["P", "e#1/" * 60], ".csv"))
    200
    >>> len(file_name(["e#1/" * 60], room=4)) + len(".png")
    200
    >>> file_name([""])  # degenerate: nothing readable is left
    '_~e3b0c44298fc1c14'
    """
    if _UNSAFE.search(suffix) or not 0 <= len(suffix) + room <= MAX_NAME_BYTES // 4:
        raise ValueError(f"file_name: unsafe suffix {suffix!r} or room {room}")
    cleaned = [_UNSAFE.sub("_", p) for p in parts]
    readable = _SEP.join(cleaned)
    # kept as is only when the parts can be read back: no part holds the separator or
    # begins or ends with "_" (``a_`` + ``b`` and ``a`` + ``_b`` would both be ``a___b``)
    exact = (cleaned == list(parts) and not readable.startswith(".")
             and all(p and _SEP not in p and p[0] != "_" and p[-1] != "_" for p in parts))
    if exact and len(readable) + len(suffix) + room <= MAX_NAME_BYTES:
        return readable + suffix
    digest = hashlib.sha256("\0".join(parts).encode("utf-8", "surrogatepass")).hexdigest()
    keep = MAX_NAME_BYTES - room - len(suffix) - 1 - _HASH_DIGITS
    head = readable.lstrip(".")[:keep] or "_"
    return f"{head}~{digest[:_HASH_DIGITS]}{suffix}"
