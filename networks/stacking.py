"""Storeys: the parts of a network that lie over or under another part of it.

A road that climbs is not a second storey. Swept paths, lanes and pavement are compared in
plan (grade is judged on its own, :mod:`clearance.analysis.vertical`); heights decide what a vehicle
meets only where the network lies over itself: a helix's turns, a garage's floors, a bridge
over a road. :func:`stacking` finds those parts: every lane is cut into pieces of at most
:data:`PIECE_M`, each with its footprint (its part of the lane's polygon) and its heights,
every junction polygon the heights of its node and internal lanes, and two footprints
that overlap in plan by more than :data:`OVERLAP_M2` with heights at least
:data:`STOREY_M` apart are *stacked*, both of them. A curve none of whose parts is stacked
has no levels and is judged in plan, however steep. On a curve that has, a storey meets
(:func:`met_pieces`) the parts within its band of heights, and every part that is not
stacked and is reached from those along the road (piece to piece along a lane, lane to
lane by the network's connections) without passing over or under another storey: a ramp
climbing out of the band is met, a deck that overhangs a lower storey's turn, reached only
through the part over that turn, is not (docs/design.md §6, "Levels").

Example
-------
>>> from clearance.networks.reader import read_network
>>> helix = stacking(read_network("networks/samples/helix/helix.net.xml"))
>>> bool(helix.lanes["helix_0"].any()), "approach_0" in helix.lanes
(True, False)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely

from clearance.networks.model import Network

__all__ = ["OVERLAP_M2", "PIECE_M", "STOREY_M", "Stacking", "densified", "densify",
           "met_pieces", "stacking"]

#: Two parts of a network that overlap in plan and whose heights are at least this far apart
#: are storeys one over the other (m): no road runs 2 m under another, and a ramp's own
#: pieces, a few metres long, never climb that much from one to the next.
STOREY_M = 2.0

#: The longest piece a lane is cut into for the test (m).
PIECE_M = 2.0

#: Footprints that share less area than this only touch (m²): lanes side by side, a lane
#: and the junction it ends on.
OVERLAP_M2 = 0.25


@dataclass
class Stacking:
    """Which parts of a network are stacked (see the module's text).

    Attributes
    ----------
    lanes
        Lane id -> a bool per piece of its :func:`densified` shape (between consecutive
        points): whether it is stacked (lanes with none are not listed).
    junctions
        The junctions whose polygon is stacked.
    junction_z
        Every junction's lowest and highest height: its node's and its internal lanes'.
    tree, footprints, z_range
        Every piece's footprint in an STR tree, and its lowest and highest height ``(N, 2)``,
        to test lines that are not lanes (:meth:`line_mask`).
    """

    lanes: dict[str, np.ndarray] = field(default_factory=dict)
    junctions: frozenset[str] = frozenset()
    #: Each junction's lowest and highest height (its lanes', :func:`_junction_heights`).
    junction_z: dict[str, tuple[float, float]] = field(default_factory=dict)
    tree: shapely.STRtree | None = None
    footprints: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=object))
    z_range: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))

    @property
    def any(self) -> bool:
        """True when some part of the network is stacked."""
        return bool(self.lanes or self.junctions)

    def lane_mask(self, lane_id: str, n_pieces: int) -> np.ndarray:
        """The stacked flags of a lane's ``n_pieces`` densified pieces (all False for a lane
        with none)."""
        hit = self.lanes.get(lane_id)
        return hit if hit is not None else np.zeros(n_pieces, dtype=bool)

    def line_mask(self, line: np.ndarray, half_width_m: float) -> np.ndarray:
        """For each piece of a 3-D line ``(N, 3)`` (a curve's own line; ``N - 1`` flags),
        whether it lies over or under a part of the network (as :func:`stacking` tests
        pieces of lanes)."""
        mask = np.zeros(max(len(line) - 1, 0), dtype=bool)
        if self.tree is None or len(line) < 2:
            return mask
        pieces = shapely.linestrings([line[i:i + 2, :2] for i in range(len(line) - 1)])
        feet = np.asarray(shapely.buffer(pieces, half_width_m, cap_style="flat", quad_segs=2))
        lo = np.minimum(line[:-1, 2], line[1:, 2])
        hi = np.maximum(line[:-1, 2], line[1:, 2])
        mine, theirs = self.tree.query(feet, predicate="intersects")
        apart = _apart(lo[mine], hi[mine], self.z_range[theirs, 0], self.z_range[theirs, 1])
        mine, theirs = mine[apart], theirs[apart]
        if len(mine):
            shared = np.asarray(shapely.area(shapely.intersection(feet[mine],
                                                                  self.footprints[theirs])))
            least = np.minimum(shapely.area(feet[mine]), shapely.area(self.footprints[theirs]))
            mask[np.unique(mine[_overlap(shared, least)])] = True
        return mask


def _overlap(shared_m2: np.ndarray, least_m2: np.ndarray) -> np.ndarray:
    """Whether two footprints overlap rather than touch: they share more than
    :data:`OVERLAP_M2`, or more than a quarter of the smaller one (a short piece).

    >>> _overlap(np.array([0.3, 0.1, 0.1]), np.array([7.0, 7.0, 0.3])).tolist()
    [True, False, True]
    """
    return (shared_m2 > OVERLAP_M2) | (shared_m2 > 0.25 * least_m2)


def _apart(lo_a: np.ndarray, hi_a: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray
           ) -> np.ndarray:
    """Whether two height ranges are at least :data:`STOREY_M` apart.

    >>> _apart(np.array([0.0, 0.0]), np.array([1.0, 1.0]), np.array([3.1, 2.5]),
    ...        np.array([4.0, 3.0])).tolist()
    [True, False]
    """
    return np.maximum(lo_b - hi_a, lo_a - hi_b) >= STOREY_M


def densify(shape: np.ndarray, step_m: float = PIECE_M) -> np.ndarray:
    """A polyline ``(N, 3)`` with points added evenly so that no segment is longer than
    ``step_m`` in plan (its own points kept, heights linear between them).

    Examples
    --------
    >>> densify(np.array([[0.0, 0, 0], [5.0, 0, 1]])).round(2).tolist()
    [[0.0, 0.0, 0.0], [1.67, 0.0, 0.33], [3.33, 0.0, 0.67], [5.0, 0.0, 1.0]]
    >>> densify(np.array([[0.0, 0, 0], [0.0, 0, 0]])).tolist()  # a repeated point
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    pts = np.asarray(shape, dtype=float)
    seg = np.hypot(*np.diff(pts[:, :2], axis=0).T)
    parts = np.maximum(np.ceil(seg / step_m).astype(np.int64), 1)
    if (parts == 1).all():
        return pts
    t = np.concatenate([np.arange(n) / n for n in parts.tolist()])
    start = np.repeat(np.arange(len(seg)), parts)
    out = pts[start] + t[:, None] * (pts[start + 1] - pts[start])
    return np.vstack([out, pts[-1:]])


def densified(net: Network, lane_id: str) -> np.ndarray:
    """A lane's shape ``(N, 3)`` with points added so that no segment is longer than
    :data:`PIECE_M` (heights linear between the points; kept on the network)."""
    key = (lane_id, PIECE_M)
    hit = net.dense.get(key)
    if hit is None:
        hit = net.dense[key] = densify(net.lanes[lane_id].shape)
    return hit


def _junction_heights(net: Network) -> dict[str, tuple[float, float]]:
    """Each junction's lowest and highest height: its node's ``z`` and its internal lanes'
    heights (netconvert draws both from the node; a street whose end was lifted above the
    node does not lift the junction with it)."""
    out: dict[str, tuple[float, float]] = {}
    lanes = net.lanes
    for j in net.junctions.values():
        zs = [j.z]
        for k in j.int_lanes:
            if k in lanes:
                zs.extend(lanes[k].shape[:, 2].tolist())
        out[j.id] = (min(zs), max(zs))
    return out


def stacking(net: Network) -> Stacking:
    """The stacked parts of ``net`` (see the module's text); none on a network whose
    heights all lie within :data:`STOREY_M` of each other."""
    lo, hi = np.inf, -np.inf
    for lane in net.lanes.values():
        z = lane.shape[:, 2]
        lo, hi = min(lo, float(z.min())), max(hi, float(z.max()))
    if not np.isfinite(lo) or hi - lo < STOREY_M:
        return Stacking()
    owners: list[tuple[str, int]] = []  # ("L:lane", piece) or ("J:junction", -1)
    lines: list[np.ndarray] = []
    widths: list[float] = []
    for lane_id, lane in net.lanes.items():
        pts = densified(net, lane_id)
        for i in range(len(pts) - 1):
            owners.append((lane_id, i))
            lines.append(pts[i:i + 2])
            widths.append(lane.width_m / 2.0)
    n_lanes = len(lines)
    feet = shapely.buffer(shapely.linestrings(lines), np.array(widths), cap_style="flat",
                          quad_segs=2) if lines else np.empty(0, dtype=object)
    z = np.array([[min(p[0, 2], p[1, 2]), max(p[0, 2], p[1, 2])] for p in lines]
                 ).reshape(-1, 2)
    heights = _junction_heights(net)
    polys = [(j.id, j.shape) for j in net.junctions.values() if len(j.shape) >= 3]
    junction_feet = np.array([shapely.make_valid(shapely.Polygon(s[:, :2])) for _, s in polys],
                             dtype=object)
    footprints = np.concatenate([feet, junction_feet])
    z_range = np.vstack([z, np.array([heights[j] for j, _ in polys]).reshape(-1, 2)])
    tree = shapely.STRtree(footprints)
    a, b = tree.query(footprints, predicate="intersects")
    keep = (a < b) & _apart(z_range[a, 0], z_range[a, 1], z_range[b, 0], z_range[b, 1])
    a, b = a[keep], b[keep]
    if len(a):
        shared = shapely.area(shapely.intersection(footprints[a], footprints[b]))
        over = _overlap(shared, np.minimum(shapely.area(footprints[a]),
                                           shapely.area(footprints[b])))
        a, b = a[over], b[over]
    stacked = np.unique(np.concatenate([a, b]))
    lane_flags: dict[str, np.ndarray] = {}
    junctions: set[str] = set()
    for k in stacked.tolist():
        if k >= n_lanes:
            junctions.add(polys[k - n_lanes][0])
            continue
        lane_id, i = owners[k]
        flags = lane_flags.get(lane_id)
        if flags is None:
            flags = lane_flags[lane_id] = np.zeros(len(densified(net, lane_id)) - 1, dtype=bool)
        flags[i] = True
    return Stacking(lane_flags, frozenset(junctions), heights, tree, footprints, z_range)


def _in_band(pts: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Per piece of a 3-D polyline, whether its heights reach into ``lo .. hi``."""
    za, zb = pts[:-1, 2], pts[1:, 2]
    return (np.minimum(za, zb) <= hi) & (np.maximum(za, zb) >= lo)


def met_pieces(lines: dict[str, np.ndarray], stacked: dict[str, np.ndarray],
               links: dict[str, list[str]], lo: float, hi: float) -> dict[str, np.ndarray]:
    """Per piece of each line, whether a vehicle whose storey's band is ``lo .. hi`` meets
    it: it is in the band, or it is not stacked and is reached from a piece in the band
    through pieces that are not stacked (along its line, and from a line's last piece to
    the first piece of each line ``links`` names after it, or back).

    Parameters
    ----------
    lines
        Id -> a densified 3-D polyline (``(N, 3)``, ``N - 1`` pieces).
    stacked
        Id -> a bool per piece (ids not given: none stacked).
    links
        Id -> the ids of the lines that follow it (SUMO's connections).

    Examples
    --------
    A ramp of four pieces climbing 0 -> 8 m, none stacked: a vehicle at 0 m meets all of
    it; the same ramp with its third piece over another storey: the fourth is cut off.

    >>> ramp = {"r": np.array([[0, 0, 0.0], [2, 0, 2], [4, 0, 4], [6, 0, 6], [8, 0, 8]])}
    >>> met_pieces(ramp, {}, {}, -1.5, 1.5)["r"].tolist()
    [True, True, True, True]
    >>> met_pieces(ramp, {"r": np.array([False, False, True, False])}, {}, -1.5, 1.5)["r"]
    array([ True,  True, False, False])

    Nothing in the band, nothing met (the degenerate case):

    >>> met_pieces(ramp, {}, {}, 20.0, 21.0)["r"].tolist()
    [False, False, False, False]
    """
    met = {k: _in_band(p, lo, hi) for k, p in lines.items()}
    free = {k: ~stacked.get(k, np.zeros(len(p) - 1, dtype=bool)) for k, p in lines.items()}
    back: dict[str, list[str]] = {}
    for k, after in links.items():
        for x in after:
            back.setdefault(x, []).append(k)
    todo = [(k, i) for k, m in met.items() for i in np.flatnonzero(m).tolist()]
    while todo:
        k, i = todo.pop()
        n = len(met[k])
        steps = [(k, i - 1), (k, i + 1)]
        if i == n - 1:
            steps += [(x, 0) for x in links.get(k, ()) if x in met]
        if i == 0:
            steps += [(x, len(met[x]) - 1) for x in back.get(k, ()) if x in met]
        for x, j in steps:
            if 0 <= j < len(met[x]) and not met[x][j] and free[x][j]:
                met[x][j] = True
                todo.append((x, j))
    return met
