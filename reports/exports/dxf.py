"""DXF export of a network's swept envelopes, for CAD: metres, SUMO plane, layers by name.

The drawing holds the network's base plan around the curves and, per vehicle, one layer
for each kind of line, named as a CAD user reads them (``P`` is the vehicle's name):

=========================  ===============================================================
layer                      holds
=========================  ===============================================================
``BASE-PAVEMENT-EDGE``     the edge of the pavement (lanes and junction areas merged)
``BASE-LANE-LINE``         lines between the lanes of one road (dashed)
``BASE-JUNCTION``          junction shapes
``P-BODY``                 body outlines along the path (when the run has them)
``P-WHEEL-PATH``           paths of the wheels that bound the sweep (when the run has them)
``P-ENVELOPE``             the swept envelope of the body
``P-CLEARANCE-ENVELOPE``   the envelope grown by the clearance offset (``--clearance``)
``P-CONFLICT-LANE``        the part outside the own lanes but paved (hatched)
``P-CONFLICT-PAVEMENT``    the part outside the pavement (hatched)
``P-LABEL``                the curve id of each envelope
``P-OVERREACH``            a run not clear: a point at its worst overreach and the extra
                           width needed there (``+0.56 m``)
=========================  ===============================================================

Envelopes are closed LWPOLYLINEs (exteriors and holes), coloured by verdict (AutoCAD colour
index), with the record's attributes in XDATA (application ``SUMO_CLEARANCE``).

Identical records give a byte-identical file, like the CSV, JSON and GeoJSON outputs: the
drawing carries no clock time and no random GUID (ezdxf's fixed metadata: dates of
2000-01-01, the null GUID, no timestamp in its own marker) and its CLASSES section is in a
fixed order (ezdxf adds the classes in use from a set, whose order varies between runs).
"""

from __future__ import annotations

import os
import re
from collections import OrderedDict
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TextIO

import ezdxf
import numpy as np
import shapely
from ezdxf.document import Drawing
from ezdxf.enums import TextEntityAlignment
from ezdxf.layouts import Modelspace
from shapely.geometry import LineString

from clearance.networks.areas import lane_polygons
from clearance.networks.model import Network
from clearance.reports.exports.envelopes import EnvelopeRecord, checked_records, polygon_parts
from clearance.reports.output.atomic import write_stream_atomic

__all__ = ["APPID", "BASE_LAYERS", "TEXT_HEIGHT_M", "VEHICLE_LAYERS", "VERDICT_ACI",
           "base_plan", "dxf_layer_name", "write_dxf"]

APPID = "SUMO_CLEARANCE"
TEXT_HEIGHT_M = 0.5
#: AutoCAD colour index of each verdict: green, orange, red, magenta.
VERDICT_ACI = {"clear": 3, "encroaches": 30, "fails": 1, "cannot-turn": 6}
#: The base plan's layers: name, colour (ACI), line type, description.
BASE_LAYERS = {
    "BASE-PAVEMENT-EDGE": (7, "CONTINUOUS", "edge of the pavement (lanes and junctions)"),
    "BASE-LANE-LINE": (8, "DASHED", "lines between the lanes of a road"),
    "BASE-JUNCTION": (9, "CONTINUOUS", "junction shapes"),
}
#: Each vehicle's layers (suffixes of its name) with colour (ACI) and description.
VEHICLE_LAYERS = {
    "BODY": (5, "body outlines along the path"),
    "WHEEL-PATH": (4, "paths of the wheels that bound the sweep"),
    "ENVELOPE": (2, "swept envelope of the body"),
    "CLEARANCE-ENVELOPE": (2, "swept envelope grown by the clearance offset"),
    "CONFLICT-LANE": (30, "outside its own lanes, on the pavement"),
    "CONFLICT-PAVEMENT": (1, "outside the pavement"),
    "LABEL": (7, "curve ids"),
    "OVERREACH": (1, "worst overreach of each run not clear (point, extra width needed)"),
}
#: Base plan drawn this far around the envelopes (m).
BASE_MARGIN_M = 30.0

