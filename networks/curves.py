"""Curves of a SUMO network: junction turns, roundabouts, ramps and tight bends.

A :class:`Curve` is a path a vehicle drives through one feature (docs/design.md §6). Its centre
line runs from ``approach_length_m`` before the feature to as far after it (where the
network has that much lane), so the longest vehicle is straight before it starts turning.

Kinds and how they are found:

``turn``
    One per connection through a junction that has internal lanes (approach lane →
    internal lanes → exit lane), for lanes that admit passenger cars, buses or trucks.
    Connections at the nodes of a ``<roundabout>`` are left to the ``roundabout`` curves.
``uturn``
    The same for netconvert's automatic turnarounds (connection ``dir="t"``, at dead
    ends and on divided roads) and for every other connection that turns back alongside
    its approach (:func:`clearance.networks.geometry.turns_back`: onto the other carriageway, round
    a turning loop): a kind of their own, left out unless asked for (:data:`DEFAULT_KINDS`).
    A network built without internal lanes (``--no-internal-links``) has no junction
    geometry to check: no turns are extracted and a warning says so.
``roundabout``
    From the network's ``<roundabout>`` elements: one per entry edge → exit edge through
    the ring (the shortest lane path; a U-turn round the ring is included).
``ramp``
    A chain of plain edges joined one-to-one (no other way in or out) whose grade exceeds
    ``ramp_min_grade_pct`` on each edge, that turns more than ``ramp_min_turn_deg`` in all
    and is tighter than ``bend_max_radius_m`` somewhere: a parking helix, a spiral ramp.
``bend``
    A stretch of a plain lane (not part of a ramp or a roundabout ring) whose radius stays under
    ``bend_max_radius_m`` while it turns at least ``bend_min_turn_deg``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from itertools import islice
from operator import itemgetter
from typing import TYPE_CHECKING

import numpy as np
from shapely.geometry.base import BaseGeometry

from clearance.analysis.levels import Level
from clearance.networks.collector import gc_paused
from clearance.networks.elevation import suspect_notes
from clearance.networks.geometry import (
    arc_length,
    clean_polyline,
    curvature_profile,
    grades_pct,
    radius_from_curvature,
    turns_back,
    unwrap,
)
from clearance.networks.model import ROAD_VCLASSES, Network
from clearance.networks.paths import (
    PathPlan,
    junction_of_internal,
    plan_path,
    realise,
    steady_lead_ins,
    steady_run_outs,
    via_lanes,
)
from clearance.networks.profiles import Stations, profiles
from clearance.vehicles.errors import OptionError

if TYPE_CHECKING:
    from clearance.networks.area_book import AreaBook

__all__ = ["Curve", "CurveOptions", "DEFAULT_KINDS", "Item", "KINDS", "MEASURE_BATCH",
           "extract_curves", "find_bends", "find_ramps", "find_roundabouts", "find_turns",
           "make_curve", "measure"]

log = logging.getLogger(__name__)

KINDS = ("turn", "uturn", "roundabout", "ramp", "bend")
"""Every kind of curve, in the order curves are sorted."""

DEFAULT_KINDS = ("turn", "roundabout", "ramp", "bend")
"""The kinds a study checks unless asked otherwise: netconvert's automatic U-turns left out."""


