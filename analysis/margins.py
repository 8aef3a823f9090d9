"""Signed margins of a swept envelope in an area, and the farthest reach beyond it.

A margin is a signed distance between the envelope (grown by the clearance offset) and an
area: ``>= 0`` is the smallest gap between the envelope and the area's boundary when the
envelope lies inside the area; ``< 0`` is minus how far the envelope reaches beyond it (the
largest distance from the area of any point of the envelope outside it, sought on that
outside part's boundary by branch and bound to within ``densify_m / 2``
(:func:`farthest_on_lines`), or at the pole of inaccessibility of a piece the envelope
covers whole, such as an island). An overreach smaller than :data:`PRECISION_M` counts as
zero: SUMO writes network coordinates to the centimetre, and its lanes kink where a smooth
path does not."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from clearance.analysis.envelope import (
    ring_segments,
)
from clearance.analysis.kernels import farthest_from_segments, segments_distance
from clearance.vehicles.errors import GeometryError

__all__ = ["DEFAULT_DENSIFY_M", "NEAR_M", "PRECISION_M", "farthest_on_lines", "signed_margin_m",
           "within_precision"]


DEFAULT_DENSIFY_M = 0.05
"""An overreach is found to within half this (m); also the pole-of-inaccessibility tolerance."""


NEAR_M = 5.0
"""Margins are first sought within this distance of the envelope's bounding box (m)."""


PRECISION_M = 0.01
"""Overreach below this (m) is within the network's precision and counts as a zero margin."""


def within_precision(margin: float) -> float:
    """``margin``, with an overreach under :data:`PRECISION_M` taken as zero.

    Examples
    --------
    >>> within_precision(-0.004), within_precision(-0.02), within_precision(0.3)
    (0.0, -0.02, 0.3)
    """
    return 0.0 if -PRECISION_M < margin < 0 else margin


def signed_margin_m(
    envelope: BaseGeometry,
    area: BaseGeometry,
    area_boundary: BaseGeometry | None = None,
    densify_m: float = DEFAULT_DENSIFY_M,
    ignore: BaseGeometry | None = None,
    area_segments: np.ndarray | None = None,
) -> float:
    """Signed margin of an envelope in an area (see the module docstring).

    ``ignore`` (optional) is a region where the area's boundary does not count for the gap
    inside: the lanes' ends where the envelope was trimmed (:func:`end_boxes`).
    ``area_segments`` (optional) are the area's boundary segments (:meth:`Areas.segments`),
    found here when not given.

    Examples
    --------
    A 2 m wide envelope centred in a 3.5 m lane has 0.75 m to spare on each side:

    >>> lane = shapely.box(0.0, 0.0, 50.0, 3.5)
    >>> signed_margin_m(shapely.box(10.0, 0.75, 20.0, 2.75), lane)
    0.75

    Shifted 1 m to the left it reaches 0.25 m beyond the lane:

    >>> signed_margin_m(shapely.box(10.0, 1.75, 20.0, 3.75), lane)
    -0.25

    Exactly on the boundary the margin is zero:

    >>> signed_margin_m(shapely.box(10.0, 1.5, 20.0, 3.5), lane)
    0.0
    """
    if envelope.is_empty:
        raise GeometryError("signed_margin_m: the envelope is empty")
    beyond = None  # the envelope beyond the area, computed only when it is not covered
    if not shapely.covers(area, envelope):  # a quick test against the prepared area first
        beyond = shapely.difference(envelope, area)
    outside = beyond
    if beyond is not None and ignore is not None and shapely.area(beyond) >= 1e-6:
        outside = shapely.difference(beyond, ignore)
    if outside is None or shapely.area(outside) < 1e-6:
        # covered, but for slivers under a square millimetre (floating-point noise along a
        # shared edge) and what pokes out in the ignored region (past the trimmed ends)
        boundary = area_boundary if area_boundary is not None else shapely.boundary(area)
        # Only the boundary near the envelope can be nearest: look within a window first
        # (a junction's boundary is long, an envelope local), the whole boundary if need be.
        x0, y0, x1, y1 = envelope.bounds
        for reach in (NEAR_M, math.inf):
            near = boundary
            if math.isfinite(reach):
                near = shapely.clip_by_rect(boundary, x0 - reach, y0 - reach, x1 + reach,
                                            y1 + reach)
            if ignore is not None:
                near = shapely.difference(near, ignore)
            if near.is_empty:
                continue
            gap = float(shapely.distance(envelope, near))
            if gap <= reach:
                return gap
        return math.inf
    # the deepest point lies on the envelope's boundary beyond the area, or, where a piece
    # beyond the area holds none of it (an island the envelope covers whole), at the
    # piece's pole of inaccessibility
    lines = shapely.difference(shapely.boundary(envelope), area)
    pieces = shapely.get_parts(beyond)
    pieces = pieces[~shapely.is_empty(pieces) & (shapely.area(pieces) > 0)]
    lone = pieces[~shapely.intersects(pieces, lines)] if not lines.is_empty else pieces
    extra = np.empty((0, 2))
    if len(lone):
        circles = shapely.maximum_inscribed_circle(lone, densify_m)
        extra = shapely.get_coordinates(shapely.get_point(circles, 0))
    coords, part = shapely.get_coordinates(shapely.get_parts(lines), return_index=True)
    probe = np.concatenate([coords, extra])
    if not len(probe):
        return 0.0
    # Distances to the area's boundary segments that reach into a window about the probes
    # first (every probe lies outside the area, so its distance to the area is that to the
    # boundary): one no larger than the window's margin is exact (the nearest boundary point
    # then lies in the window, on one of those segments); a larger one is measured on the area.
    segs = area_segments if area_segments is not None else np.stack(ring_segments(area), axis=1)
    lo, hi = probe.min(axis=0) - NEAR_M, probe.max(axis=0) + NEAR_M
    into = (np.all(np.maximum(segs[:, 0], segs[:, 1]) >= lo, axis=1)
            & np.all(np.minimum(segs[:, 0], segs[:, 1]) <= hi, axis=1))
    segs = np.ascontiguousarray(segs[into])

    def distance(xy: np.ndarray) -> np.ndarray:
        d = segments_distance(xy, segs)
        far = ~(d <= NEAR_M)
        if far.any():
            d[far] = shapely.distance(shapely.points(xy[far]), area)
        return d

    # compiled; the same search with the area's own distance when a probe is beyond the window
    deepest = farthest_from_segments(coords, part[1:] == part[:-1], segs, densify_m / 2, NEAR_M)
    if math.isnan(deepest):
        deepest = farthest_on_lines(lines, distance, densify_m / 2)
    if len(extra):
        deepest = max(deepest, float(np.max(distance(extra))))
    return -deepest


