"""The three nested areas that decide a verdict (DESIGN.md §6), as shapely geometry.

``own_lanes``
    The curve's centre line buffered by half its lane width (flat ends): the lanes it
    drives on, trimmed to the part the centre line covers.

Lane polygons in ``roadway`` and ``paved`` have round ends, so that lanes meeting at an
angle leave no wedge uncovered on the outside of the joint; lanes and junction polygons
are grown by :data:`SEAL_M` (1 mm) so that they overlap rather than touch (a union of
touching polygons can keep hairline cracks);
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
A paved area is the union of its plain lanes, edges and junction polygon first, then of
that with only the internal lanes it does not already cover (the same area, far fewer
crossings to node). The vectorised shapely calls are split over :data:`WORKERS` threads.
``own_lanes`` is a buffer of the centre line, so at lane joins it may stick out of the
lane polygons of ``roadway`` by slivers of a few square centimetres.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import shapely

from networks.paths import junction_of_internal, via_lanes
from networks.reader import Network, gc_paused

#: The polygons ``roadway`` and ``paved`` are made of are grown by this much (metres), so
#: that they overlap where they would touch: a union of touching polygons can keep hairline
#: cracks, and a point of the boundary then lies inside the area.
SEAL_M = 1e-3

#: Holes in ``roadway`` and ``paved`` smaller than this (m²) are gaps between lane pieces,
#: not islands, and are filled (a traffic island is several square metres).
MIN_HOLE_M2 = 1.0

if TYPE_CHECKING:
    from networks.curves import Curve


def lane_polygons(
    net: Network, lane_ids: Sequence[str], cap_style: str = "flat", grow_m: float = 0.0
) -> np.ndarray:
    """Polygons of lanes: each shape buffered by half its width (vectorised).

    ``grow_m`` widens every lane by that much on each side. With ``cap_style="round"``
    the ends are half discs: where two lanes meet at an angle,
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
    buffer = partial(shapely.buffer, cap_style=cap_style, join_style="round", quad_segs=4)
    return _threaded(buffer, lines, widths / 2.0 + grow_m)


def own_lane_polygons(curves: Sequence[Curve]) -> np.ndarray:
    """Each curve's centre line buffered by half its lane width (vectorised)."""
    if not curves:
        return np.empty(0, dtype=object)
    shapes = [c.centerline[:, :2] for c in curves]
    counts = np.array([len(s) for s in shapes])
    index = np.repeat(np.arange(len(shapes)), counts)
    lines = shapely.linestrings(np.vstack(shapes), indices=index)
    half = np.array([c.lane_width_m / 2.0 for c in curves])
    buffer = partial(shapely.buffer, cap_style="flat", join_style="round", quad_segs=4)
    return _threaded(buffer, lines, half)


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
        """Lane polygons (round ends) and junction polygons, all grown by :data:`SEAL_M`."""
        lanes = [k[2:] for k in self.keys if k.startswith("L:")]
        lane_geoms = iter(lane_polygons(self.net, lanes, "round", grow_m=SEAL_M))
        out = np.empty(len(self.keys), dtype=object)
        for i, k in enumerate(self.keys):
            if k.startswith("L:"):
                out[i] = next(lane_geoms)
            else:
                shape = self.net.junctions[k[2:]].shape
                poly = shapely.Polygon(shape[:, :2]) if len(shape) >= 3 else None
                out[i] = shapely.make_valid(poly) if poly is not None else None
        junctions = np.array([k.startswith("J:") for k in self.keys], dtype=bool)
        if junctions.any():
            out[junctions] = shapely.buffer(out[junctions], SEAL_M, quad_segs=1, join_style="mitre")
        return out


