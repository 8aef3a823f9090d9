"""Where a station of a curve lies: approach, feature or exit, and kinks of the approach."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.places import KINK_DEG, kink_near, place_of
from clearance.networks.reader import read_network

NODES = ('<node id="A" x="-100" y="0"/><node id="J" x="0" y="0"/>'
         '<node id="B" x="100" y="0"/><node id="C" x="0" y="-100"/>')
# the approach kinks by about 40 degrees 15 m before J's centre (about 11 m before its corner)
EDGES = ('<edge id="AJ" from="A" to="J" numLanes="1" shape="-100,-10 -15,-10 0,0"/>'
         '<edge id="JB" from="J" to="B" numLanes="1"/>'
         '<edge id="JC" from="J" to="C" numLanes="1"/>')


@pytest.fixture()
def kinked(build_net):
    net = read_network(build_net(NODES, EDGES, name="kinked"))
    curves = extract_curves(net, ("turn",), areas=False)
    return net, next(c for c in curves if "AJ_0->JC_0" in c.curve_id)


def test_places_along_a_turn(kinked):
    net, c = kinked
    before = place_of(net, c, c.core_start_m - 3.0)
    assert before.part == "approach" and before.lane == "AJ_0"
    assert math.isclose(before.distance_m, 3.0) and before.words.startswith("approach AJ 3.0 m")
    inside = place_of(net, c, (c.core_start_m + c.core_end_m) / 2)
    assert inside.part == "feature" and inside.words == "in junction J"
    after = place_of(net, c, c.core_end_m + 5.0)
    assert after.part == "exit" and after.words == "exit JC 5.0 m after J"
    assert place_of(net, c, math.nan) is None


def test_a_kink_of_the_approach_is_named_where_it_is(kinked):
    """The drawn kink of AJ lies where its shape turns: the station there names it, a station
    well clear of it does not."""
    net, c = kinked
    pts, length = net.lane_line("AJ_0")
    d = np.diff(pts[:, :2], axis=0)
    corner_from_end = float(np.hypot(d[-1, 0], d[-1, 1]))  # the last straight piece
    at = place_of(net, c, c.core_start_m - corner_from_end)
    assert at.kink_deg >= KINK_DEG and "kink of AJ" in at.words
    clear = place_of(net, c, c.core_start_m - corner_from_end - 30.0)
    assert clear.kink_deg == 0.0 and "kink" not in clear.words


def test_kink_near_is_the_polyline_turn():
    """Against the closed form: a polyline turning by 90 then 30 degrees."""
    xy = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0],
                   [10.0 - 10 * math.sin(math.radians(30)), 10 + 10 * math.cos(math.radians(30))]])
    assert kink_near(xy, 10.0, 1.0) == pytest.approx(90.0)
    assert kink_near(xy, 20.0, 1.0) == pytest.approx(30.0)
    assert kink_near(xy, 15.0, 1.0) == 0.0
