"""Storeys are where a network lies over itself: a road that climbs is not a second storey."""

from __future__ import annotations

import doctest

import numpy as np
import shapely

import clearance.networks.stacking
from clearance.networks.area_book import curve_levels
from clearance.networks.area_groups import AreaIndex
from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.sources import SAMPLES_DIR
from clearance.networks.stacking import densify, met_pieces, stacking
from tests.networks.sumo.test_parity import HAND_PICKED

#: The networks of SUMO's test suite in tests/data/sumo_corpus whose roads climb: nothing
#: lies over anything in any of them (climbing roads, a height map, 3-D junctions).
ELEVATED = ("xml_shapes_elevation", "xml_3d_internal_lanes", "xml_3d_large_junction",
            "opendrive_elevation_roundtrip", "utm_heightmap")

#: A junction whose fourth arm climbs away east, turns and crosses over its south arm 7 m
#: up, then runs west over nothing (a flyover).
FLYOVER_NODES = """
<node id="J" x="0" y="0" z="0"/><node id="W" x="-100" y="0" z="0"/>
<node id="E" x="100" y="0" z="0"/><node id="S" x="0" y="-100" z="0"/>
<node id="L" x="-100" y="-30" z="7"/>
"""
FLYOVER_EDGES = """
<edge id="WJ" from="W" to="J"/><edge id="JW" from="J" to="W"/>
<edge id="EJ" from="E" to="J"/><edge id="JE" from="J" to="E"/>
<edge id="SJ" from="S" to="J"/><edge id="JS" from="J" to="S"/>
<edge id="JL" from="J" to="L" shape="0,0,0 30,-10,2 40,-30,5 0,-30,7 -100,-30,7"/>
"""


def test_doctests():
    assert doctest.testmod(clearance.networks.stacking).failed == 0


def test_the_helix_and_the_garage_are_stacked_and_climbing_roads_are_not():
    helix = stacking(read_network(SAMPLES_DIR / "helix" / "helix.net.xml"))
    assert helix.lanes["helix_0"].mean() > 0.8  # every turn lies over the one below
    garage = stacking(read_network(SAMPLES_DIR / "garage" / "garage.net.xml"))
    assert garage.any and garage.junctions
    for name in ELEVATED:
        net = read_network(HAND_PICKED / f"{name}.net.xml")
        heights = np.concatenate([lane.shape[:, 2] for lane in net.lanes.values()])
        assert np.ptp(heights) > 2.0, name  # they do climb
        assert not stacking(net).any, name
        assert all(curve_levels(AreaIndex(net), c) == () for c in extract_curves(net)), name


def test_a_flyover_is_a_storey_where_it_crosses_and_a_ramp_where_it_climbs(build_net):
    net = read_network(build_net(FLYOVER_NODES, FLYOVER_EDGES, name="flyover"))
    st = stacking(net)
    assert set(st.lanes) == {"JL_0", "JS_0", "SJ_0"}  # the deck and the arm it crosses
    turn = next(c for c in extract_curves(net) if c.curve_id == "turn:J:SJ_0->JW_0")
    (ground,) = [lv for lv in curve_levels(AreaIndex(net), turn) if lv.z_lo_m <= 0 < lv.z_hi_m]
    deck = net.lanes["JL_0"].shape
    climbing = shapely.Point(*(0.5 * (deck[2, :2] + deck[3, :2])))  # 3.7 m up over nothing
    beyond = shapely.Point(deck[4, 0] - 30.0, deck[4, 1])  # past the crossing, 7 m up
    for p in (climbing, beyond):
        assert turn.paved.covers(p)  # in plan both are pavement
    assert ground.areas.paved.covers(climbing)
    assert not ground.areas.paved.intersects(beyond.buffer(1.0))
    assert ground.areas.paved.covers(turn.own_lanes.buffer(-0.01))


def test_met_pieces_cross_from_lane_to_lane_and_stop_at_a_storey():
    a = densify(np.array([[0.0, 0, 0], [10.0, 0, 0]]))
    b = densify(np.array([[10.0, 0, 0], [20.0, 0, 6]]))
    c = densify(np.array([[20.0, 0, 6], [30.0, 0, 6]]))
    lines = {"a": a, "b": b, "c": c}
    links = {"a": ["b"], "b": ["c"]}
    met = met_pieces(lines, {}, links, -1.5, 1.5)
    assert all(m.all() for m in met.values())  # one road climbing 6 m: met all along
    met = met_pieces(lines, {"c": np.ones(len(c) - 1, dtype=bool)}, links, -1.5, 1.5)
    assert met["a"].all() and met["b"].all() and not met["c"].any()
