"""What SUMO refuses, and what it loads though no vehicle can be judged on it.

The tool reads exactly the networks SUMO loads (docs/design.md §7). Two kinds of fault are
told apart here, after the reader has parsed a file:

- **Refused.** A reference SUMO itself refuses to load (a connection from or to an unknown
  edge, a lane index a connection's edge does not have, a ``via`` lane that does not exist,
  a roundabout naming an unknown edge) raises :class:`~clearance.vehicles.errors.InputError` naming
  the element (:func:`check_references`). SUMO's own check
  (:func:`clearance.networks.sumo.load_check.sumo_refusal`) says the same in SUMO's words first.
- **Left out or repaired.** What SUMO loads but gives no geometry a vehicle can be judged
  on is left out, or repaired the way SUMO reads it, each with a note naming the element
  (:attr:`clearance.networks.model.Network.repairs`): a lane whose shape has fewer than two points
  or a coordinate that is not a finite number within :data:`~clearance.networks.shapes.MAX_COORD_M`
  (SUMO loads a walking area drawn as one point), with its connections, and an edge left
  with no lane (:func:`leave_out_lanes`); a lane index beyond its edge's lanes and a
  roundabout naming an unknown junction (:func:`check_references`). Curves through what was
  left out are simply not extracted.
"""

from __future__ import annotations

from collections.abc import Mapping
from itertools import repeat
from operator import attrgetter, itemgetter
from pathlib import Path

import numpy as np

from clearance.networks.model import Edge, Junction, Lane, Roundabout
from clearance.vehicles.errors import NetworkError

__all__ = ["ConnectionRow", "MIN_ROAD_LANE_M", "check_references", "leave_out_lanes",
           "not_at_road_scale"]

#: A connection as the reader collects it: from edge, to edge, fromLane, toLane, via, dir.
ConnectionRow = tuple[str, str, int, int, str | None, str]


#: A network none of whose road lanes is at least this wide is not drawn at road scale (m):
#: road lanes are 2.5-5 m wide, a cycle lane 1 m; a network drawn 10,000 times too small
#: (a junction 5 mm across) has lanes of 0.35 mm, whose every run would be judged on nothing.
MIN_ROAD_LANE_M = 1.0


def not_at_road_scale(lanes: Mapping[str, Lane], road_vclasses: frozenset[str]) -> str:
    """Why a network cannot be driven at road scale (``""`` when it can): its widest lane
    that road vehicles may use is narrower than :data:`MIN_ROAD_LANE_M`.

    Examples
    --------
    >>> lane = Lane("a_0", "a", 0, 0.00035, "normal", frozenset({"passenger"}),
    ...             np.zeros((2, 3)), 0.01, 9)
    >>> not_at_road_scale({"a_0": lane}, frozenset({"passenger"}))[:56]
    'not drivable at road scale: its widest road lane is 0.00'
    >>> not_at_road_scale({}, frozenset({"passenger"}))  # no road lane: nothing to drive
    ''
    """
    widths = [ln.width_m for ln in lanes.values() if not ln.allowed.isdisjoint(road_vclasses)]
    if not widths or max(widths) >= MIN_ROAD_LANE_M:
        return ""
    return (f"not drivable at road scale: its widest road lane is {max(widths):.2g} m wide "
            f"(road lanes are 2.5-5 m; a vehicle is judged on lanes of {MIN_ROAD_LANE_M:g} m "
            "or more): is it drawn in another unit?")


