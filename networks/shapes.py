"""SUMO shape strings (``"x,y x,y,z ..."``) parsed into (N, 3) arrays, one or many at once.

Example
-------
>>> parse_shape("0,0 3,4,1.5")[1]
array([3. , 4. , 1.5])
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from itertools import repeat

import numpy as np

from clearance.vehicles.errors import NetworkError

__all__ = ["EMPTY_SHAPE", "MAX_COORD_M", "parse_shape", "parse_shapes"]

#: The largest coordinate accepted, in metres (after the network's ``netOffset``). No
#: projection of the earth SUMO uses gives more (web Mercator reaches +/-2.0e7 m), and a
#: double resolves 1.5e-8 m at 1e8 m, far finer than the millimetres a clearance is given
#: in; beyond it precision is lost (at 1e15 m the step is 0.125 m and radii come out wrong).
MAX_COORD_M = 1e8

#: The shape of a lane or junction without one (read-only, shared).
EMPTY_SHAPE = np.zeros((0, 3))
EMPTY_SHAPE.flags.writeable = False


def parse_shape(text: str) -> np.ndarray:
    """Parse one SUMO shape string (points ``x,y`` or ``x,y,z``) into an (N, 3) array.

    Examples
    --------
    >>> parse_shape("0,0 3,4,1.5")
    array([[0. , 0. , 0. ],
           [3. , 4. , 1.5]])
    >>> parse_shape("").shape
    (0, 3)
    """
    pts = text.split()
    out = np.zeros((len(pts), 3))
    for i, pt in enumerate(pts):
        vals = pt.split(",")
        if len(vals) not in (2, 3):
            raise ValueError(f"point {pt!r} is not x,y or x,y,z")
        out[i, : len(vals)] = [float(v) for v in vals]
    return out


def parse_shapes(
    texts: list[str], names: list[str] | None = None, what: str = "shape",
    on_bad: Callable[[int, str], None] | None = None,
) -> list[np.ndarray]:
    """Parse many shape strings at once (fast path: one numpy call per kind of shape).

    Strings that are all ``x,y`` or all ``x,y,z`` with single spaces are parsed in bulk,
    grouped by dimensionality and number of points (each group becomes one (M, N, 3)
    array whose rows are the shapes returned); others (mixed, or irregular spacing) one
    by one with :func:`parse_shape`. A bad shape (not numbers, a coordinate not finite or
    beyond :data:`MAX_COORD_M`) raises :class:`~clearance.vehicles.errors.InputError` naming
    ``what`` and the string's entry in ``names``; with ``on_bad``, it is called with the
    string's index and the reason instead, and the shape is empty.

    Examples
    --------
    >>> [a.shape for a in parse_shapes(["0,0 1,1", "0,0,1 1,1,2 2,2", ""])]
    [(2, 3), (3, 3), (0, 3)]
    >>> bad = []
    >>> [a.shape for a in parse_shapes(["0,0 -nan,1", "0,0 1,1"], on_bad=lambda i, why:
    ...                                 bad.append((i, why)))]
    [(0, 3), (2, 3)]
    >>> bad
    [(0, "shape #1: non-finite coordinate in shape '0,0 -nan,1'")]
    """
    n = len(texts)
    length = np.fromiter(map(len, texts), np.int64, n)
    trimmed = np.fromiter(map(len, map(str.strip, texts, repeat(" "))), np.int64, n)
    counts = np.fromiter(map(str.count, texts, repeat(" ")), np.int64, n) + 1
    commas = np.fromiter(map(str.count, texts, repeat(",")), np.int64, n)
    regular = (length > 0) & (trimmed == length)
    dims = np.where(commas == counts, 2, np.where(commas == 2 * counts, 3, 0)) * regular
    pool: list[np.ndarray] = [EMPTY_SHAPE]  # out[i] is pool[where[i]]
    where = np.zeros(n, dtype=np.int64)

    def add(indices: list[int], arrays: list[np.ndarray]) -> None:
        where[indices] = np.arange(len(pool), len(pool) + len(arrays))
        pool.extend(arrays)

    def one(i: int) -> np.ndarray:
        if on_bad is None:
            return _parse_one(texts[i], names, what, i)
        try:
            return _parse_one(texts[i], names, what, i)
        except NetworkError as exc:
            on_bad(i, str(exc))
            return EMPTY_SHAPE

    odd = np.flatnonzero((length > 0) & (dims == 0)).tolist()
    add(odd, [one(i) for i in odd])
    failed: dict[int, list[int]] = {2: [], 3: []}
    key = dims * (counts.max(initial=0) + 1) + counts
    order = np.argsort(key, kind="stable")[np.count_nonzero(dims == 0) :]
    cuts = np.flatnonzero(np.diff(key[order])) + 1
    for group in np.split(order, cuts) if len(order) else []:
        dim, count = int(dims[group[0]]), int(counts[group[0]])
        for k in range(0, len(group), _BATCH):
            idx = group[k : k + _BATCH].tolist()
            flat = _bulk_floats(" ".join([texts[i] for i in idx]), dim, count * len(idx))
            if flat is None:
                failed[dim].extend(idx)  # parsed one by one below, to find the bad one
                continue
            block = flat.reshape(len(idx), count, dim)
            if dim == 2:
                block = np.concatenate((block, np.zeros((len(idx), count, 1))), axis=2)
            add(idx, list(block))
    for dim in (2, 3):
        bad = sorted(failed[dim])
        add(bad, [one(i) for i in bad])
    return list(map(pool.__getitem__, where.tolist()))


_BATCH = 20000


def _bulk_floats(joined: str, dim: int, n_points: int) -> np.ndarray | None:
    """The coordinates of ``n_points`` points ``x,y`` (``dim`` 2) or ``x,y,z`` separated by
    single spaces, as parsed one by one would give them; None when ``joined`` is not
    exactly that (a separator out of place, an empty or bad number, one not finite or
    beyond :data:`MAX_COORD_M`).

    Examples
    --------
    >>> _bulk_floats("0,1 2,3.5", 2, 2)
    array([0. , 1. , 2. , 3.5])
    >>> _bulk_floats("0,1 2,3,4", 2, 2) is None
    True
    """
    expected = ((", " if dim == 2 else ",, ") * n_points)[:-1].encode()
    if joined.encode("ascii", "replace").translate(None, _NUMBER_CHARS) != expected:
        return None
    text = joined.replace(",", " ")
    if "  " in text or text[:1] == " " or text[-1:] == " ":
        return None  # an empty number (np.fromstring would skip it)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", DeprecationWarning)  # text left unread
            arr = np.fromstring(text, dtype=np.float64, sep=" ")
    except (ValueError, DeprecationWarning):
        return None
    ok = arr.size == dim * n_points and bool((np.abs(arr) <= MAX_COORD_M).all())  # NaN too
    return arr if ok else None


_NUMBER_CHARS = b"0123456789.+-eE"


def _parse_one(text: str, names: list[str] | None, what: str, i: int) -> np.ndarray:
    what = f"{what} {names[i]!r}" if names is not None else f"{what} #{i + 1}"
    try:
        arr = parse_shape(text)
    except ValueError as exc:
        raise NetworkError(f"{what}: bad shape: {exc}") from exc
    if not np.isfinite(arr).all():
        raise NetworkError(f"{what}: non-finite coordinate in shape {text[:60]!r}")
    if not (np.abs(arr) <= MAX_COORD_M).all():
        raise NetworkError(f"{what}: coordinate beyond +/-{MAX_COORD_M:g} m in shape "
                         f"{text[:60]!r} (precision would be lost)")
    return arr
