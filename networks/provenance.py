"""Where a network's geometry came from: the data it was built from, or netconvert's defaults.

Most SUMO networks come from OpenStreetMap through netconvert, and much of their geometry is
netconvert's guess. The network file says which, element by element:

- a lane whose ``<lane>`` has no ``width`` is SUMO's default width (3.2 m): netconvert writes
  a width only where its input gave one (``width`` of an edge or lane, an OSM ``width`` or
  ``lanes`` tag, a type map's width). A width equal to the header's ``default.lanewidth`` is
  that option's default, written out;
- a junction without ``customShape`` is a polygon netconvert computed from the lanes meeting
  there, its corners rounded at ``radius`` when the file gives one, else at
  ``default.junctions.radius`` (4 m unless the header says otherwise), shrunk where the lanes
  leave no room: the corner is computed, not surveyed;
- a roundabout ring of one lane at the default width is the ring netconvert draws for an OSM
  ``junction=roundabout`` way that says nothing of its lanes.

The header is the XML comment netconvert and netedit write before ``<net>``: the tool, its
version and the options of the build (:func:`read_header`).

A curve's verdict rests on its feature's lanes (the approach and exit edges with the lanes
beside them, the ring, the bent lane) and, for a turn or a roundabout, on the junctions it
crosses; :func:`curve_assumptions` names the defaults among them in words.

Examples
--------
>>> header = BuildHeader.parse('<!-- generated on 2024 by Eclipse SUMO netconvert Version 1.21.0'
...                            ' <default.lanewidth value="3.5"/> -->')
>>> header.tool, header.default_lane_width_m, header.corner_radius_m
('netconvert 1.21.0', 3.5, 4.0)
"""

from __future__ import annotations

import functools
import math
import os
import re
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from clearance.networks.curves import Curve
from clearance.networks.model import ROAD_VCLASSES, Junction, Lane, Network
from clearance.networks.places import core_span, feature_ends
from clearance.networks.safe_xml import open_binary

__all__ = ["CORNER_COMPUTED", "CORNER_FITTED", "CORNER_TURN_DEG", "DEFAULT_CORNER_RADIUS_M",
           "LANE_WIDTH_DEFAULT", "LANE_WIDTH_FITTED", "LANES_OFFSET", "MAX_OFFSET_M",
           "MIN_OFFSET_M", "RING_ONE_LANE", "assumption_key", "BuildHeader", "corner_computed",
           "curve_assumptions", "feature_edges", "geometry_words", "lane_offset_m",
           "lane_width_is_default", "read_header"]

#: netconvert's ``default.junctions.radius`` when the header does not set it (m).
DEFAULT_CORNER_RADIUS_M = 4.0

#: The words that start each kind of assumption (the key the summaries count them by).
LANE_WIDTH_DEFAULT = "lane width default"
CORNER_COMPUTED = "corner computed"
RING_ONE_LANE = "roundabout ring one default lane"
LANES_OFFSET = "lanes offset"
#: Widths and radii a fit patch of this tool proposed (the network was built with it).
LANE_WIDTH_FITTED = "lane width fitted by patch (a proposal)"
CORNER_FITTED = "corner fitted by patch (a proposal)"

#: A straight passage (turning less than ``JOG_TURN_DEG``) whose exit lane starts between
#: these distances (m) beside its approach lane's line has a jog drawn in its junction: lanes
#: that do not line up, joined sideways (further off, the junction carries the road
#: elsewhere, which is no jog).
MIN_OFFSET_M, MAX_OFFSET_M = 0.5, 5.0
JOG_TURN_DEG = 10.0

#: A turn under this (degrees, either way) is straight on: its corner does not carry it.
CORNER_TURN_DEG = 30.0

#: The header is read from the first bytes of the file.
_HEADER_BYTES = 1 << 16

_OPTION = re.compile(r"<([A-Za-z][\w.\-]*)\s+value=\"([^\"]*)\"\s*/>")
_ROOT = re.compile(r"<net[\s>/]")
_TOOL = re.compile(r"by Eclipse SUMO (\w+)(?: Version)? (\S+)")
#: Options naming a build's input files.
_INPUT_OPTIONS = ("osm-files", "sumo-net-file", "node-files", "edge-files", "connection-files",
                  "type-files", "opendrive-files", "shapefile-prefix", "visum-file")