def _union_rows(groups: list[list[int]], geoms: np.ndarray, seal: bool = True) -> np.ndarray:
    """Union each group of entries (one ``union_all`` call per group size).

    With ``seal``, the results are cleared of small holes.
    """
    out = np.empty(len(groups), dtype=object)
    if not groups:
        return out
    missing = shapely.is_missing(geoms)
    if missing.any():  # a junction without a polygon
        groups = [[i for i in g if not missing[i]] for g in groups]
    sizes = np.array([len(g) for g in groups])
    for size in np.unique(sizes):
        rows = np.flatnonzero(sizes == size)
        if size == 0:
            out[rows] = shapely.Polygon()
            continue
        if size == 1:
            out[rows] = geoms[[groups[g][0] for g in rows]]
            continue
        table = geoms[np.array([groups[g] for g in rows], dtype=np.intp)]
        if size <= 3:  # pairwise unions beat the cascaded union on a few polygons
            acc = table[:, 0]
            for col in range(1, int(size)):
                acc = _threaded(shapely.union, acc, table[:, col])
            out[rows] = acc
        else:
            out[rows] = _threaded(_union_all_rows, table)
    if not seal:
        return out
    parts = shapely.get_parts(out, return_index=True)
    holed = np.unique(parts[1][shapely.get_num_interior_rings(parts[0]) > 0])
    for i in holed:
        out[i] = _fill_small_holes(out[i])
    return out


def _union_all_rows(table: np.ndarray) -> np.ndarray:
    return shapely.union_all(table, axis=1)


#: Threads for the vectorised shapely calls (they release the GIL): one per core, at most 4
#: (the environment variable ``CLEARANCE_THREADS`` overrides it).
WORKERS = int(os.environ.get("CLEARANCE_THREADS", 0)) or max(1, min(4, len(
    os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)))

#: Arrays shorter than this are not split between threads.
MIN_SPLIT = 256


def _threaded(func: Callable[..., np.ndarray], *arrays: np.ndarray) -> np.ndarray:
    """``func(*arrays)`` computed on :data:`WORKERS` slices of the arrays at once.

    ``func`` must work row by row (a vectorised shapely call), so that the slices'
    results concatenated are its result on the whole.

    Examples
    --------
    >>> a = shapely.points(np.arange(5000.0), 0)
    >>> out = _threaded(shapely.buffer, a, np.full(5000, 1.0))
    >>> len(out), round(float(shapely.area(out).sum()) / 5000, 2)
    (5000, 3.12)
    """
    n = len(arrays[0])
    if WORKERS == 1 or n < MIN_SPLIT:
        return func(*arrays)
    bounds = np.linspace(0, n, WORKERS + 1).astype(int)
    with ThreadPoolExecutor(WORKERS) as pool:
        cuts = zip(bounds[:-1], bounds[1:], strict=True)
        slices = [tuple(x[a:b] for x in arrays) for a, b in cuts]
        parts = list(pool.map(lambda args: func(*args), slices))
    return np.concatenate(parts)


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
    """Set ``own_lanes``, ``roadway`` and ``paved`` on each curve (in place).

    Unions are built in two levels: pieces first (an edge's road lanes, an edge's lanes,
    the internal road lanes of one movement ``a -> b``), then each roadway from its
    pieces and each junction's paved area from its polygon and pieces. Curves share the
    results: one paved area per junction, one roadway per movement.
    """
    if not curves:
        return
    with gc_paused():
        _attach(net, curves)


def _attach(net: Network, curves: Sequence[Curve]) -> None:
    own = own_lane_polygons(curves)
    b = _AreaBuilder(net)
    road_of = []
    paved_of = []
    for c in curves:
        plain = tuple(_plain_edges_of(net, c.lanes))
        road_of.append(b.roadway_group(c, plain))
        paved_of.append(b.paved_group(c, plain))
    roadway, paved = b.build()
    for curve, o, r_i, p_i in zip(curves, own, road_of, paved_of, strict=True):
        curve.own_lanes, curve.roadway, curve.paved = o, roadway[r_i], paved[p_i]


