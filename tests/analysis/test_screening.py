"""The screening bound never promises more than the exact judging finds."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from clearance.analysis.clearance import Areas, judge
from clearance.analysis.polyline import prepare_path
from clearance.analysis.screening import paved_reach_bound_m
from clearance.analysis.tracking import simulate_batch
from tests.analysis.helpers import bus, car, semi, turn


@pytest.mark.parametrize("offset_m", [0.0, 0.3])
def test_the_bound_is_never_beyond_the_judged_reach(offset_m: float) -> None:
    """A car, a bus and a tractor-semitrailer on a 12 m corner, their lines moved 0 to
    2.4 m toward the inside of pavement that ends 3 m inside the centre line: wherever
    the bound says the envelope leaves the pavement, the judged paved margin is at least
    that far out, over the whole run and over a window; and the bound is tight, within the
    sweep's tolerance, the search's half step and an outline step's sagitta of the exact
    reach."""
    centre = turn(12.0, 90.0, lead_m=20.0, tail_m=20.0)
    paved = shapely.buffer(shapely.LineString(centre), 3.0, quad_segs=32, cap_style="flat")
    lanes = shapely.buffer(shapely.LineString(centre), 1.75, quad_segs=32, cap_style="flat")
    areas = Areas(lanes, paved)
    lines, vehicles = [], []
    for shift in np.arange(0.0, 2.41, 0.4):
        line = shapely.offset_curve(shapely.LineString(centre), shift, quad_segs=32)
        for v in (car(), bus(), semi()):
            lines.append(prepare_path(shapely.get_coordinates(line), 0.1))
            vehicles.append(v)
    bounded = 0
    for run in simulate_batch(vehicles, lines):
        for window in (None, (22.0, 35.0)):
            bound = paved_reach_bound_m(run, areas, offset_m, window)
            paved_m = judge(run, areas, offset_m, feature_m=window).paved_margin_m
            if math.isfinite(bound) and bound >= 0.01:
                bounded += 1
                assert paved_m <= -bound + 1e-9
                assert -paved_m - bound < 0.1
            # else no bound: where only a side bulges over the curved edge, its corners
            # in, the screen is weaker, never wrong
    assert bounded >= 10
