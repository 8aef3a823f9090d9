"""Centre lines: SUMO's coarse junction shapes smoothed without losing the designed radius."""

import math

import numpy as np
import pytest

from clearance.analysis.polyline import catmull_rom, prepare_path, smooth_polyline
from clearance.analysis.tracking import simulate_batch
from clearance.vehicles.vehicle import Vehicle

CAR = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, math.atan(2.7 / 4.5), 0.65, 0.4)


def sumo_like_turn(radius: float) -> np.ndarray:
    """25 m straight, a 90-degree arc drawn with five points (as netconvert does), 25 m."""
    a = np.radians(np.linspace(0.0, 90.0, 5))
    arc = np.c_[radius * np.sin(a), radius * (1 - np.cos(a))]
    return np.vstack([[(-25.0, 0.0)], arc, [(radius, radius + 25.0)]])


def test_smoothing_follows_the_designed_arc_not_the_chords():
    radius = 12.0
    pts = smooth_polyline(sumo_like_turn(radius), 0.1)
    centre = np.array([0.0, radius])
    on_arc = (pts[:, 0] > 2.0) & (pts[:, 1] < radius - 2.0)  # well inside the arc
    r = np.hypot(*(pts[on_arc] - centre).T)
    # the chords of 22.5 degrees miss the arc by R (1 - cos 11.25 deg) = 0.23 m
    assert np.abs(r - radius).max() < 0.08
    chords = prepare_path(sumo_like_turn(radius), 0.1)
    chord_r = np.hypot(*(chords.xy[(chords.xy[:, 0] > 2.0) & (chords.xy[:, 1] < 10.0)]
                         - centre).T)
    assert chord_r.min() < radius - 0.2


def test_smoothing_keeps_straight_lines_and_the_ends():
    line = smooth_polyline([(0.0, 0.0), (30.0, 0.0), (60.0, 0.0)], 0.5)
    assert np.abs(line[:, 1]).max() < 1e-9
    assert np.allclose(line[0], [0.0, 0.0]) and np.allclose(line[-1], [60.0, 0.0])


def test_catmull_rom_passes_through_every_vertex():
    pts = sumo_like_turn(10.0)
    spline = catmull_rom(pts, 0.2)
    for p in pts:
        assert np.hypot(*(spline - p).T).min() < 1e-9


def test_a_run_that_starts_inside_a_curve_starts_steering():
    # a circle entered at its own start: no straight to turn in on
    a = np.radians(np.linspace(0.0, 180.0, 361))
    circle = np.c_[10 * np.sin(a), 10 * (1 - np.cos(a))]
    run = simulate_batch([CAR], [circle])[0]
    assert run.followed and run.max_error_m < 0.02
    # the front axle on the 10 m circle: sin(phi) = l / R (tan(phi) = l / R is 0.01 less)
    expected_phi = math.asin(CAR.wheelbase_m / 10.0)
    assert abs(run.trajectory.phi_rad[0] - expected_phi) < 0.002


def _arc_from(radius: float, step_deg: float, first: float = 1.0) -> np.ndarray:
    """A 180-degree arc from (0, 0) heading +x, vertices every ``step_deg``, rounded to 1 cm
    as SUMO writes them; the first chord is ``first`` of a chord (a curve cut inside it)."""
    a = np.radians(np.concatenate([[0.0], np.arange(first * step_deg, 180.0 + 1e-9, step_deg)]))
    return np.round(np.c_[radius * np.sin(a), radius * (1 - np.cos(a))], 2)


def test_a_smoothed_line_that_starts_inside_an_arc_starts_on_it():
    radius = 9.0
    for step_deg, first in [(5.0, 1.0), (10.0, 1.0), (22.5, 1.0), (4.0, 0.3)]:
        path = prepare_path(_arc_from(radius, step_deg, first), 0.1, smooth=True)
        start = path.station_m <= 2.0
        # the curvature over the first two metres is the arc's up to SUMO's rounding (the
        # first chord led straight: 15-85 % low; a short first chord: 7 % high), so is the
        # heading at the start (off by half the first chord's turn: up to 0.2 rad) and the
        # line lies on the arc (it was up to 0.10 m inside it)
        assert np.median(path.curvature_1_m[start]) * radius == pytest.approx(1.0, abs=0.04)
        assert abs(path.heading_rad[0]) < 0.008, (step_deg, first)
        xy = path.xy[start]
        assert np.abs(np.hypot(xy[:, 0], xy[:, 1] - radius) - radius).max() < 0.015
