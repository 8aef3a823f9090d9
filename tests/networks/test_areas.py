"""Areas of curves: nesting, sealed joins, shared results."""

from __future__ import annotations

import math

import numpy as np
import shapely

from networks.areas import MIN_HOLE_M2, _fill_small_holes, _union_rows, attach_areas
from networks.curves import extract_curves
from networks.reader import read_network


def test_union_rows_skip_missing_geometry():
    g = np.array([shapely.box(0, 0, 1, 1), None, shapely.box(1, 0, 2, 1)], dtype=object)
    out = _union_rows([[0, 1, 2], [1], [0, 1]], g)
    assert [round(x.area, 9) for x in out] == [2.0, 0.0, 1.0]


def test_small_holes_are_filled_islands_kept():
    square = shapely.box(0, 0, 20, 20)
    wedge = shapely.box(5, 5, 5.5, 5.5)  # 0.25 m2: a gap between lane pieces
    island = shapely.box(10, 10, 14, 14)  # 16 m2: a traffic island
    area = square.difference(wedge).difference(island)
    filled = _fill_small_holes(area)
    assert filled.area == 400 - 16 and 0.25 < MIN_HOLE_M2 < 16


def test_kinked_lanes_leave_no_gap_and_areas_nest(build_net):
    # two one-lane edges meeting at 30 degrees, and a side road making a junction
    a = math.radians(30)
    nodes = (
        '<node id="A" x="-60" y="0"/><node id="B" x="0" y="0" type="priority"/>'
        f'<node id="C" x="{60 * math.cos(a):.3f}" y="{60 * math.sin(a):.3f}"/>'
        '<node id="D" x="0" y="-60"/>'
    )
    edges = (
        '<edge id="AB" from="A" to="B" numLanes="1"/><edge id="BC" from="B" to="C" numLanes="1"/>'
        '<edge id="DB" from="D" to="B" numLanes="1"/><edge id="BA" from="B" to="A" numLanes="1"/>'
    )
    net = read_network(build_net(nodes, edges))
    curves = extract_curves(net, ["turn"], areas=False)
    assert all(c.own_lanes is None for c in curves)
    attach_areas(net, curves)
    for c in curves:
        assert c.own_lanes.difference(c.paved).area < 1e-3, c.curve_id
        assert c.roadway.difference(c.paved).area < 1e-6, c.curve_id
        assert shapely.covers(c.paved, shapely.LineString(c.centerline[:, :2]).buffer(0.5))
    # every turn at B shares one paved area
    at_b = [c for c in curves if c.junction == "B"]
    assert len(at_b) >= 3 and len({id(c.paved) for c in at_b}) == 1
