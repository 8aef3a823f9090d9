"""The room a swing has: how far a lane's centre line may move sideways on the pavement.

A swung path (:mod:`clearance.networks.driving.candidates`) is sized by the room the pavement gives
the vehicle's side toward the outside of the turn (and toward the inside, for a corner cut),
measured along the centre line's normals at the feature's start, middle and end.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from clearance.analysis.polyline import Path

__all__ = ["ROOM_SAMPLES", "THROUGH_SEARCH_DEG", "THROUGH_TURN_DEG", "outside_room_m",
           "outside_rooms_m", "outside_sign", "search_turn_deg"]


def outside_sign(turn_angle_deg: float) -> float:
    """The sign of an offset toward the outside of a turn (left positive offsets).

    Examples
    --------
    >>> outside_sign(90.0), outside_sign(-35.0), outside_sign(0.0)
    (-1.0, 1.0, 0.0)
    """
    return 0.0 if turn_angle_deg == 0 else math.copysign(1.0, -turn_angle_deg)


#: A net turn this small (degrees) is a through passage's float noise, not a hand: the
#: roundabout's passages straight across come out at +-1e-13 degrees, whose sign chose the
#: side of their swing search at random.
THROUGH_TURN_DEG = 1e-6
#: The turn a through passage is searched as (degrees): as small as the noise it replaces.
THROUGH_SEARCH_DEG = 1e-3


def search_turn_deg(turn_angle_deg: float, path: Path, feature_m: tuple[float, float]
                    ) -> float:
    """The turn a run's swing search takes its outside from: the feature's own turn, or for
    a through passage (net turn within :data:`THROUGH_TURN_DEG`) a tiny turn against the
    hand of the feature's middle (:data:`THROUGH_SEARCH_DEG`), so that it swings toward the
    inside of what it goes around: across a roundabout, the ring's inside (the apron side),
    which its entry and exit deflections turn away from. A straight passage stays 0.

    Examples
    --------
    Straight across a ring drawn counter-clockwise (right-hand traffic): deflected right on
    entry, left around the ring, right on exit; searched as a hair's right turn, whose
    outside is the left, the island's side:

    >>> from clearance.analysis.polyline import prepare_path
    >>> a = np.radians(np.linspace(-120, 120, 49))
    >>> ring = np.c_[12 * np.sin(a), -12 * np.cos(a)]
    >>> line = np.vstack([[(-30.0, -20.0)], ring, [(30.0, -20.0)]])
    >>> p = prepare_path(line, 0.1)
    >>> t = search_turn_deg(0.0, p, (10.0, p.station_m[-1] - 10.0))
    >>> t < 0, outside_sign(t)
    (True, 1.0)

    A real turn keeps its angle, and a straight line (the degenerate case) stays straight:

    >>> search_turn_deg(-90.0, p, (10.0, 20.0))
    -90.0
    >>> s = prepare_path(np.array([[0.0, 0.0], [50.0, 0.0]]), 0.1)
    >>> search_turn_deg(0.0, s, (10.0, 40.0))
    0.0
    """
    if abs(turn_angle_deg) >= THROUGH_TURN_DEG:
        return turn_angle_deg
    a, b = feature_m
    mid = 0.5 * (a + b)
    third = (b - a) / 6.0
    st = path.station_m
    inside = (st >= mid - third) & (st <= mid + third)
    if int(inside.sum()) < 2:
        return turn_angle_deg
    turned = float(np.sum(np.diff(np.unwrap(path.heading_rad[inside]))))
    if abs(math.degrees(turned)) < 1.0:
        return turn_angle_deg
    return -math.copysign(THROUGH_SEARCH_DEG, turned)


def outside_room_m(path: Path, feature_m: tuple[float, float], side: float,
                   paved: BaseGeometry, half_width_m: float, reach_m: float = 12.0) -> float:
    """How far the centre line may move outward and keep the body's side on the pavement.

    The smallest of :func:`outside_rooms_m` (the feature's start, middle and end), and
    at least 0.

    Examples
    --------
    A lane along y = 0 paved from y = -1.5 to y = 5.1; a 2 m wide car may move left 4.1 m:

    >>> from clearance.analysis.polyline import prepare_path
    >>> p = prepare_path([(0.0, 0.0), (40.0, 0.0)])
    >>> paved = shapely.box(-5.0, -1.5, 45.0, 5.1)
    >>> round(outside_room_m(p, (15.0, 25.0), 1.0, paved, 1.0), 6)
    4.1
    >>> round(outside_room_m(p, (15.0, 25.0), -1.0, paved, 1.0), 6)
    0.5
    """
    return max(0.0, min(outside_rooms_m(path, feature_m, side, paved, half_width_m, reach_m)))


#: Where the room at a feature's end is also looked for: ``(metres beyond the end, the
#: share of the swing a ramp of 8 m still has there)`` (a half cosine, 1 at the end).
ROOM_SAMPLES = ((0.0, 1.0), (2.0, 0.854), (4.0, 0.5), (6.0, 0.146))


def outside_rooms_m(path: Path, feature_m: tuple[float, float], side: float,
                    paved: BaseGeometry, half_width_m: float, reach_m: float = 12.0
                    ) -> tuple[float, float, float]:
    """How far the centre line may move toward ``side`` at the feature's start, middle and
    end: the distance along the normal to the paved area's edge less ``half_width_m``
    (``-half_width_m`` where a point is off the pavement; ``reach_m - half_width_m`` where
    the pavement goes on further).

    The room at the start (end) is the smallest over :data:`ROOM_SAMPLES`: at the
    feature's start and 2, 4 and 6 m before it, each divided by the share of the swing a
    ramp still has there, so that a lane that narrows just before (after) the feature, as
    where a junction's pavement gives way to a one-lane street, bounds the swing too.

    Examples
    --------
    A lane along y = 0 paved to y = 5.1 up to x = 22 and to y = 1.5 beyond; a swing may
    be 4.1 m wide at the feature's start (x = 15) but only 0.5 m at its end (x = 25):

    >>> from clearance.analysis.polyline import prepare_path
    >>> p = prepare_path([(0.0, 0.0), (40.0, 0.0)])
    >>> paved = shapely.union(shapely.box(-5.0, -1.5, 22.0, 5.1), shapely.box(19, -1.5, 45, 1.5))
    >>> [round(r, 6) for r in outside_rooms_m(p, (15.0, 25.0), 1.0, paved, 1.0)]
    [4.1, 4.1, 0.5]

    The same lane with its feature ending at x = 20: the lane narrows 2 m after it, where
    the ramp down still has 85 % of the swing, so the room at the end is 0.5 / 0.854:

    >>> [round(r, 3) for r in outside_rooms_m(p, (10.0, 20.0), 1.0, paved, 1.0)]
    [4.1, 4.1, 0.585]
    """
    cs, ce = feature_m
    ahead = [(cs - x, w) for x, w in ROOM_SAMPLES]
    after = [(ce + x, w) for x, w in ROOM_SAMPLES]
    where = [*ahead, (0.5 * (cs + ce), 1.0), *after]
    s = np.clip(np.array([x for x, _ in where]), 0.0, path.length_m)
    share = np.array([w for _, w in where])
    xy = path.point_at(s)
    h = path.heading_at(s)
    n = side * np.stack([-np.sin(h), np.cos(h)], axis=1)
    rays = shapely.linestrings(np.stack([xy, xy + reach_m * n], axis=1))
    start = shapely.points(xy)
    edge = shapely.boundary(paved)
    room = []
    covered = np.asarray(shapely.covers(paved, start), dtype=bool)
    for ray, p0, inside in zip(np.asarray(rays, dtype=object), np.asarray(start, dtype=object),
                               covered, strict=True):
        if not inside:
            room.append(0.0)
            continue
        hit = shapely.intersection(ray, edge)
        room.append(float(shapely.distance(p0, hit)) if not hit.is_empty else reach_m)
    free = (np.array(room) - half_width_m) / share
    k = len(ahead)
    return float(free[:k].min()), float(free[k]), float(free[k + 1:].min())
