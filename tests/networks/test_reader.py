"""The streaming network reader: content, shapes, and refusal of bad input."""

from __future__ import annotations

import doctest
import gzip
from pathlib import Path

import numpy as np
import pytest

import clearance.networks.areas
import clearance.networks.curves
import clearance.networks.geometry
import clearance.networks.paths
import clearance.networks.plot
import clearance.networks.profiles
import clearance.networks.reader
import clearance.networks.safe_xml
import clearance.networks.samples.sources
import clearance.networks.shapes
from clearance.networks.model import DEFAULT_LANE_WIDTH_M, resolve_allowed
from clearance.networks.reader import read_network
from clearance.networks.samples.sources import SAMPLES_DIR
from clearance.networks.shapes import parse_shape, parse_shapes
from clearance.vehicles.errors import InputError
from tests.networks import damaged

NODES = """
<node id="A" x="0" y="0" type="priority"/>
<node id="B" x="100" y="0" z="2" type="priority"/>
<node id="C" x="100" y="100" type="priority"/>
"""
EDGES = """
<edge id="AB" from="A" to="B" numLanes="2" width="3.5"/>
<edge id="BC" from="B" to="C" numLanes="1" disallow="pedestrian"/>
"""


def test_doctests_of_network_modules():
    modules = (
        clearance.networks.areas,
        clearance.networks.curves,
        clearance.networks.geometry,
        clearance.networks.paths,
        clearance.networks.plot,
        clearance.networks.profiles,
        clearance.networks.reader,
        clearance.networks.safe_xml,
        clearance.networks.shapes,
        clearance.networks.samples.sources,
    )
    for mod in modules:
        result = doctest.testmod(mod)
        assert result.failed == 0, mod.__name__


def test_reads_lanes_edges_connections_junctions(build_net):
    path = build_net(NODES, EDGES)
    net = read_network(path)
    assert set(net.edges) >= {"AB", "BC"}
    ab = net.edges["AB"]
    assert (ab.from_junction, ab.to_junction, ab.function) == ("A", "B", "normal")
    assert ab.lanes == ["AB_0", "AB_1"]
    lane = net.lanes["AB_1"]
    assert lane.index == 1 and lane.width_m == pytest.approx(3.5)
    assert lane.shape.shape[1] == 3
    # z rises from 0 at A to 2 at B along the lane
    assert lane.shape[0, 2] == pytest.approx(0.0, abs=0.05)
    assert lane.shape[-1, 2] > 1.5
    bc = net.lanes["BC_0"]
    assert bc.width_m == DEFAULT_LANE_WIDTH_M
    assert "pedestrian" not in bc.allowed and "passenger" in bc.allowed
    conns = [c for c in net.connections if c.from_edge == "AB" and c.to_edge == "BC"]
    assert conns and all(c.via and c.via.startswith(":B_") for c in conns)
    via = net.lanes[conns[0].via]
    assert via.function == "internal" and via.is_internal
    assert net.junctions["B"].shape.shape[0] >= 3
    assert net.has_internal_lanes
    assert net.location.conv_boundary[2] == pytest.approx(100.0)
    assert net.outgoing(conns[0].from_lane) == [
        c for c in conns if c.from_lane == conns[0].from_lane
    ]
    assert net.incoming("BC_0")


def test_reads_gzip_the_same(build_net, tmp_path):
    path = build_net(NODES, EDGES)
    gz = tmp_path / "copy.net.xml.gz"
    gz.write_bytes(gzip.compress(path.read_bytes()))
    a, b = read_network(path), read_network(gz)
    assert a.lanes.keys() == b.lanes.keys()
    for k in a.lanes:
        np.testing.assert_array_equal(a.lanes[k].shape, b.lanes[k].shape)


def test_shapes_mix_2d_and_3d():
    out = parse_shapes(["0,0 1,2", "0,0,1 1,1,2", "0,0 5,5,3 6,6", ""])
    assert out[0].tolist() == [[0, 0, 0], [1, 2, 0]]
    assert out[1][:, 2].tolist() == [1, 2]
    assert out[2].tolist() == [[0, 0, 0], [5, 5, 3], [6, 6, 0]]
    assert out[3].shape == (0, 3)


def test_bulk_shapes_are_parsed_like_one_by_one():
    # separators out of place or an empty number are not read as some other shape
    for text in ("1.5 0,0,3", "1+5,2 3,e", "1,2 ,3", "0,0\t1,1"):
        try:
            expected = parse_shape(text)
        except ValueError:
            with pytest.raises(InputError, match="bad shape"):
                parse_shapes([text, "0,0 1,1"], ["x_0", "y_0"], "lane")
        else:
            np.testing.assert_array_equal(parse_shapes([text])[0], expected)


def test_bad_shape_names_the_lane():
    with pytest.raises(InputError, match="lane 'x_0'.*bad shape"):
        parse_shapes(["0,0 1"], ["x_0"], "net.xml: lane")