def leave_out_lanes(edges: dict[str, Edge], lanes: dict[str, Lane],
                    connections: list[ConnectionRow], roundabouts: list[Roundabout],
                    junctions: Mapping[str, Junction], broken: Mapping[str, str],
                    repairs: list[str]) -> tuple[list[ConnectionRow], list[Roundabout]]:
    """Leave out the ``broken`` lanes (id -> why), every edge left without a lane, and the
    connections and roundabout references that go through them; a note each in ``repairs``.

    ``lanes`` and ``edges`` are changed in place; the connections and roundabouts kept are
    returned.

    Examples
    --------
    >>> e = {"a": Edge("a", "j", "k", "normal", 1, ["a_0"]),
    ...      "b": Edge("b", "k", "m", "normal", 1, ["b_0"])}
    >>> lanes = {k: Lane(k, k[0], 0, 3.2, "normal", frozenset(), np.zeros((2, 3)), 9, 9)
    ...          for k in ("a_0", "b_0")}
    >>> notes = []
    >>> rows, rings = leave_out_lanes(e, lanes, [("a", "b", 0, 0, None, "s")], [], {},
    ...                               {"b_0": "shape has fewer than 2 points"}, notes)
    >>> sorted(lanes), sorted(e), rows
    (['a_0'], ['a'], [])
    >>> print("\\n".join(notes))
    lane 'b_0': shape has fewer than 2 points: left out
    edge 'b': no lane left: left out
    1 connection(s) through what was left out: left out

    Nothing broken, nothing changed (the degenerate case):

    >>> leave_out_lanes(e, lanes, [], [], {}, {}, notes)
    ([], [])
    """
    if not broken:
        return connections, roundabouts
    gone_lanes = {k for k in broken if k in lanes}
    for k in sorted(gone_lanes):
        repairs.append(f"lane {k!r}: {broken[k]}: left out")
        edge = edges.get(lanes.pop(k).edge)
        if edge is not None:
            edge.lanes = [x for x in edge.lanes if x != k]
    gone_edges = {e for e, edge in edges.items() if not edge.lanes}
    for e in sorted(gone_edges):
        repairs.append(f"edge {e!r}: no lane left: left out")
        del edges[e]
    for j in junctions.values():
        if not gone_lanes.isdisjoint(j.inc_lanes) or not gone_lanes.isdisjoint(j.int_lanes):
            j.inc_lanes = tuple(k for k in j.inc_lanes if k not in gone_lanes)
            j.int_lanes = tuple(k for k in j.int_lanes if k not in gone_lanes)

    def through_gone(row: ConnectionRow) -> bool:
        frm, to, fl, tl, via, _ = row
        return (frm in gone_edges or to in gone_edges or via in gone_lanes
                or f"{frm}_{fl}" in gone_lanes or f"{to}_{tl}" in gone_lanes)

    kept = [r for r in connections if not through_gone(r)]
    if len(kept) < len(connections):
        repairs.append(f"{len(connections) - len(kept)} connection(s) through what was left "
                       "out: left out")
    rings = []
    for r in roundabouts:
        left = tuple(e for e in r.edges if e not in gone_edges)
        if len(left) < len(r.edges):
            repairs.append(f"<roundabout edges=...>: edge(s) left out: "
                           f"{', '.join(map(repr, sorted(set(r.edges) - set(left))[:5]))}")
        if left:
            rings.append(Roundabout(r.nodes, left))
    return kept, rings


def check_references(path: Path, edges: dict[str, Edge], lanes: dict[str, Lane],
                     connections: list[ConnectionRow], roundabouts: list[Roundabout],
                     junctions: Mapping[str, Junction],
                     repairs: list[str] | None = None) -> list[Roundabout]:
    """Refuse what SUMO itself refuses to load, naming the element; repair what it loads.

    Refused: a connection that leaves or enters an edge the network does not have, by a
    lane its edge does not have (``fromLane``, ``toLane``), or through a ``via`` lane that
    does not exist; a roundabout naming an unknown edge. Repaired (SUMO loads them; a note
    each in ``repairs``): a lane whose ``index`` is beyond its edge's lanes gets its
    place among them; a roundabout's unknown junctions are dropped from it. Returns the
    roundabouts as repaired.

    Examples
    --------
    >>> e = Edge("a", "j", "k", "normal", 1, ["a_0"])
    >>> lanes = {"a_0": Lane("a_0", "a", 0, 3.2, "normal", frozenset(), np.zeros((2, 3)), 9, 9)}
    >>> check_references(Path("n"), {"a": e}, lanes, [("a", "a", 0, 0, None, "t")], [], {})
    []
    >>> check_references(Path("n"), {"a": e}, lanes, [("a", "b", 0, 0, None, "s")], [], {})
    Traceback (most recent call last):
    ...
    clearance.vehicles.errors.NetworkError: n: <connection from="a" to="b">: unknown to-edge 'b'
    """
    repairs = [] if repairs is None else repairs
    _repair_lane_indices(edges, lanes, repairs)
    if connections:
        _check_connections(path, edges, lanes, connections)
    out = []
    for r in roundabouts:
        unknown = [e for e in r.edges if e not in edges]
        if unknown:
            raise NetworkError(f"{path}: <roundabout edges=...>: unknown edge(s) "
                             f"{', '.join(map(repr, unknown[:5]))}", file=path)
        nodes = tuple(j for j in r.nodes if j in junctions)
        if len(nodes) < len(r.nodes):
            repairs.append(f"<roundabout nodes=...>: unknown junction(s) "
                           f"{', '.join(repr(j) for j in r.nodes if j not in junctions)[:200]}"
                           ": dropped from it")
        out.append(Roundabout(nodes, r.edges))
    return out


