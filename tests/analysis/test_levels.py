"""Levels: height slots, band pieces, path stretches, corridors, and judging by storey."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from clearance.analysis.clearance import Areas, evaluate
from clearance.analysis.levels import (
    CORRIDOR_OVERLAP_M,
    LEVEL_BAND_M,
    LEVEL_STEP_M,
    SLOT_HYSTERESIS_M,
    Level,
    band_pieces,
    corridor,
    is_flat,
    level_slots,
    path_segments,
)
from clearance.analysis.polyline import prepare_path
from clearance.analysis.tracking import simulate
from clearance.vehicles.vehicle import Vehicle

CAR = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)


def test_band_pieces_of_a_v_profile_are_two_pieces_at_the_crossings():
    # down from 4 m to 0 m and up again, 40 m each way: the band 1..2 m is met twice,
    # each time over 10 m, at 20..30 m and 50..60 m of plan length
    line = np.array([[0.0, 0.0, 4.0], [40.0, 0.0, 0.0], [80.0, 0.0, 4.0]])
    pieces = band_pieces(line, 1.0, 2.0)
    assert [p[:, 0].tolist() for p in pieces] == [[20.0, 30.0], [50.0, 60.0]]
    # the whole line within a wide band is one piece with every vertex
    (whole,) = band_pieces(line, -1.0, 5.0)
    assert whole.tolist() == line[:, :2].tolist()


def test_band_pieces_keep_the_length_of_a_helix_within_the_band():
    # a helix of radius 9 m rising 3.2 m per turn: the part within a 3 m band is 3 / 3.2
    # of a turn, whatever the points
    a = np.linspace(0.0, 4 * np.pi, 721)
    helix = np.column_stack([9 * np.cos(a), 9 * np.sin(a), 3.2 * a / (2 * np.pi)])
    pieces = band_pieces(helix, 2.0, 5.0)
    length = sum(shapely.LineString(p).length for p in pieces)
    assert length == pytest.approx(2 * np.pi * 9 * 3.0 / 3.2, rel=1e-3)


def test_level_slots_cover_the_heights_in_steps():
    slots = level_slots(np.array([0.2, 9.8]))
    assert len(slots) == 10 and slots[0] == (0.2, 1.2)
    assert slots[-1][0] <= 9.8 < slots[-1][1]
    assert all(hi - lo == pytest.approx(LEVEL_STEP_M) for lo, hi in slots)


def test_is_flat_is_the_step():
    assert is_flat(np.array([0.0, LEVEL_STEP_M]))
    assert not is_flat(np.array([0.0, LEVEL_STEP_M + 0.01]))


def test_path_segments_do_not_flicker_on_a_floor_at_a_slot_edge():
    levels = [Level(0.0, 1.0, None), Level(1.0, 2.0, None), Level(2.0, 3.0, None)]
    s = np.arange(0.0, 50.0, 0.5)
    z = 1.0 + 0.05 * np.sin(s)  # a floor at 1.0 m with 5 cm of noise
    assert len(path_segments(s, z, levels)) == 1
    # a ramp through the slots changes slot once per slot, a hysteresis beyond each edge
    ramp = path_segments(s, s / 49.5 * 3.0, levels)
    assert [k for _, _, k in ramp] == [0, 1, 2]
    cut = ramp[0][1]
    assert cut / 49.5 * 3.0 == pytest.approx(1.0 + SLOT_HYSTERESIS_M, abs=0.05)
    assert ramp[0][0] == 0.0 and ramp[-1][1] == s[-1]


def test_consecutive_corridors_cover_the_whole_buffer_of_a_bend():
    # a tight circle, cut in stretches: with the overlap, no wedge on the outside is lost
    a = np.linspace(0.0, 1.5 * np.pi, 200)
    xy = np.column_stack([8 * np.cos(a), 8 * np.sin(a)])
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))))
    cuts = np.linspace(0.0, s[-1], 7)
    parts = [corridor(xy, s, lo - CORRIDOR_OVERLAP_M, hi + CORRIDOR_OVERLAP_M, 3.0)
             for lo, hi in zip(cuts[:-1], cuts[1:], strict=True)]
    whole = shapely.buffer(shapely.LineString(xy), 3.0, cap_style="flat")
    assert shapely.difference(whole, shapely.union_all(parts)).area < 1e-6


def _two_storeys() -> tuple[Areas, Areas]:
    """An upper floor's 2.0 m lane (z 3 m) above a lower floor's 6 m aisle (z 0): the plan
    areas (their union) and the areas by level."""
    upper = shapely.box(-10.0, -1.0, 40.0, 1.0)
    lower = shapely.box(-10.0, -3.0, 40.0, 3.0)
    plan = Areas(shapely.union(upper, lower), shapely.union(upper, lower))
    levels = (Level(-0.5, 0.5, Areas(lower, lower)), Level(2.5, 3.5, Areas(upper, upper)))
    return plan, Areas(plan.own_lanes, plan.paved, levels=levels)


def test_a_car_on_the_upper_floor_is_judged_against_its_own_floor_only():
    plan, by_level = _two_storeys()
    # a 1.8 m car driving 0.3 m off the upper lane's centre: inside the aisle below in plan,
    # 0.2 m beyond its own 2.0 m lane
    run = simulate(CAR, prepare_path([(0.0, 0.3, 3.0), (30.0, 0.3, 3.0)]))
    assert evaluate(run, plan).verdict == "clear"
    res = evaluate(run, by_level)
    assert res.verdict == "fails"
    assert res.margin_m == pytest.approx(-0.2, abs=0.01)
    assert "on the level at 3.0 m" in res.clearance.reason
    # on the lower floor the same run is clear: the aisle is its own
    low = simulate(CAR, prepare_path([(0.0, 0.3, 0.0), (30.0, 0.3, 0.0)]))
    assert evaluate(low, by_level).verdict == "clear"
    # a path without heights is judged in plan
    flat = simulate(CAR, prepare_path([(0.0, 0.3), (30.0, 0.3)]))
    assert evaluate(flat, by_level).verdict == "clear"


def test_a_ramp_is_judged_by_each_stretch_and_the_worst_decides():
    plan, by_level = _two_storeys()
    # up from the aisle to the upper floor over 30 m, 0.3 m off centre: the upper stretch
    # leaves its lane, the lower does not
    run = simulate(CAR, prepare_path([(0.0, 0.3, 0.0), (30.0, 0.3, 3.0)]))
    res = evaluate(run, by_level)
    assert res.verdict == "fails" and res.margin_m == pytest.approx(-0.2, abs=0.01)
    assert evaluate(run, plan).verdict == "clear"


def test_level_swept_widths_are_those_of_one_passage():
    # two passages of a straight lane on top of each other in plan cannot be told apart by
    # the stations, only by height: each is the car's width, 1.8 m
    _, by_level = _two_storeys()
    run = simulate(CAR, prepare_path([(0.0, 0.0, 3.0), (30.0, 0.0, 3.0)]))
    res = evaluate(run, by_level, feature_m=(10.0, 20.0))
    assert res.swept.max_swept_width_m == pytest.approx(1.8, abs=1e-6)
    stations = res.swept.swept_width_m[:, 0]
    assert stations.min() >= 10.0 - 1e-9 and stations.max() <= 20.0 + 1e-9


def test_the_band_leaves_out_the_next_storey():
    # the guarantee of the module docstring: a storey 2.4 m above is never in the band of
    # any station's slot, a part within 0.75 m always is
    assert LEVEL_STEP_M / 2 + SLOT_HYSTERESIS_M + LEVEL_BAND_M < 2.4
    assert LEVEL_BAND_M - LEVEL_STEP_M / 2 - SLOT_HYSTERESIS_M == pytest.approx(0.75)
    assert math.isclose(LEVEL_BAND_M, 1.5)
