"""The passages of a route: the curves a vehicle driving it goes through, in order.

A *passage* is a stretch of a route that one or more curves of the network cover: the turn
from one edge to the next through a junction (one curve per lane-to-lane connection), a
roundabout passage from its entry to its exit, a ramp or a tight bend on the way. A curve
covers a stretch when the normal edges of its feature (its ``core_lanes``, lead-ins and
run-outs left out) are consecutive edges of the route. A passage with several curves is
judged by the one a driver would take (the best verdict; :mod:`clearance.reports.results.routes`).

Each distinct passage is one key, whatever the number of routes through it, so a route
study drives its passages, not the network.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from clearance.networks.curves import Curve
from clearance.networks.model import Network

__all__ = ["Passage", "core_edges", "passages_of", "route_passages"]


@dataclass(frozen=True)
class Passage:
    """One passage: the route's edges it covers (``edges``), where, and its curves."""

    edges: tuple[str, ...]
    junction: str
    kind: str
    curve_ids: tuple[str, ...]

    @property
    def from_edge(self) -> str:
        return self.edges[0]

    @property
    def to_edge(self) -> str:
        return self.edges[-1]


def core_edges(net: Network, curve: Curve) -> tuple[str, ...]:
    """The edges a route drives through the curve's feature, in order, each once: the
    normal edges of its ``core_lanes`` and, where the feature starts or ends inside a
    junction, the normal edge it comes from or goes to (a turn's feature is the junction's
    internal lane alone: its edges are the approach and the exit).

    Examples
    --------
    >>> from types import SimpleNamespace as S
    >>> lane = lambda i, e: S(edge=e, is_internal=i.startswith(":"))
    >>> net = S(lanes={i: lane(i, i.rsplit("_", 1)[0]) for i in
    ...                ("a_0", ":J_0_0", "b_0", ":K_1_0", "c_0")})
    >>> turn = S(lanes=("a_0", ":J_0_0", "b_0"), core_lanes=(":J_0_0",))
    >>> bend = S(lanes=("a_0", ":J_0_0", "b_0", ":K_1_0", "c_0"), core_lanes=("b_0",))
    >>> core_edges(net, turn), core_edges(net, bend)
    (('a', 'b'), ('b',))
    """
    lanes, core = list(curve.lanes), list(curve.core_lanes)
    n = len(core)
    start = next((i for i in range(len(lanes) - n + 1) if lanes[i:i + n] == core), None)
    if start is None or not core:
        return ()
    span = lanes[start:start + n]
    if net.lanes[span[0]].is_internal and start > 0:
        span.insert(0, lanes[start - 1])
    if net.lanes[span[-1]].is_internal and start + n < len(lanes):
        span.append(lanes[start + n])
    out: list[str] = []
    for lane_id in span:
        lane = net.lanes.get(lane_id)
        if lane is None or lane.is_internal:
            continue
        if not out or out[-1] != lane.edge:
            out.append(lane.edge)
    return tuple(out)


def passages_of(net: Network, curves: Iterable[Curve]) -> dict[tuple[str, ...], Passage]:
    """The passages the curves make, by their edges: curves with the same core edges are
    one passage (its lane-to-lane alternatives)."""
    groups: dict[tuple[str, ...], list[Curve]] = {}
    for c in curves:
        key = core_edges(net, c)
        if key:
            groups.setdefault(key, []).append(c)
    return {key: Passage(key, cs[0].junction, cs[0].kind, tuple(c.curve_id for c in cs))
            for key, cs in groups.items()}


def route_passages(edges: Sequence[str], passages: dict[tuple[str, ...], Passage]
                   ) -> list[tuple[int, Passage]]:
    """The passages along a route's ``edges``, each with the index of its first edge in
    the route, in driving order (a passage the route makes twice is listed twice).

    Examples
    --------
    >>> p = {("a", "b"): Passage(("a", "b"), "J1", "turn", ("t1", "t2")),
    ...      ("b",): Passage(("b",), "", "bend", ("b1",)),
    ...      ("c", "r", "d"): Passage(("c", "r", "d"), "R", "roundabout", ("r1",))}
    >>> [(i, q.kind) for i, q in route_passages(["a", "b", "c", "r", "d"], p)]
    [(0, 'turn'), (1, 'bend'), (2, 'roundabout')]
    >>> route_passages([], p)
    []
    """
    lengths = sorted({len(k) for k in passages})
    out = []
    for i in range(len(edges)):
        for n in lengths:
            key = tuple(edges[i:i + n])
            if len(key) == n and key in passages:
                out.append((i, passages[key]))
    return out