def farthest_on_lines(
    lines: BaseGeometry,
    distance: Callable[[np.ndarray], np.ndarray],
    tolerance_m: float,
) -> float:
    """Largest value of a distance function over lines, found to within ``tolerance_m``.

    ``distance`` maps ``(k, 2)`` points to ``(k,)`` distances and must be 1-Lipschitz (a
    distance to a fixed set is). Branch and bound: on a segment of length ``L`` whose ends
    are at ``d_a`` and ``d_b`` no point is farther than ``(d_a + d_b + L) / 2``, so only
    segments that could beat the best point found so far by more than the tolerance are
    halved and probed at their midpoints, until none is left. The result is short of the
    true maximum by at most ``tolerance_m``, with far fewer probes than an even densification
    where most of the lines are not the farthest.

    Examples
    --------
    The distance from a circle of radius 1 about the origin, along a 10 m segment through it:

    >>> line = shapely.LineString([(-5.0, 0.2), (5.0, 0.2)])
    >>> to_circle = lambda p: np.abs(np.hypot(p[:, 0], p[:, 1]) - 1.0)
    >>> round(farthest_on_lines(line, to_circle, 0.01), 2)
    4.0

    The farthest point inside a segment, not at its ends (the distance to the x axis along a
    roof line); and no lines at all:

    >>> roof = shapely.LineString([(0.0, 0.0), (4.0, 3.0), (8.0, 0.0)])
    >>> farthest_on_lines(roof, lambda p: np.abs(p[:, 1]), 0.01)
    3.0
    >>> farthest_on_lines(shapely.LineString(), lambda p: np.abs(p[:, 1]), 0.01)
    0.0
    """
    coords, part = shapely.get_coordinates(shapely.get_parts(lines), return_index=True)
    if not len(coords):
        return 0.0
    d = distance(coords)
    best = float(np.max(d))
    joined = part[1:] == part[:-1]
    a, b = coords[:-1][joined], coords[1:][joined]
    da, db = d[:-1][joined], d[1:][joined]
    while len(a):
        bound = 0.5 * (da + db + np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]))
        open_ = bound > best + tolerance_m
        if not open_.any():
            break
        a, b, da, db = a[open_], b[open_], da[open_], db[open_]
        mid = 0.5 * (a + b)
        dm = distance(mid)
        best = max(best, float(np.max(dm)))
        a, b = np.concatenate([a, mid]), np.concatenate([mid, b])
        da, db = np.concatenate([da, dm]), np.concatenate([dm, db])
    return best
