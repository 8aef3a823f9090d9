"""The three nested areas that decide a verdict (docs/design.md §6), as shapely geometry.

``own_lanes``
    The curve's designed line (its centre line smoothed as the vehicle follows it,
    :func:`designed_line`) buffered by half its lane width (flat ends): the lanes it
    drives on as designed, not SUMO's chords of them, trimmed to the part the centre line
    covers.

Lane polygons in ``roadway`` and ``paved`` have round ends, so that lanes meeting at an
angle leave no wedge uncovered on the outside of the joint; lanes and junction polygons
are grown by :data:`SEAL_M` (1 mm) so that they overlap rather than touch (a union of
touching polygons can keep hairline cracks); holes under :data:`MIN_HOLE_M2` (wedges between lane
pieces) are filled. The paved area is closed over :data:`CRACK_M` (:func:`close_cracks`): the
slivers SUMO leaves between the lanes of a street's two directions, or between a lane and a
junction polygon, where their shapes are offset from different centre lines, are pavement.
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
    edge. It always covers the curve's roadway and own lanes (:func:`covering_paved`):
    every lane the run drives on, lead-in and run-out included.

Areas are built for a batch of curves at a time (:func:`build_areas`; all curves at once
with :func:`attach_areas`, on demand per batch with :class:`clearance.networks.area_book.AreaBook`):
the lane polygons the batch needs with vectorised ``shapely.buffer``, then the pieces, then
the areas; curves of the batch that share an area (one junction's paved area serves all
its turns) share the object. Which lanes and pieces make each area is decided in
:mod:`clearance.networks.area_groups`, in a fixed order, so that an area is the same whichever batch
builds it. Unions of a few polygons are pairwise, larger ones ``shapely.union_all`` over
rows of an array. A paved area is the union of its plain lanes, edges and junction polygon
first, then of that with the union of only the internal lanes it does not already cover
(the same area, far fewer crossings to node).

Building has two steps: grouping the curves (:class:`~clearance.networks.area_groups.BatchPlan`,
then :func:`make_job`: Python, which needs the network) and making the geometry from the
resulting :class:`Job` of plain arrays (:func:`run_job`: GEOS only). Areas are built in the
process that reads them, on one core: a study spends its time in the runs, which go to
worker processes (docs/design.md §8). ``own_lanes`` is a buffer of the centre line, so at
lane joins it may stick out of the lane polygons of ``roadway`` by slivers of a few square
centimetres.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal, NamedTuple, cast

import numpy as np
import shapely

from clearance.analysis.polyline import DEFAULT_SPACING_M, prepare_path
from clearance.networks.area_groups import AreaCurve, AreaIndex, BatchPlan
from clearance.networks.collector import gc_paused
from clearance.networks.model import Network
from clearance.vehicles.errors import GeometryError

__all__ = ["CRACK_M", "CapStyle", "DESIGNED_TOLERANCE_M", "Job", "MIN_HOLE_M2", "PAIRWISE_MAX",
           "SEAL_M", "attach_areas", "build_areas", "close_cracks", "covering_paved",
           "designed_line", "junction_polygons", "lane_polygons", "make_job", "run_job"]

#: The polygons ``roadway`` and ``paved`` are made of are grown by this much (metres), so
#: that they overlap where they would touch: a union of touching polygons can keep hairline
#: cracks, and a point of the boundary then lies inside the area.
SEAL_M = 1e-3

#: Holes in ``roadway`` and ``paved`` smaller than this (m²) are gaps between lane pieces,
#: not islands, and are filled (a traffic island is several square metres).
MIN_HOLE_M2 = 1.0

#: Gaps in the paved area narrower than twice this (m) are closed (:func:`close_cracks`).
#: SUMO offsets each edge's lanes from the edge's own centre line, so the lanes of a
#: street's two directions, drawn from two slightly different lines, part along a wedge a
#: few centimetres wide (bs3d, bologna: up to about 0.15 m); a real separation between
#: pavements (a raised median, a verge) is drawn as a gap of a metre or more.
CRACK_M = 0.1

#: The ends of a lane polygon (shapely's cap styles).
CapStyle = Literal["round", "flat", "square"]


def lane_polygons(
    net: Network, lane_ids: Sequence[str], cap_style: CapStyle = "flat", grow_m: float = 0.0
) -> np.ndarray:
    """Polygons of lanes: each shape buffered by half its width (vectorised).

    ``grow_m`` widens every lane by that much on each side. With ``cap_style="round"``
    the ends are half discs: where two lanes meet at an angle,
    the wedge that flat ends leave open on the outside of the bend is covered (the areas
    use this; it also reaches half a lane width past a dead end).

    Examples
    --------
    >>> from clearance.networks.reader import Lane, Network, Location
    >>> lane = Lane("e_0", "e", 0, 3.0, "normal", frozenset(), np.array([[0, 0, 0], [10, 0, 0.0]]),
    ...             10.0, 13.9)
    >>> net = Network(None, {"e_0": lane}, {}, [], {}, [], Location())
    >>> round(lane_polygons(net, ["e_0"])[0].area, 6)
    30.0
    >>> round(lane_polygons(net, ["e_0"], "round")[0].area, 1)  # + a disc of r 1.5 (16-gon)
    36.9
    """
    return _lane_polygons(*_lane_arrays(net, lane_ids, grow_m), cap_style)


def _lane_arrays(
    net: Network, lane_ids: Sequence[str], grow_m: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lanes' shapes (x, y; lane after lane), point counts and buffer radii (half the
    width plus ``grow_m``)."""
    lanes = [net.lanes[k] for k in lane_ids]
    counts = np.fromiter((len(lane.shape) for lane in lanes), dtype=np.intp, count=len(lanes))
    points = np.vstack([lane.shape for lane in lanes])[:, :2] if lanes else np.empty((0, 2))
    radius = np.fromiter((lane.width_m for lane in lanes), float, len(lanes)) / 2.0 + grow_m
    return points, counts, radius


