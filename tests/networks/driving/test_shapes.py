"""Shapes of swung paths: offsets of a centre line, profiles and corner cuts."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from clearance.analysis.polyline import prepare_path
from clearance.analysis.tracking import simulate
from clearance.networks.driving.shapes import (
    apex_bump,
    corner_cut,
    max_curvature_1_m,
    nearest_on,
    offset_path,
    offset_profile,
    shaped_profile,
)
from clearance.vehicles.table import bundled_table, load_tables
from tests.analysis.helpers import corner_path


@pytest.fixture(scope="module")
def car():
    return load_tables([bundled_table("aashto_green_book")], ["P"]).vehicle("P")


def test_offset_of_a_straight_line_is_the_parallel_line():
    p = prepare_path([(0.0, 0.0), (30.0, 40.0)], 0.1)
    q = offset_path(p, np.full(len(p.xy), -2.0))  # 2 m to the right
    # the right normal of heading (3, 4)/5 is (4, -3)/5
    assert np.allclose(q.xy - p.xy, [1.6, -1.2], atol=1e-9)
    assert q.length_m == pytest.approx(50.0, abs=1e-9)
    assert np.allclose(q.heading_rad, p.heading_rad[0], atol=1e-9)


def test_offset_of_an_arc_is_the_concentric_arc():
    # outward (left of a right turn, whose centre lies to the right) by 1.5 m: radius 5.5
    path, feature = corner_path(4.0, smooth=False)
    centre = np.array([0.0, 25.0])
    d = np.full(len(path.xy), 1.5)
    q = offset_path(path, d)
    on_arc = (q.xy[:, 1] > 25.5) & (q.xy[:, 0] > 0.5)
    r = np.hypot(*(q.xy[on_arc] - centre).T)
    assert np.allclose(r, 5.5, atol=0.01)


def test_zero_offset_candidate_is_the_lane_path(car):
    path, feature = corner_path(8.0)
    d = offset_profile(path.station_m, feature, 0.0, 6.0, 0.3)
    assert np.all(d == 0.0)
    q = offset_path(path, d)
    assert np.allclose(q.xy, path.xy) and np.allclose(q.heading_rad, path.heading_rad)
    a, b = simulate(car, path), simulate(car, q)
    assert np.allclose(a.trajectory.x_m, b.trajectory.x_m)
    assert np.allclose(a.trajectory.phi_rad, b.trajectory.phi_rad)


def test_profile_is_zero_outside_its_ramps_and_within_the_amplitude():
    s = np.arange(0.0, 80.0, 0.1)
    feature = (30.0, 40.0)
    for cut in (0.0, 0.3, 0.6):
        d = offset_profile(s, feature, 2.0, 8.0, cut)
        assert np.all(d[s <= 22.0] == 0.0) and np.all(d[s >= 48.0] == 0.0)
        assert np.all((d >= 0.0) & (d <= 2.0 + 1e-12))
        # symmetric about the feature's middle
        assert np.allclose(d, np.interp(70.0 - s, s, d), atol=1e-6)
        assert d[np.argmin(abs(s - 35.0))] == pytest.approx(2.0 * (1.0 - cut), abs=1e-6)


def test_corner_cut_of_a_right_angle_is_the_tangent_arc():
    # cut from t before to t after a 3 m quarter circle: the arc of radius 3 + t tangent
    # to both straights; its apex (R' - 3)(sqrt 2 - 1) inside the old one
    path, feature = corner_path(3.0, smooth=False)
    for t in (2.0, 5.0, 9.0):
        q, d, station, (s0, s1) = corner_cut(path, feature, t)
        assert 1 / max_curvature_1_m(q) == pytest.approx(3.0 + t, rel=0.03)
        assert -d.min() == pytest.approx(t * (math.sqrt(2) - 1), abs=0.03)
        assert s0 == pytest.approx(feature[0] - t, abs=0.05)
        # the same ends and headings as the lane: it rejoins the line
        assert np.allclose(q.xy[[0, -1]], path.xy[[0, -1]], atol=1e-6)
        assert np.allclose(q.heading_rad[[0, -1]], path.heading_rad[[0, -1]], atol=1e-3)
        assert np.all(np.diff(station) >= -1e-9)  # the station map runs forward


def test_fitted_profile_and_apex_bump_keep_their_ends():
    s = np.arange(0.0, 80.0, 0.1)
    d = shaped_profile(s, (30.0, 40.0), 3.0, 0.5, 12.0, 6.0, 0.3)
    assert np.all(d[s <= 18.0] == 0.0) and np.all(d[s >= 46.0] == 0.0)
    assert d.max() <= 3.0 + 1e-12 and d.min() >= 0.0
    b = apex_bump(s, (30.0, 40.0), 1.2, 6.0)
    assert np.all(b[s <= 24.0] < 1e-12) and np.all(b[s >= 46.0] < 1e-12)
    assert b.max() == pytest.approx(1.2, abs=1e-3)
    assert s[np.argmax(b)] == pytest.approx(35.0, abs=0.1)  # deepest at the middle


def test_nearest_on_agrees_with_shapely_linear_referencing() -> None:
    """The numpy projection gives shapely's station and point for points all around a
    winding line (an independent implementation of the same definition)."""
    rng = np.random.default_rng(7)
    a = np.radians(np.linspace(0.0, 250.0, 80))
    line = np.c_[9.0 * np.cos(a) + 0.02 * a**2, 6.0 * np.sin(a)]
    pts = rng.uniform(-14.0, 14.0, size=(300, 2))
    station, near = nearest_on(line, pts)
    geom = shapely.LineString(line)
    want = shapely.line_locate_point(geom, shapely.points(pts))
    got_d = np.hypot(*(near - pts).T)
    want_d = shapely.distance(geom, shapely.points(pts))
    assert np.allclose(got_d, want_d, atol=1e-9)
    unique = np.abs(station - want) < 1e-6  # points equally near two parts may differ
    assert unique.mean() > 0.97
    assert np.allclose(shapely.get_coordinates(shapely.line_interpolate_point(geom, station)),
                       near, atol=1e-9)
