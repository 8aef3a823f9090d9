"""Drive options, curve selection, a curve's areas and its swung lines driven again
(clearance.networks.driving.runs)."""

from __future__ import annotations

import math

import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.driving.drive import drive
from clearance.networks.driving.runs import (
    DrivenRun,
    DriveOptions,
    curve_areas,
    drive_lines,
    select_curves,
)
from clearance.networks.reader import read_network
from clearance.networks.samples import build as samples
from clearance.vehicles.errors import GeometryError, InputError, OptionError
from clearance.vehicles.table import bundled_table, load_tables


@pytest.fixture(scope="module")
def intersection():
    net = read_network(samples.SAMPLES_DIR / "intersection" / "intersection.net.xml")
    return net, extract_curves(net, ["turn"])


def test_unknown_curve_lists_close_matches(intersection):
    _, curves = intersection
    with pytest.raises(OptionError, match=r"unknown curve 'turn:X:XN_in_0->XW_out_1'; "
                                         r"did you mean 'turn:X:XN_in_0->XW_out_0'"):
        select_curves(curves, ["turn:X:XN_in_0->XW_out_1"])
    picked = select_curves(curves, ["turn:T:TW_in_0->TS_out_0", "turn:X:XN_in_0->XW_out_0"])
    assert [c.curve_id for c in picked] == ["turn:T:TW_in_0->TS_out_0",
                                            "turn:X:XN_in_0->XW_out_0"]
    assert select_curves(curves, None) == curves


def test_curve_areas_need_extraction_with_areas(intersection):
    net, curves = intersection
    areas = curve_areas(curves[0])
    assert areas.own_lanes.within(areas.paved.buffer(0.05))
    (bare, *_) = extract_curves(net, ["turn"], areas=False)
    with pytest.raises(GeometryError, match="no areas"):
        curve_areas(bare)


@pytest.mark.parametrize("kwargs, message", [
    ({"batch_size": 0}, "batch_size must be >= 1"),
    ({"offset_m": -0.1}, "clearance offset"),
    ({"match_threshold_m": math.nan}, "match_threshold_m must be > 0"),
    ({"sumo_step_s": 0.0}, "SUMO step must be a positive number"),
    ({"sumo_step_s": math.inf}, "SUMO step must be a positive number"),
])
def test_bad_options_refused(kwargs, message):
    with pytest.raises((ValueError, OptionError), match=message):
        DriveOptions(**kwargs)


@pytest.mark.parametrize("step, dt, every", [(0.2, 0.1, 2), (None, 0.1, 1), (0.1, 0.1, 1),
                                             (0.3, 0.1, 3), (1.0, 0.05, 20)])
def test_sumo_step_in_model_samples(step, dt, every):
    assert DriveOptions(sumo_step_s=step).samples_per_step(dt) == every


@pytest.mark.parametrize("step, dt", [(0.25, 0.1), (0.05, 0.1), (0.15, 0.1)])
def test_sumo_step_must_be_a_multiple(step, dt):
    with pytest.raises(InputError, match="whole multiple"):
        DriveOptions(sumo_step_s=step).samples_per_step(dt)


def test_a_run_without_result_is_an_error(intersection):
    _, curves = intersection
    car = load_tables([bundled_table("aashto_green_book")], ["P"]).vehicle("P")
    run = DrivenRun(car, curves[0], error="SUMO refused the vehicle")
    assert run.verdict == "error" and run.reason == "SUMO refused the vehicle"
    assert DrivenRun(car, curves[0]).verdict == "error"


def test_a_swung_line_driven_again_is_judged_as_the_search_judged_it(intersection):
    net, curves = intersection
    bus = load_tables([bundled_table("aashto_green_book")], ["CITY-BUS"]).vehicle("CITY-BUS")
    # the designed corner: the bus fails on its lane, swings into the opposing lanes
    [curve] = select_curves(curves, ["turn:X:XN_in_0->XW_out_0"])
    [searched] = drive(net, [(bus, curve)], options=DriveOptions(use_sumo=False))
    assert searched.path == "swung" and searched.line is not None
    assert searched.line.swing_m == searched.swing_m
    [again] = drive(net, [(bus, curve)], options=DriveOptions(use_sumo=False, swing=False))
    assert again.path == "lane" and again.line is None
    assert drive_lines([again], [searched.line], 0.0) == 1
    assert (again.path, again.swing_m, again.line) == ("swung", searched.swing_m,
                                                       searched.line)
    assert again.result is not None and searched.result is not None
    assert again.verdict == searched.verdict == "encroaches"
    assert again.result.clearance.margin_m == searched.result.clearance.margin_m
    assert again.result.clearance.paved_margin_m == searched.result.clearance.paved_margin_m
    assert again.result.measured.equals_exact(searched.result.measured, 0.0)
    assert again.lane_verdict == searched.lane_verdict == "fails"
    assert again.lane_margin_m == searched.lane_margin_m
    # a curve without its areas: that run's error, not the others'
    (bare, *_) = extract_curves(net, ["turn"], areas=False)
    lost = DrivenRun(bus, bare)
    assert drive_lines([lost], [searched.line], 0.0) == 0
    assert lost.verdict == "error" and "could not be judged" in lost.error
