"""The three nested areas that decide a verdict (DESIGN.md §6), as shapely geometry.

``own_lanes``
    The curve's centre line buffered by half its lane width (flat ends): the lanes it
    drives on, trimmed to the part the centre line covers.

Lane polygons in ``roadway`` and ``paved`` have round ends, so that lanes meeting at an
angle leave no wedge uncovered on the outside of the joint, and both areas are grown by
:data:`SEAL_M` (1 mm) to seal the hairline cracks a union of touching polygons can leave;
holes under :data:`MIN_HOLE_M2` (wedges between lane pieces) are filled.
``roadway``
    Everything a vehicle going the same way could use: the curve's lanes, all road lanes
    (admitting passenger cars, buses or trucks) of the plain edges it runs on, and the
    internal road lanes of every connection between consecutive plain edges of the curve
    (the parallel lanes of the same movement). A truck apron (a lane no road vehicle may
    use) is paved but not roadway.
``paved``
    The roadway plus, for each junction the curve passes through, the junction polygon,
    all its internal lanes and every lane of the edges that meet there (sidewalks and
    the opposite direction included). A bend's neighbourhood is the two junctions of its
    edge.

Lane polygons are made once for the whole network with vectorised ``shapely.buffer``;
areas shared by many curves (one junction's paved area serves all its turns) are unioned
once, with ``shapely.union_all`` over rows of an array, and the curves share the object.
``own_lanes`` is a buffer of the centre line, so at lane joins it may stick out of the
lane polygons of ``roadway`` by slivers of a few square centimetres.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import shapely

from networks.paths import junction_of_internal
from networks.reader import Network

#: ``roadway`` and ``paved`` are grown by this much (metres) to seal hairline cracks.
SEAL_M = 1e-3

#: Holes in ``roadway`` and ``paved`` smaller than this (m²) are gaps between lane pieces,
#: not islands, and are filled (a traffic island is several square metres).
MIN_HOLE_M2 = 1.0

if TYPE_CHECKING:
    from networks.curves import Curve


def lane_polygons(net: Network, lane_ids: Sequence[str], cap_style: str = "flat") -> np.ndarray:
    """Polygons of lanes: each shape buffered by half its width (vectorised).

    With ``cap_style="round"`` the ends are half discs: where two lanes meet at an angle,
    the wedge that flat ends leave open on the outside of the bend is covered (the areas
    use this; it also reaches half a lane width past a dead end).

    Examples
    --------
    >>> from networks.reader import Lane, Network, Location
    >>> lane = Lane("e_0", "e", 0, 3.0, "normal", frozenset(), np.array([[0, 0, 0], [10, 0, 0.0]]),
    ...             10.0, 13.9)
    >>> net = Network(None, {"e_0": lane}, {}, [], {}, [], Location())
    >>> round(lane_polygons(net, ["e_0"])[0].area, 6)
    30.0
    >>> round(lane_polygons(net, ["e_0"], "round")[0].area, 1)  # + a disc of r 1.5 (16-gon)
    36.9
    """
    if not lane_ids:
        return np.empty(0, dtype=object)
    shapes = [net.lanes[k].shape[:, :2] for k in lane_ids]
    counts = np.array([len(s) for s in shapes])
    index = np.repeat(np.arange(len(shapes)), counts)
    lines = shapely.linestrings(np.vstack(shapes), indices=index)
    widths = np.array([net.lanes[k].width_m for k in lane_ids])
    return shapely.buffer(lines, widths / 2.0, cap_style=cap_style, join_style="round", quad_segs=4)


def own_lane_polygons(curves: Sequence[Curve]) -> np.ndarray:
    """Each curve's centre line buffered by half its lane width (vectorised)."""
    if not curves:
        return np.empty(0, dtype=object)
    shapes = [c.centerline[:, :2] for c in curves]
    counts = np.array([len(s) for s in shapes])
    index = np.repeat(np.arange(len(shapes)), counts)
    lines = shapely.linestrings(np.vstack(shapes), indices=index)
    half = np.array([c.lane_width_m / 2.0 for c in curves])
    return shapely.buffer(lines, half, cap_style="flat", join_style="round", quad_segs=4)


class _Catalogue:
    """Numbered geometries (lane and junction polygons) made on demand, in batches."""

    def __init__(self, net: Network):
        self.net = net
        self.index: dict[str, int] = {}
        self.keys: list[str] = []

    def ref(self, key: str) -> int:
        i = self.index.get(key)
        if i is None:
            i = self.index[key] = len(self.keys)
            self.keys.append(key)
        return i

    def build(self) -> np.ndarray:
        lanes = [k[2:] for k in self.keys if k.startswith("L:")]
        lane_geoms = iter(lane_polygons(self.net, lanes, "round"))
        out = np.empty(len(self.keys), dtype=object)
        for i, k in enumerate(self.keys):
            if k.startswith("L:"):
                out[i] = next(lane_geoms)
            else:
                shape = self.net.junctions[k[2:]].shape
                poly = shapely.Polygon(shape[:, :2]) if len(shape) >= 3 else None
                out[i] = shapely.make_valid(poly) if poly is not None else None
        return out