def _lane_polygons(
    points: np.ndarray, counts: np.ndarray, radius: np.ndarray, cap_style: CapStyle
) -> np.ndarray:
    """:func:`lane_polygons` of lanes given as points (lane after lane), point counts and
    buffer radii."""
    out = np.empty(len(counts), dtype=object)
    if not len(counts):
        return out
    lines = shapely.linestrings(points, indices=np.repeat(np.arange(len(counts)), counts))
    out[:] = shapely.buffer(lines, radius, cap_style=cap_style, join_style="round",
                            quad_segs=4)
    return out


def _own_arrays(curves: Sequence[AreaCurve]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The curves' centre lines (x, y; curve after curve), point counts and half widths."""
    if not curves:
        return np.empty((0, 2)), np.empty(0, dtype=np.intp), np.empty(0)
    lines = [designed_line(c.centerline, c.curve_id) for c in curves]
    counts = np.fromiter((len(x) for x in lines), np.intp, len(curves))
    points = np.vstack(lines)
    half = np.fromiter((c.lane_width_m for c in curves), float, len(curves)) / 2.0
    return points, counts, half


#: The designed line is simplified to within this (m) before it is buffered.
DESIGNED_TOLERANCE_M = 0.005


def designed_line(centerline: np.ndarray, name: str = "centre line") -> np.ndarray:
    """The designed lane's centre line: SUMO's vertices smoothed as the vehicle follows them.

    The own lanes are this line buffered by half the lane width, so that they are built
    from the same smoothed line the vehicle's steering point follows
    (:func:`clearance.analysis.polyline.prepare_path` with ``smooth=True``): SUMO's chords and the
    kinks where its lanes meet are drawing artefacts, not the design. Simplified to
    within :data:`DESIGNED_TOLERANCE_M`. A line that cannot be smoothed (it turns back on
    itself) is returned as it is, ``(N, 2)``.

    Examples
    --------
    A right angle drawn as one corner is rounded off (the line passes inside the corner);
    a straight line stays straight:

    >>> line = designed_line(np.array([[0.0, 0.0, 0.0], [20.0, 0.0, 0.0], [20.0, 20.0, 0.0]]))
    >>> corner = shapely.Point(20.0, 0.0)
    >>> bool(shapely.LineString(line).distance(corner) > 0.05)
    True
    >>> straight = designed_line(np.array([[0.0, 0.0], [10.0, 0.0]]))
    >>> np.round(straight, 9).tolist() == [[0, 0], [10, 0]]
    True
    """
    pts = np.asarray(centerline, dtype=float)[:, :2]
    try:
        xy = prepare_path(pts, DEFAULT_SPACING_M, name=name, smooth=True).xy
    except GeometryError:
        return pts
    simple = shapely.simplify(shapely.LineString(xy), DESIGNED_TOLERANCE_M)
    return shapely.get_coordinates(simple)


def _own_polygons(points: np.ndarray, counts: np.ndarray, half: np.ndarray) -> np.ndarray:
    if not len(counts):
        return np.empty(0, dtype=object)
    lines = shapely.linestrings(points, indices=np.repeat(np.arange(len(counts)), counts))
    return shapely.buffer(lines, half, cap_style="flat", join_style="round", quad_segs=4)


def _union_rows(
    groups: list[list[int]], geoms: np.ndarray, seal: bool = True, pairwise_max: int = 3
) -> np.ndarray:
    """Union each group of entries, in the group's order (one call per group size).

    Groups of up to ``pairwise_max`` entries are unioned pairwise from the first entry on
    (faster than the cascaded union when the entries overlap little), larger ones with
    ``union_all``. With ``seal``, the results are cleared of small holes.

    Examples
    --------
    >>> g = np.array([shapely.box(0, 0, 2, 1), shapely.box(1, 0, 3, 1), shapely.box(5, 0, 6, 1)])
    >>> [float(a.area) for a in _union_rows([[0, 1], [0, 1, 2], [2]], g)]
    [3.0, 4.0, 1.0]
    >>> [float(a.area) for a in _union_rows([[0, 1, 2], [0, 1, 0], [1, 2, 0]], g)]  # 0 + 1 once
    [4.0, 3.0, 4.0]
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
        index = np.array([groups[g] for g in rows], dtype=np.intp)
        if size > pairwise_max:
            out[rows] = _union_all_rows(geoms[index])
            continue
        # rows that start with the same two entries (the two edges of a street, for a
        # U-turn at either end) share their first union
        pairs, first = np.unique(index[:, :2], axis=0, return_inverse=True)
        if size > 2 and len(pairs) < len(index):
            start = shapely.union(geoms[pairs[:, 0]], geoms[pairs[:, 1]])
            table = np.column_stack((start[first.ravel()], geoms[index[:, 2:]]))
        else:
            table = geoms[index]
        out[rows] = _pairwise_rows(table)
    return _seal(out) if seal else out


def _seal(areas: np.ndarray) -> np.ndarray:
    """Clear areas of holes smaller than :data:`MIN_HOLE_M2` (in place; returned)."""
    parts = shapely.get_parts(areas, return_index=True)
    holed = np.unique(parts[1][shapely.get_num_interior_rings(parts[0]) > 0])
    for i in holed:
        areas[i] = _fill_small_holes(areas[i])
    return areas


def _union_all_rows(table: np.ndarray) -> np.ndarray:
    # a 2-d table with an axis gives an array, one union per row
    return cast("np.ndarray", shapely.union_all(table, axis=1))


def _pairwise_rows(table: np.ndarray) -> np.ndarray:
    acc = table[:, 0]
    for col in range(1, table.shape[1]):
        acc = shapely.union(acc, table[:, col])
    return acc


def _fill_small_holes(geom, min_hole_m2: float | None = None):
    """The geometry without holes smaller than ``min_hole_m2`` (gaps between lane pieces).

    Examples
    --------
    >>> ring = shapely.box(0, 0, 10, 10).difference(shapely.box(4, 4, 4.5, 4.5))
    >>> _fill_small_holes(ring).area
    100.0
    >>> _fill_small_holes(shapely.box(0, 0, 10, 10).difference(shapely.box(2, 2, 8, 8))).area
    64.0

    A union can leave a zero-length line beside its polygons (GEOS did, on tavf_hamburg);
    an area has none, so lines and points are dropped:

    >>> odd = shapely.GeometryCollection([shapely.box(0, 0, 1, 1),
    ...                                   shapely.LineString([(5, 5), (5, 5 + 1e-13)])])
    >>> _fill_small_holes(odd).wkt
    'POLYGON ((1 0, 1 1, 0 1, 0 0, 1 0))'
    """
    limit = MIN_HOLE_M2 if min_hole_m2 is None else min_hole_m2
    parts = []
    changed = False
    for poly in shapely.get_parts(geom):
        if not isinstance(poly, shapely.Polygon):  # a sliver line or point of a union
            changed = True
            continue
        holes = [r for r in poly.interiors if shapely.Polygon(r).area >= limit]
        if len(holes) != len(poly.interiors):
            changed = True
            poly = shapely.Polygon(poly.exterior, holes)
        parts.append(poly)
    if not changed:
        return geom
    if not parts:
        return shapely.Polygon()
    return parts[0] if len(parts) == 1 else shapely.MultiPolygon(parts)


def junction_polygons(net: Network, junction_ids: Sequence[str]) -> np.ndarray:
    """Junction polygons (made valid) grown by :data:`SEAL_M`; None where a junction has
    fewer than three shape points.

    Examples
    --------
    >>> from clearance.networks.reader import Junction, Location
    >>> sq = np.array([[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0.0]])
    >>> j = Junction("J", "priority", 2.0, 2.0, 0.0, sq, (), ())
    >>> net = Network(None, {}, {}, [], {"J": j}, [], Location())
    >>> round(float(junction_polygons(net, ["J"])[0].area), 3)  # (4 + 2 mm)^2
    16.016
    """
    return _junction_polygons(*_junction_arrays(net, junction_ids))


def _junction_arrays(net: Network, junction_ids: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """The junctions' shapes (x, y; junction after junction) and point counts."""
    shapes = [net.junctions[j].shape for j in junction_ids]
    counts = np.fromiter(map(len, shapes), dtype=np.intp, count=len(shapes))
    points = np.vstack(shapes)[:, :2] if shapes else np.empty((0, 2))
    return points, counts


def _junction_polygons(points: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """:func:`junction_polygons` of shapes given as points (junction after junction) and
    point counts."""
    out = np.empty(len(counts), dtype=object)
    some = np.flatnonzero(counts >= 3)
    if not len(some):
        return out
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    take = np.repeat(counts >= 3, counts)
    try:  # all rings at once (each closed as shapely.Polygon closes it)
        rings = shapely.linearrings(points[take], indices=np.repeat(np.arange(len(some)),
                                                                    counts[some]))
        out[some] = shapely.polygons(rings)
    except (ValueError, shapely.errors.GEOSException):  # a ring of fewer than three distinct points
        out[some] = [shapely.Polygon(points[first[i] : first[i] + counts[i]]) for i in some]
    out[some] = shapely.buffer(shapely.make_valid(out[some]), SEAL_M, quad_segs=1,
                               join_style="mitre")
    return out


def build_areas(index: AreaIndex, curves: Sequence[AreaCurve]
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ``own_lanes``, ``roadway`` and ``paved`` areas of some curves (one array each).

    Curves with the same roadway members share one object, and so do those with the same
    paved members (one paved area per junction, one roadway per movement). The lanes,
    junction polygons and pieces are made for this call only; the areas are the same
    whichever batch builds them.
    """
    if not curves:
        empty = np.empty(0, dtype=object)
        return empty, empty, empty
    with gc_paused():
        plan = BatchPlan(index)
        of = np.array([plan.add(c) for c in curves], dtype=np.intp)
        own, roadway, paved = run_job(make_job(plan, curves))
        return covering_paved(own, roadway[of[:, 0]], paved[of[:, 1]])


def covering_paved(
    own: np.ndarray, roadway: np.ndarray, paved: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The areas with each paved area grown to cover its curve's roadway and own lanes.

    The paved area must hold every lane the run drives on, lead-in and run-out included
    (docs/design.md §6): a junction's paved area holds its polygon and the lanes of its edges,
    and a run's approach and exit reach beyond them. Each distinct (roadway, paved) pair is
    unioned once (the curves of one movement share it); a curve whose own lanes (the
    designed lane, :func:`designed_line`) still stick out gets a paved area of its own.

    Examples
    --------
    >>> own = np.array([shapely.box(0, 0, 10, 1)], dtype=object)
    >>> road = np.array([shapely.box(0, 0, 5, 1)], dtype=object)
    >>> paved = np.array([shapely.box(0, 0, 4, 4)], dtype=object)
    >>> _, _, p = covering_paved(own, road, paved)
    >>> float(p[0].area), bool(p[0].covers(own[0]))
    (22.0, True)
    """
    out = np.empty(len(paved), dtype=object)
    pairs: dict[tuple[int, int], list[int]] = {}
    for i, (r, p) in enumerate(zip(roadway, paved, strict=True)):
        pairs.setdefault((id(r), id(p)), []).append(i)
    firsts = [ix[0] for ix in pairs.values()]
    grown = shapely.union(paved[firsts], np.where(shapely.is_missing(roadway[firsts]),
                                                  paved[firsts], roadway[firsts]))
    for g, ix in zip(grown.tolist(), pairs.values(), strict=True):
        for i in ix:
            out[i] = g
    shapely.prepare(out)
    loose = np.flatnonzero(~shapely.covers(out, own))
    if len(loose):
        out[loose] = _fill_small_holes_each(shapely.union(out[loose], own[loose]))
    return own, roadway, out


def _fill_small_holes_each(geoms: np.ndarray) -> np.ndarray:
    return np.array([_fill_small_holes(g) for g in geoms.tolist()], dtype=object)


def attach_areas(net: Network, curves: Sequence[AreaCurve]) -> None:
    """Build ``own_lanes``, ``roadway`` and ``paved`` of every curve now and keep them on
    the curves (in place; :func:`clearance.networks.curves.extract_curves` builds them on demand
    instead, see :class:`clearance.networks.area_book.AreaBook`).

    Unions are built in two levels: pieces first (an edge's road lanes, an edge's lanes,
    the internal road lanes of one movement ``a -> b``), then each roadway from its
    pieces and each junction's paved area from its polygon and pieces. Curves share the
    results: one paved area per junction, one roadway per movement.
    """
    own, roadway, paved = build_areas(AreaIndex(net), curves)
    for curve, o, r, p in zip(curves, own, roadway, paved, strict=True):
        curve.set_areas(o, r, p)


class Job(NamedTuple):
    """What a run of curves' areas are made from, as plain arrays and index rows (no
    network, no curves): made by :func:`make_job` and built by :func:`run_job`.

    Rows index *members*: the lanes (0 ..), then the junctions, then the pieces.
    """

    lane_points: np.ndarray  # (n, 2): the shapes of the lanes, lane after lane
    lane_counts: np.ndarray  # points per lane
    lane_radius: np.ndarray  # half width + SEAL_M
    junction_points: np.ndarray  # (m, 2): the junction shapes
    junction_counts: np.ndarray  # points per junction (under three: no polygon)
    pieces: list[list[int]]  # the lanes of each piece
    road_rows: list[list[int]]  # the members of each roadway group
    paved_base: list[list[int]]  # the members of each paved group but its internal lanes
    paved_inner: list[list[int]]  # its internal lanes (lanes not already in the base)
    own_points: np.ndarray  # (k, 2): the centre lines of the curves
    own_counts: np.ndarray  # points per centre line
    own_half: np.ndarray  # half lane width of each curve


def make_job(plan: BatchPlan, curves: Sequence[AreaCurve]) -> Job:
    """The :class:`Job` of a plan's groups and of the curves' own lanes (Python only)."""
    lane_at: dict[str, int] = {}
    for lanes in plan.pieces.values():
        for k in lanes:
            lane_at.setdefault(k, len(lane_at))
    junction_ids: dict[str, int] = {}
    for members in (*plan.road_groups, *plan.paved_groups):
        if not members or members[0][0] not in "LJ":
            continue  # its members are pieces only (lanes and junctions sort first)
        for m in members:
            if m[0] == "L":
                lane_at.setdefault(m[2:], len(lane_at))
            elif m[0] == "J":
                junction_ids.setdefault(m[2:], len(junction_ids))
    # pieces with the same lanes (an edge's lanes that are all road lanes) share one union
    n_base = len(lane_at) + len(junction_ids)
    rows_of: dict[tuple[int, ...], int] = {}
    piece_at = {}
    for key, piece in plan.pieces.items():
        row = tuple(lane_at[k] for k in piece)
        piece_at[key] = n_base + rows_of.setdefault(row, len(rows_of))
    n_lanes = len(lane_at)

    def at(member: str) -> int:
        kind = member[0]
        if kind == "L":
            return lane_at[member[2:]]
        if kind == "J":
            return n_lanes + junction_ids[member[2:]]
        return piece_at[member]

    # a paved area: the union of its plain lanes, edges and junction polygon first, then
    # of that with the internal lanes it does not already cover (most lie inside the
    # junction polygon: leaving them out is the same union, much cheaper)
    base_rows: list[list[int]] = []
    inner_rows: list[list[int]] = []
    for members in plan.paved_groups:
        base: list[int] = []
        inner: set[str] = set()
        for m in members:
            if m[0] == "M":
                inner.update(plan.pieces[m])
            elif m.startswith("L::"):
                inner.add(m[2:])
            else:
                base.append(at(m))
        in_base = set(base)
        base_rows.append(base)
        inner_rows.append([i for i in (lane_at[k] for k in sorted(inner)) if i not in in_base])
    return Job(
        *_lane_arrays(plan.net, list(lane_at), SEAL_M),
        *_junction_arrays(plan.net, list(junction_ids)),
        [list(r) for r in rows_of],
        [list(map(piece_at.__getitem__, g)) if g and g[0][0] not in "LJ" else [at(m) for m in g]
         for g in plan.road_groups],
        base_rows, inner_rows, *_own_arrays(curves),
    )


def run_job(job: Job) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The geometry of a :class:`Job`: the curves' own lanes, then every roadway group's
    area and every paved group's area (GEOS only, through vectorised shapely calls).

    Examples
    --------
    >>> from clearance.networks.area_groups import AreaCurve, AreaIndex
    >>> from clearance.networks.curves import extract_curves
    >>> from clearance.networks.reader import read_network
    >>> net = read_network("networks/samples/intersection/intersection.net.xml")
    >>> curves = extract_curves(net, areas=False)
    >>> plan = BatchPlan(AreaIndex(net))
    >>> groups = [plan.add(c) for c in curves]
    >>> own, roadway, paved = run_job(make_job(plan, curves))
    >>> len(own) == len(curves), len(roadway) == len(plan.road_groups), len(paved)
    (True, True, 2)
    """
    own = _own_polygons(job.own_points, job.own_counts, job.own_half)
    geoms = np.concatenate((
        _lane_polygons(job.lane_points, job.lane_counts, job.lane_radius, "round"),
        _junction_polygons(job.junction_points, job.junction_counts),
    ))
    all_geoms = np.concatenate((geoms, _union_rows(job.pieces, geoms, seal=False)))
    roadway = _union_rows(job.road_rows, all_geoms)
    first = _union_rows(job.paved_base, all_geoms, seal=False, pairwise_max=PAIRWISE_MAX)
    shapely.prepare(first)
    inner_rows = job.paved_inner
    row_of = np.repeat(np.arange(len(inner_rows)), [len(r) for r in inner_rows])
    inner = np.array([i for r in inner_rows for i in r], dtype=np.intp)
    covered = shapely.covers(first[row_of], geoms[inner])
    shapely.destroy_prepared(first)
    rest: list[list[int]] = [[] for _ in range(len(first))]
    for g, i in zip(row_of[~covered].tolist(), inner[~covered].tolist(), strict=True):
        rest[g].append(i)
    # the lanes that stick out are unioned together first, then with the rest
    paved = first.copy()
    some = np.flatnonzero([len(r) > 0 for r in rest])
    if len(some):
        lanes = _union_rows([rest[g] for g in some], geoms, seal=False)
        paved[some] = shapely.union(first[some], lanes)
    return own, roadway, _seal(close_cracks(paved))


def close_cracks(areas: np.ndarray, crack_m: float = CRACK_M) -> np.ndarray:
    """The areas with every gap narrower than ``2 crack_m`` filled (a closing, in place).

    Each area is grown by ``crack_m`` and shrunk back with mitred joins, which leaves its
    corners, concave ones included, where they were (a round closing would fillet them):
    only where the grown outline met itself, across a crack, does the result differ.
    Joined to the original area, so that a spike the mitre limit bevels is kept.

    Examples
    --------
    Two lanes 3 m wide parting along a wedge that opens to 0.15 m over 20 m: closed, and
    the outer corners unmoved (the area gains only the crack):

    >>> a = shapely.Polygon([(0, 0), (20, 0), (20, 3), (0, 3)])
    >>> b = shapely.Polygon([(0, 3), (20, 3.15), (20, 6.15), (0, 6)])
    >>> two = shapely.union(a, b)
    >>> closed = close_cracks(np.array([two], dtype=object))[0]
    >>> closed.geom_type, round(float(closed.area - two.area), 3), closed.bounds
    ('Polygon', 1.5, (0.0, 0.0, 20.0, 6.15))

    A concave corner (an L of two 3 m lanes) keeps its corner; an empty area stays empty:

    >>> ell = shapely.Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)])
    >>> float(close_cracks(np.array([ell], dtype=object))[0].area)
    51.0
    >>> close_cracks(np.array([shapely.Polygon()], dtype=object))[0].is_empty
    True
    """
    if not len(areas):
        return areas
    grown = shapely.buffer(areas, crack_m, join_style="mitre", mitre_limit=10.0)
    closed = shapely.buffer(grown, -crack_m, join_style="mitre", mitre_limit=10.0)
    areas[:] = shapely.union(areas, closed)
    return areas


#: Paved areas of up to this many pieces and polygons are unioned pairwise (see
#: :func:`_union_rows`; a junction of four two-way edges has nine).
PAIRWISE_MAX = 16
