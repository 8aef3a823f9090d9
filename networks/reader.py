"""A streaming reader of SUMO ``.net.xml`` / ``.net.xml.gz`` geometry.

Only what curve extraction needs is kept: lanes (with 3-D shapes as numpy arrays), edges,
connections, junction polygons, roundabouts and the location. The parser is lxml's
target (SAX-style) parser with entity resolution and network access off: no tree is
built, so memory grows with the geometry, not with the XML. Shapes are kept as strings
while reading and parsed in bulk at the end (:func:`parse_shapes`).

The reader reads what SUMO loads: what SUMO refuses raises
:class:`~clearance.vehicles.errors.InputError` naming the element, and what SUMO loads but no
vehicle can be judged on (a lane width that is not one, a shape point that is not a finite
coordinate, a walking area drawn as one point) is repaired or left out with a note in
:attr:`Network.repairs <clearance.networks.model.Network.repairs>`
(:mod:`clearance.networks.integrity`).

Example
-------
>>> net = read_network("networks/samples/intersection/intersection.net.xml")  # doctest: +SKIP
>>> net.lanes["E0_0"].shape[:2]                                               # doctest: +SKIP
array([[...]])
"""

from __future__ import annotations

import logging
import math
import os
from collections.abc import Mapping
from itertools import islice
from pathlib import Path
from sys import intern
from typing import TYPE_CHECKING, cast

from lxml import etree

from clearance.networks.collector import gc_paused
from clearance.networks.elevation import repair_suspect_heights
from clearance.networks.integrity import ConnectionRow, check_references, leave_out_lanes
from clearance.networks.model import (
    DEFAULT_LANE_WIDTH_M,
    MAX_LANE_WIDTH_M,
    Edge,
    Junction,
    Lane,
    Location,
    Network,
    Roundabout,
    new_connection,
    resolve_allowed,
)
from clearance.networks.safe_xml import (
    MAX_ELEMENTS_ENV,
    max_elements,
    open_binary,
    read_chunks,
    scan_prolog,
    too_big,
)
from clearance.networks.shapes import EMPTY_SHAPE, MAX_COORD_M, parse_shapes
from clearance.vehicles.errors import NetworkError

if TYPE_CHECKING:  # names of the lxml stubs only, not of lxml itself
    from lxml.etree._parser import CustomTargetParser
    from lxml.etree._saxparser import ParserTarget

__all__ = ["make_parser", "read_network"]

log = logging.getLogger(__name__)


def read_network(path: str | os.PathLike[str]) -> Network:
    """Read the geometry of a SUMO network file (plain or gzip-compressed).

    Parameters
    ----------
    path
        A ``.net.xml`` or ``.net.xml.gz`` file.

    Returns
    -------
    Network
        With :attr:`~clearance.networks.model.Network.repairs` naming what was repaired or left out
        (a lane width outside (0, :data:`~clearance.networks.model.MAX_LANE_WIDTH_M`] taken as
        SUMO's default, a lane whose shape is not two finite points within
        :data:`~clearance.networks.shapes.MAX_COORD_M` left out, ...:
        :mod:`clearance.networks.integrity`).

    Raises
    ------
    InputError
        The file is missing, not a regular file, not XML, truncated, declares entities, is
        larger than the caps of :mod:`clearance.networks.safe_xml`, is not a SUMO network, holds no
        edges, holds a number that is not one, or a reference SUMO itself refuses
        (:func:`clearance.networks.integrity.check_references`).
    """
    p = Path(path)
    root_tag = scan_prolog(p)
    if root_tag != "net":
        raise NetworkError(f"{p}: not a SUMO network (root element <{root_tag}>, expected <net>)")
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
            raise NetworkError(f"{p}: malformed or truncated XML ({exc})") from exc
        except (EOFError, OSError) as exc:
            raise NetworkError(f"{p}: truncated or corrupt file ({exc})") from exc
        net = state.finish()
    repair_suspect_heights(net)  # lone heights are no ramps (clearance.networks.elevation)
    return net


def make_parser(state: _ParseState) -> CustomTargetParser[None]:
    """lxml's target parser feeding ``state``: no entities, no network, no DTD, no tree.

    ``collect_ids`` keeps its default on purpose: ``collect_ids=False`` makes lxml set
    libxml2's ``XML_SKIP_IDS`` in the context's ``loadsubset``, and libxml2 loads the
    external DTD whenever ``loadsubset`` is not zero, whatever ``load_dtd`` says (a
    ``<!DOCTYPE net SYSTEM "fifo">`` then hung the reader). A target parser builds no tree,
    so there are no ids to collect anyway.

    ``resolve_entities="internal"``: XML's own five (``&amp;`` and the like) and character
    references are read as the characters they stand for, as SUMO reads them; with
    ``False`` libxml2 hands ``&amp;`` over as ``&#38;``, and an id such as ``a&b`` would not
    be the network's. No other entity can be met: a DOCTYPE that declares one is refused
    before parsing (:func:`~clearance.networks.safe_xml.scan_prolog`), and external ones are never
    resolved.
    """
    # lxml looks the target's methods up by name and calls only those it has; the stubs'
    # ParserTarget protocol lists them all (comment, pi, doctype, ...), hence the cast.
    return etree.XMLParser(
        target=cast("ParserTarget[None]", state),
        resolve_entities="internal",
        no_network=True,
        load_dtd=False,
        huge_tree=True,
        remove_comments=True,
        remove_pis=True,
    )


