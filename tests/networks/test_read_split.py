"""Reading a network in two processes gives exactly what reading it in one pass gives."""

from __future__ import annotations

import doctest
import gzip
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import networks.read_split
from networks import read_split
from networks.read_split import read_in_two, split_offset
from networks.reader import Network, read_network
from vehicles.errors import InputError

SAMPLES = Path(__file__).resolve().parents[2] / "networks" / "samples"
ROUNDABOUT = SAMPLES / "roundabout" / "roundabout.net.xml"


def _same_value(a: object, b: object) -> bool:
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.shape == b.shape and np.array_equal(a, b)
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return type(a) is type(b) and a == b


def assert_same_network(a: Network, b: Network) -> None:
    """Field by field, in the same order (the order of the file)."""
    assert list(a.lanes) == list(b.lanes)
    for key, lane in a.lanes.items():
        other = b.lanes[key]
        for name in lane.__slots__:
            assert _same_value(getattr(lane, name), getattr(other, name)), (key, name)
    assert list(a.junctions) == list(b.junctions)
    for key, junction in a.junctions.items():
        other = b.junctions[key]
        for name in junction.__slots__:
            assert _same_value(getattr(junction, name), getattr(other, name)), (key, name)
    assert list(a.edges.values()) == list(b.edges.values())
    assert a.connections == b.connections
    assert all(type(c) is type(d) for c, d in zip(a.connections, b.connections, strict=True))
    assert a.roundabouts == b.roundabouts
    assert a.location == b.location


@pytest.fixture
def two_cores(monkeypatch):
    """Let the reader use two cores and split files of any size."""
    monkeypatch.setenv("CLEARANCE_THREADS", "2")
    monkeypatch.setattr(read_split, "MIN_SPLIT_BYTES", 0)


def _one_pass(path: Path, monkeypatch) -> Network:
    with monkeypatch.context() as m:
        m.setenv("CLEARANCE_THREADS", "1")
        return read_network(path)


def test_doctests():
    assert doctest.testmod(networks.read_split).failed == 0


@pytest.mark.parametrize("fraction", [0.0, 0.5, 0.8])
def test_samples_read_in_two_equal_one_pass(two_cores, monkeypatch, fraction):
    monkeypatch.setattr(read_split, "SPLIT_FRACTION", fraction)
    for name in ("intersection", "roundabout", "parking_ramp"):
        path = SAMPLES / name / f"{name}.net.xml"
        offset = split_offset(path)
        assert offset is not None
        state = read_in_two(path, offset)
        assert state is not None, f"{name}: the split read fell back"
        assert_same_network(state.finish(), _one_pass(path, monkeypatch))


