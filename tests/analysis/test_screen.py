"""Floors under the judged reach: never above what the judging finds, on turns of every kind."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from clearance.analysis.clearance import Areas, judge
from clearance.analysis.screen import AREAS, boundary_corners, reach_floors
from clearance.analysis.tracking import simulate
from tests.analysis.helpers import bus, car, semi, turn

MARGIN_OF = {"own_lanes": "margin_m", "paved": "paved_margin_m",
             "roadway": "roadway_margin_m"}


def _areas(centre: np.ndarray, inner_m: float, outer_m: float, paved_m: float,
           road_m: float) -> Areas:
    """A lane about a centre line, ``inner_m`` to the inside of a left turn (the left) and
    ``outer_m`` to the outside; the roadway and the pavement wider on both sides."""
    line = shapely.LineString(centre)

    def band(left: float, right: float) -> shapely.Polygon:
        return shapely.Polygon(np.concatenate([
            shapely.get_coordinates(line.offset_curve(left, quad_segs=16)),
            shapely.get_coordinates(line.offset_curve(-right, quad_segs=16))[::-1]]))

    return Areas(band(inner_m, outer_m), band(inner_m + paved_m, outer_m + paved_m),
                 band(inner_m + road_m, outer_m + road_m))


CASES = [(vehicle, radius, angle, inner, outer)
         for vehicle in ("car", "bus", "semi")
         for radius in (6.0, 12.0, 25.0)
         for angle in (45.0, 90.0, 160.0)
         for inner, outer in ((1.0, 1.0), (1.75, 1.0), (0.8, 2.5))]


@pytest.mark.parametrize(("vehicle", "radius", "angle", "inner", "outer"), CASES)
def test_floors_are_never_above_the_judged_reach(vehicle, radius, angle, inner, outer):
    v = {"car": car, "bus": bus, "semi": semi}[vehicle]()
    centre = turn(radius, angle, lead_m=20.0, tail_m=20.0)
    run = simulate(v, centre)
    areas = _areas(centre, inner, outer, 0.4, 0.2)
    clearance = judge(run, areas)
    for names in (AREAS, ("own_lanes",), ("roadway", "own_lanes")):
        for name, floor in reach_floors(run, areas, names=names).items():
            margin = getattr(clearance, MARGIN_OF[name])
            assert margin <= -floor + 1e-12, (name, floor, margin)


def test_the_floors_find_most_reaches_beyond_the_lanes():
    """The test above could pass with no floor at all: on these turns most runs that leave
    their lanes get one, and where the farthest reach is a body corner it is the judged
    reach itself."""
    found = reached = exact = 0
    for vehicle, radius, angle, inner, outer in CASES:
        v = {"car": car, "bus": bus, "semi": semi}[vehicle]()
        centre = turn(radius, angle, lead_m=20.0, tail_m=20.0)
        run = simulate(v, centre)
        areas = _areas(centre, inner, outer, 0.4, 0.2)
        margin = judge(run, areas).margin_m
        if margin < -0.05:
            reached += 1
            floors = reach_floors(run, areas, names=("own_lanes",))
            found += "own_lanes" in floors
            exact += "own_lanes" in floors and math.isclose(floors["own_lanes"], -margin,
                                                            abs_tol=1e-5)
    assert reached > 30 and found > 0.6 * reached and exact > 5


def test_no_floor_with_an_offset_or_where_the_run_stays_in_its_lanes():
    centre = turn(12.0, 90.0)
    run = simulate(bus(), centre)
    tight = _areas(centre, 0.8, 0.8, 0.4, 0.2)
    assert reach_floors(run, tight)
    assert reach_floors(run, tight, offset_m=0.3) == {}
    assert reach_floors(run, _areas(centre, 8.0, 8.0, 1.0, 0.5)) == {}


def test_boundary_corners_lie_on_the_judged_envelope():
    """Every corner kept is on the boundary of the envelope the judging sweeps (to the
    floating point of the union)."""
    from clearance.analysis.envelope import swept_envelope

    for v in (car(), bus(), semi()):
        run = simulate(v, turn(9.0, 120.0))
        pts = boundary_corners(run)
        envelope = swept_envelope(run)[0]
        assert len(pts) > 10
        d = shapely.distance(shapely.points(pts), envelope.boundary)
        assert float(np.max(d)) < 1e-9
