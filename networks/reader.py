"""A streaming reader of SUMO ``.net.xml`` / ``.net.xml.gz`` geometry.

Only what curve extraction needs is kept: lanes (with 3-D shapes as numpy arrays), edges,
connections, junction polygons, roundabouts and the location. The parser is lxml's
target (SAX-style) parser with entity resolution and network access off: no tree is
built, so memory grows with the geometry, not with the XML. Shapes are kept as strings
while reading and parsed in bulk at the end (:func:`parse_shapes`).

Example
-------
>>> net = read_network("networks/samples/intersection/intersection.net.xml")  # doctest: +SKIP
>>> net.lanes["E0_0"].shape[:2]                                               # doctest: +SKIP
array([[...]])
"""

from __future__ import annotations

import gc
import logging
import math
import os
from collections import defaultdict
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import partial
from itertools import islice, repeat
from operator import attrgetter, itemgetter
from pathlib import Path
from sys import intern
from typing import NamedTuple

import numpy as np
from lxml import etree

from networks.safe_xml import (
    MAX_ELEMENTS_ENV,
    max_elements,
    open_binary,
    read_chunks,
    scan_prolog,
    too_big,
)
from networks.shapes import EMPTY_SHAPE, MAX_COORD_M, parse_shapes
from vehicles.errors import InputError

log = logging.getLogger(__name__)

#: SUMO's lane width when a lane has none (``SUMO_const_laneWidth``).
DEFAULT_LANE_WIDTH_M = 3.2

#: The widest lane accepted, in metres. Road lanes are 2.5-4.5 m wide and netconvert's
#: widest defaults (sidewalks, wide shoulders, OSM squares mapped as one lane) stay well under
#: 20 m; a lane of 50 m or more is a broken file, not a road. A width must also be > 0.
MAX_LANE_WIDTH_M = 50.0

#: Every SUMO vehicle class (``allow="all"`` means these).
SUMO_VCLASSES = frozenset(
    (
        "private emergency authority army vip pedestrian passenger hov taxi bus coach delivery "
        "truck trailer motorcycle moped bicycle evehicle tram rail_urban rail rail_electric "
        "rail_fast ship container cable_car subway aircraft wheelchair scooter drone custom1 "
        "custom2"
    ).split()
)

#: Classes whose lanes carry the vehicles this tool checks.
ROAD_VCLASSES = frozenset(("passenger", "bus", "truck", "coach", "delivery", "trailer"))


@dataclass(slots=True)
class Lane:
    """One lane: ``shape`` is an (N, 3) array of x, y, z in metres (z = 0 where absent)."""

    id: str
    edge: str
    index: int
    width_m: float
    function: str
    allowed: frozenset[str]
    shape: np.ndarray
    length_m: float
    speed_mps: float

    @property
    def is_internal(self) -> bool:
        """True for a junction-internal lane (``function="internal"``)."""
        return self.function == "internal"

    def allows_road_vehicles(self) -> bool:
        """True when passenger cars, buses or trucks may use the lane."""
        return not self.allowed.isdisjoint(ROAD_VCLASSES)


@dataclass(slots=True)
class Edge:
    """One edge; ``lanes`` lists its lane ids by index (rightmost first)."""

    id: str
    from_junction: str
    to_junction: str
    function: str
    priority: int
    lanes: list[str] = field(default_factory=list)


class Connection(NamedTuple):
    """A link from one lane to another, through ``via`` (the first internal lane) if any.

    A named tuple: a large network has hundreds of thousands, made from parsed rows in
    one C-level call each.
    """

    from_edge: str
    to_edge: str
    from_lane_index: int
    to_lane_index: int
    via: str | None
    direction: str

    @property
    def from_lane(self) -> str:
        """Id of the lane the connection leaves."""
        return f"{self.from_edge}_{self.from_lane_index}"

    @property
    def to_lane(self) -> str:
        """Id of the lane the connection enters."""
        return f"{self.to_edge}_{self.to_lane_index}"


#: A :class:`Connection` from a row of its six fields (``tuple.__new__`` in C, without the
#: Python-level checks of ``Connection._make``: the rows come from this module).
_new_connection = partial(tuple.__new__, Connection)