@dataclass(eq=False, slots=True)
class Curve:
    """A path through one feature of a network, with its geometry and areas.

    Attributes
    ----------
    curve_id
        Stable id, e.g. ``turn:J0:E1_0->E3_0``, ``uturn:J0:E1_0->-E1_0``,
        ``roundabout:R2:in_0->out_0``,
        ``ramp:H0_0->H3_0``, ``bend:E7_1:0``.
    kind
        ``turn``, ``uturn``, ``roundabout``, ``ramp`` or ``bend``.
    junction
        The junction of the feature (a turn's junction, the ring node entered, the junction
        a ramp starts from, a bend's edge's start junction).
    lanes
        Every lane the centre line runs on, in driving order.
    core_lanes
        The lanes of the feature itself (internal lanes of a turn, ring and its internal
        lanes, ramp edges' lanes, the bent lane).
    centerline
        (N, 3) x, y, z in metres (SUMO plane coordinates).
    core_start_m, core_end_m
        Where the feature begins and ends along the centre line (plane arc length).
    stations, profile_s_m, profile_radius_m
        Radius fitted over arc length at stations every ``step_m`` over the feature and a
        fitting window either side (``inf`` where straight). ``profile_s_m`` (a property:
        an array made from the four numbers of ``stations`` when asked) is measured along
        ``centerline``.
    min_radius_m
        Smallest radius over the feature (the CSV's ``min_radius``).
    turn_angle_deg
        Signed heading change from the approach to the exit (degrees, left positive,
        unwrapped: a loop round a roundabout may exceed 180). Use its absolute value for
        a size.
    length_m
        Arc length of the feature, ``core_end_m - core_start_m``.
    lane_width_m
        The narrowest lane of the feature.
    max_grade_pct, max_grade_change_pct
        Largest grade and largest algebraic change of grade over the feature and 3 m
        either side (see :func:`clearance.networks.geometry.grades_pct`), without suspect heights.
    suspect_elevation
        Lone heights of the curve's lanes far off their neighbours', named by lane and
        point (:mod:`clearance.networks.elevation`): repaired in the network on reading, so left out
        of the centre line's z, the grade, the vertical checks and the levels; ``""`` when
        there are none.
    own_lanes, roadway, paved
        Shapely areas (properties): the curve's lanes (its centre line buffered by half
        the lane width), the same-direction roadway, the paved area (see
        :mod:`clearance.networks.areas`). ``None`` when areas were not requested. Curves from
        :func:`extract_curves` build them on first use, a batch of curves at a time, and
        release them again (see :mod:`clearance.networks.area_book`).
    area_book, area_batch
        The :class:`~clearance.networks.area_book.AreaBook` that builds the areas, and the curve's
        batch in it (None and -1 when the areas are set for good or not requested).
    """

    curve_id: str
    kind: str
    junction: str
    lanes: tuple[str, ...]
    core_lanes: tuple[str, ...]
    centerline: np.ndarray
    core_start_m: float
    core_end_m: float
    stations: Stations
    profile_radius_m: np.ndarray
    min_radius_m: float
    turn_angle_deg: float
    length_m: float
    lane_width_m: float
    max_grade_pct: float
    max_grade_change_pct: float
    suspect_elevation: str = ""
    area_book: AreaBook | None = field(default=None, init=False, repr=False)
    area_batch: int = field(default=-1, init=False, repr=False)
    _own: BaseGeometry | None = field(default=None, init=False, repr=False)
    _roadway: BaseGeometry | None = field(default=None, init=False, repr=False)
    _paved: BaseGeometry | None = field(default=None, init=False, repr=False)
    _levels: tuple[Level, ...] | None = field(default=None, init=False, repr=False)

    @property
    def profile_s_m(self) -> np.ndarray:
        """Arc length of each station of the radius profile (made from :attr:`stations`)."""
        return self.stations.array()

    @property
    def own_lanes(self) -> BaseGeometry | None:
        """The curve's lanes: its centre line buffered by half the lane width."""
        if self._own is None and self.area_book is not None:
            self.area_book.load(self.area_batch)
        return self._own

    @property
    def roadway(self) -> BaseGeometry | None:
        """The same-direction roadway (see :mod:`clearance.networks.areas`)."""
        if self._roadway is None and self.area_book is not None:
            self.area_book.load(self.area_batch)
        return self._roadway

    @property
    def paved(self) -> BaseGeometry | None:
        """The paved area (see :mod:`clearance.networks.areas`)."""
        if self._paved is None and self.area_book is not None:
            self.area_book.load(self.area_batch)
        return self._paved

    @property
    def levels(self) -> tuple[Level, ...]:
        """The curve's level segments with their storeys' areas (docs/design.md §6,
        "Levels"; :func:`clearance.networks.area_book.curve_levels`): none on a flat network."""
        if self._levels is None:
            self._levels = self.area_book.levels(self) if self.area_book is not None else ()
        return self._levels

    def set_areas(
        self,
        own_lanes: BaseGeometry | None,
        roadway: BaseGeometry | None,
        paved: BaseGeometry | None,
        book: AreaBook | None = None,
        levels: tuple[Level, ...] | None = None,
    ) -> None:
        """Give the curve its three areas. Without ``book`` they are the curve's for good;
        with it, they are that book's to release (and to build again when asked).
        ``levels`` (its level segments) are kept likewise; None: found again when asked."""
        self._own, self._roadway, self._paved = own_lanes, roadway, paved
        self._levels = levels
        self.area_book = book