def test_resolve_allowed():
    assert resolve_allowed("bus", None) == frozenset({"bus"})
    assert "passenger" not in resolve_allowed(None, "passenger truck")
    assert resolve_allowed("all", "all") == frozenset()


def _write(tmp_path: Path, name: str, text: str | bytes) -> Path:
    p = tmp_path / name
    p.write_bytes(text if isinstance(text, bytes) else text.encode())
    return p


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_network(tmp_path / "nope.net.xml")


def test_directory_is_refused(tmp_path):
    with pytest.raises(InputError, match="not a regular file"):
        read_network(tmp_path)


def test_not_xml(tmp_path):
    p = _write(tmp_path, "a.net.xml", "this is not xml at all\n")
    with pytest.raises(InputError, match=r"a\.net\.xml.*not XML"):
        read_network(p)


def test_empty_file(tmp_path):
    p = _write(tmp_path, "e.net.xml", "")
    with pytest.raises(InputError, match="empty"):
        read_network(p)


def test_xml_that_is_not_a_network(tmp_path):
    p = _write(tmp_path, "r.xml", '<?xml version="1.0"?><routes><vehicle id="v"/></routes>')
    with pytest.raises(InputError, match=r"r\.xml: not a SUMO network \(root element <routes>"):
        read_network(p)


def test_a_network_without_edges_is_read_empty_as_sumo_loads_it(tmp_path):
    # `sumo -n` loads <net version="1.20"></net>: nothing to study, not bad input
    p = _write(tmp_path, "n.net.xml", '<net version="1.20"></net>')
    net = read_network(p)
    assert (net.edges, net.lanes, net.repairs) == ({}, {}, ["the network has no edge"])
    assert clearance.networks.curves.extract_curves(net) == []


def test_entity_declarations_are_refused(tmp_path):
    bomb = (
        '<?xml version="1.0"?>\n<!DOCTYPE net [\n <!ENTITY a "aaaaaaaaaa">\n'
        ' <!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">\n <!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;">\n'
        ']>\n<net><edge id="&c;"/></net>\n'
    )
    p = _write(tmp_path, "bomb.net.xml", bomb)
    with pytest.raises(InputError, match=r"bomb\.net\.xml: refused.*entities"):
        read_network(p)


def test_external_entity_is_never_fetched(tmp_path):
    secret = _write(tmp_path, "secret.txt", "SECRET")
    xxe = (
        f'<?xml version="1.0"?><!DOCTYPE net [<!ENTITY x SYSTEM "file://{secret}">]>'
        '<net><edge id="&x;"/></net>'
    )
    p = _write(tmp_path, "xxe.net.xml", xxe)
    with pytest.raises(InputError, match="entities"):
        read_network(p)


def test_undeclared_entity_reference_is_an_error(tmp_path):
    p = _write(tmp_path, "u.net.xml", '<net><edge id="&x;" from="a" to="b"/></net>')
    with pytest.raises(InputError, match=r"u\.net\.xml: malformed"):
        read_network(p)