@dataclass(slots=True)
class Junction:
    """A junction: its position and its polygon (``shape``, (N, 3), may be empty)."""

    id: str
    type: str
    x: float
    y: float
    z: float
    shape: np.ndarray
    inc_lanes: tuple[str, ...]
    int_lanes: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Roundabout:
    """A ``<roundabout>`` element: its ring junctions and ring edges."""

    nodes: tuple[str, ...]
    edges: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Location:
    """The ``<location>`` element: offsets and boundaries in metres."""

    net_offset: tuple[float, float] = (0.0, 0.0)
    conv_boundary: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    orig_boundary: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    proj_parameter: str = "!"


@dataclass
class Network:
    """The geometry of a SUMO network as read by :func:`read_network`."""

    path: Path
    lanes: dict[str, Lane]
    edges: dict[str, Edge]
    connections: list[Connection]
    junctions: dict[str, Junction]
    roundabouts: list[Roundabout]
    location: Location
    _out: dict[str, list[Connection]] | None = field(default=None, repr=False)
    _in: dict[str, list[Connection]] | None = field(default=None, repr=False)
    _clean: dict[str, tuple[np.ndarray, float]] = field(default_factory=dict, repr=False)

    def lane_line(self, lane_id: str) -> tuple[np.ndarray, float]:
        """A lane's shape without repeated points, and its plane length (cached)."""
        hit = self._clean.get(lane_id)
        if hit is None:
            pts = self.lanes[lane_id].shape
            d = pts[1:, :2] - pts[:-1, :2]
            step = np.hypot(d[:, 0], d[:, 1])
            if len(step) and step.min() <= 1e-6:
                pts = pts[np.concatenate(([True], step > 1e-6))]
            hit = self._clean[lane_id] = (pts, float(step.sum()))
        return hit

    @property
    def has_internal_lanes(self) -> bool:
        """True when the network was built with junction-internal lanes."""
        return any(c.via for c in self.connections)

    def outgoing(self, lane_id: str) -> list[Connection]:
        """Connections leaving lane ``lane_id`` (also from internal lanes)."""
        if self._out is None:
            self._out = self._index(0)
        return self._out.get(lane_id, [])

    def incoming(self, lane_id: str) -> list[Connection]:
        """Connections entering lane ``lane_id`` (also into internal lanes)."""
        if self._in is None:
            self._in = self._index(1)
        return self._in.get(lane_id, [])

    def _index(self, end: int) -> dict[str, list[Connection]]:
        """The connections by the lane they leave (``end`` 0) or enter (1); each index is
        made when first asked for (extracting turns needs only the first)."""
        index: dict[str, list[Connection]] = defaultdict(list)
        edge, lane = end, end + 2  # the lane ids as the from_lane / to_lane properties make them
        for c in self.connections:
            index[f"{c[edge]}_{c[lane]}"].append(c)
        return dict(index)


def read_network(path: str | os.PathLike[str]) -> Network:
    """Read the geometry of a SUMO network file (plain or gzip-compressed).

    Parameters
    ----------
    path
        A ``.net.xml`` or ``.net.xml.gz`` file.

    Returns
    -------
    Network

    Raises
    ------
    InputError
        The file is missing, not a regular file, not XML, truncated, declares entities, is
        larger than the caps of :mod:`networks.safe_xml`, is not a SUMO network, holds no
        edges, holds a number outside its physical range (a lane width outside
        (0, :data:`MAX_LANE_WIDTH_M`], a coordinate beyond :data:`~networks.shapes.MAX_COORD_M`,
        a NaN anywhere) or a reference SUMO itself would refuse (:func:`check_references`).
    """
    p = Path(path)
    root_tag = scan_prolog(p)
    if root_tag != "net":
        raise InputError(f"{p}: not a SUMO network (root element <{root_tag}>, expected <net>)")
    with gc_paused():  # a million objects that live on: collections would only scan them
        state = _ParseState(p)
        parser = make_parser(state)
        try:
            with open_binary(p) as fh:
                for chunk in read_chunks(fh, p, _CHUNK_BYTES):
                    parser.feed(chunk)
                    state.check_size()
            parser.close()
        except etree.XMLSyntaxError as exc:
            raise InputError(f"{p}: malformed or truncated XML ({exc})") from exc
        except (EOFError, OSError) as exc:
            raise InputError(f"{p}: truncated or corrupt file ({exc})") from exc
        return state.finish()