@dataclass(frozen=True)
class CurveOptions:
    """Parameters of curve extraction (lengths in metres, angles in degrees)."""

    approach_length_m: float = 25.0
    step_m: float = 0.25
    window_m: float = 3.0
    grade_window_m: float = 3.0
    bend_max_radius_m: float = 50.0
    bend_min_turn_deg: float = 20.0
    ramp_min_grade_pct: float = 2.0
    ramp_min_turn_deg: float = 90.0


#: A curve found but not measured yet: id, kind, junction, planned path.
Item = tuple[str, str, str, PathPlan]


#: Paths measured per batch (bounds the memory of the temporary arrays).
MEASURE_BATCH = 4096


def measure(
    net: Network,
    items: Iterable[Item],
    opts: CurveOptions,
    each: Callable[[list[Curve]], None] | None = None,
) -> list[Curve]:
    """Measure paths in batches: radius profile, turn angle, grades, width of the core.

    ``items`` are taken :data:`MEASURE_BATCH` at a time as they come; ``each`` is given
    the curves measured so far after every batch."""
    out: list[Curve] = []
    pending = iter(items)
    while batch := list(islice(pending, MEASURE_BATCH)):
        out.extend(_measure(net, batch, opts))
        if each is not None:
            each(out)
    return out


def _measure(
    net: Network, items: Sequence[Item], opts: CurveOptions
) -> list[Curve]:
    if not items:
        return []
    paths = steady_run_outs(steady_lead_ins(realise(net, [it[3] for it in items]), opts.step_m,
                                            opts.window_m), opts.step_m, opts.window_m)
    prof = profiles(
        [p.centerline for p in paths],
        [p.core_start_m for p in paths],
        [p.core_end_m for p in paths],
        opts.step_m,
        opts.window_m,
    )
    curves = []
    w = opts.grade_window_m
    sloped = _sloped([p.centerline for p in paths])
    lanes = net.lanes
    for n, ((cid, kind, junction, _), path, min_r, turn, slope) in enumerate(zip(
        items, paths, prof.min_radius_m.tolist(), prof.turn_deg.tolist(), sloped, strict=True
    )):
        # lone heights were repaired on reading (clearance.networks.elevation)
        line = path.centerline
        suspect = suspect_notes(net, path.lanes) if net.suspect_heights else ""
        a, b = path.core_start_m, path.core_end_m
        g, dg = grades_pct(line, a - w, b + w, w) if slope else (0.0, 0.0)
        width = float(min(lanes[x].width_m for x in (path.core_lanes or path.lanes)))
        curves.append(Curve(
            cid, kind, junction, path.lanes, path.core_lanes, line, a, b, prof.stations[n],
            prof.radius_m[n], min_r, turn, b - a, width, g, dg, suspect_elevation=suspect,
        ))
    return curves


def _sloped(lines: Sequence[np.ndarray]) -> list[bool]:
    """For each line, whether its z varies (vectorised over the lines).

    Examples
    --------
    >>> _sloped([np.zeros((2, 3)), np.array([[0, 0, 0], [1, 0, 0.5]])])
    [False, True]
    """
    z = np.concatenate([x[:, 2] for x in lines])
    counts = np.fromiter(map(len, lines), dtype=np.int64, count=len(lines))
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    return (np.minimum.reduceat(z, first) != np.maximum.reduceat(z, first)).tolist()


def make_curve(
    net: Network, curve_id: str, kind: str, junction: str, path: PathPlan, opts: CurveOptions
) -> Curve:
    """Measure one path (see :func:`measure`)."""
    return measure(net, [(curve_id, kind, junction, path)], opts)[0]


def _road_lane(net: Network, lane_id: str) -> bool:
    lane = net.lanes.get(lane_id)
    return lane is not None and lane.allows_road_vehicles()