class _AreaBuilder:
    """Registers the lanes, pieces and groups the curves need, then unions them in batches."""

    def __init__(self, net: Network):
        self.net = net
        self.cat = _Catalogue(net)
        self.pieces: dict[str, list[int]] = {}
        self.groups: dict[str, dict[frozenset[str], int]] = {"road": {}, "paved": {}}
        self.incident = _incident_edges(net)
        self.internal = _internal_lanes_by_junction(net)
        self.movement_at: dict[tuple[str, str], str] = {}
        self.junction_members: dict[str, frozenset[str]] = {}
        self.road_pieces: dict[tuple[str, ...], tuple[list[str], frozenset[str]]] = {}
        self.paved_near: dict[tuple[str, ...], frozenset[str]] = {}
        self.group_of: dict[str, dict[tuple, int]] = {"road": {}, "paved": {}}

    def _piece(self, key: str, lanes: Sequence[str]) -> str | None:
        if key not in self.pieces:
            if not lanes:
                return None
            self.pieces[key] = [self.cat.ref("L:" + k) for k in lanes]
        return key

    def edge_piece(self, edge: str, road_only: bool) -> str | None:
        lanes = self.net.edges[edge].lanes
        if road_only:
            lanes = [k for k in lanes if self.net.lanes[k].allows_road_vehicles()]
        return self._piece(("ER:" if road_only else "EA:") + edge, lanes)

    def movement_piece(self, a: str, b: str) -> str | None:
        key = f"M:{a}>{b}"
        if key in self.pieces:
            return key
        lanes: list[str] = []
        for lane_id in self.net.edges[a].lanes:
            for c in self.net.outgoing(lane_id):
                if c.to_edge == b and c.via:
                    lanes.extend(
                        k for k in via_lanes(self.net, c) or [] if self._road(k) and k not in lanes
                    )
        return self._piece(key, lanes)

    def _road(self, lane_id: str) -> bool:
        return self.net.lanes[lane_id].allows_road_vehicles()

    def roadway_group(self, curve: Curve, plain: tuple[str, ...]) -> int:
        """The roadway group of a curve running on the plain edges ``plain``."""
        hit = self.road_pieces.get(plain)
        if hit is None:
            keys = [self.edge_piece(e, True) for e in plain]
            keys += [self.movement_piece(a, b) for a, b in zip(plain, plain[1:], strict=False)]
            keys = [k for k in keys if k]
            covered = frozenset(self.cat.keys[i][2:] for k in keys for i in self.pieces[k])
            hit = self.road_pieces[plain] = (keys, covered)
        keys, covered = hit
        # a lane of the curve in no piece (e.g. a ring passage without a connection)
        extra = tuple(k for k in curve.lanes if k not in covered)
        return self._group("road", (plain, extra), lambda: [*keys, *("L:" + k for k in extra)])

    def paved_group(self, curve: Curve, plain: tuple[str, ...]) -> int:
        """The paved group of a curve: its junctions' areas and what they miss of it."""
        junctions = tuple(_junctions_of(self.net, curve))
        hit = self.paved_near.get(junctions)
        if hit is None:
            near_edges: set[str] = set()
            for j in junctions:
                near_edges.update(self.incident.get(j, []))
            hit = self.paved_near[junctions] = frozenset(near_edges)
        near = hit
        extra = tuple(
            k for k in curve.lanes
            if not k.startswith(":") and self.net.lanes[k].edge not in near
            and self.net.lanes[k].edge not in plain
        )
        return self._group(
            "paved", (junctions, plain, extra), lambda: self._paved_members(junctions, plain, extra)
        )

    def _paved_members(
        self, junctions: tuple[str, ...], plain: tuple[str, ...], extra: tuple[str, ...]
    ) -> list[str]:
        members: set[str] = set()
        near = self.paved_near[junctions]
        for j in junctions:
            members |= self.junction(j)
        for e in plain:
            if e not in near:
                members.add(self.edge_piece(e, False) or "")
        for a, b in zip(plain, plain[1:], strict=False):
            if self.net.edges[a].to_junction not in junctions:
                members.add(self.movement_piece(a, b) or "")
        members.update("L:" + k for k in extra)  # lanes of the curve nothing above covers
        members.discard("")
        return sorted(members)

    def _group(self, kind: str, key: tuple, members: Callable[[], list[str]]) -> int:
        """The group of a curve by ``key``; a new key's members are deduplicated by value."""
        ids = self.group_of[kind]
        hit = ids.get(key)
        if hit is None:
            hit = ids[key] = self.group(kind, frozenset(members()))
        return hit

    def junction(self, j: str) -> frozenset[str]:
        hit = self.junction_members.get(j)
        if hit is not None:
            return hit
        keys = {"J:" + j}
        in_movements: set[str] = set()
        for e in self.incident.get(j, []):
            keys.add(self.edge_piece(e, False) or "")
            if self.net.edges[e].to_junction == j:
                outs = {c.to_edge for k in self.net.edges[e].lanes for c in self.net.outgoing(k)}
                for b in sorted(outs):
                    key = self.movement_piece(e, b) if b in self.net.edges else None
                    if key:
                        keys.add(key)
                        in_movements.update(self.cat.keys[i][2:] for i in self.pieces[key])
        keys.update("L:" + k for k in self.internal.get(j, []) if k not in in_movements)
        keys.discard("")
        self.cat.ref("J:" + j)
        hit = self.junction_members[j] = frozenset(keys)
        return hit

    def group(self, kind: str, members: frozenset[str]) -> int:
        table = self.groups[kind]
        return table.setdefault(members, len(table))

    def build(self) -> tuple[np.ndarray, np.ndarray]:
        for table in self.groups.values():
            for members in table:
                for k in members:
                    if k.startswith(("L:", "J:")):
                        self.cat.ref(k)
        geoms = self.cat.build()
        # pieces with the same lanes (an edge's lanes that are all road lanes) share one union
        rows_of: dict[tuple[int, ...], int] = {}
        piece_row = {k: rows_of.setdefault(tuple(m), len(rows_of)) for k, m in self.pieces.items()}
        piece_geoms = _union_rows([list(r) for r in rows_of], geoms, seal=False)
        index = {k: len(geoms) + r for k, r in piece_row.items()}
        index.update({k: i for i, k in enumerate(self.cat.keys)})
        all_geoms = np.concatenate((geoms, piece_geoms))
        roadway = _union_rows([sorted(index[k] for k in m) for m in self.groups["road"]], all_geoms)
        return roadway, self._paved(geoms, all_geoms, index)

    def _paved(self, geoms: np.ndarray, all_geoms: np.ndarray, index: dict[str, int]) -> np.ndarray:
        """Paved areas: the union of each group's plain lanes, edges and junction polygon
        first, then of that with the internal lanes it does not already cover (most lie
        inside the junction polygon: leaving them out is the same union, much cheaper)."""
        base_rows: list[list[int]] = []
        inner_rows: list[list[int]] = []
        for members in self.groups["paved"]:
            base: set[int] = set()
            inner: set[int] = set()
            for k in members:
                if k.startswith("M:"):
                    inner.update(self.pieces[k])
                elif k.startswith("L::"):
                    inner.add(index[k])
                else:
                    base.add(index[k])
            base_rows.append(sorted(base))
            inner_rows.append(sorted(inner - base))
        first = _union_rows(base_rows, all_geoms, seal=False)
        shapely.prepare(first)
        row_of = np.repeat(np.arange(len(inner_rows)), [len(r) for r in inner_rows])
        inner = np.array([i for r in inner_rows for i in r], dtype=np.intp)
        covered = _threaded(shapely.covers, first[row_of], geoms[inner])
        shapely.destroy_prepared(first)
        rest: list[list[int]] = [[len(geoms) + g] for g in range(len(first))]
        for g, i in zip(row_of[~covered].tolist(), inner[~covered].tolist(), strict=True):
            rest[g].append(i)
        return _union_rows(rest, np.concatenate((geoms, first)))


def _plain_edges_of(net: Network, lanes: Sequence[str]) -> list[str]:
    plain = [net.lanes[k].edge for k in lanes if net.lanes[k].function != "internal"]
    return list(dict.fromkeys(plain))


def _incident_edges(net: Network) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for e in net.edges.values():
        if e.function == "internal":
            continue
        out.setdefault(e.from_junction, []).append(e.id)
        out.setdefault(e.to_junction, []).append(e.id)
    return out


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