def make_parser(state: _ParseState) -> etree.XMLParser:
    """lxml's target parser feeding ``state``: no entities, no network, no DTD, no tree.

    ``collect_ids`` keeps its default on purpose: ``collect_ids=False`` makes lxml set
    libxml2's ``XML_SKIP_IDS`` in the context's ``loadsubset``, and libxml2 loads the
    external DTD whenever ``loadsubset`` is not zero, whatever ``load_dtd`` says (a
    ``<!DOCTYPE net SYSTEM "fifo">`` then hung the reader). A target parser builds no tree,
    so there are no ids to collect anyway.
    """
    return etree.XMLParser(
        target=state,
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        huge_tree=True,
        remove_comments=True,
        remove_pis=True,
    )


@contextmanager
def gc_paused() -> Iterator[None]:
    """Pause Python's cyclic garbage collector inside the block (restored after).

    Building many objects that all stay alive makes the collector scan them again and
    again for nothing (about a third of the time of reading a large network); the
    objects made here hold no reference cycles, so nothing is left for it to free.

    On leaving the outermost such block, what it made is moved to the collector's oldest
    generation at once (``gc.freeze()`` then ``gc.unfreeze()``: no scan), instead of
    being scanned by the next young collection and again by the one after (about 0.3 s
    after reading the 10,000-junction grid, 1.1 s after extracting its curves). Nothing
    is kept from the collector: full collections still scan everything. Skipped when the
    program keeps objects frozen itself (``gc.get_freeze_count()``), which it would undo.

    Examples
    --------
    >>> import gc
    >>> with gc_paused():
    ...     gc.isenabled()
    False
    >>> gc.isenabled(), gc.get_freeze_count()
    (True, 0)
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            if gc.get_freeze_count() == 0:
                gc.freeze()
                gc.unfreeze()
            gc.enable()


_CHUNK_BYTES = 1 << 22
_ALLOW_CACHE: dict[tuple[str | None, str | None], frozenset[str]] = {}


def resolve_allowed(allow: str | None, disallow: str | None) -> frozenset[str]:
    """The vehicle classes a lane admits, from its ``allow`` and ``disallow`` attributes.

    Examples
    --------
    >>> sorted(resolve_allowed("bus passenger", None))
    ['bus', 'passenger']
    >>> "pedestrian" in resolve_allowed(None, "pedestrian")
    False
    >>> resolve_allowed(None, "all")
    frozenset()
    """
    key = (allow, disallow)
    hit = _ALLOW_CACHE.get(key)
    if hit is not None:
        return hit
    if allow is not None:
        words = set(allow.split())
        result = set(SUMO_VCLASSES) if "all" in words else words
    else:
        result = set(SUMO_VCLASSES)
    if disallow is not None:
        words = set(disallow.split())
        result = set() if "all" in words else result - words
    frozen = frozenset(result)
    _ALLOW_CACHE[key] = frozen
    return frozen


def _floats(text: str | None, n: int, default: tuple[float, ...]) -> tuple[float, ...]:
    if not text:
        return default
    vals = tuple(float(v) for v in text.split(","))
    if not all(map(math.isfinite, vals)):
        raise ValueError(f"{text[:60]!r} is not finite")
    return vals if len(vals) == n else default


def _coordinate(text: str) -> float:
    """A junction's coordinate: finite and within :data:`MAX_COORD_M`."""
    value = float(text)
    if not abs(value) <= MAX_COORD_M:
        raise ValueError(f"coordinate {text[:40]!r} is not a number within "
                         f"+/-{MAX_COORD_M:g} m")
    return value