def find_turns(
    net: Network, opts: CurveOptions, uturns: bool = False
) -> Iterable[Item]:
    """Yield one ``turn`` per connection through a junction's internal lanes; with
    ``uturns``, one ``uturn`` per U-turn (``dir="t"`` or :func:`turns_back`) instead."""
    kind = "uturn" if uturns else "turn"
    if not net.has_internal_lanes:
        if uturns or not net.connections:  # nothing to warn of on a network without any
            return
        log.warning(
            "%s: built without internal lanes (--no-internal-links): junction turns have no "
            "geometry and are not extracted; rebuild the network with internal links",
            net.path,
        )
        return
    ring_nodes = {n for r in net.roundabouts for n in r.nodes}
    lanes = net.lanes
    approach = opts.approach_length_m
    junction_ids: dict[str, str] = {}  # one string per junction, shared by its turns
    named = []  # every candidate with its id first, to be planned in id order
    for conn in net.connections:
        from_edge, to_edge, from_index, to_index, via, _ = conn
        if not via or from_edge.startswith(":"):
            continue
        junction = junction_of_internal(via)  # (the first of its via lanes)
        if junction in ring_nodes:
            continue
        from_lane, to_lane = f"{from_edge}_{from_index}", f"{to_edge}_{to_index}"
        back = conn.direction == "t" or (
            from_lane in lanes and to_lane in lanes
            and turns_back(lanes[from_lane].shape, lanes[to_lane].shape))
        if back != uturns:
            continue
        junction = junction_ids.setdefault(junction, junction)
        named.append((f"{kind}:{junction}:{from_lane}->{to_lane}", junction, from_lane,
                      to_lane, conn))
    named.sort(key=itemgetter(0))
    for curve_id, junction, from_lane, to_lane, conn in named:
        a, b = lanes.get(from_lane), lanes.get(to_lane)
        if a is None or b is None or a.function == "internal":
            continue
        if a.allowed.isdisjoint(ROAD_VCLASSES) or b.allowed.isdisjoint(ROAD_VCLASSES):
            continue
        vias = via_lanes(net, conn)
        if not vias:
            continue
        path = plan_path(net, [from_lane], vias, [to_lane], approach, approach)
        yield (curve_id, kind, junction, path)


def find_roundabouts(
    net: Network, opts: CurveOptions
) -> Iterable[Item]:
    """Yield one ``roundabout`` curve per entry edge → exit edge of each ring."""
    import heapq

    from clearance.networks.paths import lane_length

    for rb in net.roundabouts:
        ring_edges = set(rb.edges)
        ring_nodes = set(rb.nodes)
        best: dict[tuple[str, str], tuple[float, list[str], str]] = {}
        for conn in net.connections:
            if (
                conn.to_edge not in ring_edges
                or conn.from_edge in ring_edges
                or conn.from_edge.startswith(":")
                or not _road_lane(net, conn.from_lane)
                or conn.from_lane not in net.lanes
            ):
                continue
            from_edge = net.edges.get(conn.from_edge)
            entry_node = from_edge.to_junction if from_edge is not None else ""
            if entry_node not in ring_nodes:
                continue
            # Dijkstra over lanes from the entry lane, through ring lanes only
            start = [*(via_lanes(net, conn) or []), conn.to_lane]
            heap = [(sum(lane_length(net, x) for x in start), 0, start)]
            done: set[str] = set()
            counter = 1
            while heap:
                dist, _, lanes = heapq.heappop(heap)
                last = lanes[-1]
                if last in done:
                    continue
                done.add(last)
                for nxt in net.outgoing(last):
                    if nxt.to_lane not in net.lanes or not _road_lane(net, nxt.to_lane):
                        continue
                    step = [*(via_lanes(net, nxt) or []), nxt.to_lane]
                    if nxt.to_edge in ring_edges:
                        if len(lanes) < 400:
                            d = dist + sum(lane_length(net, x) for x in step)
                            heapq.heappush(heap, (d, counter, lanes + step))
                            counter += 1
                        continue
                    key = (conn.from_edge, nxt.to_edge)
                    core = lanes + step[:-1]
                    if key not in best or dist < best[key][0]:
                        best[key] = (dist, [conn.from_lane, *core, nxt.to_lane], entry_node)
        for (_, _), (_, lanes, entry_node) in sorted(best.items()):
            path = plan_path(
                net,
                [lanes[0]],
                lanes[1:-1],
                [lanes[-1]],
                opts.approach_length_m,
                opts.approach_length_m,

            )
            cid = f"roundabout:{entry_node}:{lanes[0]}->{lanes[-1]}"
            yield (cid, "roundabout", entry_node, path)


