"""Grouping curves by the lanes, pieces and junction polygons of their areas."""

from __future__ import annotations

from dataclasses import replace

import pytest

from clearance.networks.area_groups import AreaIndex, BatchPlan, junctions_of, plain_edges_of
from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.sources import SAMPLES_DIR

SAMPLES = ("intersection", "roundabout", "parking_ramp")


def _net(name: str):
    return read_network(SAMPLES_DIR / name / f"{name}.net.xml")


@pytest.mark.parametrize("name", SAMPLES)
def test_looked_up_edges_and_junctions_equal_the_lane_by_lane_ones(name):
    net = _net(name)
    index = AreaIndex(net)
    curves = extract_curves(net, areas=False)
    assert curves
    for c in curves:
        assert index.plain_edges(c.lanes) == plain_edges_of(net, c.lanes), c.curve_id
        assert index.junctions_of(c) == junctions_of(net, c), c.curve_id
        reversed_lanes = tuple(reversed(c.lanes))  # order and repeats kept as given
        assert index.plain_edges(reversed_lanes) == plain_edges_of(net, reversed_lanes)


def test_an_unknown_lane_is_left_to_the_lane_by_lane_lookup():
    net = _net("intersection")
    index = AreaIndex(net)
    assert index.plain_edges(("no_such_lane",)) is None
    with pytest.raises(KeyError):
        plain_edges_of(net, ("no_such_lane",))


def _groups(plan: BatchPlan, curves, numbers):
    """Each curve's roadway and paved members (numbers differ between plans)."""
    return [(plan.road_groups[r], plan.paved_groups[p]) for r, p in numbers]


@pytest.mark.parametrize("name", SAMPLES)
def test_fast_grouping_gives_the_same_members_as_the_slow_one(name, monkeypatch):
    net = _net(name)
    curves = extract_curves(net, areas=False)
    # and variants whose plain edges pass a junction that is not the curve's (reversed),
    # or come back to an edge already run on (a lane repeated)
    curves += [replace(c, lanes=tuple(reversed(c.lanes))) for c in curves] + [
        replace(c, lanes=(*c.lanes, c.lanes[0])) for c in curves
    ]
    curves += _u_turns_elsewhere(net, curves)
    _same_groups_fast_and_slow(net, curves)


def _u_turns_elsewhere(net, curves):
    """Paths over two edges at a curve's junction that join at another junction (a U-turn
    there): their movement is a paved member of its own, beside the junction's."""
    index = AreaIndex(net)
    out = []
    for c in curves:
        near = set(index.incident.get(c.junction, ()))
        for conn in net.connections:
            p, q = conn.from_edge, conn.to_edge
            if p in near and q in near and index.to_junction[p] != c.junction:
                out.append(replace(c, lanes=(conn.from_lane, conn.to_lane)))
    return out


def test_a_path_through_a_u_turn_at_the_next_junction(build_net):
    nodes = (
        '<node id="A" x="-60" y="0"/><node id="B" x="0" y="0" type="priority"/>'
        '<node id="C" x="60" y="0"/><node id="D" x="0" y="-60"/>'
    )
    edges = "".join(
        f'<edge id="{a}{b}" from="{a}" to="{b}" numLanes="1"/>'
        for a, b in ("AB", "BA", "BC", "CB", "DB", "BD")
    )
    net = read_network(build_net(nodes, edges))
    curves = extract_curves(net, areas=False)
    odd = _u_turns_elsewhere(net, curves)
    assert odd, "turnarounds at A and C make such paths"
    plan = BatchPlan(AreaIndex(net))
    usual = {plan.paved_groups[plan.add(c)[1]] for c in curves if c.junction == "B"}
    extra = {plan.paved_groups[plan.add(c)[1]] for c in odd if c.junction == "B"}
    assert len(usual) == 1 and extra and not extra & usual  # + the U-turn's movement
    _same_groups_fast_and_slow(net, curves + odd)


def _same_groups_fast_and_slow(net, curves):
    fast_plan = BatchPlan(AreaIndex(net))
    fast = _groups(fast_plan, curves, [fast_plan.add(c) for c in curves])
    # every lane treated as odd: each curve goes the lane-by-lane way
    slow_index = AreaIndex(net)
    slow_index.odd_lanes = frozenset(net.lanes)
    slow_plan = BatchPlan(slow_index)
    slow = _groups(slow_plan, curves, [slow_plan.add(c) for c in curves])
    assert fast == slow
    assert len(fast_plan.road_groups) == len(slow_plan.road_groups)
    assert len(fast_plan.paved_groups) == len(slow_plan.paved_groups)


def test_a_lane_no_piece_covers_is_a_member_of_its_own():
    net = _net("intersection")
    turn = next(c for c in extract_curves(net, areas=False) if c.kind == "turn")
    plan = BatchPlan(AreaIndex(net))
    road, _ = plan.add(turn)
    # the same turn with an extra internal lane of the junction that no piece lists
    spare = next(
        k for k in net.lanes
        if k.startswith(":") and k not in turn.lanes
        and all(k not in lanes for lanes in plan.pieces.values())
    )
    other = replace(turn, lanes=(*turn.lanes[:-1], spare, turn.lanes[-1]))
    road2, _ = plan.add(other)
    assert road2 != road and plan.road_groups[road2] == tuple(
        sorted((*plan.road_groups[road], "L:" + spare), key=lambda k: (k[0] not in "LJ", k))
    )
