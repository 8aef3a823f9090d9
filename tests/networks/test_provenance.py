"""Provenance: which of a network's widths and corners are data and which netconvert's defaults,
checked against what netconvert was given and against the raw XML of real networks."""

from __future__ import annotations

import gzip
import re
from pathlib import Path

import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.provenance import (
    CORNER_COMPUTED,
    LANE_WIDTH_DEFAULT,
    RING_ONE_LANE,
    BuildHeader,
    assumption_key,
    curve_assumptions,
    lane_width_is_default,
    read_header,
)
from clearance.networks.reader import read_network

REALNETS = Path(__file__).resolve().parents[3] / "shared" / "realnets"
SAMPLES = Path(__file__).resolve().parents[2] / "networks" / "samples"

NODES = ('<node id="A" x="-100" y="0"/><node id="J" x="0" y="0" {attrs}/>'
         '<node id="B" x="100" y="0"/><node id="C" x="0" y="-100"/>')
EDGES = ('<edge id="AJ" from="A" to="J" numLanes="1" {w}/><edge id="JB" from="J" to="B" '
         'numLanes="1"/><edge id="JC" from="J" to="C" numLanes="1" {w}/>')


def _keys(net, header):
    curves = extract_curves(net, ("turn",), areas=False)
    return {c.curve_id: {assumption_key(a) for a in curve_assumptions(net, c, header)}
            for c in curves}


def test_hand_drawn_samples_name_no_default():
    """Every lane of the samples has its width and every junction its drawn shape."""
    for name in ("intersection", "roundabout"):
        path = SAMPLES / name / f"{name}.net.xml"
        net = read_network(path)
        curves = extract_curves(net, areas=False)
        assert curves
        assert all(curve_assumptions(net, c, read_header(path)) == () for c in curves), name


def test_netconvert_defaults_are_named(build_net):
    """Built without widths or radius: the default width and the computed corner are named;
    a width and a radius given make the same turn rest on data."""
    plain = read_network(build_net(NODES.format(attrs=""), EDGES.format(w=""), name="plain"))
    keys = _keys(plain, BuildHeader())
    right = next(k for k in keys if "AJ_0->JC_0" in k)
    assert keys[right] == {f"{LANE_WIDTH_DEFAULT} 3.2 m", CORNER_COMPUTED}
    given = read_network(build_net(NODES.format(attrs='radius="9"'),
                                   EDGES.format(w='width="3.5"'), name="given"))
    keys = _keys(given, BuildHeader())
    right = next(k for k in keys if "AJ_0->JC_0" in k)
    assert keys[right] == set()  # AJ and JC widths given, J's radius given
    straight = next(k for k in keys if "AJ_0->JB_0" in k)
    assert keys[straight] == {f"{LANE_WIDTH_DEFAULT} 3.2 m"}  # JB has no width


def test_default_lanewidth_option_written_out_is_still_a_default(build_net):
    path = build_net(NODES.format(attrs=""), EDGES.format(w=""), None,
                     "--default.lanewidth", "3.5", name="wide")
    header = read_header(path)
    assert header.default_lane_width_m == 3.5 and header.tool.startswith("netconvert")
    net = read_network(path)
    assert all(lane.width_given for lane in net.lanes.values() if not lane.is_internal)
    assert all(lane_width_is_default(lane, header) for lane in net.lanes.values()
               if not lane.is_internal)
    assert {f"{LANE_WIDTH_DEFAULT} 3.5 m"} <= next(iter(_keys(net, header).values()))


@pytest.mark.parametrize("name", ["doerpfeldstr", "wildau", "tavf_hamburg", "bologna_joined"])
def test_real_network_widths_match_the_raw_xml(name):
    """The lanes read as default are exactly the ``<lane>`` elements without ``width`` (an
    independent count over the file's text), and the header names the tool."""
    path = REALNETS / f"{name}.net.xml.gz"
    if not path.exists():
        pytest.skip("shared real networks not present")
    text = gzip.open(path, "rt", encoding="utf-8").read()
    lanes = re.findall(r"<lane [^>]*>", text)
    no_width = sum(' width="' not in x for x in lanes)
    net = read_network(path)
    assert sum(not lane.width_given for lane in net.lanes.values()) == no_width
    assert read_header(path).tool.split()[0] in ("netconvert", "netedit")
    # no junction of these networks has a radius; the few custom shapes are kept as data
    custom = len(re.findall(r'<junction [^>]*customShape="1"', text))
    assert sum(j.custom_shape for j in net.junctions.values()) == custom


def test_one_lane_default_ring_is_named():
    path = REALNETS / "wildau.net.xml.gz"
    if not path.exists():
        pytest.skip("shared real networks not present")
    net = read_network(path)
    rings = extract_curves(net, ("roundabout",), areas=False)
    words = [curve_assumptions(net, c, read_header(path)) for c in rings]
    assert rings and all(RING_ONE_LANE in w for w in words)
    assert all(any(a.startswith(CORNER_COMPUTED) for a in w) for w in words)
