"""Waivers: known tight spots a team has accepted, honoured by ``check`` and ``report``.

A waiver file is a CSV file (csv module quoting; ``#`` comment lines only before the
header, see :mod:`clearance.reports.results.csv_rows`) with the columns

``curve_id``
    A curve id, or a glob of ids (:func:`fnmatch.fnmatchcase`: ``*``, ``?``, ``[...]``).
    An id is matched literally first, so an id holding ``*`` or ``[`` still matches
    itself (and, as a glob, ids like it: ``a77[0]_0`` also matches ``a770_0``; write
    ``a77[[]0]_0`` to match the bracket only).
``vehicle``
    A vehicle name from the vehicle tables, or ``*`` for every vehicle.
``verdict``
    The accepted verdict: ``encroaches``, ``fails`` or ``cannot-turn``.
``reason``
    Why it is accepted (required: it is shown wherever the run is).
``network`` (optional)
    A network name (the file's stem, as in ``clearance.csv``) or glob; ``*`` when absent.

A run is *waived* when a waiver matches its network, vehicle and curve and its verdict is
not clear and no worse than the accepted one (``error`` is never waived: a run the tool
could not judge is not a design finding). Where several waivers match, the first in the
file that accepts the run's verdict waives it. A waiver that matches no run at all is
reported as unused.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fnmatch import fnmatchcase
from pathlib import Path

import pandas as pd

from clearance.reports.results.csv_rows import read_rows
from clearance.reports.results.records import VERDICT_ORDER
from clearance.vehicles.errors import InputError

__all__ = ["Key", "WAIVABLE", "Waived", "Waiver", "apply_waivers", "read_waivers", "study_waivers"]

#: Verdicts a waiver may accept (worst last).
WAIVABLE = ("encroaches", "fails", "cannot-turn")

#: A run's key: network, vehicle, curve id.
Key = tuple[str, str, str]


@dataclass(frozen=True)
class Waiver:
    """One row of a waiver file."""

    path: str
    line: int
    curve_id: str
    vehicle: str
    verdict: str
    reason: str
    network: str = "*"

    @property
    def where(self) -> str:
        return f"{self.path}:{self.line}"

    def matches(self, network: str, vehicle: str, curve_id: str) -> bool:
        """Whether this waiver is about that run (whatever its verdict).

        Examples
        --------
        >>> w = Waiver("w.csv", 2, "turn:1:a#*", "*", "fails", "known")
        >>> w.matches("n", "P", "turn:1:a#13_0->b_0"), w.matches("n", "P", "turn:2:a#1")
        (True, False)
        >>> Waiver("w.csv", 2, "ramp:[x]", "P", "fails", "r").matches("n", "P", "ramp:[x]")
        True
        """
        return ((self.vehicle == "*" or self.vehicle == vehicle)
                and _glob(self.network, network) and _glob(self.curve_id, curve_id))

    def accepts(self, verdict: str) -> bool:
        """Whether a run with ``verdict`` is no worse than the accepted one (and not clear
        nor an error).

        Examples
        --------
        >>> w = Waiver("w.csv", 2, "*", "*", "fails", "r")
        >>> [w.accepts(v) for v in ("clear", "encroaches", "fails", "cannot-turn", "error")]
        [False, True, True, False, False]
        """
        if verdict not in WAIVABLE:
            return False
        return VERDICT_ORDER[verdict] >= VERDICT_ORDER[self.verdict]


def _glob(pattern: str, value: str) -> bool:
    return pattern == value or fnmatchcase(value, pattern)


def read_waivers(path: Path, vehicles: Sequence[str]) -> list[Waiver]:
    """The waivers of a file; ``vehicles`` are the names a waiver may give (besides ``*``).

    Raises
    ------
    InputError
        A missing or malformed file, a missing column, an empty curve id or reason, an
        accepted verdict that is not one of :data:`WAIVABLE`, or an unknown vehicle: the
        message names the file and line.
    """
    _, rows = read_rows(path, "waiver file", ["curve_id", "vehicle", "verdict", "reason"])
    known = set(vehicles)
    out = []
    for line, row in rows:
        where = f"{path}:{line}"
        curve, vehicle = row["curve_id"].strip(), row["vehicle"].strip()
        verdict, reason = row["verdict"].strip(), row["reason"].strip()
        network = row.get("network", "").strip() or "*"
        if not curve:
            raise InputError(f"{where}: empty curve_id (give an id or a glob such as "
                             "'turn:J1:*')")
        if verdict not in WAIVABLE:
            raise InputError(f"{where}: verdict {verdict!r} cannot be accepted; use one of "
                             f"{', '.join(WAIVABLE)}")
        if vehicle != "*" and vehicle not in known:
            from clearance.vehicles.table import unknown_name_message

            raise InputError(f"{where}: {unknown_name_message(vehicle, sorted(known))}")
        if not reason:
            raise InputError(f"{where}: empty reason (say why the run is accepted)")
        out.append(Waiver(str(path), line, curve, vehicle, verdict, reason, network))
    return out


@dataclass
class Waived:
    """Waivers applied to the runs of a study."""

    reasons: dict[Key, str]  # each waived run -> its waiver's reason
    by: dict[Key, Waiver]  # each waived run -> its waiver
    too_bad: dict[Key, Waiver]  # runs a waiver matches but whose verdict is worse
    unused: list[Waiver]  # waivers that match no run

    def __len__(self) -> int:
        return len(self.reasons)


def apply_waivers(runs: Iterable[tuple[str, str, str, str]],
                  waivers: Sequence[Waiver]) -> Waived:
    """Waive the runs (``network, vehicle, curve_id, verdict``) that ``waivers`` accept.

    Examples
    --------
    >>> ws = [Waiver("w.csv", 2, "turn:J1:*", "*", "encroaches", "narrow lane"),
    ...       Waiver("w.csv", 3, "bend:*", "WB-62", "fails", "service road")]
    >>> w = apply_waivers([("n", "P", "turn:J1:a_0->b_0", "encroaches"),
    ...                    ("n", "WB-62", "turn:J1:a_0->b_0", "fails")], ws)
    >>> w.reasons, [k for k in w.too_bad], [u.line for u in w.unused]
    ({('n', 'P', 'turn:J1:a_0->b_0'): 'narrow lane'}, [('n', 'WB-62', 'turn:J1:a_0->b_0')], [3])
    """
    reasons: dict[Key, str] = {}
    by: dict[Key, Waiver] = {}
    too_bad: dict[Key, Waiver] = {}
    used: set[int] = set()
    for network, vehicle, curve_id, verdict in runs:
        key = (network, vehicle, curve_id)
        for i, w in enumerate(waivers):
            if not w.matches(network, vehicle, curve_id):
                continue
            used.add(i)
            if w.accepts(verdict):
                if key not in by:
                    reasons[key], by[key] = w.reason, w
                    too_bad.pop(key, None)
            elif verdict != "clear" and key not in by:
                too_bad.setdefault(key, w)
    return Waived(reasons, by, too_bad, [w for i, w in enumerate(waivers) if i not in used])


def study_waivers(frame: pd.DataFrame, waivers: Sequence[Waiver]) -> Waived:
    """:func:`apply_waivers` on the rows of a study frame (``clearance.csv`` columns)."""
    return apply_waivers(zip(frame.network, frame.vehicle, frame.curve_id, frame.verdict,
                             strict=True), waivers)