def _edge_grade_pct(net: Network, edge_id: str) -> float:
    edge = net.edges[edge_id]
    shape = net.lanes[edge.lanes[0]].shape
    if shape[-1, 2] == shape[0, 2]:
        return 0.0  # level ends (as below, without measuring the length)
    s = arc_length(shape)
    if s[-1] <= 0:
        return 0.0
    return 100.0 * abs(float(shape[-1, 2] - shape[0, 2])) / float(s[-1])


def _plain_edges(net: Network) -> list[str]:
    return [
        e.id
        for e in net.edges.values()
        if e.function in ("normal", "") and e.lanes and any(_road_lane(net, x) for x in e.lanes)
    ]


def find_ramps(net: Network, opts: CurveOptions) -> tuple[list[Curve], set[str]]:
    """Find ``ramp`` curves; also return the edges they cover (no bends are sought there)."""
    plain = set(_plain_edges(net))
    graded = {e for e in plain if _edge_grade_pct(net, e) > opts.ramp_min_grade_pct}
    if not graded:  # a level network (no edge steep enough to start a ramp)
        return [], set()
    succ: dict[str, set[str]] = {}
    pred: dict[str, set[str]] = {}
    for c in net.connections:
        if c.from_edge in plain and c.to_edge in plain and c.direction != "t":
            succ.setdefault(c.from_edge, set()).add(c.to_edge)
            pred.setdefault(c.to_edge, set()).add(c.from_edge)

    def link(a: str) -> str | None:
        nxt = succ.get(a, set())
        if len(nxt) == 1:
            b = next(iter(nxt))
            if b in graded and pred.get(b) == {a}:
                return b
        return None

    heads = [
        e for e in sorted(graded) if not any(p in graded and link(p) == e for p in pred.get(e, ()))
    ]
    curves: list[Curve] = []
    covered: set[str] = set()
    for head in heads:
        chain = [head]
        while (nxt := link(chain[-1])) is not None and nxt not in chain:
            chain.append(nxt)
        for lane_id in net.edges[head].lanes:
            if not _road_lane(net, lane_id):
                continue
            lanes = _follow_lanes(net, lane_id, chain)
            if lanes is None:
                continue
            path = plan_path(net, [], lanes, [], opts.approach_length_m, opts.approach_length_m)
            curve = make_curve(
                net,
                f"ramp:{lanes[0]}->{lanes[-1]}",
                "ramp",
                net.edges[head].from_junction,
                path,
                opts,
            )
            if (
                abs(curve.turn_angle_deg) > opts.ramp_min_turn_deg
                and curve.min_radius_m < opts.bend_max_radius_m
            ):
                curves.append(curve)
                covered.update(chain)
    return curves, covered


def _follow_lanes(net: Network, lane_id: str, chain: list[str]) -> list[str] | None:
    """Lanes along an edge chain from ``lane_id`` (same index where possible)."""
    lanes = [lane_id]
    cur = lane_id
    for nxt_edge in chain[1:]:
        conns = [c for c in net.outgoing(cur) if c.to_edge == nxt_edge]
        if not conns:
            return None
        idx = net.lanes[cur].index
        conn = min(conns, key=lambda c: (abs(c.to_lane_index - idx), c.to_lane_index))
        lanes.extend([*(via_lanes(net, conn) or []), conn.to_lane])
        cur = conn.to_lane
    return lanes


