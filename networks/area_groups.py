"""Which lanes and junction polygons make up each curve's ``roadway`` and ``paved`` area.

The areas (docs/design.md §6, :mod:`clearance.networks.areas`) are unions of *members*, named by
keys:

``L:<lane>``
    One lane's polygon (round ends, grown by :data:`~clearance.networks.areas.SEAL_M`).
``J:<junction>``
    A junction polygon (grown likewise).
``ER:<edge>`` / ``EA:<edge>``
    The union of an edge's road lanes / of all its lanes (a *piece*).
``M:<a>><b>``
    The union of the internal road lanes of the connections from edge ``a`` to edge ``b``
    (the parallel lanes of one movement; a piece).

:class:`BatchPlan` registers the curves of one batch, gives each the number of its roadway
group and of its paved group (curves with the same members share one), and lists the
lanes, junction polygons and pieces those groups need. A group's members are kept in a
fixed order (lanes and junction polygons, then pieces, each by key), so that an area is
the same union in the same order whichever batch builds it.
:class:`AreaIndex` holds what every batch of a network looks up (the plain edges at each
junction, the internal lanes of each junction).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol

import numpy as np

from clearance.networks.model import ROAD_VCLASSES, Network
from clearance.networks.paths import junction_of_internal, via_lanes
from clearance.networks.stacking import Stacking, stacking

__all__ = ["AreaCurve", "AreaIndex", "BatchPlan", "is_road", "junctions_of", "plain_edges_of"]


class AreaCurve(Protocol):
    """What building a curve's areas needs of it (:class:`clearance.networks.curves.Curve` has it):
    a protocol, so that the area modules need not import the curves module that uses them."""

    curve_id: str
    kind: str
    junction: str
    lanes: tuple[str, ...]
    core_lanes: tuple[str, ...]
    centerline: np.ndarray
    lane_width_m: float
    area_book: Any
    area_batch: int

    def set_areas(self, own_lanes: Any, roadway: Any, paved: Any, book: Any = None) -> None:
        """Give the curve its three areas (see
        :meth:`clearance.networks.curves.Curve.set_areas`)."""


class AreaIndex:
    """The topology every batch of a network's areas looks up (made once per network).

    Attributes
    ----------
    net
        The network.
    incident
        Junction id -> the plain (not internal) edges that start or end there.
    internal
        Junction id -> every internal lane under it (also those after an internal junction,
        which the junction's ``intLanes`` may not list).
    to_junction
        Edge id -> the junction it ends at.
    plain_edge
        Plain lane id -> its edge.
    junction_at
        Lane id named as internal (``:...``) -> its junction (None when the network has no
        such junction).
    odd_lanes
        Internal lanes whose id does not start with ``:`` (curves using them are grouped
        the slow way, lane by lane).
    road_lanes
        Lanes that passenger cars, buses or trucks may use (:func:`is_road`).
    stacking
        The parts of the network over or under another part (:mod:`clearance.networks.stacking`).
    """

    def __init__(self, net: Network):
        self.net = net
        self._stacking: Stacking | None = None
        self.incident: dict[str, list[str]] = {}
        for e in net.edges.values():
            if e.function == "internal":
                continue
            self.incident.setdefault(e.from_junction, []).append(e.id)
            self.incident.setdefault(e.to_junction, []).append(e.id)
        self.to_junction = {e.id: e.to_junction for e in net.edges.values()}
        self.internal: dict[str, list[str]] = {}
        self.plain_edge: dict[str, str] = {}
        self.junction_at: dict[str, str | None] = {}
        odd: list[str] = []
        road: list[str] = []
        junctions = net.junctions
        for k, lane in net.lanes.items():
            if not lane.allowed.isdisjoint(ROAD_VCLASSES):
                road.append(k)
            named_internal = k.startswith(":")
            if named_internal:
                j = junction_of_internal(k)
                self.junction_at[k] = j if j in junctions else None
            if lane.function == "internal":
                if named_internal:
                    self.internal.setdefault(j, []).append(k)
                else:
                    odd.append(k)
                    self.internal.setdefault(junction_of_internal(k), []).append(k)
            else:
                self.plain_edge[k] = lane.edge
        self.odd_lanes = frozenset(odd)
        self.road_lanes = frozenset(road)


    @property
    def stacking(self) -> Stacking:
        """The network's stacked parts (:func:`clearance.networks.stacking.stacking`, made when
        first
        asked: only curves with heights ask)."""
        if self._stacking is None:
            self._stacking = stacking(self.net)
        return self._stacking
    def plain_edges(self, lanes: Sequence[str]) -> tuple[str, ...] | None:
        """The plain edges a lane sequence runs on, as :func:`plain_edges_of` gives them;
        None when a lane is neither a plain lane nor named as an internal one (an unknown
        lane, or an internal lane named without ``:``: ask :func:`plain_edges_of`).

        Examples
        --------
        >>> from clearance.networks.samples.sources import SAMPLES_DIR
        >>> from clearance.networks.reader import read_network
        >>> net = read_network(SAMPLES_DIR / "intersection" / "intersection.net.xml")
        >>> index = AreaIndex(net)
        >>> a, b = [k for k in net.lanes if not k.startswith(":")][:2]
        >>> index.plain_edges([a, a, b]) == plain_edges_of(net, [a, a, b])
        True
        >>> index.plain_edges(["no_such_lane"]) is None
        True
        """
        edge_of = self.plain_edge
        out: list[str] = []
        for k in lanes:
            e = edge_of.get(k)
            if e is not None:
                out.append(e)
            elif k not in self.junction_at:
                return None
        if len(out) == 2:
            return (out[0],) if out[0] == out[1] else (out[0], out[1])
        return tuple(dict.fromkeys(out))

    def junctions_of(self, curve: AreaCurve) -> tuple[str, ...]:
        """The junctions a curve passes through, as :func:`junctions_of` gives them (a
        turn's or roundabout's from the junctions of its internal lanes, looked up)."""
        if curve.kind not in ("turn", "roundabout"):
            return junctions_of(self.net, curve)
        at = self.junction_at
        out: list[str] = []
        for k in curve.core_lanes:
            if k.startswith(":"):
                j = at[k] if k in at else _existing(self.net, junction_of_internal(k))
                if j is not None and j not in out:
                    out.append(j)
        return tuple(out)


def _existing(net: Network, junction: str) -> str | None:
    return junction if junction in net.junctions else None


def is_road(net: Network, lane_id: str) -> bool:
    """True when passenger cars, buses or trucks may use the lane (a road lane)."""
    return not net.lanes[lane_id].allowed.isdisjoint(ROAD_VCLASSES)


def plain_edges_of(net: Network, lanes: Sequence[str]) -> tuple[str, ...]:
    """The plain edges a lane sequence runs on, in order, each once.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> net = NS(lanes={"a_0": NS(edge="a", function="normal"), ":J_0_0": NS(edge=":J_0",
    ...     function="internal"), "b_0": NS(edge="b", function="normal")})
    >>> plain_edges_of(net, ["a_0", ":J_0_0", "b_0"])
    ('a', 'b')
    """
    lanes_of = net.lanes
    out: dict[str, None] = {}
    for k in lanes:
        lane = lanes_of[k]
        if lane.function != "internal":
            out[lane.edge] = None
    return tuple(out)


def junctions_of(net: Network, curve: AreaCurve) -> tuple[str, ...]:
    """The junctions a curve's feature passes through (its paved neighbourhood).

    A bend: the two junctions of its edge; a turn or roundabout: the junctions of its
    internal lanes; a ramp: those and the junctions of its plain edges.
    """
    if curve.kind == "bend":
        edge = net.edges[net.lanes[curve.core_lanes[0]].edge]
        out = [edge.from_junction, edge.to_junction]
    else:
        out = [junction_of_internal(k) for k in curve.core_lanes if k.startswith(":")]
        if curve.kind == "ramp":
            for k in curve.core_lanes:
                if not k.startswith(":"):
                    e = net.edges[net.lanes[k].edge]
                    out.extend((e.from_junction, e.to_junction))
    junctions = net.junctions
    return tuple(j for j in dict.fromkeys(out) if j in junctions)


class BatchPlan:
    """The groups (and what they are made of) of one batch of curves.

    Call :meth:`add` for each curve; then :attr:`pieces`, :attr:`road_groups` and
    :attr:`paved_groups` say what to build (:func:`clearance.networks.areas.build_areas`).

    Attributes
    ----------
    pieces
        Piece key -> its lanes, in a fixed order.
    road_groups, paved_groups
        Members (sorted keys) of each group, by group number.
    """

    def __init__(self, index: AreaIndex):
        self.index = index
        self.net = index.net
        self.pieces: dict[str, tuple[str, ...]] = {}
        self.road_groups: list[tuple[str, ...]] = []
        self.paved_groups: list[tuple[str, ...]] = []
        self._road_ids: dict[frozenset[str], int] = {}
        self._paved_ids: dict[frozenset[str], int] = {}
        self._road_of: dict[tuple, int] = {}
        self._paved_of: dict[tuple, int] = {}
        self._road_pieces: dict[tuple[str, ...], tuple[list[str], set[str]]] = {}
        self._near: dict[tuple[str, ...], frozenset[str]] = {}
        self._junction: dict[str, frozenset[str]] = {}
        self._movements: dict[str, dict[str, list[str]]] = {}

    def add(self, curve: AreaCurve) -> tuple[int, int]:
        """Register a curve; return the numbers of its roadway group and paved group."""
        plain = self.index.plain_edges(curve.lanes)
        if plain is None or not self.index.odd_lanes.isdisjoint(curve.lanes):
            plain = plain_edges_of(self.net, curve.lanes)
            return self._roadway(curve, plain), self._paved(curve, plain)
        # every plain lane's edge is in ``plain``: no lane of the curve is left out of the
        # paved members, which depend on its junctions and plain edges only
        junctions = self.index.junctions_of(curve)
        near = self._near.get(junctions)
        if near is None:
            near = self._near_edges(junctions)
        to_junction = self.index.to_junction
        if not self._passed(curve, junctions) and near.issuperset(plain) and (
            to_junction[plain[0]] in junctions if len(plain) == 2
            else all(to_junction[a] in junctions for a in plain[:-1])
        ):
            paved = self._paved_of.get((junctions,))  # its junctions' areas cover it all
            if paved is None:
                paved = self._paved(curve, plain, junctions)
        else:
            paved = self._paved(curve, plain, junctions)
        return self._roadway(curve, plain), paved

    # pieces --------------------------------------------------------------------------
    def _piece(self, key: str, lanes: Sequence[str]) -> str | None:
        if key not in self.pieces:
            if not lanes:
                return None
            self.pieces[key] = tuple(lanes)
        return key

    def edge_piece(self, edge: str, road_only: bool) -> str | None:
        """``ER:edge`` (its road lanes) or ``EA:edge`` (all its lanes); None if empty."""
        key = ("ER:" if road_only else "EA:") + edge
        if key in self.pieces:
            return key
        lanes = self.net.edges[edge].lanes
        if road_only:
            road = self.index.road_lanes
            lanes = [k for k in lanes if k in road]
        return self._piece(key, lanes)

    def movement_piece(self, a: str, b: str) -> str | None:
        """``M:a>b``: the internal road lanes of the connections from ``a`` to ``b``."""
        key = f"M:{a}>{b}"
        if key in self.pieces:
            return key
        return self._piece(key, self.movements(a).get(b, ()))

    def movements(self, a: str) -> dict[str, list[str]]:
        """Edge ``b`` -> the internal road lanes from ``a`` to ``b`` (in the order of
        ``a``'s lanes and their connections), for every ``b`` that ``a`` connects to."""
        hit = self._movements.get(a)
        if hit is None:
            net = self.net
            road = self.index.road_lanes
            hit = self._movements[a] = {}
            for lane_id in net.edges[a].lanes:
                for c in net.outgoing(lane_id):
                    lanes = hit.setdefault(c.to_edge, [])
                    if c.via:
                        lanes.extend(
                            k for k in via_lanes(net, c) or [] if k not in lanes and k in road
                        )
        return hit

    # roadway -------------------------------------------------------------------------
    def _roadway(self, curve: AreaCurve, plain: tuple[str, ...]) -> int:
        hit = self._road_pieces.get(plain)
        if hit is None:
            pieces = [self.edge_piece(e, True) for e in plain]
            pieces += [self.movement_piece(a, b) for a, b in zip(plain, plain[1:], strict=False)]
            found = [k for k in pieces if k]
            covered: set[str] = set()
            for k in found:
                covered.update(self.pieces[k])
            hit = self._road_pieces[plain] = (found, covered)
        keys, covered = hit
        # a lane of the curve in no piece (e.g. a ring passage without a connection)
        extra = [] if covered.issuperset(curve.lanes) else [
            k for k in curve.lanes if k not in covered
        ]
        key = (plain, *extra) if extra else plain
        group = self._road_of.get(key)
        if group is None:
            members = frozenset([*keys, *("L:" + k for k in extra)])
            group = self._road_of[key] = _number(members, self._road_ids, self.road_groups)
        return group

    # paved ---------------------------------------------------------------------------
    def _paved(
        self, curve: AreaCurve, plain: tuple[str, ...], junctions: tuple[str, ...] | None = None
    ) -> int:
        net = self.net
        if junctions is None:
            junctions = junctions_of(net, curve)
        near = self._near.get(junctions)
        if near is None:
            near = self._near_edges(junctions)
        lanes = net.lanes
        extra = tuple(
            k for k in curve.lanes
            if not k.startswith(":") and lanes[k].edge not in near and lanes[k].edge not in plain
        )
        edges = net.edges
        passed = self._passed(curve, junctions)
        if not extra and not passed and all(e in near for e in plain) and all(
            edges[a].to_junction in junctions for a in plain[:-1]
        ):
            key: tuple = (junctions,)  # its junctions' areas cover it all (the usual case)
        else:
            key = (junctions, plain, extra, passed)
        group = self._paved_of.get(key)
        if group is None:
            found = self._paved_members(junctions, near, plain, extra)
            found.update("J:" + j for j in passed)
            members = frozenset(found)
            group = self._paved_of[key] = _number(members, self._paved_ids, self.paved_groups)
        return group

    def _passed(self, curve: AreaCurve, junctions: tuple[str, ...]) -> tuple[str, ...]:
        """The junctions the curve's lead-in or run-out drives through (those of its
        internal lanes that are not its feature's): their polygons are pavement too."""
        at = self.index.junction_at
        out = [at.get(k) for k in curve.lanes if k.startswith(":")]
        return tuple(j for j in dict.fromkeys(out) if j is not None and j not in junctions)

    def _near_edges(self, junctions: tuple[str, ...]) -> frozenset[str]:
        edges: set[str] = set()
        for j in junctions:
            edges.update(self.index.incident.get(j, ()))
        near = self._near[junctions] = frozenset(edges)
        return near

    def _paved_members(
        self,
        junctions: tuple[str, ...],
        near: frozenset[str],
        plain: tuple[str, ...],
        extra: tuple[str, ...],
    ) -> set[str]:
        members: set[str] = set()
        for j in junctions:
            members |= self.junction(j)
        for e in plain:
            if e not in near:
                members.add(self.edge_piece(e, False) or "")
        edges = self.net.edges
        junctions_of_net = self.net.junctions
        for a, b in zip(plain, plain[1:], strict=False):
            through = edges[a].to_junction
            if through not in junctions:
                members.add(self.movement_piece(a, b) or "")
                if through in junctions_of_net:  # a junction of the lead-in or run-out: paved
                    members.add("J:" + through)
        members.update("L:" + k for k in extra)  # lanes of the curve nothing above covers
        members.discard("")
        return members

    def junction(self, j: str) -> frozenset[str]:
        """Members of a junction's paved area: its polygon, every lane of its plain edges,
        the movements into it and its other internal lanes."""
        hit = self._junction.get(j)
        if hit is not None:
            return hit
        net = self.net
        keys = {"J:" + j}
        in_movements: set[str] = set()
        for e in self.index.incident.get(j, []):
            keys.add(self.edge_piece(e, False) or "")
            if net.edges[e].to_junction == j:
                for b in sorted(self.movements(e)):
                    key = self.movement_piece(e, b) if b in net.edges else None
                    if key:
                        keys.add(key)
                        in_movements.update(self.pieces[key])
        keys.update("L:" + k for k in self.index.internal.get(j, []) if k not in in_movements)
        keys.discard("")
        hit = self._junction[j] = frozenset(keys)
        return hit


def _number(members: frozenset[str], ids: dict[frozenset[str], int], out: list) -> int:
    """The number of a group by its members (a new one gets the next number)."""
    n = ids.get(members)
    if n is None:
        n = ids[members] = len(out)
        out.append(_in_order(members))
    return n


def _in_order(members: frozenset[str]) -> tuple[str, ...]:
    """Lanes and junction polygons first, then pieces; by key within each (plain string
    sorts: most groups are pieces only).

    Examples
    --------
    >>> _in_order(frozenset(["M:a>b", "ER:a", "L:x_0", "J:B"]))
    ('J:B', 'L:x_0', 'ER:a', 'M:a>b')
    >>> _in_order(frozenset(["M:a>b", "ER:b", "ER:a"]))
    ('ER:a', 'ER:b', 'M:a>b')
    """
    first = sorted(m for m in members if m[0] in "LJ")
    if not first:
        return tuple(sorted(members))
    return (*first, *sorted(m for m in members if m[0] not in "LJ"))
