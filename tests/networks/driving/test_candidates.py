"""Swung-path candidates: offsets, profiles, the lock, and which path is best."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.analysis.clearance import Clearance
from clearance.analysis.tracking import simulate_batch
from clearance.networks.driving.candidates import SwingSearch, candidates
from clearance.networks.driving.judging import encroaches_on, rank
from clearance.networks.driving.shapes import max_curvature_1_m
from clearance.vehicles.table import bundled_table, load_tables
from tests.analysis.helpers import corner_path


@pytest.fixture(scope="module")
def car():
    return load_tables([bundled_table("aashto_green_book")], ["P"]).vehicle("P")


def test_candidates_are_bounded_and_go_outside(car):
    path, feature = corner_path(4.0)
    search = SwingSearch()
    cs = candidates(path, feature, -90.0, search)
    assert 0 < len(cs) <= search.count
    assert all(c.offset_m.min() >= 0 for c in cs)  # left of a right turn
    assert [c.amplitude_m for c in cs] == sorted(c.amplitude_m for c in cs)
    left = candidates(path, feature, 90.0, search)  # taken as a left turn: to the right
    assert all(c.offset_m.max() <= 0 for c in left)
    # the same for every call: deterministic
    again = candidates(path, feature, -90.0, search)
    assert all(np.array_equal(a.path.xy, b.path.xy) for a, b in zip(cs, again, strict=True))


def test_every_candidate_respects_the_lock_or_the_follower_reports_it(car):
    path, feature = corner_path(3.5)
    cs = candidates(path, feature, -90.0)
    runs = simulate_batch([car], [c.path for c in cs])
    limit = math.sin(car.max_steer_rad) / car.wheelbase_m  # the front axle's tightest circle
    over = 0
    for c, run in zip(cs, runs, strict=True):
        assert np.abs(run.trajectory.phi_rad).max() <= car.max_steer_rad + 1e-9
        if max_curvature_1_m(c.path) > limit:
            over += 1
            # the follower cut the command (at the lock or the rate) or gave up
            assert run.steps_at_lock + run.steps_rate_limited > 0 or run.cannot_turn
    assert over > 0  # the small swings of a 3.5 m corner are beyond the lock
    assert any(run.followed for run in runs)  # and the wide ones are not


def _c(verdict, own, paved, road):
    return Clearance(verdict, own, paved, road, 0.0, "")


def test_rank_prefers_the_better_area_then_the_margin():
    lane = _c("fails", -1.0, -0.3, -0.8)
    opposing = _c("encroaches", -1.5, 0.4, -0.9)
    own_road = _c("encroaches", -1.1, 0.4, 0.1)
    assert rank([lane, opposing, own_road]) == 2
    assert rank([lane, None, opposing]) == 2
    assert rank([lane, _c("fails", -1.0, -0.1, -0.8)]) == 1  # fails by less
    assert rank([lane, _c("fails", -1.0, -0.27, -0.8)]) == 0  # the lane wins near ties
    assert rank([_c("cannot-turn", -1.0, -0.3, -0.8), None, None]) == 0
    assert [encroaches_on(c) for c in (lane, opposing, own_road)] == [
        "shoulder", "opposing lanes", "same-direction lanes"]


def test_inside_cut_is_the_wider_radius_a_car_takes_across_a_junction(car):
    # a right-angle turn drawn with a 3 m radius (SUMO's internal lane at an OSM corner):
    # tighter than P's lock, so the lane path cannot be followed; cutting the corner
    # across the junction, on the same approach and exit lanes, opens it to a radius P
    # can take
    path, feature = corner_path(3.0, smooth=False)
    limit = math.sin(car.max_steer_rad) / car.wheelbase_m  # 1 / 6.4 m
    assert max_curvature_1_m(path) > 1.5 * limit
    cs = candidates(path, feature, -90.0, room_m=0.3, rooms_m=(0.3, 6.0, 0.3),
                    inside_room_m=4.0)
    inside = [c for c in cs if c.shape == "inside"]
    # leaving the line 2, 4, 8 m before the corner: arcs of about 5, 7, 11 m whose apexes
    # are (R' - 3)(sqrt 2 - 1) inside: 0.8, 1.7, 3.3 m (16 m would cut 6.6 m: beyond the room)
    depths = [c.inside_m for c in inside]
    assert depths == pytest.approx([0.83, 1.66, 3.31], abs=0.05)
    assert all(c.offset_m.max() <= 1e-9 for c in inside)  # right of a right turn
    radii = [1 / max_curvature_1_m(c.path) for c in inside]
    assert radii == pytest.approx([5.0, 7.0, 11.0], rel=0.03)
    lane_run, *runs = simulate_batch([car], [path] + [c.path for c in inside])
    assert lane_run.cannot_turn
    # 7 m and 11 m are within the lock (6.4 m); the 5 m arc only within the tolerance
    assert [max_curvature_1_m(c.path) < limit for c in inside] == [False, True, True]
    assert all(r.followed for r in runs)
    # judged over the whole manoeuvre: from where it leaves the line to where it rejoins
    assert inside[1].window_m[0] == pytest.approx(feature[0] - 4.0, abs=0.05)


def test_fitted_swing_follows_the_room_at_each_end():
    # 3 m of room on the approach (an opposing lane), 0.5 m at the exit (one lane): the
    # fitted shapes swing f 3 m out before the turn and f 0.5 m after it
    path, feature = corner_path(4.0)
    cs = candidates(path, feature, -90.0, room_m=0.5, rooms_m=(3.0, 6.0, 0.5))
    fitted = [c for c in cs if c.shape == "fitted"]
    assert [(c.amplitude_m, c.exit_m) for c in fitted] == [
        (0.75, 0.125), (1.5, 0.25), (2.25, 0.375), (3.0, 0.5)]
    top = fitted[-1]
    s = path.station_m
    at = lambda x: float(np.interp(x, s, top.offset_m))  # noqa: E731
    # times 1 - 0.3 sin^2 (the middle apex cut) from the ramps' middles
    assert 0.7 * 3.0 < at(feature[0]) < 3.0 and 0.7 * 0.5 < at(feature[1]) < 0.5
    assert at(feature[0] - 6.0) == pytest.approx(3.0 * 0.5, abs=0.01)  # the cut starts there
    assert at(0.0) == 0.0 and at(s[-1]) == 0.0
    # equal rooms: no fitted shape (it would be a held one)
    same = candidates(path, feature, -90.0, room_m=2.0, rooms_m=(2.0, 6.0, 2.1))
    assert not [c for c in same if c.shape == "fitted"]


def test_a_jog_is_cut_into_one_s_curve_a_car_can_follow(car):
    # a straight road drawn with a 4.8 m sideways step over 5 m (netconvert's motorway
    # junction 1658939360 of the wheel's tools/game/highway, where two edges spread their
    # lanes differently): it turns by 0 degrees overall, through two 3 m kinks P cannot
    # hold; cut from 8 and 16 m before the step to as far after it, it is one S-curve
    # from the approach to the exit that P follows
    from clearance.analysis.polyline import prepare_path

    xy = np.array([(-30.0, 0.0), (0.0, 0.0), (0.3, 4.8), (30.3, 4.8)])
    path = prepare_path(xy)
    feature = (29.0, 35.5)
    limit = math.sin(car.max_steer_rad) / car.wheelbase_m
    assert max_curvature_1_m(path) > 1.5 * limit
    cs = candidates(path, feature, -0.5, room_m=6.0, rooms_m=(6.0, 6.0, 6.0),
                    inside_room_m=0.5)  # little room inside: a jog's cut is not bound by it
    assert len(cs) <= SwingSearch().count
    cuts = {c.path.name.split("corner cut ")[1][:-1]: c for c in cs
            if c.shape == "inside" and "corner cut" in c.path.name}
    assert set(cuts) == {"16 to 2 m", "2 to 16 m", "8 m", "16 m"}
    s_curve = cuts["16 m"]  # from 16 m before to 16 m after
    # an S from y 0 to y 4.8: it stays between the two straights and is gentle
    y = s_curve.path.xy[:, 1]
    assert y.min() > -0.05 and y.max() < 4.85
    assert max_curvature_1_m(s_curve.path) < 0.5 * limit
    # one-sided: on the approach's line up to 2 m before the step, across in 16 m after it
    late = cuts["2 to 16 m"].path
    assert np.abs(late.xy[late.xy[:, 0] < -3.05, 1]).max() < 1e-6  # 2 m before x -1
    assert max_curvature_1_m(late) < limit
    lane_run, *runs = simulate_batch([car], [path, s_curve.path, late])
    assert lane_run.cannot_turn
    assert all(r.followed for r in runs)
    # a real turn keeps its inside cuts within the room inside
    corner, feat = corner_path(3.0, smooth=False)
    assert all(c.inside_m <= 0.5 for c in candidates(
        corner, feat, -90.0, room_m=0.3, rooms_m=(0.3, 6.0, 0.3), inside_room_m=0.5)
        if c.shape == "inside")


def test_a_looped_junction_lane_gets_direct_cuts_that_a_car_can_drive(car):
    # a right turn whose internal lane SUMO drew with a 2 m loop (the junction shape of
    # an OSM network): its centre line turns 360 degrees more than the turn; the looped
    # search adds corner cuts that leave the line before the loop and rejoin it after,
    # and the car drives the best of them where it cannot follow the loop
    from clearance.analysis.polyline import prepare_path
    from clearance.networks.driving.candidates import LOOPED_EXCESS_DEG, excess_turning_deg

    t = np.radians(np.linspace(90, 450, 91))
    loop = np.c_[2 * np.cos(t), -2 + 2 * np.sin(t)]  # one turn round (0, -2), ends at (0, 0)
    a = np.radians(np.linspace(90, 0, 31))
    corner = np.c_[12 * np.cos(a), -12 + 12 * np.sin(a)]  # right turn, radius 12
    xy = np.vstack([[(-30.0, 0.0)], loop, corner[1:], [(12.0, -40.0)]])
    path = prepare_path(xy, 0.1, smooth=True)
    feature = (28.0, 30.0 + 4 * math.pi + 6 * math.pi + 2.0)
    assert excess_turning_deg(path, feature, -90.0) > LOOPED_EXCESS_DEG
    plain = candidates(path, feature, -90.0, SwingSearch(), inside_room_m=0.0)
    looped = candidates(path, feature, -90.0, SwingSearch(), inside_room_m=0.0, looped=True)
    cuts = [c for c in looped if c.shape == "inside"]
    assert not [c for c in plain if c.shape == "inside"] and cuts
    assert len(looped) == len(plain) + len(cuts)
    # the lane's loop is far tighter than the lock; the longest cut is not
    lane = simulate_batch([car], [path])[0]
    best = simulate_batch([car], [cuts[-1].path])[0]
    assert lane.cannot_turn and not best.cannot_turn
