"""The worst overreach of an envelope beyond an area: where, how far, and the extra width."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from clearance.analysis.margins import signed_margin_m
from clearance.analysis.overreach import DEFAULT_TOLERANCE_M, worst_overreach


def test_a_box_beyond_a_lane_by_a_known_depth():
    # closed form: the envelope's top edge lies 1.25 m beyond the lane's, over x 10..20
    lane = shapely.box(0.0, 0.0, 50.0, 3.5)
    env = shapely.box(10.0, 1.0, 20.0, 4.75)
    o = worst_overreach(env, lane, [(0.0, 1.75), (50.0, 1.75)])
    assert o.distance_m == pytest.approx(1.25, abs=1e-9)
    assert o.y == pytest.approx(4.75) and 10.0 <= o.x <= 20.0
    assert o.station_m == pytest.approx(o.x)  # the line runs along x from x = 0
    assert o.extra_width_m == pytest.approx(1.28)  # 1.25 + 0.025, up to the centimetre


def test_the_worst_point_is_found_inside_an_edge_not_only_at_vertices():
    # a roof-shaped envelope over a round area: the farthest point of the edge from the
    # circle is its apex; the tolerance bounds how far short the probe can fall
    disc = shapely.Point(0.0, 0.0).buffer(5.0, quad_segs=64)
    env = shapely.Polygon([(-3.0, 3.0), (0.0, 7.0), (3.0, 3.0), (0.0, 0.0)])
    o = worst_overreach(env, disc)
    true = 7.0 - 5.0
    assert true - DEFAULT_TOLERANCE_M <= o.distance_m <= true + 1e-3
    assert math.hypot(o.x, o.y) == pytest.approx(5.0 + o.distance_m, abs=1e-3)
    assert math.isnan(o.station_m)


def test_an_island_the_envelope_covers_whole_is_measured_at_its_pole():
    # a paved area with a 2 m x 2 m hole (a traffic island) the envelope covers: the
    # envelope's boundary never leaves the area, the island's middle is 1 m from it
    paved = shapely.box(0.0, 0.0, 20.0, 20.0).difference(shapely.box(9.0, 9.0, 11.0, 11.0))
    env = shapely.box(5.0, 5.0, 15.0, 15.0)
    o = worst_overreach(env, paved)
    assert o.distance_m == pytest.approx(1.0, abs=DEFAULT_TOLERANCE_M)
    assert (o.x, o.y) == pytest.approx((10.0, 10.0), abs=DEFAULT_TOLERANCE_M)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_agrees_with_the_clearance_margin_and_the_extra_width_clears(seed):
    """Independent of :func:`signed_margin_m` (branch and bound on segments): the two
    overreaches agree within the tolerances, the point lies on the envelope beyond the
    area, and the area grown by the extra width holds the envelope (margin >= 0)."""
    rng = np.random.default_rng(seed)
    area = shapely.Point(0.0, 0.0).buffer(8.0, quad_segs=6)  # a polygon with corners
    ang = np.sort(rng.uniform(0, 2 * math.pi, 9))
    rad = rng.uniform(4.0, 11.0, 9)
    env = shapely.Polygon(np.c_[rad * np.cos(ang), rad * np.sin(ang)] + rng.uniform(-2, 2, 2))
    env = shapely.make_valid(env)
    margin = signed_margin_m(env, area)
    o = worst_overreach(env, area)
    assert margin < 0 and o is not None
    assert o.distance_m == pytest.approx(-margin, abs=DEFAULT_TOLERANCE_M)
    point = shapely.Point(o.x, o.y)
    beyond = shapely.difference(env, area)
    assert shapely.distance(point, beyond) < 1e-6
    assert shapely.distance(point, area) == pytest.approx(o.distance_m, abs=1e-9)
    widened = shapely.buffer(area, o.extra_width_m, quad_segs=32)
    assert signed_margin_m(env, widened) >= 0.0


def test_an_envelope_inside_its_area_or_on_its_edge_has_none():
    lane = shapely.box(0.0, 0.0, 50.0, 3.5)
    assert worst_overreach(shapely.box(10.0, 0.5, 20.0, 3.0), lane) is None
    assert worst_overreach(shapely.box(10.0, 1.5, 20.0, 3.5), lane) is None  # touching
    assert worst_overreach(shapely.Polygon(), lane) is None
    with pytest.raises(ValueError, match="tolerance"):
        worst_overreach(shapely.box(0, 0, 1, 1), lane, tolerance_m=0.0)