@dataclass(frozen=True)
class BuildHeader:
    """What a network's header says of its build.

    Attributes
    ----------
    tool
        ``netconvert 1.21.0``, ``netedit v1_18_0+0023-ef591d47046``, or ``""`` (no header).
    options
        The build's options as the header lists them (name -> value).
    """

    tool: str = ""
    options: dict[str, str] = field(default_factory=dict)

    @classmethod
    def parse(cls, text: str) -> BuildHeader:
        """The header of a network's text (its first comment, before ``<net``).

        >>> BuildHeader.parse("<net/>")
        BuildHeader(tool='', options={})
        >>> BuildHeader.parse('<!-- by Eclipse SUMO netconvert Version 1.22.0 '
        ...                   '<netconvertConfiguration><default.junctions.radius value="6"/>'
        ...                   ' --><net>').corner_radius_m
        6.0
        """
        start = text.find("<!--")
        end = text.find("-->", start)
        root = _ROOT.search(text)
        if start < 0 or end < 0 or (root is not None and root.start() < start):
            return cls()
        comment = text[start + 4:end]
        tool = _TOOL.search(comment)
        return cls(f"{tool[1]} {tool[2]}" if tool else "", dict(_OPTION.findall(comment)))

    @property
    def default_lane_width_m(self) -> float | None:
        """``default.lanewidth`` when the build set it (m), else None."""
        return _positive(self.options.get("default.lanewidth"))

    @property
    def corner_radius_m(self) -> float:
        """The corner radius netconvert rounds computed junctions with (m)."""
        return _positive(self.options.get("default.junctions.radius")) or DEFAULT_CORNER_RADIUS_M

    def fitted(self) -> tuple[frozenset[str], frozenset[str]]:
        """The lanes and junctions a fit patch of this tool set (``*.fit.edg.xml``,
        ``*.fit.nod.xml`` among the build's inputs, read where the header names them): their
        widths and radii are proposals, not data. Empty where the files are gone.

        >>> BuildHeader(options={"edge-files": "/nowhere/n.fit.edg.xml"}).fitted()
        (frozenset(), frozenset())
        """
        lanes: set[str] = set()
        nodes: set[str] = set()
        for name in self.inputs:
            if name.endswith(".fit.edg.xml"):
                lanes |= _fit_file(name, "lane")
            elif name.endswith(".fit.nod.xml"):
                nodes |= _fit_file(name, "node")
        return frozenset(lanes), frozenset(nodes)

    @property
    def inputs(self) -> list[str]:
        """The build's input files, as the header names them."""
        return [f for k in _INPUT_OPTIONS for f in self.options.get(k, "").split(",") if f]


def _positive(value: str | None) -> float | None:
    try:
        x = float(value) if value is not None else math.nan
    except ValueError:
        return None
    return x if x > 0 and math.isfinite(x) else None


@functools.lru_cache(maxsize=16)
def _fit_file(path: str, tag: str) -> frozenset[str]:
    """The lane ids (``edge_index``) or node ids a fit patch sets; empty if unreadable."""
    from lxml import etree

    try:
        root = etree.parse(path, etree.XMLParser(resolve_entities=False, no_network=True)
                           ).getroot()
    except (OSError, etree.XMLSyntaxError):
        return frozenset()
    if tag == "node":
        return frozenset(n.get("id", "") for n in root.iter("node"))
    return frozenset(f"{e.get('id')}_{lane.get('index')}" for e in root.iter("edge")
                     for lane in e.iter("lane"))


def read_header(path: str | os.PathLike[str]) -> BuildHeader:
    """The build header of a network file (plain or gzip); an empty one when it has none."""
    with open_binary(path) as fh:
        head = fh.read(_HEADER_BYTES)
    return BuildHeader.parse(head.decode("utf-8", "replace"))