# Characters AutoCAD refuses in symbol-table names, plus control characters.
_BAD_LAYER_CHARS = re.compile(r"[<>/\\\":;?*|=,'`\x00-\x1f\x7f]+")
_CONTROL = re.compile(r"[\x00-\x1f\x7f]+")


def dxf_layer_name(vehicle: str) -> str:
    """A vehicle name made valid as a DXF layer name (at most 230 characters, leaving room
    for a layer suffix such as ``-CLEARANCE-ENVELOPE``).

    >>> dxf_layer_name('Bus 12/18 m "city"')
    'Bus 12_18 m _city_'
    >>> dxf_layer_name('///')
    '_'
    """
    return _BAD_LAYER_CHARS.sub("_", vehicle).strip()[:230] or "_"


def _text(value: str, limit: int = 255) -> str:
    """A string fit for a DXF TEXT or XDATA string: no control characters, bounded length."""
    return _CONTROL.sub(" ", value)[:limit]


def _lines(geom: Any) -> list[np.ndarray]:
    """The coordinate arrays of every line or ring of ``geom`` (x, y only)."""
    out = []
    for g in shapely.get_parts(shapely.boundary(geom) if geom.geom_type.endswith("Polygon")
                               else geom):
        if g.is_empty:
            continue
        for part in shapely.get_parts(shapely.line_merge(g) if g.geom_type == "MultiLineString"
                                      else g):
            xy = shapely.get_coordinates(part)
            if len(xy) >= 2:
                out.append(xy)
    return out


def base_plan(net: Network, box: tuple[float, float, float, float] | None = None
              ) -> dict[str, list[np.ndarray]]:
    """The base plan of ``net`` as polylines by layer (:data:`BASE_LAYERS`).

    Only the road lanes (and junctions) that meet ``box`` (x min, y min, x max, y max) are
    drawn; all of them without a box.

    Examples
    --------
    >>> from clearance.networks.reader import Edge, Lane, Location
    >>> def lane(i):
    ...     return Lane(f"e_{i}", "e", i, 3.0, "normal", frozenset({"passenger"}),
    ...                 np.array([[0.0, 1.5 + 3 * i, 0], [50, 1.5 + 3 * i, 0]]), 50.0, 13.9)
    >>> net = Network(None, {"e_0": lane(0), "e_1": lane(1)},
    ...               {"e": Edge("e", "a", "b", "normal", 1, ["e_0", "e_1"])}, [], {}, [],
    ...               Location())
    >>> plan = base_plan(net)
    >>> [len(plan[k]) for k in ("BASE-PAVEMENT-EDGE", "BASE-LANE-LINE", "BASE-JUNCTION")]
    [1, 1, 0]
    >>> plan["BASE-LANE-LINE"][0].tolist()  # between the two lanes, at y = 3
    [[0.0, 3.0], [50.0, 3.0]]
    """
    def near(shape: np.ndarray) -> bool:
        if box is None:
            return True
        return bool(len(shape)) and not (
            shape[:, 0].max() < box[0] or shape[:, 0].min() > box[2]
            or shape[:, 1].max() < box[1] or shape[:, 1].min() > box[3])

    road = sorted(k for k, lane in net.lanes.items()
                  if lane.allows_road_vehicles() and len(lane.shape) >= 2 and near(lane.shape))
    junctions = [net.junctions[k] for k in sorted(net.junctions)
                 if len(net.junctions[k].shape) >= 3 and near(net.junctions[k].shape)]
    polys = [shapely.make_valid(p) for p in lane_polygons(net, road)] if road else []
    polys += [shapely.make_valid(shapely.Polygon(j.shape[:, :2])) for j in junctions]
    paved = shapely.union_all(polys) if polys else shapely.Polygon()
    plan: dict[str, list[np.ndarray]] = {k: [] for k in BASE_LAYERS}
    if not paved.is_empty:
        plan["BASE-PAVEMENT-EDGE"] = _lines(shapely.set_precision(paved, 1e-3))
    road_set = set(road)
    for eid in sorted(net.edges):
        lanes = [k for k in net.edges[eid].lanes if k in road_set]
        lanes.sort(key=lambda k: net.lanes[k].index)
        for k in lanes[:-1]:  # the line on the left of each lane but the leftmost
            lane = net.lanes[k]
            if lane.is_internal:
                continue
            line = LineString(lane.shape[:, :2]).offset_curve(lane.width_m / 2.0)
            plan["BASE-LANE-LINE"] += _lines(line)
    for j in junctions:
        xy = np.asarray(j.shape[:, :2], dtype=float)
        if (xy[0] != xy[-1]).any():
            xy = np.vstack([xy, xy[:1]])
        plan["BASE-JUNCTION"].append(xy)
    return plan


