"""Lane sequences through a network and the centre lines they make.

A *path* is an ordered list of lane ids a vehicle drives: approach lanes, the core (the
lanes of the feature: a junction's internal lanes, a ring, a ramp), exit lanes. The
approach is extended back through upstream lanes when the approach lane is shorter than
wanted (preferring straight-on connections), the exit forward likewise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from networks.geometry import arc_length, clean_polyline, cut_polyline
from networks.reader import Connection, Network

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
    while via:
        if via in out or via not in net.lanes or len(out) > 8:
            return None
        out.append(via)
        nxt = [c for c in net.outgoing(via) if c.to_edge == conn.to_edge] or net.outgoing(via)
        if not nxt:
            return None
        via = nxt[0].via
    return out


def _rank(conn: Connection) -> tuple[int, str]:
    return (_DIR_RANK.get(conn.direction, 5), conn.from_lane + ">" + conn.to_lane)


def _is_internal(net: Network, lane_id: str) -> bool:
    lane = net.lanes.get(lane_id)
    return lane is None or lane.function == "internal"


def extend_back(net: Network, lane_id: str, need_m: float) -> list[str]:
    """Lanes upstream of ``lane_id`` (farthest first) covering at least ``need_m`` metres.

    Follows the straightest connection into each lane (its internal lanes included);
    stops early where nothing leads in, at a loop, or after :data:`MAX_EXTENSION_LANES`.
    """
    out: list[str] = []
    seen = {lane_id}
    cur = lane_id
    while need_m > 0 and len(out) < MAX_EXTENSION_LANES:
        cands = [
            c
            for c in net.incoming(cur)
            if not _is_internal(net, c.from_lane) and c.from_lane not in seen
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


def extend_forward(net: Network, lane_id: str, need_m: float) -> list[str]:
    """Lanes downstream of ``lane_id`` (nearest first) covering at least ``need_m`` metres."""
    out: list[str] = []
    seen = {lane_id}
    cur = lane_id
    while need_m > 0 and len(out) < MAX_EXTENSION_LANES:
        cands = [c for c in net.outgoing(cur) if c.to_lane in net.lanes and c.to_lane not in seen]
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
    """Join lanes into a centre line with ``approach_m`` before the core and ``exit_m`` after.

    ``before`` ends with the approach lane, ``after`` starts with the exit lane; both are
    extended through the network when they are too short. ``core_from_m`` / ``core_to_m``
    place the core inside the concatenated core lanes (default: all of them).
    """
    core_total = sum(net.lane_line(k)[1] for k in core)
    c_from = min(max(core_from_m, 0.0), core_total)
    c_to = core_total if core_to_m is None else min(max(core_to_m, c_from), core_total)
    before_len = sum(lane_length(net, k) for k in before)
    after_len = sum(lane_length(net, k) for k in after)
    need_back = approach_m - c_from - before_len
    if need_back > 0:
        first = before[0] if before else core[0]
        before = extend_back(net, first, need_back) + before
    need_fwd = exit_m - (core_total - c_to) - after_len
    if need_fwd > 0:
        last = after[-1] if after else core[-1]
        after = after + extend_forward(net, last, need_fwd)
    lanes = before + core + after
    pieces = [net.lane_line(k)[0] for k in lanes]
    counts = np.array([len(p) for p in pieces])
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    joined = np.vstack(pieces)
    s = arc_length(joined)
    piece_start = s[first]
    piece_end = s[first + counts - 1]
    n_before = len(before)
    core_start = float(piece_start[n_before]) + c_from
    core_end = float(piece_end[n_before + len(core) - 1]) - (core_total - c_to)
    lo = max(core_start - approach_m, 0.0)
    hi = min(core_end + exit_m, float(s[-1]))
    keep = [i for i in range(len(lanes)) if piece_end[i] > lo + 1e-9 and piece_start[i] < hi - 1e-9]
    if not keep:
        keep = list(range(n_before, n_before + len(core)))
    centre = clean_polyline(cut_polyline(joined, lo, hi))
    return Path(
        lanes=tuple(lanes[i] for i in keep),
        centerline=centre,
        core_start_m=core_start - lo,
        core_end_m=min(core_end - lo, float(arc_length(centre)[-1])),
        core_lanes=tuple(core),
    )
