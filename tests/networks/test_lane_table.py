"""Every lane's cleaned shape and length at once, the same as one lane at a time."""

from __future__ import annotations

import numpy as np
import pytest

from networks.lane_table import LaneTable
from networks.reader import Lane, Location, Network, read_network
from networks.samples.sources import SAMPLES_DIR


@pytest.mark.parametrize("name", ["intersection", "roundabout", "parking_ramp"])
def test_same_points_and_lengths_as_lane_line(name):
    net = read_network(SAMPLES_DIR / name / f"{name}.net.xml")
    table = LaneTable(net)
    for k in net.lanes:
        pts, length = net.lane_line(k)
        assert np.array_equal(table.line(k), pts) and table.length_m(k) == length, k


def test_long_lanes_repeated_points_and_gather():
    rng = np.random.default_rng(3)
    shapes = {
        "long_0": np.c_[np.cumsum(rng.uniform(0.1, 3.0, 40)), rng.uniform(0, 1, 40), np.zeros(40)],
        "dup_0": np.array([[0, 0, 0], [0, 0, 1], [1, 0, 0], [1, 1e-7, 0], [2, 0, 0.0]]),
        "one_0": np.array([[5.0, 5.0, 0.0]]),
    }
    lanes = {k: Lane(k, k[:-2], 0, 3.2, "normal", frozenset(), v, 0.0, 13.9)
             for k, v in shapes.items()}
    net = Network(None, lanes, {}, [], {}, [], Location())
    table = LaneTable(net)
    for k in shapes:
        pts, length = net.lane_line(k)
        assert np.array_equal(table.line(k), pts) and table.length_m(k) == length, k
    assert len(table.line("dup_0")) == 3  # the point on top of the first and the 1e-7 m step
    rows = np.array([table.row("dup_0"), table.row("one_0"), table.row("dup_0")])
    pts, count = table.gather(rows)
    assert count.tolist() == [3, 1, 3]
    assert np.array_equal(pts, np.vstack([table.line("dup_0"), table.line("one_0"),
                                          table.line("dup_0")]))


def test_flat_shapes_read_as_points():
    """A shape given as flat x, y, z values (not as read) is taken three by three."""
    points = np.array([[0, 0, 0], [3, 4, 0], [3, 5, 1.0]])
    made = {}
    for layout, shape in (("rows", points), ("flat", points.ravel())):
        lanes = {"e_0": Lane("e_0", "e", 0, 3.2, "normal", frozenset(), shape, 0.0, 13.9),
                 "f_0": Lane("f_0", "f", 0, 3.2, "normal", frozenset(), points[:2], 0.0, 13.9)}
        made[layout] = LaneTable(Network(None, lanes, {}, [], {}, [], Location()))
    for k in ("e_0", "f_0"):
        assert np.array_equal(made["flat"].line(k), made["rows"].line(k)), k
        assert made["flat"].length_m(k) == made["rows"].length_m(k) == (6.0 if k == "e_0" else 5.0)
