"""Path following: steady states, limits, cannot-turn, batches, symmetry."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from clearance.analysis.envelope import swept_path
from clearance.analysis.kinematics import SpeedProfile, ramp_step
from clearance.analysis.polyline import prepare_path
from clearance.analysis.tracking import TrackingSettings, simulate, simulate_batch, simulate_grid
from clearance.analysis.trailer import steady_articulation_rad, steady_trailer_radius_m
from clearance.vehicles.errors import GeometryError
from clearance.vehicles.vehicle import Vehicle
from tests.analysis.helpers import bus, car, semi, steady_rho, turn


def test_straight_path_no_steering_and_exact_duration() -> None:
    run = simulate(bus(), [(0.0, 0.0, 1.0), (30.0, 0.0, 2.0)], TrackingSettings(speed=1.5))
    tr = run.trajectory
    assert run.followed and run.reached_end
    assert np.max(np.abs(tr.phi_rad)) < 1e-12
    assert tr.t_s[-1] == pytest.approx(20.0, abs=1e-9)
    assert tr.xf_m[-1] == pytest.approx(30.0, abs=1e-9)
    assert np.allclose(tr.x_m, tr.xf_m - 6.0)


def test_long_arc_reaches_steady_steering_angle() -> None:
    radius = 14.0
    run = simulate(bus(), turn(radius, 400.0, lead_m=5.0, tail_m=5.0))
    tr = run.trajectory
    assert run.followed
    rho = steady_rho(radius, 6.0)
    # The body settles like a tractrix (an e-fold per ~l / cos(phi) of travel); compare over
    # the last 20 m of the arc, after 78 m (12 e-folds). The chords' sagitta (0.5 mm) makes
    # the cross-track term ripple a little.
    arc_end = 5.0 + radius * math.radians(400.0)
    late = (tr.s_m > arc_end - 20.0) & (tr.s_m < arc_end - 1.0)
    assert np.median(tr.phi_rad[late]) == pytest.approx(math.atan(6.0 / rho), rel=1e-3)
    assert np.allclose(tr.phi_rad[late], math.atan(6.0 / rho), rtol=5e-3)
    r_rear = np.hypot(tr.x_m[late], tr.y_m[late] - radius)
    assert np.allclose(r_rear, rho, rtol=1e-3)
    # the largest error is where the arc ends: the wheel, turned back at its finite rate
    # early enough not to overshoot the exit, cuts it by 2.6 cm
    assert run.max_error_m < 0.03


def test_steering_rate_limit_bounds_phi_rate_and_costs_accuracy() -> None:
    path = turn(9.0, 90.0)
    fast = TrackingSettings(speed=5.0)
    slow_wheel = simulate(bus(rate=0.15), path, fast)
    quick_wheel = simulate(bus(rate=math.inf), path, fast)
    dt = fast.dt_s
    slow_rate = np.abs(np.diff(slow_wheel.trajectory.phi_rad[:-1])) / dt
    quick_rate = np.abs(np.diff(quick_wheel.trajectory.phi_rad[:-1])) / dt
    assert np.max(slow_rate) <= 0.15 + 1e-9
    assert np.count_nonzero(slow_rate > 0.15 - 1e-9) > 5  # it saturates for a while
    assert np.max(quick_rate) > 0.3  # the unlimited wheel turns faster
    assert slow_wheel.steps_rate_limited > 10
    assert slow_wheel.max_error_m > 3 * quick_wheel.max_error_m


def test_path_tighter_than_lock_cannot_turn_and_looser_path_is_followed() -> None:
    v = bus()
    ctr_min = math.hypot(v.min_radius_m, v.wheelbase_m)
    tight, loose = simulate_batch([v, v], [turn(0.8 * ctr_min, 180.0), turn(1.1 * ctr_min, 180.0)])
    assert tight.cannot_turn and not tight.followed
    assert tight.max_error_m > tight.settings.tolerance_m
    assert "left the centre line" in tight.reason and "at lock" in tight.reason
    assert tight.steps_at_lock > 0
    assert loose.followed and loose.max_error_m < 0.05 and loose.steps_at_lock == 0


def test_runs_always_end_and_a_step_cap_means_cannot_turn() -> None:
    capped = simulate(car(), turn(10.0, 90.0), TrackingSettings(max_steps=20))
    assert len(capped.trajectory) == 21
    assert not capped.reached_end and capped.cannot_turn
    assert "did not reach the end" in capped.reason


def test_batch_equals_one_by_one() -> None:
    vehicles = [car(), bus(), semi(), bus(rate=0.2)]
    paths = [turn(8.0, 90.0), turn(12.0, 120.0, left=False), turn(15.0, 90.0), turn(20.0, 45.0)]
    batch = simulate_batch(vehicles, paths)
    for v, p, b in zip(vehicles, paths, batch, strict=True):
        one = simulate(v, p)
        assert len(one.trajectory) == len(b.trajectory)
        for name in ("x_m", "y_m", "theta_rad", "phi_rad", "error_m"):
            assert np.allclose(getattr(one.trajectory, name), getattr(b.trajectory, name),
                               atol=1e-12)
        assert one.reason == b.reason


def test_grid_pairs_every_vehicle_with_every_path() -> None:
    grid = simulate_grid([car(), bus()], [turn(10.0, 30.0), turn(25.0, 60.0), turn(30.0, 5.0)])
    assert [[r.vehicle.name for r in row] for row in grid] == [["car"] * 3, ["bus"] * 3]
    assert grid[1][2].path.length_m == pytest.approx(30.0 + 30.0 * math.radians(5.0), rel=1e-3)


def test_right_turn_mirrors_left_turn() -> None:
    left, right = simulate_batch([semi(), semi()], [turn(16.0, 90.0), turn(16.0, 90.0, left=False)])
    a, b = left.trajectory, right.trajectory
    assert len(a) == len(b)
    assert np.allclose(a.phi_rad, -b.phi_rad, atol=1e-9)
    assert np.allclose(a.x_m, b.x_m, atol=1e-9) and np.allclose(a.y_m, -b.y_m, atol=1e-9)
    assert np.allclose(a.psi_rad, -b.psi_rad, atol=1e-9)


def test_semitrailer_closed_loop_steady_state_matches_closed_form() -> None:
    v = semi()
    radius = 16.0
    run = simulate(v, turn(radius, 600.0, lead_m=2.0, tail_m=5.0),
                   TrackingSettings(speed=2.0))
    tr = run.trajectory
    assert run.followed and run.jackknife_time_s is None
    rho = steady_rho(radius, v.wheelbase_m)
    t = v.trailer
    psi_ss = float(steady_articulation_rad(rho, t.hitch_offset_m, t.wheelbase_m))
    # the front axle 1 m before the end of the arc, after 166 m on it: the articulation
    # settles by an e-fold per l_t / cos(psi) ~ 13 m
    i = int(np.searchsorted(tr.s_m, 2.0 + radius * math.radians(600.0) - 1.0))
    assert tr.psi_rad[i] == pytest.approx(psi_ss, rel=1e-3)
    r_t = math.hypot(tr.xt_m[i], tr.yt_m[i] - radius)
    assert r_t == pytest.approx(float(steady_trailer_radius_m(rho, t.hitch_offset_m,
                                                              t.wheelbase_m)), rel=1e-3)


def test_articulation_limit_is_recorded_as_jackknife() -> None:
    run = simulate(semi(max_articulation_deg=20.0), turn(14.0, 120.0))
    assert run.jackknife_time_s is not None and run.cannot_turn
    assert "articulation" in run.reason
    tr = run.trajectory
    assert abs(tr.psi_rad[-1]) > math.radians(20.0)
    assert np.all(np.abs(tr.psi_rad[:-1]) <= math.radians(20.0))


def test_speed_profile_by_station_slows_the_run() -> None:
    path = turn(12.0, 90.0)
    profile = SpeedProfile("station", (0.0, 10.0, 20.0), (4.0, 1.0, 4.0))
    run = simulate(car(), path, TrackingSettings(speed=profile))
    tr = run.trajectory
    i = int(np.argmin(np.abs(tr.s_m - 10.0)))
    assert tr.speed_m_s[i] == pytest.approx(1.0, abs=0.05)
    assert tr.speed_m_s[0] == pytest.approx(4.0)
    constant = simulate(car(), path, TrackingSettings(speed=4.0))
    assert tr.t_s[-1] > constant.trajectory.t_s[-1]


def test_bad_input_is_refused_with_names() -> None:
    odd = dataclasses.replace(car(), steered_axle="middle")
    with pytest.raises(ValueError, match="'car'.*steered_axle"):
        simulate(odd, turn(10.0, 90.0))
    rear_semi = dataclasses.replace(semi(), steered_axle="rear")
    with pytest.raises(ValueError, match="'semi'.*rear-steered.*trailer"):
        simulate(rear_semi, turn(10.0, 90.0))
    with pytest.raises(ValueError, match="wheelbase_m"):
        simulate(dataclasses.replace(car(), wheelbase_m=-1.0), turn(10.0, 90.0))
    with pytest.raises(GeometryError, match="path 0.*not finite"):
        simulate(car(), [(0.0, 0.0), (math.nan, 1.0)])
    with pytest.raises(ValueError, match="paired"):
        simulate_batch([car(), car()], [turn(10, 9), turn(10, 9), turn(10, 9)])
    with pytest.raises(ValueError, match="tolerance_m"):
        TrackingSettings(tolerance_m=0.0)


def test_rear_steered_vehicle_follows_with_its_front_axle_and_swings_out() -> None:
    v = dataclasses.replace(car(), name="forklift", steered_axle="rear")
    radius = 9.0
    left, right = simulate_batch([v, v], [turn(radius, 360.0, lead_m=5.0, tail_m=5.0),
                                          turn(radius, 360.0, lead_m=5.0, tail_m=5.0,
                                               left=False)])
    tr = left.trajectory
    assert left.followed and left.max_error_m < 0.1
    arc_end = 5.0 + radius * math.radians(360.0)
    late = (tr.s_m > arc_end - 15.0) & (tr.s_m < arc_end - 1.0)
    # the unsteered front axle turns about a centre on its own line: rho = R, phi = atan(l/R)
    assert np.median(tr.phi_rad[late]) == pytest.approx(math.atan(v.wheelbase_m / radius),
                                                        rel=2e-3)
    # the rear axle runs outside, on sqrt(R^2 + l^2)
    r_rear = np.hypot(tr.x_m[late], tr.y_m[late] - radius)
    assert np.allclose(r_rear, math.hypot(radius, v.wheelbase_m), rtol=2e-3)
    assert np.allclose(tr.phi_rad, -right.trajectory.phi_rad, atol=1e-9)


def test_tolerance_decides_cannot_turn_on_the_same_drive() -> None:
    v = bus()
    ctr_min = math.hypot(v.min_radius_m, v.wheelbase_m)
    path = turn(0.85 * ctr_min, 120.0)
    base = simulate(v, path)
    err = base.max_error_m
    assert 0.1 < err < 1.0
    loose = simulate(v, path, TrackingSettings(tolerance_m=1.5 * err))
    strict = simulate(v, path, TrackingSettings(tolerance_m=0.5 * err))
    assert loose.followed and strict.cannot_turn
    assert loose.max_error_m == pytest.approx(strict.max_error_m)  # same drive, other verdict
    assert f"tolerance {0.5 * err:.2f} m" in strict.reason


@pytest.mark.parametrize("smooth", [False, True])
def test_a_run_that_starts_on_a_circle_starts_in_its_steady_state(smooth: bool) -> None:
    # the front axle starts on a 9 m circle (vertices every 5 degrees, as SUMO draws a helix)
    radius, v = 9.0, car()
    a = np.radians(np.arange(0.0, 270.0 + 1e-9, 5.0 if smooth else 1.0))
    path = prepare_path(np.c_[radius * np.sin(a), radius * (1 - np.cos(a))], smooth=smooth)
    run = simulate(v, path)
    tr = run.trajectory
    rho = steady_rho(radius, v.wheelbase_m)
    # the rear axle starts on its steady circle: sin(phi) = l / R, not tan(phi) = l / R
    assert math.hypot(tr.x_m[0], tr.y_m[0] - radius) == pytest.approx(rho, abs=0.01)
    assert tr.phi_rad[0] == pytest.approx(math.asin(v.wheelbase_m / radius), abs=2e-3)
    # and the offtracking is the steady state's, CTR - rho (docs/design.md §4), from the start on
    assert swept_path(run).max_offtracking_m == pytest.approx(radius - rho, rel=0.01)
    assert run.followed and run.max_error_m < 0.01


def _passenger_car() -> Vehicle:
    # AASHTO P: l = 11 ft, lock for CTR 21 ft, road wheels lock to lock in 4 s
    return Vehicle("P", 3.3528, 2.1336, 2.1336, 0.9144, 1.524, 0.5513, 0.6527, 0.2757)


@pytest.mark.parametrize("left", [True, False])
@pytest.mark.parametrize("dt", [0.1, 0.05])
def test_after_a_corner_tighter_than_the_lock_it_rejoins_without_overshooting(left, dt) -> None:
    # a 3 m corner (P's centre-line turning radius is 6.4 m) between two straights
    radius, lead = 3.0, 15.0
    run = simulate(_passenger_car(), turn(radius, 90.0, lead_m=lead, tail_m=40.0, left=left),
                   TrackingSettings(dt_s=dt, tolerance_m=50.0))
    tr = run.trajectory
    assert run.reached_end
    after = tr.s_m >= lead + radius * math.pi / 2
    e, s = tr.error_m[after], tr.s_m[after]
    peak = int(np.argmax(np.abs(e)))
    assert abs(e[peak]) > 0.5  # it cannot follow the corner: it runs wide, to the outside
    assert np.sign(e[peak]) == (-1.0 if left else 1.0)
    # then it comes back without crossing the centre line by more than a few centimetres
    # (the plain Stanley law swung 2.8 m across, lock to lock, and grew)
    assert np.max(-np.sign(e[peak]) * e[peak:]) < 0.05
    # and it is back on it within 15 m of the corner
    assert np.all(np.abs(e[s > s[0] + 15.0]) < 0.05)


def test_the_loop_turns_the_wheel_over_each_step_as_ramp_step_integrates_it() -> None:
    # a slow wheel (rate-limited for most of the corner): the recorded states are the
    # recorded steering's ramps integrated step by step (second order in the step, see
    # tests/analysis/test_kinematics.py), not the new steering held over each step
    v = bus(rate=0.15)
    tr = simulate(v, turn(12.0, 90.0), TrackingSettings(speed=3.0)).trajectory
    d = tr.speed_m_s[:-1] * np.diff(tr.t_s)
    x, y, th = ramp_step(tr.x_m[:-1], tr.y_m[:-1], tr.theta_rad[:-1], d, tr.phi_rad[:-1],
                         tr.phi_rad[1:], v.wheelbase_m)
    assert np.allclose(x, tr.x_m[1:], atol=1e-9) and np.allclose(y, tr.y_m[1:], atol=1e-9)
    assert np.allclose(th, tr.theta_rad[1:], atol=1e-12)
    assert np.count_nonzero(np.abs(np.diff(tr.phi_rad)) > 0.15 * 0.1 - 1e-9) > 10
