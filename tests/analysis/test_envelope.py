"""Swept envelopes, offtracking and swept width against closed forms and symmetry."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import shapely
from shapely import affinity

from clearance.analysis.envelope import body_corners, interval_hulls, key_samples, sweep, swept_path
from clearance.analysis.kinematics import ramp_step
from clearance.analysis.tracking import simulate, simulate_batch
from tests.analysis.helpers import bus, car, semi, steady_rho, turn


def _steady(vehicle, radius):
    rho = steady_rho(radius, vehicle.wheelbase_m)
    half_b = vehicle.width_m / 2
    ctr = math.hypot(rho, vehicle.wheelbase_m)
    width = math.hypot(rho + half_b, vehicle.wheelbase_m + vehicle.front_overhang_m) - (
        rho - half_b)
    return rho, ctr, width


@pytest.mark.parametrize(("vehicle", "radius"), [(car(), 8.0), (bus(), 20.0)])
def test_long_arc_offtracking_and_swept_width_match_steady_state(vehicle, radius) -> None:
    # 270 degrees: the body settles (an e-fold per ~l of travel) well before the end
    run = simulate(vehicle, turn(radius, 270.0, lead_m=5.0, tail_m=0.0))
    assert run.followed
    sp = swept_path(run)
    rho, ctr, width = _steady(vehicle, radius)
    assert sp.max_offtracking_m == pytest.approx(ctr - rho, rel=0.01)
    assert sp.max_swept_width_m == pytest.approx(width, rel=0.01)
    # and the maximum sits late on the arc
    assert sp.max_offtracking_station_m > 5.0 + radius * math.radians(135.0)


@pytest.mark.parametrize("vehicle", [car(), bus()])
def test_transient_offtracking_through_90_degrees_stays_below_steady_state(vehicle) -> None:
    radius = 1.3 * math.hypot(vehicle.min_radius_m, vehicle.wheelbase_m)
    run = simulate(vehicle, turn(radius, 90.0))
    sp = swept_path(run)
    rho, ctr, width = _steady(vehicle, radius)
    assert 0.5 * (ctr - rho) < sp.max_offtracking_m < ctr - rho
    assert sp.max_swept_width_m < width * 1.001


def test_left_turn_mirrors_right_turn() -> None:
    left, right = simulate_batch([bus(), bus()], [turn(12.0, 90.0), turn(12.0, 90.0, left=False)])
    a, b = swept_path(left), swept_path(right)
    mirrored = affinity.scale(b.envelope, xfact=1.0, yfact=-1.0, origin=(0.0, 0.0))
    assert shapely.symmetric_difference(a.envelope, mirrored).area < 1e-6 * a.envelope.area
    assert np.allclose(a.offtracking_m, b.offtracking_m, atol=1e-9)
    assert np.allclose(a.swept_width_m, b.swept_width_m, atol=1e-6)
    left_rear = np.asarray(a.wheel_tracks["rear_left"].coords)
    right_rear = np.asarray(b.wheel_tracks["rear_right"].coords)
    assert np.allclose(left_rear * [1, -1], right_rear, atol=1e-9)


def test_straight_run_envelope_is_a_stretched_body() -> None:
    v = bus()
    run = simulate(v, [(0.0, 0.0), (25.0, 0.0)])
    sp = swept_path(run)
    assert sp.envelope.area == pytest.approx((v.length_m + 25.0) * v.width_m, rel=1e-9)
    assert np.allclose(sp.swept_width_m[:, 1], v.width_m)
    assert sp.max_offtracking_m < 1e-9
    assert sp.trailer is None and sp.trailer_offtracking_m is None


@pytest.mark.parametrize("vehicle", [car(), semi()])
def test_envelope_has_no_gaps_between_steps(vehicle) -> None:
    run = simulate(vehicle, turn(15.0, 110.0))
    sp = swept_path(run, tolerance_m=0.01)
    tr = run.trajectory
    grown = shapely.buffer(sp.envelope, 0.01 + 1e-9)
    rng = np.random.default_rng(7)
    k = rng.integers(0, len(tr) - 1, size=200)
    f = rng.uniform(0.0, 1.0, size=200)
    # poses between samples: the wheel part of the way through its turn over the step
    dt = np.diff(tr.t_s)[k] * f
    phi_f = tr.phi_rad[k] + f * (tr.phi_rad[k + 1] - tr.phi_rad[k])
    x, y, th = ramp_step(tr.x_m[k], tr.y_m[k], tr.theta_rad[k], tr.speed_m_s[k] * dt,
                         tr.phi_rad[k], phi_f, vehicle.wheelbase_m)
    bodies = shapely.polygons(body_corners(x, y, th, vehicle.wheelbase_m
                                           + vehicle.front_overhang_m,
                                           vehicle.rear_overhang_m, vehicle.width_m))
    assert shapely.covers(grown, bodies).all()
    all_bodies = shapely.polygons(body_corners(tr.x_m, tr.y_m, tr.theta_rad,
                                               vehicle.wheelbase_m + vehicle.front_overhang_m,
                                               vehicle.rear_overhang_m, vehicle.width_m))
    assert shapely.covers(grown, all_bodies).all()
    if vehicle.trailer is not None:
        t = vehicle.trailer
        trailers = shapely.polygons(body_corners(tr.xt_m, tr.yt_m, tr.theta_t_rad,
                                                 t.wheelbase_m + t.front_overhang_m,
                                                 t.rear_overhang_m, t.width_m))
        assert shapely.covers(grown, trailers).all()
        assert shapely.covers(shapely.buffer(sp.trailer, 0.011), trailers).all()


def test_wheel_tracks_in_steady_state_give_the_turning_radii() -> None:
    v = car()
    radius = 9.0
    run = simulate(v, turn(radius, 270.0, lead_m=5.0, tail_m=0.0))
    sp = swept_path(run)
    rho = steady_rho(radius, v.wheelbase_m)
    late = run.trajectory.s_m > 5.0 + radius * math.radians(200.0)
    half_w = v.track_m / 2
    inner_rear = np.asarray(sp.wheel_tracks["rear_left"].coords)[late]
    outer_front = np.asarray(sp.wheel_tracks["front_right"].coords)[late]
    assert np.allclose(np.hypot(inner_rear[:, 0], inner_rear[:, 1] - radius), rho - half_w,
                       rtol=2e-3)
    # curb-to-curb turning circle D_curb / 2 = sqrt((rho + w/2)^2 + l^2)
    assert np.allclose(np.hypot(outer_front[:, 0], outer_front[:, 1] - radius),
                       math.hypot(rho + half_w, v.wheelbase_m), rtol=2e-3)


def test_semitrailer_offtracking_reaches_its_closed_form() -> None:
    v = semi()
    t = v.trailer
    radius = 16.0
    run = simulate(v, turn(radius, 600.0, lead_m=2.0, tail_m=0.0))
    sp = swept_path(run, width_step_m=2.0)
    rho = steady_rho(radius, v.wheelbase_m)
    r_t = math.sqrt(rho**2 + t.hitch_offset_m**2 - t.wheelbase_m**2)
    assert sp.trailer_offtracking_m[-1] == pytest.approx(radius - r_t, rel=0.01)
    assert sp.max_trailer_offtracking_m == pytest.approx(radius - r_t, rel=0.01)
    assert set(sp.wheel_tracks) >= {"trailer_left", "trailer_right"}


def test_rear_steered_swept_width_and_outswing_in_steady_state() -> None:
    v = dataclasses.replace(bus(), name="rear-steer", steered_axle="rear")
    radius = 15.0
    run = simulate(v, turn(radius, 270.0, lead_m=5.0, tail_m=0.0))
    assert run.followed
    sp = swept_path(run)
    half_b = v.width_m / 2
    # centre of rotation on the front axle line at R: the rear outer corner is outermost,
    # the inner side at the front axle innermost
    width = math.hypot(radius + half_b, v.wheelbase_m + v.rear_overhang_m) - (radius - half_b)
    # late on the arc (the entry transient, where the steering rate makes the front axle
    # run wide and the tail swing out further, is over), but not in the last 50 degrees,
    # where the tail, which trails the front axle, has not yet swept
    station = sp.swept_width_m[:, 0] - 5.0
    late = (station > radius * math.radians(150.0)) & (station < radius * math.radians(220.0))
    assert np.allclose(sp.swept_width_m[late, 1], width, rtol=0.01)
    s = run.trajectory.s_m
    late = (s > 5.0 + radius * math.radians(200.0)) & (s < s[-1] - 1.0)  # not the path's end
    outswing = math.hypot(radius, v.wheelbase_m) - radius
    assert np.allclose(sp.offtracking_m[late], outswing, rtol=0.01)


def test_interval_hulls_are_shapely_convex_hulls_also_without_area() -> None:
    rng = np.random.default_rng(11)
    th = np.cumsum(rng.normal(0.0, 0.3, 12))
    x, y = np.cumsum(rng.uniform(0, 1, 12)), np.cumsum(rng.uniform(-1, 1, 12))
    for width in (2.5, 0.0):  # a body, and a bar of no width (hulls without area)
        for theta in (th, np.zeros(12)):  # turning, and sliding along the bar itself
            corners = body_corners(x if theta is th else np.arange(12.0),
                                   y if theta is th else np.zeros(12), theta, 4.0, 1.0, width)
            got = interval_hulls(corners)
            ref = shapely.convex_hull(shapely.multipoints(
                np.concatenate([corners[:-1], corners[1:]], axis=1)))
            assert len(got) == 11
            assert list(shapely.get_type_id(got)) == list(shapely.get_type_id(ref))
            assert shapely.equals(got, ref).all()


@pytest.mark.parametrize("axle", [0.0, 4.5, 1.0])  # rear axle, a rear-steered front axle, between
def test_sweep_is_the_union_of_every_interval_hull_of_both_parts(axle) -> None:
    # the union leaves out the shorter part's hulls that the longer part's sweep covers:
    # the area must be the union of them all, as shapely computes it
    rng = np.random.default_rng(5)
    th = np.cumsum(np.concatenate([np.zeros(20), rng.normal(0.02, 0.03, 200)]))
    x, y = np.cumsum(0.3 * np.cos(th)), np.cumsum(0.3 * np.sin(th))
    got = sweep(x, y, th, 4.5, 2.0, 2.5, axle_m=axle)
    along = np.array([-2.0, 4.5, 4.5, -2.0, axle, axle])
    across = np.array([-1.25, -1.25, 1.25, 1.25, -1.25, 1.25])
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    keys = key_samples(x[:, None] + along * c - across * s, y[:, None] + along * s + across * c)
    hulls = []
    for ahead, behind in ((4.5, -axle), (axle, 2.0)):
        corners = body_corners(x[keys], y[keys], th[keys], ahead, behind, 2.5)
        hulls += list(shapely.convex_hull(shapely.multipoints(
            np.concatenate([corners[:-1], corners[1:]], axis=1))))
    expected = shapely.union_all(hulls)
    assert shapely.area(shapely.symmetric_difference(got, expected)) < 1e-9
    assert got.area == pytest.approx(expected.area, rel=1e-12)