def lane_width_is_default(lane: Lane, header: BuildHeader) -> bool:
    """True when a lane's width is a default, not data: no ``width`` in the file, or the
    header's ``default.lanewidth`` written out.

    >>> import numpy as np
    >>> lane = Lane("a_0", "a", 0, 3.2, "normal", frozenset(), np.zeros((2, 3)), 9.0, 9.0, False)
    >>> lane_width_is_default(lane, BuildHeader())
    True
    >>> lane.width_given, lane.width_m = True, 3.5
    >>> lane_width_is_default(lane, BuildHeader()), lane_width_is_default(
    ...     lane, BuildHeader(options={"default.lanewidth": "3.5"}))
    (False, True)
    """
    if not lane.width_given:
        return True
    default = header.default_lane_width_m
    return default is not None and abs(lane.width_m - default) < 1e-6


def corner_computed(junction: Junction) -> bool:
    """True when netconvert computed the junction's polygon and its corners (no
    ``customShape``, no ``radius`` of its own)."""
    return not junction.custom_shape and math.isnan(junction.radius_m)


def feature_edges(net: Network, curve: Curve) -> list[str]:
    """The normal edges a curve's verdict rests on, in driving order: the approach edge, the
    feature's own normal edges (a ring, a ramp, a bent lane's edge), the exit edge.

    >>> from clearance.networks.reader import read_network
    >>> from clearance.networks.curves import extract_curves
    >>> net = read_network("networks/samples/intersection/intersection.net.xml")
    >>> c = extract_curves(net, ("turn",), areas=False)[0]
    >>> feature_edges(net, c) == [net.lanes[c.lanes[0]].edge, net.lanes[c.lanes[-1]].edge]
    True
    """
    first, last = core_span(curve) or (0, len(curve.lanes) - 1)
    picked = [k for k in curve.lanes[first:last + 1] if not _internal(net, k)]
    before, after = feature_ends(net, curve)
    lanes = [*([before] if before else []), *picked, *([after] if after else [])]
    return list(dict.fromkeys(net.lanes[k].edge for k in lanes))


def _internal(net: Network, lane_id: str) -> bool:
    lane = net.lanes.get(lane_id)
    return lane is None or lane.is_internal


def _road_lanes(net: Network, edges: Iterable[str]) -> list[Lane]:
    return [net.lanes[k] for e in edges if e in net.edges for k in net.edges[e].lanes
            if k in net.lanes and not net.lanes[k].allowed.isdisjoint(ROAD_VCLASSES)]


def curve_assumptions(net: Network, curve: Curve, header: BuildHeader) -> tuple[str, ...]:
    """The netconvert defaults a curve's verdict rests on, in words (empty: all data).

    Lane widths of the feature's edges (:func:`feature_edges`, their road lanes), the corner
    of a turn's junction (turns of at least :data:`CORNER_TURN_DEG`; ``r`` the drawn turn's
    inner edge: its centre line's least radius less half its width), the corners where a
    roundabout route enters and leaves the ring, and a ring of one default lane.

    >>> from clearance.networks.reader import read_network
    >>> from clearance.networks.curves import extract_curves
    >>> net = read_network("networks/samples/intersection/intersection.net.xml")
    >>> curves = extract_curves(net, ("turn",), areas=False)
    >>> [a for c in curves for a in curve_assumptions(net, c, BuildHeader())]  # drawn by hand
    []
    """
    out: list[str] = []
    edges = feature_edges(net, curve)
    fit_lanes, fit_nodes = header.fitted()
    road = _road_lanes(net, edges)
    widths = sorted({round(lane.width_m, 2) for lane in road
                     if lane_width_is_default(lane, header) and lane.id not in fit_lanes})
    if widths:
        out.append(f"{LANE_WIDTH_DEFAULT} {' and '.join(f'{w:g} m' for w in widths)}")
    if any(lane.id in fit_lanes for lane in road):
        out.append(LANE_WIDTH_FITTED)
    if curve.junction in fit_nodes and curve.kind in ("turn", "uturn"):
        out.append(CORNER_FITTED)
    if curve.kind in ("turn", "uturn") and abs(curve.turn_angle_deg) >= CORNER_TURN_DEG:
        j = net.junctions.get(curve.junction)
        if j is not None and corner_computed(j):
            r = max(0.0, curve.min_radius_m - curve.lane_width_m / 2)
            out.append(f"{CORNER_COMPUTED} (r {r:.1f} m)" if math.isfinite(r)
                       else CORNER_COMPUTED)
    elif curve.kind == "turn":
        j = net.junctions.get(curve.junction)
        jog = lane_offset_m(net, curve)
        if j is not None and corner_computed(j) and abs(curve.turn_angle_deg) < JOG_TURN_DEG \
                and MIN_OFFSET_M <= jog <= MAX_OFFSET_M:
            out.append(f"{LANES_OFFSET} {jog:.1f} m in computed junction")
    if curve.kind == "roundabout":
        out += _ring_assumptions(net, curve, edges, header)
    return tuple(out)