def test_cut_inside_edges_carries_lanes_and_location(two_cores, tmp_path, monkeypatch):
    # the <location> moved to the end, the cut between two edges: the second process
    # sends edges, their lanes, the junctions, connections and the location
    text = ROUNDABOUT.read_text()
    start = text.index("<location")
    end = text.index(">", start) + 1
    location = text[start:end]
    text = text[:start] + text[end:]
    text = text.replace("</net>", f"    {location}\n</net>")
    path = tmp_path / "moved.net.xml"
    path.write_text(text)
    edges = [i for i in range(len(text)) if text.startswith("<edge ", i)]
    offset = len(text[: edges[len(edges) // 2]].encode())
    state = read_in_two(path, offset)
    assert state is not None
    net = state.finish()
    assert net.location.conv_boundary != (0.0, 0.0, 0.0, 0.0)
    assert_same_network(net, _one_pass(path, monkeypatch))


def test_a_real_osm_network(two_cores, monkeypatch):
    try:
        from networks.sumo_tools import sumo_home

        path = sumo_home() / "tools" / "game" / "A10KW" / "osm.net.xml"
    except FileNotFoundError as exc:  # pragma: no cover
        pytest.skip(f"SUMO is not installed: {exc}")
    if not path.exists():  # pragma: no cover
        pytest.skip("A10KW is not shipped in this SUMO version")
    state = read_in_two(path, split_offset(path))
    assert state is not None
    assert_same_network(state.finish(), _one_pass(path, monkeypatch))


def test_cut_at_a_tag_inside_a_comment_falls_back(two_cores, tmp_path, monkeypatch):
    text = ROUNDABOUT.read_text()
    middle = text.index("<junction ")
    text = text[:middle] + '<!-- <junction id="ghost"/> -->\n    ' + text[middle:]
    path = tmp_path / "commented.net.xml"
    path.write_text(text)
    offset = text.index("<junction id=\"ghost\"")
    assert read_in_two(path, offset) is None  # the first part ends inside the comment
    monkeypatch.setattr(read_split, "SPLIT_FRACTION", offset / len(text) - 0.001)
    assert split_offset(path) == offset
    net = read_network(path)  # falls back to one pass
    assert "ghost" not in net.junctions
    assert_same_network(net, _one_pass(path, monkeypatch))


@pytest.mark.parametrize(
    "damage",
    [
        lambda t: t[: int(len(t) * 0.9)],  # truncated in the second part
        lambda t: t.replace('fromLane="0"', 'fromLane="x"', 1),  # a bad value there
        lambda t: t.replace("<roundabout", '<lane id="stray" shape="0,0 1,1"/><roundabout', 1),
        lambda t: t.replace("<roundabout", '<lane id="stray" shape="0,0 1,1"/><roundabout'),
    ],
    ids=["truncated", "bad-value", "lane-outside-edge", "lane-id-twice"],
)
def test_errors_are_those_of_one_pass(two_cores, tmp_path, monkeypatch, damage):
    path = tmp_path / "damaged.net.xml"
    path.write_text(damage(ROUNDABOUT.read_text()))
    monkeypatch.setattr(read_split, "SPLIT_FRACTION", 0.3)
    try:
        expected = _one_pass(path, monkeypatch)
    except InputError as exc:
        assert read_in_two(path, split_offset(path)) is None
        with pytest.raises(InputError) as got:
            read_network(path)
        assert str(got.value) == str(exc)
    else:  # a lane outside any edge joins the last edge read, as in one pass
        assert_same_network(read_network(path), expected)


def test_lane_before_any_edge_of_the_second_part(two_cores, tmp_path, monkeypatch):
    # one pass adds a lane outside any edge to the last edge read, which the second
    # process cannot see: it gives up and the file is read in one pass
    text = ROUNDABOUT.read_text()
    text = text.replace("</junction>", '</junction><lane id="stray" shape="0,0 1,1"/>', 1)
    path = tmp_path / "stray.net.xml"
    path.write_text(text)
    offset = len(text[: text.index("<junction ")].encode())
    assert read_in_two(path, offset) is None
    net = read_network(path)
    assert "stray" in net.lanes
    assert_same_network(net, _one_pass(path, monkeypatch))


@pytest.mark.parametrize("executable", ["/nonexistent/python", "/bin/true", "/bin/false"])
def test_a_second_process_that_fails_falls_back(two_cores, monkeypatch, executable):
    # cannot start; exits 0 without a word; exits 1
    if not Path(executable).exists() and executable != "/nonexistent/python":
        pytest.skip(f"{executable} is not on this machine")
    monkeypatch.setattr(sys, "executable", executable)
    offset = split_offset(ROUNDABOUT)
    assert read_in_two(ROUNDABOUT, offset) is None
    assert_same_network(read_network(ROUNDABOUT), _one_pass(ROUNDABOUT, monkeypatch))


def test_files_that_are_read_in_one_pass(two_cores, tmp_path, monkeypatch):
    text = ROUNDABOUT.read_text()
    packed = tmp_path / "r.net.xml.gz"
    packed.write_bytes(gzip.compress(text.encode()))
    assert split_offset(packed) is None
    latin = tmp_path / "latin.net.xml"
    latin.write_bytes(
        text.replace('encoding="UTF-8"', 'encoding="ISO-8859-1"', 1).encode("latin-1")
    )
    if b"ISO-8859-1" in latin.read_bytes()[:200]:
        assert split_offset(latin) is None
    doctype = tmp_path / "doctype.net.xml"
    doctype.write_text(text.replace("<net ", "<!DOCTYPE net>\n<net ", 1))
    assert split_offset(doctype) is None
    monkeypatch.setenv("CLEARANCE_THREADS", "1")
    assert split_offset(ROUNDABOUT) is None
    monkeypatch.setenv("CLEARANCE_THREADS", "2")
    monkeypatch.setattr(read_split, "MIN_SPLIT_BYTES", 1 << 40)
    assert split_offset(ROUNDABOUT) is None
