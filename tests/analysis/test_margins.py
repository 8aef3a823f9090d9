"""Signed margins (clearance.analysis.margins) against closed forms and a dense reference."""

import math

import numpy as np
import pytest
import shapely
import shapely.affinity

from clearance.analysis.margins import signed_margin_m

LANE = shapely.box(0.0, 0.0, 60.0, 3.5)
ROADWAY = shapely.box(0.0, 0.0, 60.0, 7.0)
PAVED = shapely.box(0.0, -0.5, 60.0, 7.5)


def test_margin_inside_is_the_smallest_gap_to_the_boundary() -> None:
    env = shapely.box(10.0, 1.0, 20.0, 2.9)
    assert signed_margin_m(env, LANE) == pytest.approx(0.6)
    assert signed_margin_m(env, ROADWAY) == pytest.approx(1.0)
    assert signed_margin_m(env, PAVED) == pytest.approx(1.5)


def test_margin_beyond_is_minus_the_deepest_overreach() -> None:
    env = shapely.Polygon([(10, 1), (20, 1), (20, 4.3), (15, 4.3), (10, 3.0)])
    assert signed_margin_m(env, LANE) == pytest.approx(-0.8, abs=1e-9)
    # a tilted edge: the deepest point is the corner farthest from the lane
    tilted = shapely.Polygon([(10, 1), (20, 1), (20, 3.9), (10, 4.6)])
    assert signed_margin_m(tilted, LANE) == pytest.approx(-1.1, abs=1e-9)


def test_margin_beyond_a_non_convex_area_uses_the_nearest_part() -> None:
    # L-shaped lanes; the envelope sits in the notch, 3 m from both arms at its far corner
    ell = shapely.difference(shapely.box(0, 0, 10, 10), shapely.box(5, 5, 10, 10))
    env = shapely.box(6, 6, 8, 8)
    assert signed_margin_m(env, ell) == pytest.approx(-3.0, abs=1e-9)
    # a roundabout ring (hole = island): 0.5 m into the island
    ring = shapely.difference(shapely.Point(0, 0).buffer(16, quad_segs=64),
                              shapely.Point(0, 0).buffer(10, quad_segs=64))
    env = shapely.box(-1.0, 9.5, 1.0, 13.0)
    expected = 10.0 * math.cos(math.pi / 256) - 9.5  # polygonal circle, apothem at y axis
    assert signed_margin_m(env, ring) == pytest.approx(-expected, abs=0.03)


def test_margin_when_the_envelope_covers_an_island_whole() -> None:
    # lanes round a 2 m x 6 m island; the envelope covers all of it: 1 m beyond at its middle
    lanes = shapely.difference(shapely.box(0, 0, 20, 10), shapely.box(8, 2, 10, 8))
    env = shapely.box(5, 1, 15, 9)
    assert signed_margin_m(env, lanes) == pytest.approx(-1.0, abs=0.05)


def test_overreach_search_matches_a_dense_reference_on_random_shapes() -> None:
    # an envelope spanning the gap of a U-shaped area: the deepest point is half-way along
    # an edge, not at a vertex. The branch-and-bound search must find it to within its
    # stated 2.5 cm (densify_m / 2), and never report more than the true overreach.
    rng = np.random.default_rng(3)
    for _ in range(20):
        gap, angle = rng.uniform(0.5, 4.0), rng.uniform(0.0, 180.0)
        area = shapely.union_all([shapely.box(0, -2, 20 + gap, 0), shapely.box(0, 0, 10, 5),
                                  shapely.box(10 + gap, 0, 20 + gap, 5)])
        envelope = shapely.box(rng.uniform(2, 9), rng.uniform(2, 4), rng.uniform(11, 18) + gap,
                               rng.uniform(4.5, 7))
        area, envelope = (shapely.affinity.rotate(g, angle, origin=(0, 0))
                          for g in (area, envelope))
        beyond = shapely.difference(envelope, area)
        dense = shapely.points(shapely.get_coordinates(shapely.segmentize(
            shapely.boundary(beyond), 0.002)))
        expected = float(np.max(shapely.distance(dense, area)))
        assert expected > 0.2  # the gap's middle, away from every vertex
        got = -signed_margin_m(envelope, area)
        # (the reference, sampled every 2 mm, may itself fall short by 1 mm)
        assert expected - 0.025 - 1e-9 <= got <= expected + 0.001 + 1e-9