def lane_offset_m(net: Network, curve: Curve) -> float:
    """How far sideways a straight passage's exit lane starts from its approach lane's line
    (m): the jog netconvert draws where lanes that do not line up meet in a junction (0 when
    the curve has no approach or exit lane).

    >>> from types import SimpleNamespace as S
    >>> import numpy as np
    >>> lanes = {"a_0": S(is_internal=False, shape=np.array([[0.0, 0, 0], [10, 0, 0]])),
    ...          ":J_0_0": S(is_internal=True, shape=np.array([[10.0, 0, 0], [12, 1.5, 0]])),
    ...          "b_0": S(is_internal=False, shape=np.array([[12.0, 1.5, 0], [30, 1.5, 0]]))}
    >>> c = S(lanes=("a_0", ":J_0_0", "b_0"), core_lanes=(":J_0_0",))
    >>> lane_offset_m(S(lanes=lanes), c)
    1.5
    """
    before, after = feature_ends(net, curve)
    a = net.lanes.get(before) if before else None
    b = net.lanes.get(after) if after else None
    if a is None or b is None or len(a.shape) < 2 or not len(b.shape):
        return 0.0
    p, q = a.shape[-2, :2], a.shape[-1, :2]
    u = q - p
    norm = float(np.hypot(u[0], u[1]))
    if norm < 1e-9:
        return 0.0
    d = b.shape[0, :2] - q
    return round(abs(float(u[0] * d[1] - u[1] * d[0])) / norm, 3)


def _ring_assumptions(net: Network, curve: Curve, edges: list[str], header: BuildHeader
                      ) -> list[str]:
    out = []
    ring = next((r for r in net.roundabouts if set(r.edges) & set(edges)), None)
    if ring is not None:
        lanes = _road_lanes(net, ring.edges)
        per_edge = {lane.edge for lane in lanes}
        if lanes and len(lanes) == len(per_edge) \
                and all(lane_width_is_default(lane, header) for lane in lanes):
            out.append(RING_ONE_LANE)
    ends = [net.edges[edges[0]].to_junction, net.edges[edges[-1]].from_junction] if edges else []
    computed = [j for j in dict.fromkeys(ends)
                if j in net.junctions and corner_computed(net.junctions[j])]
    if computed:
        out.append(f"{CORNER_COMPUTED} (entry and exit {', '.join(computed)})"
                   if len(computed) > 1 else f"{CORNER_COMPUTED} ({computed[0]})")
    return out


def geometry_words(assumptions: Iterable[str]) -> str:
    """The ``geometry`` column: the assumptions joined, or ``data`` when there are none.

    >>> geometry_words([]), geometry_words(["lane width default 3.2 m", "corner computed"])
    ('data', 'lane width default 3.2 m; corner computed')
    """
    return "; ".join(assumptions) or "data"


def assumption_key(assumption: str) -> str:
    """The kind of an assumption, without its numbers (what the summaries count by).

    >>> assumption_key("corner computed (r 3.1 m)"), assumption_key("lane width default 3.2 m")
    ('corner computed', 'lane width default 3.2 m')
    >>> assumption_key("lanes offset 1.6 m in computed junction")
    'lanes offset'
    """
    if assumption.startswith(LANES_OFFSET):
        return LANES_OFFSET
    return assumption.split(" (", 1)[0]
