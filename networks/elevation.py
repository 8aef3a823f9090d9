"""Suspect elevation on a curve's centre line: lone heights that are not a ramp.

A network may hold a single point far off its neighbours' heights (a real network has a
218 m point on a motorway at about 40 m, which a grade over it reports as 247 %). Such a
point is found with :func:`analysis.vertical.suspect_points` on the centre line's profile
(points at the same station, where lanes join, taken as one), named by its lane and its
index in that lane's shape, and left out: its height is replaced by the line between the
points kept, so that neither the grade nor the vertical checks see it.
"""

from __future__ import annotations

import numpy as np

from analysis.vertical import suspect_points, without_points
from networks.geometry import arc_length
from networks.model import Network

__all__ = ["drop_suspect_elevation"]


def _where(net: Network, lanes: tuple[str, ...], point: np.ndarray) -> str:
    """``lane L point i`` of the first lane whose shape has ``point`` (x, y, z)."""
    for lane in lanes:
        shape = net.lanes[lane].shape if lane in net.lanes else None
        if shape is None or shape.shape[1] < 3:
            continue
        hit = np.flatnonzero(np.all(np.abs(shape[:, :3] - point[:3]) < 1e-6, axis=1))
        if len(hit):
            return f"lane {lane} point {int(hit[0])}"
    return f"point at x {point[0]:.2f}, y {point[1]:.2f}"


def drop_suspect_elevation(net: Network, lanes: tuple[str, ...],
                           line: np.ndarray) -> tuple[np.ndarray, str]:
    """The centre line with its suspect heights taken out, and what was taken out (``""``
    when nothing was).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> net = SimpleNamespace(lanes={})  # a network without lanes: no lane to name
    >>> line = np.array([[0, 0, 40.0], [50, 0, 40.2], [122, 0, 218], [200, 0, 40.6]])
    >>> clean, note = drop_suspect_elevation(net, (), line)
    >>> clean[:, 2].round(2).tolist()
    [40.0, 40.2, 40.39, 40.6]
    >>> note.split(" (")[0]
    'point at x 122.00, y 0.00: z 218.00 m, 177.6 m off the line through its neighbours'
    >>> note.split(" (")[1]
    'grades +247 % and -227 %): suspect geometry, left out of the grade'

    A line without a lone point (the degenerate case of one with two points) is returned as
    it is:

    >>> drop_suspect_elevation(net, (), line[:2])[1]
    ''
    """
    if len(line) < 3 or line.shape[1] < 3:
        return line, ""
    s = arc_length(line)
    first = np.r_[True, np.diff(s) > 1e-6]  # one point per station (lanes' joints)
    su, zu = s[first], line[first, 2]
    found = suspect_points(su, zu)
    if not len(found):
        return line, ""
    notes = []
    rows = np.flatnonzero(first)
    for i in found.tolist():
        ds_in, ds_out = su[i] - su[i - 1], su[i + 1] - su[i]
        g_in = 100 * (zu[i] - zu[i - 1]) / ds_in
        g_out = 100 * (zu[i + 1] - zu[i]) / ds_out
        off = zu[i] - (zu[i - 1] + ds_in / (ds_in + ds_out) * (zu[i + 1] - zu[i - 1]))
        notes.append(f"{_where(net, lanes, line[rows[i]])}: z {zu[i]:.2f} m, {abs(off):.1f} m "
                     f"off the line through its neighbours (grades {g_in:+.0f} % and "
                     f"{g_out:+.0f} %): suspect geometry, left out of the grade")
    drop = np.flatnonzero(np.isin(s, su[found]))
    clean = line.copy()
    clean[:, 2] = without_points(s, line[:, 2], drop)
    return clean, "; ".join(notes)