class _ParseState:
    """Accumulates the elements of one file; shapes are parsed in one batch at the end."""

    def __init__(self, path: Path):
        self.path = path
        self.lanes: dict[str, Lane] = {}
        self.edges: dict[str, Edge] = {}
        #: (from, to, fromLane, toLane, via, dir) rows; objects are made by :meth:`finish`
        self.connection_rows: list[tuple[str, str, int, int, str | None, str]] = []
        self.junctions: dict[str, Junction] = {}
        self.roundabouts: list[Roundabout] = []
        self.location = Location()
        self.seen_root = False
        self.edge: Edge | None = None
        self.lane_shapes: list[str] = []
        self.junction_shapes: list[str] = []
        self.location_seen = False
        self.lanes_settled = 0  # lanes and junctions whose shapes are parsed
        self.junctions_settled = 0
        self.orphan_lanes = False

    def add_lane(self, lane: Lane, shape: str) -> None:
        """Add a lane read elsewhere (its shape string is parsed by :meth:`finish`)."""
        self.lane_shapes.append(shape)
        self.lanes[lane.id] = lane

    def add_junction(self, junction: Junction, shape: str) -> None:
        """Add a junction read elsewhere (its shape string is parsed by :meth:`finish`)."""
        self.junction_shapes.append(shape)
        self.junctions[junction.id] = junction

    def start(self, tag: str, attrib: dict[str, str]) -> None:
        """Called by lxml for each start tag (a SAX-style target: no tree is built).

        One method, its branches in order of frequency (connections, lanes, edges):
        it runs for every element of the file, so every call it saves counts.
        """
        try:
            get = attrib.get
            if tag == "connection":
                frm = get("from")
                to = get("to")
                if frm is None or to is None:
                    raise InputError(f"{self.path}: a <connection> lacks 'from' or 'to'")
                self.connection_rows.append((  # edge ids interned: one string per edge
                    intern(frm), intern(to), int(get("fromLane", "0")),
                    int(get("toLane", "0")), get("via"), get("dir", "")))
            elif tag == "lane":
                edge = self.edge
                if edge is None:
                    self.orphan_lanes = True
                    return
                lane_id = get("id")
                if lane_id is None:
                    raise InputError(f"{self.path}: a <lane> of edge {edge.id!r} has no id")
                width = get("width")
                width_m = float(width) if width is not None else DEFAULT_LANE_WIDTH_M
                if not 0.0 < width_m <= MAX_LANE_WIDTH_M:  # NaN too
                    raise InputError(f"{self.path}: lane {lane_id!r}: width {width!r}: not a "
                                     f"width in (0, {MAX_LANE_WIDTH_M:g}] m")
                self.lane_shapes.append(get("shape") or "")
                self.lanes[lane_id] = Lane(
                    lane_id, edge.id, int(get("index", "0")), width_m,
                    edge.function, resolve_allowed(get("allow"), get("disallow")), EMPTY_SHAPE,
                    float(get("length", "nan")), float(get("speed", "nan")))
                edge.lanes.append(lane_id)
            elif tag == "edge":
                edge_id = get("id")
                if edge_id is None:
                    raise InputError(f"{self.path}: an <edge> has no id")
                if edge_id in self.edges:
                    raise InputError(f"{self.path}: edge {edge_id!r} is defined twice")
                self.edge = self.edges[edge_id] = Edge(
                    edge_id, get("from", ""), get("to", ""), get("function", "normal"),
                    int(get("priority", "-1")), [])
            elif tag == "request":
                return
            elif not self.seen_root:
                if tag != "net":
                    raise InputError(f"{self.path}: not a SUMO network (root element <{tag}>)")
                self.seen_root = True
            else:
                self._start_rare(tag, get)
        except ValueError as exc:
            ident = attrib.get("id") or " ".join(f"{k}={v!r}" for k, v in attrib.items())[:80]
            raise InputError(f"{self.path}: bad value in <{tag} {ident}>: {exc}") from exc

    def _start_rare(self, tag: str, get) -> None:  # noqa: ANN001 - attrib.get
        if tag == "junction":
            jid = get("id")
            if jid is None:
                raise InputError(f"{self.path}: a <junction> has no id")
            self.junction_shapes.append(get("shape") or "")
            self.junctions[jid] = Junction(
                jid,
                get("type", ""),
                _coordinate(get("x", "0")),
                _coordinate(get("y", "0")),
                _coordinate(get("z", "0")),
                EMPTY_SHAPE,
                tuple((get("incLanes") or "").split()),
                tuple((get("intLanes") or "").split()),
            )
        elif tag == "roundabout":
            self.roundabouts.append(
                Roundabout(
                    nodes=tuple((get("nodes") or "").split()),
                    edges=tuple((get("edges") or "").split()),
                )
            )
        elif tag == "location":
            off = _floats(get("netOffset"), 2, (0.0, 0.0))
            if not max(map(abs, off)) <= MAX_COORD_M:
                raise ValueError(f"netOffset {get('netOffset')!r} beyond +/-{MAX_COORD_M:g} m")
            self.location_seen = True
            self.location = Location(
                net_offset=(off[0], off[1]),
                conv_boundary=_floats(get("convBoundary"), 4, (0.0,) * 4),  # type: ignore[arg-type]
                orig_boundary=_floats(get("origBoundary"), 4, (0.0,) * 4),  # type: ignore[arg-type]
                proj_parameter=get("projParameter", "!"),
            )

    def close(self) -> None:
        """Called by lxml at the end of the document."""

    def check_size(self) -> None:
        """Refuse more elements than :func:`~networks.safe_xml.max_elements` (called after
        each chunk fed: a chunk adds at most about 150,000)."""
        n = (len(self.connection_rows) + len(self.lanes) + len(self.edges)
             + len(self.junctions) + len(self.roundabouts))
        limit = max_elements()
        if n > limit:
            raise too_big(self.path, "the number of elements", limit, MAX_ELEMENTS_ENV)

    def settle_shapes(self) -> None:
        """Parse the shape strings read since the last call into the lanes' and junctions'
        arrays (in bulk, :func:`parse_shapes`)."""
        for what, items, shapes, done in (
            ("lane", self.lanes, self.lane_shapes, self.lanes_settled),
            ("junction", self.junctions, self.junction_shapes, self.junctions_settled),
        ):
            if len(items) - done != len(shapes):
                raise InputError(f"{self.path}: {len(shapes) - len(items) + done} {what}(s) "
                                 "reuse an id already read")
            objs = list(islice(items.values(), done, None))
            arrays = parse_shapes(shapes, [o.id for o in objs], f"{self.path}: {what}")
            for obj, shape in zip(objs, arrays, strict=True):
                if what == "lane" and len(shape) < 2:
                    raise InputError(f"{self.path}: lane {obj.id!r}: shape has fewer than 2 points")
                obj.shape = shape
            shapes.clear()
        self.lanes_settled = len(self.lanes)
        self.junctions_settled = len(self.junctions)

    def finish(self) -> Network:
        if not self.seen_root and not self.edges:
            raise InputError(f"{self.path}: not a SUMO network (no <edge> elements)")
        if not self.edges:
            raise InputError(f"{self.path}: the network is empty (no <edge> elements)")
        self.settle_shapes()
        self.check_size()
        check_references(self.path, self.edges, self.lanes, self.connection_rows,
                         self.roundabouts, self.junctions)
        net = Network(
            path=self.path,
            lanes=self.lanes,
            edges=self.edges,
            connections=list(map(_new_connection, self.connection_rows)),
            junctions=self.junctions,
            roundabouts=self.roundabouts,
            location=self.location,
        )
        # the state and its parser keep each other alive until a full collection (lxml's
        # target parser): what only the state holds is freed now
        self.connection_rows, self.lane_shapes, self.junction_shapes = [], [], []
        return net