def _layer_names(vehicles: Iterable[str], taken: set[str]) -> dict[str, str]:
    """A unique layer prefix for each vehicle (layer names are case-insensitive)."""
    out = {}
    for vehicle in sorted(vehicles):
        name, k = dxf_layer_name(vehicle), 1
        while any(f"{name}-{s}".casefold() in taken for s in VEHICLE_LAYERS) or \
                name.casefold() in taken:
            k += 1
            name = f"{dxf_layer_name(vehicle)[:225]}~{k}"
        taken.add(name.casefold())
        taken.update(f"{name}-{s}".casefold() for s in VEHICLE_LAYERS)
        out[vehicle] = name
    return out


#: Polygons smaller than this (m²) are slivers of a difference, not drawn.
MIN_AREA_M2 = 1e-4


def _has_area(geom: Any) -> bool:
    """True when ``geom`` holds a polygon of at least :data:`MIN_AREA_M2`."""
    return geom is not None and any(p.geom_type == "Polygon" and p.area >= MIN_AREA_M2
                                    for p in shapely.get_parts(geom))


class _At:
    """Where a drawing's points go: SUMO's plane shifted by ``(dx, dy)`` (into the
    projected CRS, :func:`_projection_shift`), rounded to the millimetre (no plan is drawn
    finer: a DXF of 17-digit coordinates is twice the size for nothing).

    >>> _At(1000.0, 0.0)([(0.12345, 1.0), (2.0, 3.99999)])
    [(1000.123, 1.0), (1002.0, 4.0)]
    """

    def __init__(self, dx: float = 0.0, dy: float = 0.0) -> None:
        self.dx, self.dy = dx, dy

    def __call__(self, coords: Iterable) -> list[tuple[float, float]]:
        xy = np.asarray([c[:2] for c in coords], dtype=float).reshape(-1, 2)
        xy = np.round(xy + (self.dx, self.dy), 3)
        return [(float(x), float(y)) for x, y in xy]


def _polygons(msp: Any, geom: Any, attribs: dict, tags: list | None, hatch: str | None,
              at: _At) -> None:
    """Closed polylines of every ring of ``geom`` (and a hatch of each part), placed by
    ``at``."""
    if geom is None or geom.is_empty:
        return
    parts = [p for p in shapely.get_parts(geom)
             if p.geom_type == "Polygon" and p.area >= MIN_AREA_M2]
    for part in polygon_parts(shapely.MultiPolygon(parts)) if parts else []:
        rings = [("exterior", part.exterior)] + [("hole", h) for h in part.interiors]
        for role, ring in rings:
            points = at(ring.coords[:-1])
            line = msp.add_lwpolyline(points, format="xy", close=True, dxfattribs=attribs)
            if tags is not None:
                line.set_xdata(APPID, [*tags, (1000, f"ring={role}")])
        if hatch is not None:
            h = msp.add_hatch(dxfattribs={"layer": attribs["layer"]})
            h.set_pattern_fill(hatch, scale=0.5)
            h.paths.add_polyline_path(at(part.exterior.coords[:-1]), is_closed=True,
                                      flags=ezdxf.const.BOUNDARY_PATH_EXTERNAL)
            for ring in part.interiors:
                h.paths.add_polyline_path(at(ring.coords[:-1]), is_closed=True)


