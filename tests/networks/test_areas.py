"""Areas of curves: nesting, sealed joins, shared results."""

from __future__ import annotations

import math

import numpy as np
import shapely

from clearance.networks.areas import (
    CRACK_M,
    MIN_HOLE_M2,
    _fill_small_holes,
    _union_rows,
    attach_areas,
    close_cracks,
)
from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network


def _wkb(parts) -> list[list[bytes]]:
    """Areas (arrays of geometries, e.g. own lanes, roadway, paved) as WKB, to compare
    them byte for byte."""
    return [[shapely.to_wkb(g) for g in part] for part in parts]


def _intersection_job():
    """The intersection sample's areas as one job (all its curves)."""
    from clearance.networks.area_groups import AreaIndex, BatchPlan
    from clearance.networks.areas import make_job
    from clearance.networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "intersection" / "intersection.net.xml")
    curves = extract_curves(net, areas=False)
    plan = BatchPlan(AreaIndex(net))
    for c in curves:
        plan.add(c)
    return make_job(plan, curves)


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


def test_cracks_between_two_directions_are_closed_a_median_is_kept():
    # a street's two directions drawn from two lines 0.06 degrees apart: the lanes part
    # along a wedge that opens to 0.15 m at 40 m (bs3d, edge 22959383); a car's envelope
    # reaching 5 cm into it left the "paved" area
    east = shapely.LineString([(0, -1.6), (40, -1.6)]).buffer(1.6, cap_style="flat")
    west = shapely.LineString([(0, 1.6), (40, 1.75)]).buffer(1.6, cap_style="flat")
    street = shapely.union(east, west)
    wedge = shapely.Polygon([(0, 0), (40, 0), (40, 0.15)])
    assert street.intersection(wedge).area < 0.01  # open before
    closed = close_cracks(np.array([street], dtype=object))[0]
    assert closed.covers(wedge.intersection(shapely.box(1, -1, 39, 1)))
    # nothing is added beyond the crack (the slanted ends' notches, mm wide): the
    # closing keeps the outline, corners included
    assert abs(closed.area - street.area - wedge.area) < 0.002
    assert np.allclose(closed.bounds, street.bounds, atol=1e-9)
    # a 1 m median between two carriageways is wider than 2 CRACK_M: kept
    far = shapely.LineString([(0, 4.2), (40, 4.2)]).buffer(1.6, cap_style="flat")
    split = shapely.union(east, far)
    kept = close_cracks(np.array([split], dtype=object))[0]
    assert 2 * CRACK_M < 1.0 and kept.geom_type == "MultiPolygon"
    assert math.isclose(kept.area, split.area, rel_tol=1e-9)


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
    # the turns at B that share a roadway (and whose own lanes it covers) share one
    # paved area: it is the junction's grown by that roadway
    at_b = [c for c in curves if c.junction == "B"]
    assert len(at_b) >= 3
    by_road: dict[int, set[int]] = {}
    for c in at_b:
        by_road.setdefault(id(c.roadway), set()).add(id(c.paved))
    assert all(len(p) == 1 for p in by_road.values()) or len(at_b) == len(
        {id(c.paved) for c in at_b})
    # every one of them holds the junction's polygon
    polygon = shapely.Polygon(net.junctions["B"].shape[:, :2])
    assert all(polygon.difference(c.paved).area < 1e-6 for c in at_b)


def test_junction_polygons_at_once_equal_one_by_one():
    from clearance.networks.areas import SEAL_M, junction_polygons
    from clearance.networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")
    ids = list(net.junctions)
    out = junction_polygons(net, ids)
    for j, poly in zip(ids, out, strict=True):
        shape = net.junctions[j].shape
        if len(shape) < 3:
            assert poly is None
            continue
        one = shapely.make_valid(shapely.Polygon(shape[:, :2]))
        one = shapely.buffer(one, SEAL_M, quad_segs=1, join_style="mitre")
        assert shapely.to_wkb(poly) == shapely.to_wkb(one), j
    assert len(junction_polygons(net, [])) == 0


def test_rows_sharing_their_first_two_entries_union_them_once(monkeypatch):
    from clearance.networks import areas

    g = np.array([shapely.box(0, 0, 2, 1), shapely.box(1, 0, 3, 1), shapely.box(2, 0, 4, 2)])
    calls = []
    union = shapely.union
    monkeypatch.setattr(areas.shapely, "union", lambda a, b: calls.append(len(a)) or union(a, b))
    out = _union_rows([[0, 1, 2], [0, 1, 2], [1, 0, 2], [0, 1, 0]], g, seal=False)
    assert [round(float(a.area), 9) for a in out] == [6.0, 6.0, 6.0, 3.0]
    assert calls[0] == 2  # (0, 1) and (1, 0): two first unions for four rows
    assert shapely.to_wkb(out[0]) == shapely.to_wkb(out[1])


