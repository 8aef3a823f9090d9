"""Suspect elevation: lone heights of a network's lanes that are not a ramp, repaired once.

A network may hold a single shape point far off its neighbours' heights (a real network has
a 218 m point on a motorway at about 40 m, which a grade over it reports as 247 %; a hostile
one a point at 1e6 m at a lane's junction end). Such a point is found with
:func:`clearance.analysis.vertical.suspect_points` on the profile of every way through the network a
vehicle drives (:func:`repair_suspect_heights`: each connection's approach lane, internal
lane and exit lane end to end, and each lane alone; points at the same station, where lanes
join, taken as one), named by its lane and its index in that lane's shape, and its height
is replaced by the line through its neighbours *in the network itself*, before any centre
line, area or storey is made of it: neither the grade, nor the vertical checks, nor the
levels (docs/design.md §6) see it. The notes name each point
(:attr:`clearance.networks.model.Network.suspect_heights`, and
:attr:`~clearance.networks.model.Network.repairs`,
which a command shows as warnings).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np

from clearance.analysis.vertical import suspect_points, without_points
from clearance.networks.geometry import arc_length
from clearance.networks.model import Network

__all__ = ["repair_suspect_heights", "suspect_notes"]


def _ways(net: Network) -> Iterator[tuple[str, ...]]:
    """The lane sequences whose profiles are searched: every lane alone, and every
    connection's from lane, ``via`` lane and to lane."""
    for lane_id in net.lanes:
        yield (lane_id,)
    lanes = net.lanes
    for c in net.connections:
        way = (c.from_lane, c.via, c.to_lane) if c.via else (c.from_lane, c.to_lane)
        if all(k in lanes for k in way):
            yield way


def repair_suspect_heights(net: Network) -> None:
    """Replace every lone height of ``net``'s lane shapes by the line through its neighbours
    (in place), and say so: a note per point in ``net.suspect_heights[lane]`` and in
    ``net.repairs``. A network without heights costs one look at its lanes.

    Examples
    --------
    A lane of a motorway at about 40 m whose middle point is at 218 m:

    >>> from clearance.networks.model import Edge, Lane, Location
    >>> shape = np.array([[0, 0, 40.0], [50, 0, 40.2], [122, 0, 218], [200, 0, 40.6]])
    >>> lane = Lane("m_0", "m", 0, 3.5, "normal", frozenset(), shape, 200.0, 33.0)
    >>> net = Network("n", {"m_0": lane}, {"m": Edge("m", "a", "b", "normal", 1, ["m_0"])},
    ...               [], {}, [], Location())
    >>> repair_suspect_heights(net)
    >>> net.lanes["m_0"].shape[:, 2].round(2).tolist()
    [40.0, 40.2, 40.39, 40.6]
    >>> print(net.suspect_heights["m_0"][0])  # doctest: +NORMALIZE_WHITESPACE
    lane m_0 point 2: z 218.00 m, 177.6 m off the line through its neighbours (grades +247 %
    and -227 %): suspect geometry, taken as the line between them

    A flat network (the degenerate case) is left as it is:

    >>> net.lanes["m_0"].shape[:, 2] = 0.0
    >>> net.suspect_heights.clear(); repair_suspect_heights(net); net.suspect_heights
    {}
    """
    if not any(np.ptp(lane.shape[:, 2]) > 0 for lane in net.lanes.values()):
        return
    fixed: dict[tuple[str, int], float] = {}
    notes: dict[tuple[str, int], str] = {}
    for way in _ways(net):
        shapes = [net.lanes[k].shape for k in way]
        if not any(np.ptp(s[:, 2]) > 0 for s in shapes):
            continue
        _search(way, shapes, fixed, notes)
    for (lane_id, i), z in sorted(fixed.items()):
        net.lanes[lane_id].shape[i, 2] = z
    for (lane_id, _), note in sorted(notes.items()):
        net.suspect_heights.setdefault(lane_id, []).append(note)
        net.repairs.append(note)


def _search(way: Sequence[str], shapes: Sequence[np.ndarray],
            fixed: dict[tuple[str, int], float], notes: dict[tuple[str, int], str]) -> None:
    """The lone points of one way's profile: their repaired heights into ``fixed`` and
    their notes into ``notes``, by (lane, point index), the first way to find one
    deciding its height."""
    line = np.concatenate(shapes)
    owner = [(k, i) for k, s in zip(way, shapes, strict=True) for i in range(len(s))]
    s = arc_length(line)
    first = np.r_[True, np.diff(s) > 1e-6]  # one point per station (lanes' joints)
    su, zu = s[first], line[first, 2]
    found = suspect_points(su, zu)
    if not len(found):
        return
    clean = without_points(s, line[:, 2], np.flatnonzero(np.isin(s, su[found])))
    for i in found.tolist():
        ds_in, ds_out = su[i] - su[i - 1], su[i + 1] - su[i]
        g_in = 100 * (zu[i] - zu[i - 1]) / ds_in
        g_out = 100 * (zu[i + 1] - zu[i]) / ds_out
        off = zu[i] - (zu[i - 1] + ds_in / (ds_in + ds_out) * (zu[i + 1] - zu[i - 1]))
        rows = np.flatnonzero(s == su[i])
        lane_id, index = owner[int(rows[0])]
        notes.setdefault((lane_id, index), (
            f"lane {lane_id} point {index}: z {zu[i]:.2f} m, {abs(off):.1f} m off the line "
            f"through its neighbours (grades {g_in:+.0f} % and {g_out:+.0f} %): suspect "
            "geometry, taken as the line between them"))
        for r in rows.tolist():
            fixed.setdefault(owner[r], float(clean[r]))


def suspect_notes(net: Network, lanes: Sequence[str]) -> str:
    """The notes on the suspect heights of ``lanes`` (``""``: none), in the order of the
    lanes, each once.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> suspect_notes(NS(suspect_heights={"a": ["x"], "b": ["y"]}), ("b", "c", "a", "b"))
    'y; x'
    """
    seen = dict.fromkeys(n for k in lanes for n in net.suspect_heights.get(k, ()))
    return "; ".join(seen)
