"""Where an envelope reaches farthest beyond an area, and how much wider the area must be.

Design feedback for a run that is not clear (docs/design.md §6, *Design feedback*): the
point of the (measured, i.e. grown by the clearance offset) envelope that lies farthest
outside the area the verdict is decided on, its station along the curve's centre line,
and the *extra width*: how far the area would have to be widened, there and wherever
else the envelope leaves it, for the envelope to stay inside it.

The farthest point is sought as :func:`clearance.analysis.margins.signed_margin_m` seeks the
overreach: on the envelope's boundary beyond the area, and at the pole of inaccessibility
of a piece beyond the area that holds none of that boundary (an island the envelope covers
whole). The boundary is probed every ``2 tolerance_m``; the distance to the area is
1-Lipschitz, so the true overreach is at most ``tolerance_m`` more than the one found, and
the extra width (the overreach found plus ``tolerance_m``, rounded up to the centimetre) is
never short: the area grown by it covers the envelope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike
from shapely.geometry.base import BaseGeometry

__all__ = ["DEFAULT_TOLERANCE_M", "Overreach", "worst_overreach"]

DEFAULT_TOLERANCE_M = 0.025
"""The overreach found is at most this short of the true one (m)."""


@dataclass(frozen=True)
class Overreach:
    """The worst overreach of an envelope beyond an area.

    Attributes
    ----------
    distance_m
        How far the envelope's farthest point lies beyond the area (m, > 0).
    x, y
        That point, in the envelope's plane coordinates (m).
    station_m
        Its station along the reference line (the nearest point of the line; m from the
        line's start), NaN without a line.
    extra_width_m
        How much the area must be widened (grown outward) for the envelope to stay in it:
        ``distance_m`` plus the search's tolerance, rounded up to the centimetre (m).
    """

    distance_m: float
    x: float
    y: float
    station_m: float
    extra_width_m: float


def worst_overreach(envelope: BaseGeometry, area: BaseGeometry,
                    line: ArrayLike | shapely.LineString | None = None,
                    tolerance_m: float = DEFAULT_TOLERANCE_M,
                    min_area_m2: float = 1e-6) -> Overreach | None:
    """The envelope's point farthest beyond ``area`` (see the module docstring).

    Parameters
    ----------
    envelope, area
        Polygons (shapely, metres).
    line
        The reference line the station is measured along: ``(n, 2+)`` points or a
        LineString (the curve's centre line); ``None``: no station.
    tolerance_m
        The overreach found is at most this short of the true one (m, > 0).
    min_area_m2
        Pieces of the envelope beyond the area smaller than this are noise of the polygon
        arithmetic along a shared edge: ``None`` when there are only those.

    Returns
    -------
    Overreach or None
        ``None`` when the envelope stays inside the area.

    Examples
    --------
    A 4 m x 3 m envelope over a 2 m deep area reaches 1 m beyond it, along its top edge;
    the station is measured along a line on y = 0:

    >>> o = worst_overreach(shapely.box(0, 0, 4, 3), shapely.box(-1, -1, 5, 2),
    ...                     [(0.0, 0.0), (10.0, 0.0)])
    >>> round(o.distance_m, 6), round(o.y, 6), 0 <= o.station_m <= 4, o.extra_width_m
    (1.0, 3.0, True, 1.03)

    An envelope inside its area has none:

    >>> worst_overreach(shapely.box(0, 0, 1, 1), shapely.box(-1, -1, 2, 2)) is None
    True
    """
    if not (math.isfinite(tolerance_m) and tolerance_m > 0):
        raise ValueError(f"worst_overreach: tolerance must be > 0 m, got {tolerance_m!r}")
    if envelope.is_empty or shapely.covers(area, envelope):
        return None
    beyond = shapely.difference(envelope, area)
    pieces = shapely.get_parts(beyond)
    pieces = pieces[~shapely.is_empty(pieces) & (shapely.area(pieces) >= min_area_m2)]
    if not len(pieces):
        return None
    lines = shapely.difference(shapely.boundary(envelope), area)
    probes = [np.empty((0, 2))]
    if not lines.is_empty:
        probes.append(shapely.get_coordinates(shapely.segmentize(lines, 2.0 * tolerance_m)))
        lone = pieces[~shapely.intersects(pieces, lines)]
    else:
        lone = pieces
    if len(lone):
        poles = shapely.maximum_inscribed_circle(lone, tolerance_m)
        probes.append(shapely.get_coordinates(shapely.get_point(poles, 0)))
    pts = np.concatenate(probes)
    if not len(pts):
        return None
    d = np.asarray(shapely.distance(shapely.points(pts), area), dtype=float)
    i = int(np.argmax(d))
    if not d[i] > 0:
        return None
    x, y = float(pts[i, 0]), float(pts[i, 1])
    station = math.nan
    if line is not None:
        ref = line if isinstance(line, shapely.LineString) else shapely.LineString(
            np.asarray(line, dtype=float)[:, :2])
        station = float(ref.project(shapely.Point(x, y)))
    extra = math.ceil(round((float(d[i]) + tolerance_m) * 100.0, 6)) / 100.0
    return Overreach(float(d[i]), x, y, station, extra)