def write_dxf(path: str | os.PathLike[str], records: Iterable[EnvelopeRecord],
              network: Network | None = None) -> Path:
    """Write one network's envelopes as a DXF drawing (R2010, UTF-8), in SUMO plane metres.

    Parameters
    ----------
    path
        The output file (conventionally ``*.dxf``); written atomically.
    records
        The envelopes, in the network's SUMO coordinates (one network's: the coordinates of
        two networks have nothing to do with each other).
    network
        The network, for the base plan (:func:`base_plan`, within :data:`BASE_MARGIN_M` of
        the envelopes); None: envelopes only.

    Returns
    -------
    Path
        The file written.

    Notes
    -----
    Layers as in the module docstring, each vehicle's prefixed with :func:`dxf_layer_name`
    of its name (a suffix ``~2``, ``~3``... when two names clash, DXF layer names being
    case-insensitive), the layer's description holding the vehicle's own name. A run whose
    envelope is grown by a clearance offset has it on ``-CLEARANCE-ENVELOPE`` and its body
    envelope (when known) on ``-ENVELOPE``. ``$INSUNITS`` is 6 (metres), ``$MEASUREMENT``
    1 (metric), and ``$EXTMIN``/``$EXTMAX`` the drawing's extents. A network with a
    projection is drawn in its projected CRS (SUMO's coordinates less ``netOffset``; the
    header's custom properties ``CRS`` and ``SUMO_NET_OFFSET`` say which); one without, in
    SUMO's plane metres. Envelope polylines carry the verdict's colour
    (:data:`VERDICT_ACI`) and XDATA ``network=``, ``vehicle=``, ``curve_id=``, ``kind=``,
    ``verdict=``, ``margin_m=``, ``ring=exterior|hole``.

    Raises
    ------
    InputError
        A bad record (see :func:`clearance.reports.exports.envelopes.checked_records`); the message
        names it.
    """
    recs = checked_records(records)
    doc = _new_drawing()
    msp = doc.modelspace()
    shift = _place_in_projection(doc, network)
    at = _At(*shift)
    bounds = []
    if network is not None:
        bounds.append(_draw_base_plan(doc, msp, network, recs, at))
    layers = _add_vehicle_layers(doc, recs)
    for r in recs:
        _draw_record(msp, r, layers[r.vehicle], at)
    if recs:
        bounds.append(shapely.total_bounds([r.envelope for r in recs]))
    _set_extents(doc, [b + np.array([*shift, *shift]) for b in bounds])
    return write_stream_atomic(path, lambda stream: _write_reproducible(doc, stream))


def _place_in_projection(doc: Drawing, network: Network | None) -> tuple[float, float]:
    """A network with a projection has its drawing placed in the projected CRS (SUMO's plane
    is that CRS less ``netOffset``), the CRS named in the header (custom property ``CRS``, a
    PROJ string) so that a CAD user's base map in that CRS and this drawing overlay; returns
    the shift to apply (0, 0 without a projection: SUMO's plane metres, as before)."""
    if network is None:
        return 0.0, 0.0
    proj = (network.location.proj_parameter or "").strip()
    if proj in ("", "!"):
        return 0.0, 0.0
    dx, dy = (-float(v) for v in network.location.net_offset)
    doc.header.custom_vars.append("CRS", proj)
    doc.header.custom_vars.append("SUMO_NET_OFFSET", " ".join(
        f"{float(v):.2f}" for v in network.location.net_offset))
    return dx, dy