def check_references(path: Path, edges: dict[str, Edge], lanes: dict[str, Lane],
                     connections: list[tuple[str, str, int, int, str | None, str]],
                     roundabouts: list[Roundabout], junctions: dict[str, Junction]) -> None:
    """Refuse what SUMO itself refuses to load, naming the element.

    Each lane's index is one of its edge's (0 .. n-1); every connection leaves and enters edges
    of the network, by lanes they have (``fromLane``, ``toLane``), through a ``via`` lane
    that exists; every roundabout names edges and junctions of the network.

    Examples
    --------
    >>> e = Edge("a", "j", "k", "normal", 1, ["a_0"])
    >>> lanes = {"a_0": Lane("a_0", "a", 0, 3.2, "normal", frozenset(), EMPTY_SHAPE, 9, 9)}
    >>> check_references(Path("n"), {"a": e}, lanes, [("a", "a", 0, 0, None, "t")], [], {})
    >>> check_references(Path("n"), {"a": e}, lanes, [("a", "b", 0, 0, None, "s")], [], {})
    Traceback (most recent call last):
    ...
    vehicles.errors.InputError: n: <connection from="a" to="b">: unknown to-edge 'b'
    """
    # a lane's index is one of its edge's: SUMO accepts repeats (old internal edges have
    # several lanes of index 0, bologna_joined of the realnets), not an index beyond
    lane_list = list(lanes.values())
    code = {e: k for k, e in enumerate(edges)}
    counts = np.fromiter(map(len, (e.lanes for e in edges.values())), np.int64, len(edges))
    of_edge = np.fromiter(map(code.__getitem__, map(attrgetter("edge"), lane_list)),
                          np.int64, len(lane_list))
    try:
        given = np.fromiter(map(attrgetter("index"), lane_list), np.int64, len(lane_list))
    except OverflowError:
        given = np.fromiter((min(max(ln.index, -1), 2**62) for ln in lane_list), np.int64,
                            len(lane_list))
    wrong = (given < 0) | (given >= counts[of_edge])
    if wrong.any():
        lane = lane_list[int(np.argmax(wrong))]
        raise InputError(f"{path}: lane {lane.id!r}: index {lane.index} out of range (edge "
                         f"{lane.edge!r} has {len(edges[lane.edge].lanes)} lane(s))")
    if connections:
        lane_counts = {e.id: len(e.lanes) for e in edges.values()}
        n = len(connections)

        def column(i: int) -> map:
            return map(itemgetter(i), connections)

        n_from = np.fromiter(map(lane_counts.get, column(0), repeat(-1)), np.int64, n)
        n_to = np.fromiter(map(lane_counts.get, column(1), repeat(-1)), np.int64, n)
        try:
            i_from = np.fromiter(column(2), np.int64, n)
            i_to = np.fromiter(column(3), np.int64, n)
        except OverflowError:
            row = next(r for r in connections if max(abs(r[2]), abs(r[3])) >= 2**63)
            _refuse_connection(path, row, lane_counts, lanes)
        bad = (i_from < 0) | (i_from >= n_from) | (i_to < 0) | (i_to >= n_to)
        missing = set(column(4)).difference(lanes)
        missing.discard(None)
        if missing:
            bad |= np.fromiter(map(missing.__contains__, column(4)), bool, n)
        if bad.any():
            _refuse_connection(path, connections[int(np.argmax(bad))], lane_counts, lanes)
    for r in roundabouts:
        unknown = [e for e in r.edges if e not in edges]
        if unknown:
            raise InputError(f"{path}: <roundabout edges=...>: unknown edge(s) "
                             f"{', '.join(map(repr, unknown[:5]))}")
        unknown = [j for j in r.nodes if j not in junctions]
        if unknown:
            raise InputError(f"{path}: <roundabout nodes=...>: unknown junction(s) "
                             f"{', '.join(map(repr, unknown[:5]))}")


def _refuse_connection(path: Path, row: tuple[str, str, int, int, str | None, str],
                       lane_counts: dict[str, int], lanes: dict[str, Lane]) -> None:
    """Raise the error that names what is wrong with one bad connection."""
    frm, to, from_lane, to_lane, via, _ = row
    tag = f'<connection from="{frm}" to="{to}">'
    n_from, n_to = lane_counts.get(frm), lane_counts.get(to)
    if n_from is None:
        raise InputError(f"{path}: {tag}: unknown from-edge {frm!r}")
    if n_to is None:
        raise InputError(f"{path}: {tag}: unknown to-edge {to!r}")
    if not 0 <= from_lane < n_from:
        raise InputError(f"{path}: {tag}: fromLane {from_lane} out of range (edge {frm!r} "
                         f"has {n_from} lane(s))")
    if not 0 <= to_lane < n_to:
        raise InputError(f"{path}: {tag}: toLane {to_lane} out of range (edge {to!r} has "
                         f"{n_to} lane(s))")
    raise InputError(f"{path}: {tag}: via lane {via!r} does not exist")
