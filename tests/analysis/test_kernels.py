"""The compiled loops against shapely's own answers on random geometry."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from clearance.analysis.kernels import (
    corner_vertices,
    farthest_from_segments,
    greedy_keys,
    look_back_distance,
    normal_widths,
    pair_hulls,
    project_near,
    segments_distance,
    vertex_path_bounds,
    windowed_distance,
)
from clearance.analysis.margins import farthest_on_lines

RNG = np.random.default_rng(7)


def test_segments_distance_matches_shapely() -> None:
    ring = shapely.Point(0, 0).buffer(5.0, quad_segs=6).exterior
    c = shapely.get_coordinates(ring)
    segs = np.stack([c[:-1], c[1:]], axis=1)
    pts = RNG.uniform(-9, 9, size=(200, 2))
    expected = shapely.distance(shapely.points(pts), ring)
    assert segments_distance(pts, segs) == pytest.approx(expected, abs=1e-9)


def test_windowed_distance_matches_shapely_on_each_window() -> None:
    t = np.linspace(0, 3 * np.pi, 300)
    px, py = 10 * np.cos(t), 10 * np.sin(t) + t  # a rising spiral: its laps do not overlap
    qx, qy = RNG.uniform(-12, 12, 50), RNG.uniform(-12, 20, 50)
    lo = RNG.integers(0, 150, 50)
    hi = lo + RNG.integers(1, 149, 50)
    got = windowed_distance(px, py, qx, qy, lo, hi)
    for i in range(50):
        piece = shapely.LineString(np.c_[px[lo[i]:hi[i] + 1], py[lo[i]:hi[i] + 1]])
        assert got[i] == pytest.approx(shapely.distance(shapely.Point(qx[i], qy[i]), piece),
                                       abs=1e-9)


def test_normal_widths_match_shapely_intersections() -> None:
    poly = shapely.Polygon([(0, 0), (10, 0), (10, 4), (6, 4), (6, 8), (0, 8)])
    c = shapely.get_coordinates(poly.exterior)
    a, d = c[:-1], np.diff(c, axis=0)
    xs = RNG.uniform(0.1, 9.9, 40)
    ys = np.full(40, 1.0)
    got = normal_widths(xs, ys, np.zeros(40), np.ones(40), a[:, 0], a[:, 1], d[:, 0], d[:, 1])
    for x, w in zip(xs, got, strict=True):
        line = shapely.LineString([(x, -1), (x, 9)])
        assert w == pytest.approx(shapely.intersection(line, poly).length, abs=1e-9)


def test_project_near_finds_the_nearest_segment_in_its_window() -> None:
    xy = np.stack([np.linspace(0, 20, 41), np.zeros(41)], axis=1)[None]
    seg, along, lat = project_near(np.array([7.3]), np.array([1.5]), xy, np.array([41]),
                                   np.array([13]), 3)
    assert (int(seg[0]), float(along[0]), float(lat[0])) == (14, pytest.approx(0.3),
                                                             pytest.approx(1.5))
    # before the start the first segment is extended: negative along, right is negative
    seg, along, lat = project_near(np.array([-2.0]), np.array([-0.5]), xy, np.array([41]),
                                   np.array([0]), 3)
    assert (int(seg[0]), float(along[0]), float(lat[0])) == (0, -2.0, -0.5)


def test_key_bounds_and_keys_on_a_circle() -> None:
    a = np.linspace(0.0, np.pi, 181)
    length, turn = vertex_path_bounds(np.c_[10 * np.cos(a)], np.c_[10 * np.sin(a)])
    assert length[-1] == pytest.approx(10 * np.pi, rel=1e-4)
    assert turn[-1] == pytest.approx(np.pi - np.pi / 180, rel=1e-9)  # every bend but the first
    keys = greedy_keys(length, turn, 0.08)
    assert keys[0] == 0 and keys[-1] == 180 and np.all(np.diff(keys) > 0)
    gaps = np.diff(keys)[:-1]
    # each interval spends the budget: L A <= 0.08 with L = 10 A
    assert np.all(10 * np.radians(gaps) * np.radians(gaps - 1) <= 0.08 + 1e-12)
    # and is as long as the budget allows (one sample more would overspend it)
    assert np.all(10 * np.radians(gaps + 1) * np.radians(gaps) > 0.08 - 1e-12)


def _wiggly_path(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A random polyline with uneven steps, sharp and gentle bends, and repeated points."""
    steps = RNG.uniform(0.0, 0.5, n - 1) * (RNG.uniform(size=n - 1) > 0.05)
    h = np.cumsum(RNG.normal(0.0, RNG.uniform(0.01, 1.0), n - 1))
    return (np.concatenate([[0.0], np.cumsum(steps * np.cos(h))]),
            np.concatenate([[0.0], np.cumsum(steps * np.sin(h))]))