def _set_extents(doc: Drawing, bounds: list[np.ndarray]) -> None:
    """``$EXTMIN``/``$EXTMAX`` from the drawing's parts' bounds (x0, y0, x1, y1), so that a CAD
    program's "zoom extents" and an insertion into a base map find the drawing at once."""
    known = [b for b in bounds if len(b) == 4 and np.isfinite(b).all()]
    if not known:
        return
    box = np.array(known)
    lo = (float(box[:, 0].min()), float(box[:, 1].min()), 0.0)
    hi = (float(box[:, 2].max()), float(box[:, 3].max()), 0.0)
    msp = doc.modelspace()  # ezdxf writes the header's extents from the layout's
    msp.dxf.extmin, msp.dxf.extmax = lo, hi
    doc.header["$EXTMIN"], doc.header["$EXTMAX"] = lo, hi


def _new_drawing() -> Drawing:
    """An empty R2010 drawing in metres, with the application id and the DASHED line type."""
    with _fixed_metadata():
        doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = 6
    doc.header["$MEASUREMENT"] = 1
    doc.appids.add(APPID)
    if "DASHED" not in doc.linetypes:
        doc.linetypes.add("DASHED", pattern=[1.5, 1.0, -0.5], description="Dashed __ __ __")
    return doc


def _draw_base_plan(doc: Drawing, msp: Modelspace, network: Network,
                    recs: list[EnvelopeRecord], at: _At) -> np.ndarray:
    """The base layers and the base plan of ``network`` within :data:`BASE_MARGIN_M` of
    the envelopes (all of it without records); returns the plan's bounds (x0, y0, x1, y1;
    NaN when it is empty)."""
    box = None
    if recs:
        x0, y0, x1, y1 = shapely.total_bounds([r.envelope for r in recs])
        box = (x0 - BASE_MARGIN_M, y0 - BASE_MARGIN_M, x1 + BASE_MARGIN_M,
               y1 + BASE_MARGIN_M)
    plan = base_plan(network, box)
    drawn = [np.asarray(xy, dtype=float)[:, :2] for lines in plan.values() for xy in lines
             if len(xy)]
    every = np.vstack(drawn) if drawn else np.empty((0, 2))
    bounds = (np.array([*every.min(axis=0), *every.max(axis=0)]) if len(every)
              else np.full(4, np.nan))
    for name, (colour, ltype, description) in BASE_LAYERS.items():
        layer = doc.layers.add(name, color=colour, linetype=ltype)
        layer.description = description
        for xy in plan[name]:
            closed = len(xy) > 3 and bool((xy[0] == xy[-1]).all())
            pts = at(xy[:-1] if closed else xy)
            msp.add_lwpolyline(pts, format="xy", close=closed, dxfattribs={"layer": name})
    return bounds


def _add_vehicle_layers(doc: Drawing, recs: list[EnvelopeRecord]) -> dict[str, str]:
    """Add the vehicle layers the records use; returns each vehicle's layer prefix."""
    taken = {"0", "defpoints"} | {n.casefold() for n in BASE_LAYERS}
    layers = _layer_names({r.vehicle for r in recs}, taken)
    used = {(r.vehicle, s) for r in recs for s, present in (
        ("BODY", bool(r.body_outlines)), ("WHEEL-PATH", bool(r.wheel_paths)),
        ("ENVELOPE", r.offset_m == 0 or r.body_envelope is not None),
        ("CLEARANCE-ENVELOPE", r.offset_m > 0),
        ("CONFLICT-LANE", _has_area(r.outside_lanes)),
        ("CONFLICT-PAVEMENT", _has_area(r.outside_pavement)),
        ("LABEL", True), ("OVERREACH", r.overreach is not None)) if present}
    for vehicle, prefix in layers.items():
        for suffix, (colour, description) in VEHICLE_LAYERS.items():
            if (vehicle, suffix) in used:
                layer = doc.layers.add(f"{prefix}-{suffix}", color=colour)
                layer.description = _text(f"{vehicle}: {description}")
    return layers


