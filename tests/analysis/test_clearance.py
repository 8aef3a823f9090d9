"""Margins and verdicts on synthetic polygons, and a full run through a junction corner."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
import shapely.affinity

from clearance.analysis.clearance import (
    VERDICTS,
    Areas,
    classify,
    evaluate,
    evaluate_batch,
    judge,
)
from clearance.analysis.feature import feature_mask
from clearance.analysis.margins import signed_margin_m
from clearance.analysis.tracking import simulate, simulate_batch
from clearance.vehicles.errors import GeometryError
from tests.analysis.helpers import bus, car, semi, turn

LANE = shapely.box(0.0, 0.0, 60.0, 3.5)
ROADWAY = shapely.box(0.0, 0.0, 60.0, 7.0)
PAVED = shapely.box(0.0, -0.5, 60.0, 7.5)


def test_verdicts_worst_first() -> None:
    areas = Areas(LANE, PAVED, ROADWAY)
    clear = classify(shapely.box(10, 0.8, 20, 2.7), areas)
    enc = classify(shapely.box(10, 2.0, 20, 4.5), areas)
    fails = classify(shapely.box(10, -1.0, 20, 1.0), areas)
    cannot = classify(shapely.box(10, 0.8, 20, 2.7), areas, cannot_turn_reason="lock")
    assert VERDICTS == ("cannot-turn", "fails", "encroaches", "clear")
    assert (clear.verdict, enc.verdict, fails.verdict, cannot.verdict) == VERDICTS[::-1]
    assert clear.margin_m == pytest.approx(0.8)
    assert enc.margin_m == pytest.approx(-1.0) and enc.paved_margin_m == pytest.approx(2.5)
    assert enc.roadway_margin_m == pytest.approx(2.0)
    assert fails.paved_margin_m == pytest.approx(-0.5) and fails.margin_m == pytest.approx(-1.0)
    assert cannot.reason == "lock" and cannot.margin_m == pytest.approx(0.8)


def test_clearance_offset_grows_the_envelope_first() -> None:
    areas = Areas(LANE, PAVED)
    env = shapely.box(10, 0.8, 20, 2.7)
    assert classify(env, areas, offset_m=0.5).margin_m == pytest.approx(0.3)
    grown = classify(env, areas, offset_m=1.0)
    assert grown.verdict == "encroaches" and grown.margin_m == pytest.approx(-0.2, abs=1e-9)
    assert "grown by 1.00 m" in grown.reason
    assert classify(env, areas, offset_m=1.4).verdict == "fails"  # 0.8 + 0.5 < 1.4


def test_bad_areas_and_offsets_raise_input_errors() -> None:
    bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    with pytest.raises(GeometryError, match="own_lanes is not a valid polygon"):
        Areas(bowtie, PAVED)
    with pytest.raises(GeometryError, match="paved is empty"):
        Areas(LANE, shapely.Polygon())
    with pytest.raises(ValueError, match="offset"):
        classify(shapely.box(1, 1, 2, 2), Areas(LANE, PAVED), offset_m=-0.1)
    run = simulate(car(), [(0.0, 1.75), (30.0, 1.75)])
    for bad in (-0.3, math.nan):
        with pytest.raises(ValueError, match="offset"):
            evaluate(run, Areas(LANE, PAVED), offset_m=bad)


def _corner_areas(path: np.ndarray, lane_half_m: float, paved_half_m: float) -> Areas:
    centre = shapely.LineString(path)
    own = shapely.buffer(centre, lane_half_m, quad_segs=32, cap_style="flat")
    paved = shapely.buffer(centre, paved_half_m, quad_segs=32, cap_style="flat")
    return Areas(own, paved)


def test_full_run_margin_equals_independent_overreach_of_the_lane() -> None:
    path = turn(12.0, 90.0, lead_m=20.0, tail_m=20.0)
    run = simulate(bus(), path)
    areas = _corner_areas(path, 1.75, 8.0)
    res = evaluate(run, areas)
    assert res.verdict == "encroaches"
    # independent: a lane is the centre line grown by 1.75 m, so a point lies beyond it by
    # (its distance to the centre line - 1.75); the envelope's farthest boundary point
    # between the path's end lines (x = -20 at the start, y = 32 at the end) decides
    xy = shapely.get_coordinates(shapely.segmentize(res.swept.envelope, 0.05))
    xy = xy[(xy[:, 0] >= -20.0) & (xy[:, 1] <= 32.0)]
    beyond = shapely.distance(shapely.points(xy), shapely.LineString(path)) - 1.75
    assert res.margin_m == pytest.approx(-float(beyond.max()), abs=0.03)
    assert res.margin_m < -0.5  # a bus does not fit a 3.5 m lane round a 12 m corner


def test_full_runs_classified_per_vehicle() -> None:
    path = turn(12.0, 90.0, lead_m=20.0, tail_m=20.0)
    tight = turn(4.0, 90.0, lead_m=20.0, tail_m=20.0)
    runs = simulate_batch([car(), bus(), bus(), bus()], [path, path, path, tight])
    wide = _corner_areas(path, 2.5, 8.0)
    narrow = _corner_areas(path, 1.75, 2.5)
    results = evaluate_batch(runs, [wide, wide, narrow, _corner_areas(tight, 3.5, 8.0)],
                             offset_m=0.3)
    assert [r.verdict for r in results] == ["clear", "encroaches", "fails", "cannot-turn"]
    assert results[0].margin_m > 0 and results[1].margin_m < 0
    assert results[2].clearance.paved_margin_m < 0
    assert "left the centre line" in results[3].clearance.reason


def test_full_run_gap_inside_the_lane_ignores_the_lane_ends() -> None:
    path = turn(12.0, 90.0, lead_m=20.0, tail_m=20.0)
    run = simulate(car(), path)
    res = evaluate(run, _corner_areas(path, 2.5, 8.0), offset_m=0.3)
    assert res.verdict == "clear"
    # independent: the gap is 2.5 - 0.3 - (largest distance of the envelope from the centre
    # line), over the envelope between the path's end lines
    xy = shapely.get_coordinates(shapely.segmentize(res.swept.envelope, 0.05))
    xy = xy[(xy[:, 0] >= -20.0) & (xy[:, 1] <= 32.0)]
    widest = float(np.max(shapely.distance(shapely.points(xy), shapely.LineString(path))))
    assert res.margin_m == pytest.approx(2.5 - 0.3 - widest, abs=0.03)
    # the measured envelope is the grown one, cut at the start line x = -20 and end y = 32
    minx, _, _, maxy = res.measured.bounds
    assert minx == pytest.approx(-20.0) and maxy == pytest.approx(32.0)
    assert shapely.covers(shapely.buffer(res.swept.envelope, 0.3 + 1e-6), res.measured)
    assert 0.3 < res.margin_m < 1.5


def test_area_segments_are_the_boundary_and_give_the_same_margins() -> None:
    rng = np.random.default_rng(9)
    for _ in range(20):
        # a ring-shaped area (a hole too), an envelope poking out of it in places
        area = shapely.difference(shapely.Point(0, 0).buffer(rng.uniform(8, 12), quad_segs=8),
                                  shapely.Point(rng.uniform(-1, 1), 0).buffer(3.0, quad_segs=4))
        areas = Areas(area, shapely.box(-20, -20, 20, 20))
        segs = areas.segments("own_lanes")
        assert float(np.hypot(*(segs[:, 1] - segs[:, 0]).T).sum()) == pytest.approx(
            shapely.boundary(area).length, rel=1e-12)
        envelope = shapely.affinity.rotate(
            shapely.box(rng.uniform(-9, -4), rng.uniform(-4, 2), rng.uniform(4, 15),
                        rng.uniform(3, 6)), rng.uniform(0, 180), origin=(0, 0))
        assert signed_margin_m(envelope, area, area_segments=segs) == pytest.approx(
            signed_margin_m(envelope, area), abs=1e-12)


# ---------------------------------------------------------------- judged by its feature

def test_only_the_sweep_in_the_feature_decides() -> None:
    # a straight 60 m run in a 3.5 m lane; 10 m of the lead-in has a curb that cuts the
    # lane to 1 m wide (a neighbouring corner): the feature, at 40..45 m, is clear
    v = car()
    run = simulate(v, [(0.0, 1.75), (60.0, 1.75)])
    pinch = shapely.box(5.0, 0.0, 15.0, 2.5)
    lane = shapely.difference(LANE, pinch)
    paved = shapely.difference(PAVED, shapely.box(5.0, -0.5, 15.0, 2.5))
    areas = Areas(lane, paved)
    whole = evaluate(run, areas)
    judged = evaluate(run, areas, feature_m=(40.0, 45.0))
    assert whole.verdict == "fails"
    assert judged.verdict == "clear"
    # 3.5 m lane, 1.8 m car centred: 0.85 m either side, in the feature
    assert judged.margin_m == pytest.approx(0.85, abs=0.01)
    # the envelope judged reaches from the front bumper at the feature's start back to the
    # rear bumper at its end (along x here), plus one sample either side
    x0, _, x1, _ = judged.measured.bounds
    assert x0 == pytest.approx(40.0 - v.length_m, abs=0.25)
    assert x1 == pytest.approx(45.0 + v.length_m, abs=0.25)
    # a feature where the curb is: fails, as the whole run
    assert evaluate(run, areas, feature_m=(8.0, 12.0)).verdict == "fails"


def test_a_tracking_error_outside_the_feature_is_not_cannot_turn() -> None:
    # a corner of 5 m radius (tighter than the bus's lock: 1.5 m off the line) on the
    # lead-in, then 70 m straight: that error belongs to that corner, not to a feature 50 m on
    line = turn(5.0, 90.0, lead_m=10.0, tail_m=70.0, left=True)
    run = simulate(bus(), line)
    assert run.cannot_turn and run.max_error_m > 1.0 and run.reached_end
    s_corner = 10.0 + 5.0 * math.pi / 2
    areas = Areas(shapely.LineString(line).buffer(6.0), shapely.LineString(line).buffer(30.0))
    feature = (s_corner + 50.0, s_corner + 55.0)
    judged = evaluate(run, areas, feature_m=feature)
    assert judged.verdict != "cannot-turn", judged.clearance.reason
    err = np.abs(run.trajectory.error_m)
    mask = feature_mask(run, feature)
    assert err[mask].max() <= run.settings.tolerance_m < err.max()
    # the corner itself as the feature: cannot-turn there, with the reason saying so
    at_corner = evaluate(run, areas, feature_m=(10.0, s_corner))
    assert at_corner.verdict == "cannot-turn"
    assert "in the feature" in at_corner.clearance.reason


def test_a_run_stopped_before_the_feature_cannot_turn_there() -> None:
    # stopped (beyond the abort distance) at a 3 m corner: it never got through the feature
    line = turn(3.0, 90.0, lead_m=10.0, tail_m=70.0, left=True)
    run = simulate(bus(), line)
    assert not run.reached_end
    areas = Areas(shapely.LineString(line).buffer(6.0), shapely.LineString(line).buffer(30.0))
    judged = evaluate(run, areas, feature_m=(60.0, 65.0))
    assert judged.verdict == "cannot-turn"
    assert judged.clearance.reason.startswith("the run stopped before the vehicle had left")


@pytest.mark.parametrize("offset_m", [0.0, 0.3])
def test_judge_gives_the_clearance_evaluate_gives(offset_m: float) -> None:
    """The search judges candidates by their clearance alone: for cars, buses and a
    semitrailer, clear, encroaching, failing and unable to turn, over the whole run and over
    a window, it is the one the full evaluation gives."""
    path = turn(12.0, 90.0, lead_m=20.0, tail_m=20.0)
    tight = turn(4.0, 90.0, lead_m=20.0, tail_m=20.0)
    runs = simulate_batch([car(), bus(), bus(), semi(), bus()], [path, path, path, path, tight])
    wide, narrow = _corner_areas(path, 2.5, 8.0), _corner_areas(path, 1.75, 2.5)
    areas = [wide, wide, narrow, wide, _corner_areas(tight, 3.5, 8.0)]
    seen = set()
    for run, a in zip(runs, areas, strict=True):
        for window in (None, (22.0, 35.0)):
            full = evaluate(run, a, offset_m, feature_m=window).clearance
            assert judge(run, a, offset_m, feature_m=window) == full
            seen.add(full.verdict)
    assert seen == set(VERDICTS)