def test_windowed_distance_equals_the_brute_force_minimum_over_each_window() -> None:
    # the search leaves segments out: the minimum must still be the whole window's, exactly
    for _ in range(100):
        n = int(RNG.integers(2, 300))
        px, py = _wiggly_path(n)
        k = int(RNG.integers(1, 200))
        qx = RNG.uniform(px.min() - 5, px.max() + 5, k)
        qy = RNG.uniform(py.min() - 5, py.max() + 5, k)
        lo = np.sort(RNG.integers(0, n - 1, k))
        hi = np.maximum(np.sort(lo + RNG.integers(0, n - lo)), lo)
        got = windowed_distance(px, py, qx, qy, lo, hi)
        segs = np.stack([np.c_[px[:-1], py[:-1]], np.c_[px[1:], py[1:]]], axis=1)
        for i in range(k):
            expected = segments_distance(np.array([[qx[i], qy[i]]]), segs[lo[i]:hi[i]])[0]
            assert got[i] == expected


def test_pair_hulls_match_shapely_convex_hulls() -> None:
    # random quadrilaterals (rectangles moved and turned, and arbitrary ones) in sequence
    for shape in range(40):
        n = int(RNG.integers(2, 30))
        if shape % 2:
            corners = RNG.uniform(-5, 5, size=(n, 4, 2))
        else:
            rect = np.array([[-1.0, -1.2], [4.0, -1.2], [4.0, 1.2], [-1.0, 1.2]])
            th = np.cumsum(RNG.normal(0, 0.2, n))
            c, s = np.cos(th)[:, None], np.sin(th)[:, None]
            corners = np.stack([rect[:, 0] * c - rect[:, 1] * s + np.arange(n)[:, None],
                                rect[:, 0] * s + rect[:, 1] * c], axis=-1)
        coords, offsets = pair_hulls(corners)
        hulls = shapely.from_ragged_array(shapely.GeometryType.POLYGON, coords,
                                          (offsets, np.arange(len(offsets))))
        ref = shapely.convex_hull(shapely.multipoints(
            np.concatenate([corners[:-1], corners[1:]], axis=1)))
        assert len(hulls) == n - 1 and shapely.is_valid(hulls).all()
        assert np.all(shapely.area(shapely.symmetric_difference(hulls, ref)) < 1e-9)
        assert np.all(shapely.area(hulls) == pytest.approx(shapely.area(ref), abs=1e-9))
        # counter-clockwise rings, as shapely's hulls
        assert shapely.is_ccw(shapely.get_exterior_ring(hulls)).all()


def test_farthest_from_segments_is_the_same_search_as_farthest_on_lines() -> None:
    ring = shapely.Point(0, 0).buffer(5.0, quad_segs=6).exterior
    c = shapely.get_coordinates(ring)
    segs = np.stack([c[:-1], c[1:]], axis=1)
    for _ in range(30):
        lines = shapely.MultiLineString([RNG.uniform(-8, 8, size=(int(RNG.integers(2, 8)), 2))
                                         for _ in range(int(RNG.integers(1, 4)))])
        coords, part = shapely.get_coordinates(shapely.get_parts(lines), return_index=True)
        got = farthest_from_segments(coords, part[1:] == part[:-1], segs, 0.01, 100.0)
        expected = farthest_on_lines(lines, lambda p: segments_distance(p, segs), 0.01)
        assert got == pytest.approx(expected, abs=1e-12)
        # and a reach shorter than the farthest probe asks the caller to take over
        assert np.isnan(farthest_from_segments(coords, part[1:] == part[:-1], segs, 0.01,
                                               0.5 * got))


