"""The room a swing has, against closed forms on a ring."""

from __future__ import annotations

import math

import numpy as np
import shapely

from clearance.analysis.polyline import prepare_path
from clearance.networks.driving.room import outside_room_m, outside_rooms_m, outside_sign


def test_room_on_a_ring_is_the_radial_distance_to_its_edges() -> None:
    """A lane on a circle of radius 10 m paved from 6 m to 15 m: a 2 m wide body may move
    15 - 10 - 1 = 4 m outward and 10 - 6 - 1 = 3 m inward, everywhere along the arc."""
    a = np.radians(np.linspace(180.0, 0.0, 361))  # clockwise: a right turn
    path = prepare_path(np.c_[10 * np.cos(a), 10 * np.sin(a)], 0.1)
    ring = shapely.Point(0, 0).buffer(15.0, 256).difference(shapely.Point(0, 0).buffer(6.0, 256))
    side = outside_sign(-180.0)  # a right turn: its outside is to the left
    feature = (8.0, path.length_m - 8.0)
    out = outside_rooms_m(path, feature, side, ring, 1.0)
    inward = outside_rooms_m(path, feature, -side, ring, 1.0)
    assert np.allclose(out, 4.0, atol=0.01)
    assert np.allclose(inward, 3.0, atol=0.01)
    assert math.isclose(outside_room_m(path, feature, side, ring, 1.0), min(out))


def test_room_is_bounded_by_the_reach_and_is_never_below_zero() -> None:
    """Pavement beyond the reach gives the reach less the half width; a path off the
    pavement has no room (``-half`` at the middle, less at the ends, where it is divided
    by the share of the swing a ramp has there), and the room is never below 0."""
    path = prepare_path([(0.0, 0.0), (40.0, 0.0)], 0.1)
    wide = shapely.box(-5, -50, 45, 50)
    assert np.allclose(outside_rooms_m(path, (15.0, 25.0), 1.0, wide, 1.0, reach_m=12.0), 11.0)
    away = shapely.box(-5, 5, 45, 50)
    start, middle, end = outside_rooms_m(path, (15.0, 25.0), 1.0, away, 1.0)
    assert middle == -1.0 and start <= -1.0 and end <= -1.0
    assert outside_room_m(path, (15.0, 25.0), 1.0, away, 1.0) == 0.0