def test_truncated_file(build_net, tmp_path):
    data = build_net(NODES, EDGES).read_bytes()
    p = _write(tmp_path, "cut.net.xml", data[: len(data) * 2 // 3])
    with pytest.raises(InputError, match=r"cut\.net\.xml: malformed or truncated"):
        read_network(p)


def test_truncated_gzip(build_net, tmp_path):
    data = gzip.compress(build_net(NODES, EDGES).read_bytes())
    p = _write(tmp_path, "cut.net.xml.gz", data[: len(data) // 2])
    with pytest.raises(InputError, match=r"cut\.net\.xml\.gz: .*(truncated|decompress)"):
        read_network(p)


def test_bad_number_names_the_element(tmp_path):
    p = _write(
        tmp_path,
        "bad.net.xml",
        '<net><edge id="e" from="a" to="b"><lane id="e_0" index="zero" shape="0,0 1,1"/></edge>'
        "</net>",
    )
    with pytest.raises(InputError, match=r"bad\.net\.xml: bad value in <lane e_0>"):
        read_network(p)


def test_what_a_paused_block_made_goes_to_the_oldest_generation_unscanned():
    import gc

    from clearance.networks.collector import gc_paused

    class Node:
        pass

    with gc_paused():
        kept = [Node() for _ in range(1000)]
        cycle = Node()
        cycle.me = cycle  # garbage once dropped: a full collection must still free it
    oldest = {id(o) for o in gc.get_objects(generation=2)}
    assert all(id(o) in oldest for o in kept) and gc.isenabled()
    assert gc.get_freeze_count() == 0
    del cycle
    assert gc.collect() >= 1  # the cycle (and its __dict__) was freed
    # a program that keeps objects frozen itself: left as it is
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        with gc_paused():
            [Node() for _ in range(10)]
        assert gc.get_freeze_count() == frozen
    finally:
        gc.unfreeze()


def test_reading_leaves_no_rows_for_the_collector(small_grid):
    import gc

    gc.collect()
    net = read_network(small_grid)
    # lxml's parser and the parse state keep each other alive until a full collection;
    # the rows only the state held are freed at once, not left to wait with them
    left = gc.collect()
    assert len(net.connections) > 300 and left < 100


@pytest.mark.parametrize("first", ["incoming", "outgoing"])
def test_connections_by_lane_whichever_index_is_made_first(first):
    net = read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")
    getattr(net, first)("no_such_lane")  # that index made first, the other when asked
    for k in net.lanes:
        assert net.outgoing(k) == [c for c in net.connections if c.from_lane == k], k
        assert net.incoming(k) == [c for c in net.connections if c.to_lane == k], k


@pytest.mark.parametrize("case", sorted(damaged.LOADED))
def test_what_sumo_loads_is_read_the_broken_element_repaired_or_left_out(tmp_path, case):
    path, expected = damaged.damage(case, tmp_path)
    net = read_network(path)
    note = expected.removeprefix(f"{path}: ")
    assert any(r.startswith(note) for r in net.repairs), (note, net.repairs)
    # every reference left is whole: the curves of what is left can be extracted
    for c in net.connections:
        assert c.from_lane in net.lanes and c.to_lane in net.lanes, c
        assert c.via is None or c.via in net.lanes, c
    assert all(len(lane.shape) >= 2 and np.isfinite(lane.shape).all()
               for lane in net.lanes.values())
    assert all(0 < lane.width_m <= 50 for lane in net.lanes.values())
    assert all(np.isfinite([j.x, j.y, j.z]).all() for j in net.junctions.values())
    clearance.networks.curves.extract_curves(net)


def test_an_intact_network_has_no_repairs():
    assert read_network(SAMPLES_DIR / "intersection" / "intersection.net.xml").repairs == []


def test_coordinates_within_the_bound_are_read_exactly(tmp_path):
    # moved by 1e6 m (a UTM-sized offset): every point exactly 1e6 further, the curves alike
    text = (SAMPLES_DIR / "intersection" / "intersection.net.xml").read_text()
    p = tmp_path / "moved.net.xml"
    p.write_text(damaged._offset_all(text, 1e6))
    moved, plain = read_network(p), read_network(SAMPLES_DIR / "intersection" /
                                                 "intersection.net.xml")
    for lane_id, lane in plain.lanes.items():
        np.testing.assert_allclose(moved.lanes[lane_id].shape[:, :2] - 1e6, lane.shape[:, :2],
                                   atol=1e-9)


# -- generated malformed networks (hypothesis): nothing but InputError escapes, nothing hangs

import re  # noqa: E402

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_SAMPLE = (SAMPLES_DIR / "intersection" / "intersection.net.xml").read_bytes()
_VALUES = [m.span(1) for m in re.finditer(rb'="([^"]*)"', _SAMPLE)]
_LINES = [m.span() for m in re.finditer(rb"[^\n]*\n", _SAMPLE)]
_JUNK = st.one_of(
    st.sampled_from([b"", b"nan", b"inf", b"-1", b"1e400", b"1e300", b"-0", b"0", b"x",
                     b"99999999999999999999", b":T_0_0", b"TE_in", b"&amp;", b"&x;", b"<",
                     b"]]>", b"0,0", b"0,0 nan,1", b"1,2,3,4", b"\xff\xfe", b"\x00",
                     b"<!ENTITY a 'b'>", b"<!DOCTYPE net SYSTEM '/dev/zero'>"]),
    st.binary(max_size=8),
)


@st.composite
def _damaged_networks(draw) -> bytes:
    data = _SAMPLE
    for _ in range(draw(st.integers(1, 3))):
        how = draw(st.sampled_from(["value", "value", "value", "drop-line", "copy-line",
                                    "insert", "truncate"]))
        if how == "value":
            a, b = _VALUES[draw(st.integers(0, len(_VALUES) - 1))]
            a, b = min(a, len(data)), min(b, len(data))
            data = data[:a] + draw(_JUNK) + data[b:]
        elif how in ("drop-line", "copy-line"):
            a, b = _LINES[draw(st.integers(0, len(_LINES) - 1))]
            a, b = min(a, len(data)), min(b, len(data))
            data = data[:a] + (data[a:b] * 2 if how == "copy-line" else b"") + data[b:]
        elif how == "insert":
            at = draw(st.integers(0, len(data)))
            data = data[:at] + draw(_JUNK) + data[at:]
        else:
            data = data[: draw(st.integers(0, len(data)))]
    return data


@settings(max_examples=200, deadline=3000)
@given(data=_damaged_networks())
def test_generated_damaged_networks_raise_nothing_but_input_errors(tmp_path_factory, data):
    p = tmp_path_factory.mktemp("n") / "n.net.xml"
    p.write_bytes(data)
    try:
        net = read_network(p)
    except InputError as exc:
        assert str(exc).startswith(f"{p}") or "environment variable" in str(exc)
        return
    for lane in net.lanes.values():  # what is read is in range
        assert 0 < lane.width_m <= 50 and np.isfinite(lane.shape).all()