def _xdata_tags(r: EnvelopeRecord) -> list[tuple[int, str]]:
    """The XDATA strings of a record's entities: ``network=``, ``vehicle=``... ``margin_m=``."""
    margin = "" if r.margin_mm is None else f"{r.margin_mm:.3f}"
    return [
        (1000, _text(f"{key}={value}"))
        for key, value in (
            ("network", r.network),
            ("vehicle", r.vehicle),
            ("curve_id", r.curve_id),
            ("kind", r.kind),
            ("verdict", r.verdict),
            ("margin_m", margin),
        )
    ]


def _draw_record(msp: Modelspace, r: EnvelopeRecord, prefix: str, at: _At) -> None:
    """Everything drawn for one record, on the layers of vehicle layer prefix ``prefix``."""
    tags = _xdata_tags(r)
    colour = VERDICT_ACI[r.verdict]
    for outline in r.body_outlines:
        _polygons(msp, outline, {"layer": f"{prefix}-BODY"}, None, None, at)
    for wheel in r.wheel_paths:
        for xy in _lines(wheel):
            msp.add_lwpolyline(at(xy), format="xy",
                               dxfattribs={"layer": f"{prefix}-WHEEL-PATH"})
    if r.offset_m > 0:
        _polygons(msp, r.envelope, {"layer": f"{prefix}-CLEARANCE-ENVELOPE",
                                    "color": colour}, tags, None, at)
        if r.body_envelope is not None:
            _polygons(msp, r.body_envelope, {"layer": f"{prefix}-ENVELOPE",
                                             "color": colour}, tags, None, at)
    else:
        _polygons(msp, r.envelope, {"layer": f"{prefix}-ENVELOPE", "color": colour},
                  tags, None, at)
    _polygons(msp, r.outside_lanes, {"layer": f"{prefix}-CONFLICT-LANE"}, None, "ANSI31", at)
    _polygons(msp, r.outside_pavement, {"layer": f"{prefix}-CONFLICT-PAVEMENT"}, None,
              "ANSI37", at)
    for part in polygon_parts(r.envelope):
        p = part.representative_point()
        text = msp.add_text(_text(r.curve_id), height=TEXT_HEIGHT_M,
                            dxfattribs={"layer": f"{prefix}-LABEL", "color": colour})
        text.set_placement(at([(p.x, p.y)])[0], align=TextEntityAlignment.MIDDLE_CENTER)
        text.set_xdata(APPID, tags)
    if r.overreach is not None:
        _draw_overreach(msp, r.overreach, f"{prefix}-OVERREACH", colour, tags, at)


def _draw_overreach(msp: Modelspace, overreach: tuple[float, float, float, float], layer: str,
                    colour: int, tags: list[tuple[int, str]], at: _At) -> None:
    """A point at the worst overreach (x, y, station, extra width) and its ``+0.56 m`` label."""
    x, y, station, extra = (float(v) for v in overreach)
    [(x, y)] = at([(x, y)])
    point = msp.add_point((x, y), dxfattribs={"layer": layer, "color": colour})
    point.set_xdata(APPID, tags + [(1000, f"station_m={station:.3f}"),
                                   (1000, f"extra_width_m={extra:.3f}")])
    label = msp.add_text(f"+{extra:.2f} m", height=TEXT_HEIGHT_M,
                         dxfattribs={"layer": layer, "color": colour})
    label.set_placement((x, y), align=TextEntityAlignment.BOTTOM_LEFT)


@contextmanager
def _fixed_metadata() -> Iterator[None]:
    """ezdxf writes fixed dates and GUIDs meanwhile (its option for reproducible files)."""
    previous = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = previous


def _write_reproducible(doc: Drawing, stream: TextIO) -> None:
    """Write the DXF text of ``doc`` to ``stream``, the same bytes for the same content
    (written as it goes: a town's drawing is 100 MB of text)."""
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = OrderedDict(sorted(doc.classes.classes.items()))
    with _fixed_metadata():
        doc.write(stream)
