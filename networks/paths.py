"""Lane sequences through a network and the centre lines they make.

A *path* is an ordered list of lane ids a vehicle drives: approach lanes, the core (the
lanes of the feature: a junction's internal lanes, a ring, a ramp), exit lanes. The
approach is extended back through upstream lanes when the approach lane is shorter than
wanted (preferring straight-on connections), the exit forward likewise, only through lanes
a road vehicle may drive (:func:`drivable`) and only straight on (never through a turn or
a U-turn, which are neighbouring curves).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import compress

import numpy as np

from clearance.networks.geometry import MIN_CHORD_M, cut_polyline, radius_from_curvature
from clearance.networks.model import ROAD_VCLASSES, Connection, Network
from clearance.networks.profiles import profiles

__all__ = ["EXTEND_DIRECTIONS", "LEAD_KEEP_M", "LEAD_MIN_RADIUS_M", "MAX_EXTENSION_LANES",
           "NOT_ROADS", "Path", "PathPlan", "build_path", "drivable", "extend_back",
           "extend_forward", "junction_of_internal", "lane_length", "plan_path", "realise",
           "steady_lead_ins", "steady_run_outs", "via_lanes"]

#: Preference among connection directions when a path is extended (straight on first).
_DIR_RANK = {"s": 0, "R": 1, "L": 2, "r": 3, "l": 4, "t": 6}

#: No path is extended through more lanes than this in either direction.
MAX_EXTENSION_LANES = 24


def junction_of_internal(lane_or_edge_id: str) -> str:
    """The junction an internal lane or edge (``:<junction>_<link>[_<lane>]``) belongs to.

    Examples
    --------
    >>> junction_of_internal(":J0_12_0")
    'J0'
    >>> junction_of_internal(":cluster_1_2_3_0")
    'cluster_1_2'
    >>> junction_of_internal("E1_0")  # not internal: returned as it is
    'E1_0'
    """
    if not lane_or_edge_id.startswith(":"):
        return lane_or_edge_id
    body = lane_or_edge_id[1:]
    parts = body.rsplit("_", 2)
    return parts[0] if len(parts) == 3 else body.rsplit("_", 1)[0]


def via_lanes(net: Network, conn: Connection) -> list[str] | None:
    """The internal lanes a connection goes through, in order ([] without ``via``).

    Returns None when the chain is broken (an unknown lane, a loop, a dead end).
    """
    out: list[str] = []
    via = conn.via
    to_edge = conn.to_edge
    lanes, outgoing = net.lanes, net.outgoing
    while via:
        if via in out or via not in lanes or len(out) > 8:
            return None
        out.append(via)
        outs = outgoing(via)
        if not outs:
            return None
        # the first connection on towards the connection's edge, else the first one
        nxt = next((c for c in outs if c.to_edge == to_edge), outs[0])
        via = nxt.via
    return out


#: Edge functions no vehicle drives on, whatever their lanes allow.
NOT_ROADS = frozenset(("walkingarea", "crossing"))


def drivable(net: Network, lane_id: str) -> bool:
    """Whether a road vehicle may drive a lane: it admits a passenger car, bus, truck,
    coach, delivery van or trailer (SUMO's ``allow``/``disallow``), and it is not a
    walking area or crossing. Sidewalks, rails and bicycle-only lanes are not.

    Examples
    --------
    >>> import numpy as np
    >>> from clearance.networks.reader import Lane, Location, Network
    >>> def lane(i, allowed, function="normal"):
    ...     return Lane(i, i[:-2], 0, 3.2, function, frozenset(allowed), np.zeros((2, 3)), 1.0, 9.0)
    >>> lanes = {"s_0": lane("s_0", {"pedestrian"}), "r_0": lane("r_0", {"passenger"}),
    ...          "w_0": lane("w_0", {"passenger"}, "walkingarea")}
    >>> net = Network(None, lanes, {}, [], {}, [], Location())
    >>> drivable(net, "r_0"), drivable(net, "s_0"), drivable(net, "w_0"), drivable(net, "x")
    (True, False, False, False)
    """
    lane = net.lanes.get(lane_id)
    return (lane is not None and lane.function not in NOT_ROADS
            and not lane.allowed.isdisjoint(ROAD_VCLASSES))


#: Connection directions a lead-in or run-out may be extended through: straight on and
#: SUMO's partial turns. A right or left turn, or a U-turn, before a feature is a curve of
#: its own (its neighbour's), never part of this one's lead-in.
EXTEND_DIRECTIONS = frozenset(("s", "R", "L"))


def _may_extend(net: Network, conn: Connection, lane_id: str) -> bool:
    """A connection an approach or exit may be extended through: straight on or a partial
    turn (:data:`EXTEND_DIRECTIONS`), onto a drivable lane, and through drivable internal
    lanes only."""
    if conn.direction not in EXTEND_DIRECTIONS or not drivable(net, lane_id):
        return False
    vias = via_lanes(net, conn) or []
    return all(drivable(net, v) for v in vias)


def _rank(conn: Connection) -> tuple[int, str]:
    return (_DIR_RANK.get(conn.direction, 5), conn.from_lane + ">" + conn.to_lane)


def _is_internal(net: Network, lane_id: str) -> bool:
    lane = net.lanes.get(lane_id)
    return lane is None or lane.function == "internal"


def extend_back(
    net: Network, lane_id: str, need_m: float
) -> list[str]:
    """Lanes upstream of ``lane_id`` (farthest first) covering at least ``need_m`` metres.

    Follows the straightest connection into each lane (its internal lanes included) that
    a road vehicle may drive and that goes straight on (:func:`_may_extend`); stops early
    where nothing leads in, at a loop, or after :data:`MAX_EXTENSION_LANES`.
    """
    out: list[str] = []
    seen = {lane_id}
    cur = lane_id
    while need_m > 0 and len(out) < MAX_EXTENSION_LANES:
        cands = [
            c
            for c in net.incoming(cur)
            if not _is_internal(net, c.from_lane) and c.from_lane not in seen
            and _may_extend(net, c, c.from_lane)
        ]
        if not cands:
            break
        conn = min(cands, key=_rank)
        vias = via_lanes(net, conn) or []
        step = [conn.from_lane, *vias]
        out[:0] = step
        seen.update(step)
        need_m -= sum(lane_length(net, k) for k in step)
        cur = conn.from_lane
    return out


def extend_forward(
    net: Network, lane_id: str, need_m: float
) -> list[str]:
    """Lanes downstream of ``lane_id`` (nearest first) covering at least ``need_m`` metres
    (as :func:`extend_back`: drivable lanes only, straight on only)."""
    out: list[str] = []
    seen = {lane_id}
    cur = lane_id
    while need_m > 0 and len(out) < MAX_EXTENSION_LANES:
        cands = [c for c in net.outgoing(cur) if c.to_lane in net.lanes and c.to_lane not in seen
                 and _may_extend(net, c, c.to_lane)]
        if not cands:
            break
        conn = min(cands, key=_rank)
        vias = via_lanes(net, conn) or []
        step = [*vias, conn.to_lane]
        out.extend(step)
        seen.update(step)
        need_m -= sum(lane_length(net, k) for k in step)
        cur = conn.to_lane
    return out


def lane_length(net: Network, lane_id: str) -> float:
    """Plane length of a lane's shape (metres)."""
    return net.lane_line(lane_id)[1]


def _total_length(net: Network, lanes: list[str]) -> float:
    """Sum of the lanes' plane lengths, added in order from 0."""
    return sum(lane_length(net, k) for k in lanes)


@dataclass(slots=True)
class Path:
    """A centre line through lanes, with the core's position on it.

    Attributes
    ----------
    lanes
        The lanes the centre line runs on, in driving order.
    centerline
        (N, 3) points x, y, z in metres.
    core_start_m, core_end_m
        Arc length (plane) along ``centerline`` where the feature begins and ends.
    core_lanes
        The lanes of the feature itself.
    """

    lanes: tuple[str, ...]
    centerline: np.ndarray
    core_start_m: float
    core_end_m: float
    core_lanes: tuple[str, ...]


@dataclass(slots=True)
class PathPlan:
    """The lanes of a path before its centre line is made (see :func:`realise`)."""

    lanes: list[str]
    n_before: int
    n_core: int
    core_from_m: float
    core_to_m: float
    core_total_m: float
    approach_m: float
    exit_m: float


def plan_path(
    net: Network,
    before: list[str],
    core: list[str],
    after: list[str],
    approach_m: float,
    exit_m: float,
    core_from_m: float = 0.0,
    core_to_m: float | None = None,
) -> PathPlan:
    """Choose the lanes of a path: ``before`` + ``core`` + ``after``, extended as needed.

    ``before`` ends with the approach lane, ``after`` starts with the exit lane; both are
    extended through the network when they are shorter than ``approach_m`` / ``exit_m``
    (less the part of the core lanes outside the core). ``core_from_m`` / ``core_to_m``
    place the core inside the concatenated core lanes (default: all of them).
    """
    core_total = _total_length(net, core)
    c_from = min(max(core_from_m, 0.0), core_total)
    c_to = core_total if core_to_m is None else min(max(core_to_m, c_from), core_total)
    before_len = _total_length(net, before)
    after_len = _total_length(net, after)
    need_back = approach_m - c_from - before_len
    if need_back > 0:
        first = before[0] if before else core[0]
        before = extend_back(net, first, need_back) + before
    need_fwd = exit_m - (core_total - c_to) - after_len
    if need_fwd > 0:
        last = after[-1] if after else core[-1]
        after = after + extend_forward(net, last, need_fwd)
    return PathPlan(
        before + core + after, len(before), len(core), c_from, c_to, core_total, approach_m, exit_m
    )


_GAP = 10.0  # key distance between consecutive paths in a batch


def realise(net: Network, plans: list[PathPlan]) -> list[Path]:
    """Make the centre lines of many planned paths at once (vectorised).

    Each centre line is its lanes' shapes joined, cut to ``approach_m`` before the core and
    ``exit_m`` after it (where the lanes reach that far), without repeated points.
    """
    if not plans:
        return []
    n_pieces = np.array([len(p.lanes) for p in plans])
    lane_lines = [net.lane_line(k)[0] for p in plans for k in p.lanes]
    piece_counts = np.fromiter(map(len, lane_lines), dtype=np.int64, count=len(lane_lines))
    pts = np.concatenate(lane_lines)
    piece_first = np.concatenate(([0], np.cumsum(piece_counts)[:-1]))
    piece_last = piece_first + piece_counts - 1
    plan_first_piece = np.concatenate(([0], np.cumsum(n_pieces)[:-1]))
    plan_first = piece_first[plan_first_piece]
    plan_last = piece_last[plan_first_piece + n_pieces - 1]
    plan_of_pt = np.repeat(np.arange(len(plans)), plan_last - plan_first + 1)
    d = pts[1:, :2] - pts[:-1, :2]
    seg = np.hypot(d[:, 0], d[:, 1])
    seg[plan_first[1:] - 1] = 0.0
    s_glob = np.concatenate(([0.0], np.cumsum(seg)))
    s0 = s_glob[plan_first]
    total = s_glob[plan_last] - s0
    key = s_glob + plan_of_pt * _GAP
    base = key[plan_first]
    nb = np.array([p.n_before for p in plans])
    nc = np.array([p.n_core for p in plans])
    core_start = s_glob[piece_first[plan_first_piece + nb]] - s0 + [p.core_from_m for p in plans]
    core_end = (
        s_glob[piece_last[plan_first_piece + nb + nc - 1]]
        - s0
        - [p.core_total_m - p.core_to_m for p in plans]
    )
    lo = np.maximum(core_start - [p.approach_m for p in plans], 0.0)
    hi = np.minimum(core_end + [p.exit_m for p in plans], total)
    hi = np.maximum(hi, lo)
    # lanes the cut line runs on
    plan_of_piece = np.repeat(np.arange(len(plans)), n_pieces)
    p_start = s_glob[piece_first] - s0[plan_of_piece]
    p_end = s_glob[piece_last] - s0[plan_of_piece]
    on = (p_end > lo[plan_of_piece] + 1e-9) & (p_start < hi[plan_of_piece] - 1e-9)
    # cut: end points interpolated, inner points strictly between
    k_lo, k_hi = base + lo, base + hi
    ends = _interp_points(pts, key, np.concatenate((k_lo, k_hi)))
    i_in = np.searchsorted(key, k_lo, side="right")
    j_in = np.searchsorted(key, k_hi, side="left")
    n_in = np.maximum(j_in - i_in, 0)
    sizes = n_in + 2
    out_first = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    out = np.empty((int(sizes.sum()), pts.shape[1]))
    n = len(plans)
    out[out_first] = ends[:n]
    out[out_first + sizes - 1] = ends[n:]
    inner_plan = np.repeat(np.arange(n), n_in)
    offset = np.arange(int(n_in.sum())) - np.repeat(np.cumsum(n_in) - n_in, n_in)
    out[out_first[inner_plan] + 1 + offset] = pts[i_in[inner_plan] + offset]
    # drop repeated points (lane joins), never a path's first point
    dd = out[1:, :2] - out[:-1, :2]
    keep = np.concatenate(([True], np.hypot(dd[:, 0], dd[:, 1]) > MIN_CHORD_M))
    keep[out_first] = True
    # a path cut to a single point keeps two copies (a degenerate, zero-length line)
    out_plan = np.repeat(np.arange(n), sizes)
    kept = np.bincount(out_plan, weights=keep, minlength=n).astype(np.int64)
    lonely = np.flatnonzero(kept < 2)
    keep[out_first[lonely] + sizes[lonely] - 1] = True
    kept[lonely] = 2
    cut = out[keep]
    ends_at = np.cumsum(kept).tolist()
    lines = [cut[a:b] for a, b in zip([0, *ends_at[:-1]], ends_at, strict=True)]
    paths = []
    on_list = on.tolist()
    first_piece = plan_first_piece.tolist()
    starts, ends = core_start - lo, np.minimum(core_end - lo, hi - lo)
    starts_l, ends_l = starts.tolist(), ends.tolist()
    for c, plan in enumerate(plans):
        f = first_piece[c]
        own = plan.lanes
        core = tuple(own[plan.n_before : plan.n_before + plan.n_core])
        lanes = tuple(compress(own, on_list[f : f + len(own)])) or core
        paths.append(Path(lanes, lines[c], starts_l[c], ends_l[c], core))
    return paths


def _interp_points(pts: np.ndarray, key: np.ndarray, at: np.ndarray) -> np.ndarray:
    k = np.clip(np.searchsorted(key, at, side="right") - 1, 0, len(key) - 2)
    seg = key[k + 1] - key[k]
    t = np.where(seg > 0, (at - key[k]) / np.where(seg > 0, seg, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    return pts[k] + t[:, None] * (pts[k + 1] - pts[k])


def build_path(
    net: Network,
    before: list[str],
    core: list[str],
    after: list[str],
    approach_m: float,
    exit_m: float,
    core_from_m: float = 0.0,
    core_to_m: float | None = None,
) -> Path:
    """Plan and realise one path (see :func:`plan_path` and :func:`realise`)."""
    plan = plan_path(net, before, core, after, approach_m, exit_m, core_from_m, core_to_m)
    return realise(net, [plan])[0]


#: A lead-in starts after the last stretch tighter than this (m) more than
#: :data:`LEAD_KEEP_M` before the feature: a corner there is a neighbouring curve, and the
#: vehicle should enter this one in a steady state, not still recovering from that one.
LEAD_MIN_RADIUS_M = 15.0

#: The lead-in kept next to the feature whatever its radius (m).
LEAD_KEEP_M = 5.0


def steady_lead_ins(paths: list[Path], step_m: float, window_m: float) -> list[Path]:
    """The paths with each lead-in cut to start after its last tight stretch (radii fitted
    every ``step_m`` over a window of ``window_m``, as the curves' profiles are).

    The lead-in is for bringing the vehicle to the feature in a steady state; extended
    back straight on only (:mod:`clearance.networks.paths`), it can still hold a tight corner
    inside a lane (an OSM service road's) or a previous junction's kink. The line then starts
    one fitting window after the last station, more than :data:`LEAD_KEEP_M` and a fitting
    window before the feature, whose radius is under :data:`LEAD_MIN_RADIUS_M`, and never
    closer to the feature than :data:`LEAD_KEEP_M`. The same for every vehicle (paths are cut
    in place). :func:`steady_run_outs` does the same after the feature.
    """
    cuts = _tight_cuts([p.centerline for p in paths], [p.core_start_m for p in paths],
                       step_m, window_m)
    for p, cut in zip(paths, cuts, strict=True):
        if cut > 0:
            p.centerline = cut_polyline(p.centerline, cut, math.inf)
            p.core_start_m -= cut
            p.core_end_m -= cut
    return paths


def steady_run_outs(paths: list[Path], step_m: float, window_m: float) -> list[Path]:
    """The paths with each run-out cut to end before its first tight stretch: a corner or a
    kink of the exit lane, or of the next junction it was extended through, more than
    :data:`LEAD_KEEP_M` and a fitting window after the feature is the next curve's, and a
    conflict there is not this feature's (the mirror of :func:`steady_lead_ins`).

    Examples
    --------
    A feature at 10-12 m on a line that turns on an 8 m radius 25 m after it: the run-out
    ends before that corner; a straight run-out is kept whole.

    >>> t = np.linspace(0.0, np.pi / 2, 20)
    >>> arc = np.column_stack([37 + 8 * np.sin(t), 8 - 8 * np.cos(t), 0 * t])
    >>> line = np.vstack([[[0.0, 0, 0]], arc, [[45.0, 30.0, 0]]])
    >>> p = Path(("a",), line, 10.0, 12.0, ("a",))
    >>> end = steady_run_outs([p], 1.0, 6.0)[0].centerline[-1]
    >>> bool(17.0 <= end[0] < 37.0 and end[1] == 0.0)
    True
    >>> q = Path(("a",), np.array([[0.0, 0, 0], [60.0, 0, 0]]), 10.0, 12.0, ("a",))
    >>> float(steady_run_outs([q], 1.0, 6.0)[0].centerline[-1, 0])
    60.0
    """
    lines, ends = [], []
    for p in paths:
        d = np.diff(p.centerline[:, :2], axis=0)
        total = float(np.hypot(d[:, 0], d[:, 1]).sum())
        lines.append(np.ascontiguousarray(p.centerline[::-1]))
        ends.append(total - p.core_end_m)
    cuts = _tight_cuts(lines, ends, step_m, window_m)
    for p, cut, end in zip(paths, cuts, ends, strict=True):
        if cut > 0:
            p.centerline = cut_polyline(p.centerline, 0.0, p.core_end_m + end - cut)
    return paths


def _tight_cuts(lines: list[np.ndarray], core_at_m: list[float], step_m: float,
                window_m: float) -> list[float]:
    """For each line whose feature starts at ``core_at_m``: how far to cut from its start so
    that it starts one fitting window after its last stretch tighter than
    :data:`LEAD_MIN_RADIUS_M` (0: no cut); see :func:`steady_lead_ins`."""
    # stations whose fitting window (a fixed one) stays clear of the feature's own bend
    reach = LEAD_KEEP_M + window_m
    cuts = [0.0] * len(lines)
    lead = [n for n, at in enumerate(core_at_m) if at > reach + window_m]
    if not lead:
        return cuts
    prof = profiles([lines[n] for n in lead], [0.0] * len(lead),
                    [core_at_m[n] - reach for n in lead], step_m, window_m,
                    margin_m=0.0, adaptive=False)
    for k, n in enumerate(lead):
        s, curvature = prof.stations[k].array(), prof.curvature_per_m[k]
        tight = np.flatnonzero(radius_from_curvature(curvature) < LEAD_MIN_RADIUS_M)
        if not len(tight):
            continue
        cuts[n] = max(0.0, min(float(s[tight[-1]]) + window_m, core_at_m[n] - LEAD_KEEP_M))
    return cuts