_CHUNK_BYTES = 1 << 22


def _floats(text: str | None, n: int) -> tuple[float, ...] | None:
    """``n`` comma-separated numbers, or None when absent or not ``n`` of them."""
    if not text:
        return None
    vals = tuple(float(v) for v in text.split(","))
    return vals if len(vals) == n else None


def _usable(values: tuple[float, ...]) -> bool:
    """Every value a finite coordinate within :data:`~clearance.networks.shapes.MAX_COORD_M`.

    >>> _usable((1.0, -2.0)), _usable((math.nan, 0.0)), _usable((1e15,))
    (True, False, False)
    """
    return all(abs(v) <= MAX_COORD_M for v in values)  # NaN too


class _ParseState:
    """Accumulates the elements of one file; shapes are parsed in one batch at the end."""

    def __init__(self, path: Path):
        self.path = path
        self.lanes: dict[str, Lane] = {}
        self.edges: dict[str, Edge] = {}
        #: (from, to, fromLane, toLane, via, dir) rows; objects are made by :meth:`finish`
        self.connection_rows: list[ConnectionRow] = []
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
        #: What was repaired or left out, in words (:attr:`Network.repairs`).
        self.repairs: list[str] = []
        #: Lanes SUMO loads that cannot be used (id -> why): left out by :meth:`finish`.
        self.broken: dict[str, str] = {}

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
                    raise NetworkError(f"{self.path}: a <connection> lacks 'from' or 'to'",
                                       file=self.path)
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
                    raise NetworkError(f"{self.path}: a <lane> of edge {edge.id!r} has no id",
                                       file=self.path)
                width = get("width")
                width_m = float(width) if width is not None else DEFAULT_LANE_WIDTH_M
                given = width is not None
                if not 0.0 < width_m <= MAX_LANE_WIDTH_M:  # NaN too; SUMO loads them
                    self.repairs.append(
                        f"lane {lane_id!r}: width {width!r} is not a lane width in "
                        f"(0, {MAX_LANE_WIDTH_M:g}] m: taken as SUMO's default "
                        f"{DEFAULT_LANE_WIDTH_M} m")
                    width_m, given = DEFAULT_LANE_WIDTH_M, False
                self.lane_shapes.append(get("shape") or "")
                self.lanes[lane_id] = Lane(
                    lane_id, edge.id, int(get("index", "0")), width_m,
                    edge.function, resolve_allowed(get("allow"), get("disallow")), EMPTY_SHAPE,
                    float(get("length", "nan")), float(get("speed", "nan")), given)
                edge.lanes.append(lane_id)
            elif tag == "edge":
                edge_id = get("id")
                if edge_id is None:
                    raise NetworkError(f"{self.path}: an <edge> has no id", file=self.path)
                if edge_id in self.edges:
                    raise NetworkError(f"{self.path}: edge {edge_id!r} is defined twice",
                                       file=self.path)
                self.edge = self.edges[edge_id] = Edge(
                    edge_id, get("from", ""), get("to", ""), get("function", "normal"),
                    int(get("priority", "-1")), [])
            elif tag == "request":
                return
            elif not self.seen_root:
                if tag != "net":
                    raise NetworkError(f"{self.path}: not a SUMO network (root element <{tag}>)",
                                       file=self.path)
                self.seen_root = True
            else:
                self._start_rare(tag, get)
        except ValueError as exc:
            ident = attrib.get("id") or " ".join(f"{k}={v!r}" for k, v in attrib.items())[:80]
            raise NetworkError(f"{self.path}: bad value in <{tag} {ident}>: {exc}",
                               file=self.path) from exc

    def _start_rare(self, tag: str, get) -> None:  # noqa: ANN001 - attrib.get
        if tag == "junction":
            jid = get("id")
            if jid is None:
                raise NetworkError(f"{self.path}: a <junction> has no id", file=self.path)
            self.junction_shapes.append(get("shape") or "")
            self.junctions[jid] = Junction(
                jid,
                get("type", ""),
                float(get("x", "0")),
                float(get("y", "0")),
                float(get("z", "0")),
                EMPTY_SHAPE,
                tuple((get("incLanes") or "").split()),
                tuple((get("intLanes") or "").split()),
                get("customShape") in ("1", "true"),
                float(get("radius", "nan")),
            )
        elif tag == "roundabout":
            self.roundabouts.append(
                Roundabout(
                    nodes=tuple((get("nodes") or "").split()),
                    edges=tuple((get("edges") or "").split()),
                )
            )
        elif tag == "location":
            self.location_seen = True
            self.location = self._location(get)

    def _location(self, get) -> Location:  # noqa: ANN001 - attrib.get
        """The ``<location>``; one SUMO loads with a number that is not a finite coordinate
        is read as no projection and no offset (a note says so): nothing is placed on the
        globe from it."""
        off = _floats(get("netOffset"), 2) or (0.0, 0.0)
        conv = _floats(get("convBoundary"), 4) or (0.0,) * 4
        orig = _floats(get("origBoundary"), 4) or (0.0,) * 4
        if _usable(off) and _usable(conv) and all(map(math.isfinite, orig)):
            return Location((off[0], off[1]), conv, orig,  # type: ignore[arg-type]
                            get("projParameter", "!"))
        attrs = " ".join(f'{k}="{get(k)}"' for k in ("netOffset", "convBoundary", "origBoundary")
                         if get(k) is not None)
        self.repairs.append(f"<location {attrs[:120]}>: a number that is not a finite "
                            "coordinate: read as no projection and no offset")
        return Location()

    def close(self) -> None:
        """Called by lxml at the end of the document."""

    def check_size(self) -> None:
        """Refuse more elements than :func:`~clearance.networks.safe_xml.max_elements` (called after
        each chunk fed: a chunk adds at most about 150,000)."""
        n = (len(self.connection_rows) + len(self.lanes) + len(self.edges)
             + len(self.junctions) + len(self.roundabouts))
        limit = max_elements()
        if n > limit:
            raise too_big(self.path, "the number of elements", limit, MAX_ELEMENTS_ENV)

    def _place_junctions(self) -> None:
        """A junction whose position SUMO loads but is not a finite coordinate within
        :data:`~clearance.networks.shapes.MAX_COORD_M` is placed at the middle of its shape (at 0
        when
        it has none), with a note."""
        for j in self.junctions.values():
            if _usable((j.x, j.y, j.z)):
                continue
            given = f"({j.x:g}, {j.y:g}, {j.z:g})"
            if len(j.shape):
                j.x, j.y, j.z = (float(v) for v in j.shape.mean(axis=0))
                how = "its shape's middle"
            else:
                j.x = j.y = j.z = 0.0
                how = "0, 0 (it has no shape)"
            self.repairs.append(f"junction {j.id!r}: position {given} is not a finite "
                                f"coordinate: taken as {how}")

    def settle_shapes(self) -> None:
        """Parse the shape strings read since the last call into the lanes' and junctions'
        arrays (in bulk, :func:`parse_shapes`)."""
        groups: tuple[tuple[str, Mapping[str, Lane | Junction], list[str], int], ...] = (
            ("lane", self.lanes, self.lane_shapes, self.lanes_settled),
            ("junction", self.junctions, self.junction_shapes, self.junctions_settled),
        )
        for what, items, shapes, done in groups:
            if len(items) - done != len(shapes):
                raise NetworkError(f"{self.path}: {len(shapes) - len(items) + done} {what}(s) "
                                 "reuse an id already read", file=self.path)
            objs = list(islice(items.values(), done, None))
            bad: dict[int, str] = {}
            arrays = parse_shapes(shapes, [o.id for o in objs], what, on_bad=bad.__setitem__)
            for i, (obj, shape) in enumerate(zip(objs, arrays, strict=True)):
                if what == "lane" and (i in bad or len(shape) < 2):
                    self.broken[obj.id] = (bad[i].split(": ", 1)[1] if i in bad
                                           else "shape has fewer than 2 points")
                elif i in bad:
                    self.repairs.append(f"{bad[i]}: shape left out")
                obj.shape = shape
            shapes.clear()
        self.lanes_settled = len(self.lanes)
        self.junctions_settled = len(self.junctions)

    def finish(self) -> Network:
        if not self.edges:  # SUMO loads a <net> without edges: nothing to study
            self.repairs.append("the network has no edge")
        self.settle_shapes()
        self.check_size()
        rows, rings = leave_out_lanes(self.edges, self.lanes, self.connection_rows,
                                      self.roundabouts, self.junctions, self.broken,
                                      self.repairs)
        rings = check_references(self.path, self.edges, self.lanes, rows, rings,
                                 self.junctions, self.repairs)
        self._place_junctions()
        net = Network(
            path=self.path,
            lanes=self.lanes,
            edges=self.edges,
            connections=list(map(new_connection, rows)),
            junctions=self.junctions,
            roundabouts=rings,
            location=self.location,
            repairs=self.repairs,
        )
        # the state and its parser keep each other alive until a full collection (lxml's
        # target parser): what only the state holds is freed now
        self.connection_rows, self.lane_shapes, self.junction_shapes = [], [], []
        return net