def test_vertex_path_bounds_match_a_numpy_reference_on_random_paths() -> None:
    # longest step and sharpest turning (the wrapped change of each vertex's step heading)
    n, m = 120, 5
    px, py = np.cumsum(RNG.normal(0, 0.3, (n, m)), axis=0), np.cumsum(RNG.normal(0, 0.3, (n, m)), 0)
    px[40:45] = px[40]  # a vertex standing still for a while turns by 0 there
    py[40:45] = py[40]
    dx, dy = np.diff(px, axis=0), np.diff(py, axis=0)
    step = np.hypot(dx, dy)
    h = np.arctan2(dy, dx)
    bend = np.abs((np.diff(h, axis=0) + np.pi) % (2 * np.pi) - np.pi)
    bend[(step[1:] <= 1e-12) | (step[:-1] <= 1e-12)] = 0.0
    length, turn = vertex_path_bounds(px, py)
    assert length == pytest.approx(np.concatenate([[0.0], np.cumsum(step.max(axis=1))]),
                                   rel=1e-12)
    assert turn == pytest.approx(np.concatenate([[0.0, 0.0], np.cumsum(bend.max(axis=1))]),
                                 abs=1e-9)


def test_look_back_distance_matches_shapely_on_each_look_back_window() -> None:
    for _ in range(20):
        n = int(RNG.integers(3, 200))
        px, py = _wiggly_path(n)
        qx, qy = px[1:] + RNG.normal(0, 1, n - 1), py[1:] + RNG.normal(0, 1, n - 1)
        reach = RNG.uniform(0.0, 10.0, n - 1)
        got = look_back_distance(px, py, qx, qy, reach)
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(px), np.diff(py)))])
        for i in range(n - 1):
            # from the last point more than reach_i behind point i + 1 (or the first point)
            behind = np.flatnonzero(arc < arc[i + 1] - reach[i])
            lo = int(behind[-1]) if len(behind) else 0
            piece = shapely.LineString(np.c_[px[lo:i + 2], py[lo:i + 2]])
            assert got[i] == pytest.approx(
                shapely.distance(shapely.Point(qx[i], qy[i]), piece), abs=1e-9)


def test_corner_vertices_are_vertices_of_shapelys_union() -> None:
    """The corners of a swept rectangle's hulls taken for vertices of the union's boundary
    are vertices of the union GEOS computes, to the bit: the floors of
    :mod:`clearance.analysis.screen` rest on it."""
    found = 0
    for _ in range(60):
        n = int(RNG.integers(3, 25))
        turn = RNG.uniform(-0.3, 0.3)
        theta = np.cumsum(np.full(n, turn)) + RNG.uniform(0, 6.3)
        step = RNG.uniform(0.2, 1.5)
        x = np.cumsum(step * np.cos(theta))
        y = np.cumsum(step * np.sin(theta))
        c, s_ = np.cos(theta)[:, None], np.sin(theta)[:, None]
        along = np.array([-1.0, 4.0, 4.0, -1.0])
        across = np.array([-1.0, -1.0, 1.0, 1.0])
        corners = np.stack([x[:, None] + along * c - across * s_,
                            y[:, None] + along * s_ + across * c], axis=-1)
        coords, offsets = pair_hulls(corners)
        assert len(offsets) == n
        union = shapely.union_all(shapely.from_ragged_array(
            shapely.GeometryType.POLYGON, coords, (offsets, np.arange(len(offsets)))))
        vertices = {tuple(p) for p in shapely.get_coordinates(union)}
        points = corners.reshape(-1, 2)
        hit = corner_vertices(points, coords, offsets, 1e-9, np.pi / 8)
        found += int(hit.sum())
        assert {tuple(p) for p in points[hit]} <= vertices
        # and none is inside the union
        assert not shapely.contains_xy(union, points[hit, 0], points[hit, 1]).any()
    assert found > 500