def _repair_lane_indices(edges: dict[str, Edge], lanes: dict[str, Lane],
                         repairs: list[str]) -> None:
    """A lane's index is one of its edge's: SUMO accepts repeats (old internal edges have
    several lanes of index 0, bologna_joined of the realnets) and loads an index beyond
    its edge's lanes too; such a lane gets its place among its edge's lanes."""
    lane_list = list(lanes.values())
    if not lane_list:
        return
    code = {e: k for k, e in enumerate(edges)}
    counts = np.fromiter(map(len, (e.lanes for e in edges.values())), np.int64, len(edges))
    of_edge = np.fromiter(map(code.__getitem__, map(attrgetter("edge"), lane_list)),
                          np.int64, len(lane_list))
    try:
        given = np.fromiter(map(attrgetter("index"), lane_list), np.int64, len(lane_list))
    except OverflowError:
        given = np.fromiter((min(max(ln.index, -1), 2**62) for ln in lane_list), np.int64,
                            len(lane_list))
    for i in np.flatnonzero((given < 0) | (given >= counts[of_edge])).tolist():
        lane = lane_list[i]
        place = edges[lane.edge].lanes.index(lane.id)
        repairs.append(f"lane {lane.id!r}: index {lane.index} beyond its edge {lane.edge!r}'s "
                       f"{len(edges[lane.edge].lanes)} lane(s): taken as {place}, its place")
        lane.index = place


def _check_connections(path: Path, edges: dict[str, Edge], lanes: dict[str, Lane],
                       connections: list[ConnectionRow]) -> None:
    """Raise :func:`_refuse_connection`'s error for the first connection SUMO refuses."""
    lane_counts = {e.id: len(e.lanes) for e in edges.values()}
    n = len(connections)

    def column(i: int) -> map:
        return map(itemgetter(i), connections)

    n_from = np.fromiter(map(lane_counts.get, column(0), repeat(-1)), np.int64, n)
    n_to = np.fromiter(map(lane_counts.get, column(1), repeat(-1)), np.int64, n)
    try:
        i_from = np.fromiter(column(2), np.int64, n)
        i_to = np.fromiter(column(3), np.int64, n)
    except OverflowError:
        row = next(r for r in connections if max(abs(r[2]), abs(r[3])) >= 2**63)
        _refuse_connection(path, row, lane_counts)
    bad = (i_from < 0) | (i_from >= n_from) | (i_to < 0) | (i_to >= n_to)
    missing = set(column(4)).difference(lanes)
    missing.discard(None)
    if missing:
        bad |= np.fromiter(map(missing.__contains__, column(4)), bool, n)
    if bad.any():
        _refuse_connection(path, connections[int(np.argmax(bad))], lane_counts)


def _refuse_connection(path: Path, row: ConnectionRow, lane_counts: dict[str, int]) -> None:
    """Raise the error that names what is wrong with one bad connection."""
    frm, to, from_lane, to_lane, via, _ = row
    tag = f'<connection from="{frm}" to="{to}">'
    n_from, n_to = lane_counts.get(frm), lane_counts.get(to)
    if n_from is None:
        raise NetworkError(f"{path}: {tag}: unknown from-edge {frm!r}", file=path)
    if n_to is None:
        raise NetworkError(f"{path}: {tag}: unknown to-edge {to!r}", file=path)
    if not 0 <= from_lane < n_from:
        raise NetworkError(f"{path}: {tag}: fromLane {from_lane} out of range (edge {frm!r} "
                         f"has {n_from} lane(s))", file=path)
    if not 0 <= to_lane < n_to:
        raise NetworkError(f"{path}: {tag}: toLane {to_lane} out of range (edge {to!r} has "
                         f"{n_to} lane(s))", file=path)
    raise NetworkError(f"{path}: {tag}: via lane {via!r} does not exist", file=path)
