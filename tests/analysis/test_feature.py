"""The feature window (analysis/feature.py): which samples judge a curve, and why not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.analysis.feature import feature_mask, feature_reason, slice_run
from clearance.analysis.tracking import simulate
from tests.analysis.helpers import bus, car, semi, turn


def test_feature_window_spans_the_whole_vehicle_trailer_included() -> None:
    v = semi()
    run = simulate(v, [(0.0, 0.0), (80.0, 0.0)])
    s = run.trajectory.s_m[feature_mask(run, (40.0, 41.0))]
    # from the front bumper reaching 40 m to the trailer's rear leaving 41 m
    assert s.min() == pytest.approx(40.0 - v.front_overhang_m, abs=0.25)
    assert s.max() == pytest.approx(41.0 + v.overall_length_m - v.front_overhang_m, abs=0.25)
    assert v.overall_length_m > v.length_m + 5.0


def test_feature_window_is_contiguous_and_grows_with_the_feature() -> None:
    run = simulate(car(), [(0.0, 0.0), (60.0, 0.0)])
    short = feature_mask(run, (20.0, 21.0))
    long = feature_mask(run, (20.0, 30.0))
    idx = np.flatnonzero(short)
    assert len(idx) and np.all(np.diff(idx) == 1)  # one stretch of samples
    assert np.all(long[short]) and long.sum() > short.sum()
    # a feature wholly before the run's start (negative stations) has no samples
    assert not feature_mask(run, (-50.0, -40.0)).any()


def test_slice_run_keeps_every_field_of_the_chosen_samples() -> None:
    run = simulate(car(), turn(12.0, 90.0))
    keep = np.flatnonzero(feature_mask(run, (15.0, 20.0)))
    cut = slice_run(run, keep)
    tr, ct = run.trajectory, cut.trajectory
    assert len(ct.s_m) == len(keep)
    np.testing.assert_array_equal(ct.s_m, tr.s_m[keep])
    np.testing.assert_array_equal(ct.error_m, tr.error_m[keep])
    assert cut.vehicle is run.vehicle and cut.settings == run.settings


def test_reason_names_the_error_in_the_feature_only() -> None:
    # a 5 m corner tighter than the bus's lock on the lead-in, then 70 m straight
    line = turn(5.0, 90.0, lead_m=10.0, tail_m=70.0, left=True)
    run = simulate(bus(), line)
    s_corner = 10.0 + 5.0 * math.pi / 2
    assert run.max_error_m > run.settings.tolerance_m
    far = feature_reason(run, feature_mask(run, (s_corner + 50.0, s_corner + 55.0)))
    assert far == ""
    here = feature_reason(run, feature_mask(run, (10.0, s_corner)))
    assert "left the centre line by" in here and "in the feature" in here
    # the station it names lies within the corner's window
    station = float(here.split("at station ")[1].split(" m")[0])
    window = run.trajectory.s_m[feature_mask(run, (10.0, s_corner))]
    assert window.min() <= station <= window.max()


def test_reason_for_a_run_stopped_before_the_feature() -> None:
    run = simulate(bus(), turn(3.0, 90.0, lead_m=10.0, tail_m=70.0, left=True))
    assert not run.reached_end
    reason = feature_reason(run, feature_mask(run, (60.0, 65.0)))
    assert reason.startswith("the run stopped before the vehicle had left the feature")