def find_bends(
    net: Network, opts: CurveOptions, skip_edges: set[str]
) -> Iterable[Item]:
    """Yield ``bend`` curves: tight curved stretches inside plain lanes."""
    min_turn = math.radians(opts.bend_min_turn_deg)
    ring_edges = {e for r in net.roundabouts for e in r.edges}
    for edge_id in _plain_edges(net):
        if edge_id in skip_edges or edge_id in ring_edges:
            continue
        for lane_id in net.edges[edge_id].lanes:
            lane = net.lanes[lane_id]
            if len(lane.shape) < 3 or not lane.allows_road_vehicles():
                continue
            pts = clean_polyline(lane.shape)
            if len(pts) < 3:
                continue
            d = pts[1:, :2] - pts[:-1, :2]
            turns = np.diff(unwrap(np.arctan2(d[:, 1], d[:, 0])))
            if np.abs(turns).sum() < min_turn:
                continue
            s, k = curvature_profile(pts, opts.step_m, opts.window_m)
            for n, (i, j) in enumerate(_bend_runs(s, k, opts)):
                path = plan_path(
                    net,
                    [],
                    [lane_id],
                    [],
                    opts.approach_length_m,
                    opts.approach_length_m,
                    float(s[i]),
                    float(s[j - 1]),

                )
                junction = net.edges[edge_id].from_junction
                yield (f"bend:{lane_id}:{n}", "bend", junction, path)


def _bend_runs(s: np.ndarray, k: np.ndarray, opts: CurveOptions) -> list[tuple[int, int]]:
    """Stretches of one sign of curvature that are tighter than the bend radius somewhere
    and turn at least the bend angle; each grown to where the curvature fades out."""
    tight = radius_from_curvature(k) < opts.bend_max_radius_m
    fade = 0.2 / opts.bend_max_radius_m
    out = []
    for sign in (1.0, -1.0):
        for i, j in _runs(sign * k > fade):
            if not tight[i:j].any() or j - i < 2:
                continue
            turn = float(np.trapezoid(k[i:j], s[i:j]))
            if abs(turn) >= math.radians(opts.bend_min_turn_deg):
                out.append((i, j))
    return sorted(out)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Half-open index ranges of the runs of True in a boolean array.

    Examples
    --------
    >>> _runs(np.array([0, 1, 1, 0, 1], dtype=bool))
    [(1, 3), (4, 5)]
    """
    m = np.concatenate(([False], mask, [False])).astype(np.int8)
    edges = np.flatnonzero(np.diff(m))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def extract_curves(
    net: Network,
    kinds: Iterable[str] = DEFAULT_KINDS,
    options: CurveOptions | None = None,
    areas: bool = True,
) -> list[Curve]:
    """Every curve of the requested kinds, sorted by kind then ``curve_id``.

    Parameters
    ----------
    net
        A network from :func:`clearance.networks.reader.read_network`.
    kinds
        Any of :data:`KINDS`; by default :data:`DEFAULT_KINDS` (``uturn`` left out).
    options
        Extraction parameters (approach length, fitting window, thresholds).
    areas
        Give each curve its three shapely areas (:mod:`clearance.networks.areas`). They are built
        on first use, for a batch of curves at a time, and at most a few batches are kept
        (:class:`clearance.networks.area_book.AreaBook`);
        :func:`clearance.networks.areas.attach_areas` builds
        and keeps them all at once.

    Raises
    ------
    InputError
        An unknown kind.
    """
    wanted = list(dict.fromkeys(kinds))
    bad = [k for k in wanted if k not in KINDS]
    if bad:
        raise OptionError(f"unknown curve kind(s) {', '.join(bad)}; choose from {', '.join(KINDS)}")
    opts = options or CurveOptions()
    with gc_paused():  # hundreds of thousands of objects that live on (see gc_paused)
        return _extract(net, wanted, opts, areas)


def _extract(net: Network, wanted: list[str], opts: CurveOptions, areas: bool) -> list[Curve]:
    from clearance.networks.area_book import AreaBook

    curves: list[Curve] = []
    if "turn" in wanted:
        curves.extend(measure(net, find_turns(net, opts), opts))
    if "uturn" in wanted:
        curves.extend(measure(net, find_turns(net, opts, uturns=True), opts))
    if "roundabout" in wanted:
        curves.extend(measure(net, list(find_roundabouts(net, opts)), opts))
    ramp_edges: set[str] = set()
    if "ramp" in wanted or "bend" in wanted:
        ramps, ramp_edges = find_ramps(net, opts)
        if "ramp" in wanted:
            curves.extend(ramps)
    if "bend" in wanted:
        curves.extend(measure(net, list(find_bends(net, opts, ramp_edges)), opts))
    order = {k: i for i, k in enumerate(KINDS)}
    curves.sort(key=lambda c: (order[c.kind], c.curve_id))
    if areas:  # the areas are built when first read
        AreaBook(net, curves)
    return curves