def _union_rows(groups: list[list[int]], geoms: np.ndarray) -> np.ndarray:
    """Union each group of catalogue entries (one ``union_all`` call per size bucket)."""
    out = np.empty(len(groups), dtype=object)
    if not groups:
        return out
    sizes = np.array([len(g) for g in groups])
    for size in np.unique(sizes):
        rows = np.flatnonzero(sizes == size)
        table = np.empty((len(rows), int(size)), dtype=object)
        for r, g in enumerate(rows):
            table[r, :] = geoms[groups[g]]
        out[rows] = shapely.union_all(table, axis=1)
    # close the hairline cracks a union of touching polygons can leave (a crack where two
    # lanes' ends meet makes a point of the boundary lie inside the area)
    sealed = shapely.buffer(out, SEAL_M, quad_segs=1, join_style="mitre")
    return np.array([_fill_small_holes(g) for g in sealed], dtype=object)


def _fill_small_holes(geom, min_hole_m2: float | None = None):
    """The geometry without holes smaller than ``min_hole_m2`` (gaps between lane pieces).

    Examples
    --------
    >>> ring = shapely.box(0, 0, 10, 10).difference(shapely.box(4, 4, 4.5, 4.5))
    >>> _fill_small_holes(ring).area
    100.0
    >>> _fill_small_holes(shapely.box(0, 0, 10, 10).difference(shapely.box(2, 2, 8, 8))).area
    64.0
    """
    limit = MIN_HOLE_M2 if min_hole_m2 is None else min_hole_m2
    parts = []
    changed = False
    for poly in shapely.get_parts(geom):
        holes = [r for r in poly.interiors if shapely.Polygon(r).area >= limit]
        if len(holes) != len(poly.interiors):
            changed = True
            poly = shapely.Polygon(poly.exterior, holes)
        parts.append(poly)
    if not changed:
        return geom
    return parts[0] if len(parts) == 1 else shapely.MultiPolygon(parts)


def attach_areas(net: Network, curves: Sequence[Curve]) -> None:
    """Set ``own_lanes``, ``roadway`` and ``paved`` on each curve (in place)."""
    if not curves:
        return
    own = own_lane_polygons(curves)
    cat = _Catalogue(net)
    road_keys: dict[frozenset[int], int] = {}
    paved_keys: dict[frozenset[int], int] = {}
    road_of: list[int] = []
    paved_of: list[int] = []
    junction_members: dict[str, frozenset[int]] = {}
    edge_incident = _incident_edges(net)
    internal = _internal_lanes_by_junction(net)
    for curve in curves:
        road = _roadway_lanes(net, curve.lanes)
        road_set = frozenset(cat.ref("L:" + k) for k in road)
        road_of.append(road_keys.setdefault(road_set, len(road_keys)))
        members = set(road_set)
        for j in _junctions_of(net, curve):
            if j not in junction_members:
                junction_members[j] = frozenset(
                    cat.ref(k) for k in _junction_neighbourhood(net, j, edge_incident, internal)
                )
            members |= junction_members[j]
        paved_set = frozenset(members)
        paved_of.append(paved_keys.setdefault(paved_set, len(paved_keys)))
    geoms = cat.build()
    road_union = _union_rows([sorted(k) for k in road_keys], geoms)
    paved_union = _union_rows([sorted(k) for k in paved_keys], geoms)
    roadway = road_union[np.array(road_of)]
    paved = paved_union[np.array(paved_of)]
    for curve, o, r, p in zip(curves, own, roadway, paved, strict=True):
        curve.own_lanes, curve.roadway, curve.paved = o, r, p


def _incident_edges(net: Network) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for e in net.edges.values():
        if e.function == "internal":
            continue
        out.setdefault(e.from_junction, []).append(e.id)
        out.setdefault(e.to_junction, []).append(e.id)
    return out


def _roadway_lanes(net: Network, lanes: Sequence[str]) -> list[str]:
    plain = [net.lanes[k].edge for k in lanes if net.lanes[k].function != "internal"]
    plain = list(dict.fromkeys(plain))
    out: list[str] = list(lanes)
    for e in plain:
        out.extend(k for k in net.edges[e].lanes if net.lanes[k].allows_road_vehicles())
    for a, b in zip(plain, plain[1:], strict=False):
        for lane_id in net.edges[a].lanes:
            for c in net.outgoing(lane_id):
                if c.to_edge == b and c.via:
                    via = c.via
                    while via and via in net.lanes and via not in out:
                        if net.lanes[via].allows_road_vehicles():
                            out.append(via)
                        nxt = net.outgoing(via)
                        via = nxt[0].via if nxt else None
    return list(dict.fromkeys(out))


def _junctions_of(net: Network, curve: Curve) -> list[str]:
    if curve.kind == "bend":
        edge = net.edges[net.lanes[curve.core_lanes[0]].edge]
        return [edge.from_junction, edge.to_junction]
    out = [junction_of_internal(k) for k in curve.core_lanes if k.startswith(":")]
    if curve.kind == "ramp":
        for k in curve.core_lanes:
            if not k.startswith(":"):
                e = net.edges[net.lanes[k].edge]
                out.extend((e.from_junction, e.to_junction))
    return [j for j in dict.fromkeys(out) if j in net.junctions]


def _internal_lanes_by_junction(net: Network) -> dict[str, list[str]]:
    """Every internal lane under the junction it belongs to (also those after an internal
    junction, which the junction's ``intLanes`` may not list)."""
    out: dict[str, list[str]] = {}
    for k, lane in net.lanes.items():
        if lane.function == "internal":
            out.setdefault(junction_of_internal(k), []).append(k)
    return out


def _junction_neighbourhood(
    net: Network, junction: str, incident: dict[str, list[str]], internal: dict[str, list[str]]
) -> list[str]:
    keys = ["J:" + junction]
    for e in incident.get(junction, []):
        keys.extend("L:" + k for k in net.edges[e].lanes)
    keys.extend("L:" + k for k in internal.get(junction, []))
    return keys
