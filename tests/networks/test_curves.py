"""Curve extraction: accuracy on networks of known geometry, kinds, areas, ids."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest

from clearance.networks.curves import CurveOptions, extract_curves
from clearance.networks.profiles import MAX_WINDOW_M
from clearance.networks.reader import read_network
from clearance.vehicles.errors import InputError


def _arc(cx, cy, r, a0_deg, a1_deg, step_deg=5.0, z0=0.0, z1=None):
    n = max(int(abs(a1_deg - a0_deg) / step_deg), 2) + 1
    a = np.radians(np.linspace(a0_deg, a1_deg, n))
    z = np.linspace(z0, z0 if z1 is None else z1, n)
    return np.c_[cx + r * np.cos(a), cy + r * np.sin(a), z]


def _fmt(points) -> str:
    return " ".join(",".join(f"{v:.4f}" for v in p) for p in points)


def helix_sources(radius_m=7.5, rise_per_turn_m=3.0, turns=2.25, lead_m=10.0):
    """A one-lane helix (counter-clockwise, rising) with straight tangent lead-in and out."""
    helix = _arc(0, 0, radius_m, -90, -90 + 360 * turns, z1=rise_per_turn_m * turns)
    top = helix[-1, 2]
    end = helix[-1]
    # the lead-out leaves along the tangent at the helix's end
    a_end = math.radians(-90 + 360 * turns)
    tangent = np.array([-math.sin(a_end), math.cos(a_end)])
    out_pt = end[:2] + lead_m * tangent
    far = end[:2] + (lead_m + 50) * tangent
    pts = [(-lead_m, -radius_m, 0.0), *map(tuple, helix), (out_pt[0], out_pt[1], top)]
    nodes = (
        f'<node id="A" x="-60" y="{-radius_m}" z="0"/>'
        f'<node id="H0" x="{-lead_m}" y="{-radius_m}" z="0"/>'
        f'<node id="H1" x="{out_pt[0]:.4f}" y="{out_pt[1]:.4f}" z="{top:.4f}"/>'
        f'<node id="B" x="{far[0]:.4f}" y="{far[1]:.4f}" z="{top:.4f}"/>'
    )
    common = 'numLanes="1" width="3.5" spreadType="center"'
    edges = (
        f'<edge id="in" from="A" to="H0" {common}/>'
        f'<edge id="helix" from="H0" to="H1" {common} shape="{_fmt(pts)}"/>'
        f'<edge id="out" from="H1" to="B" {common}/>'
    )
    return nodes, edges


def test_helix_radius_grade_and_angle(build_net):
    path = build_net(*helix_sources())
    net = read_network(path)
    (ramp,) = extract_curves(net, ["ramp"])
    assert ramp.curve_id == "ramp:helix_0->helix_0"
    assert ramp.min_radius_m == pytest.approx(7.5, rel=0.03)
    expected_grade = 100 * 3.0 / (2 * math.pi * 7.5)
    assert ramp.max_grade_pct == pytest.approx(expected_grade, abs=0.5)
    assert ramp.turn_angle_deg == pytest.approx(810.0, abs=2.0)
    # the helix has no bend of its own: it is a ramp
    assert not extract_curves(net, ["bend"])
    # the centre line climbs 3 m per turn
    assert ramp.centerline[-1, 2] - ramp.centerline[0, 2] == pytest.approx(6.75, abs=0.1)


def roundabout_sources(ring_radius_m=16.0, arm_m=80.0):
    """A one-lane ring of known radius (lane centre on the circle) with four two-way arms."""
    r = ring_radius_m
    nodes, edges, ring = [], [], []
    for k, ang in enumerate((0, 90, 180, 270)):
        a = math.radians(ang)
        nodes.append(f'<node id="R{k}" x="{r * math.cos(a):.4f}" y="{r * math.sin(a):.4f}"/>')
        ax, ay = (r + arm_m) * math.cos(a), (r + arm_m) * math.sin(a)
        nodes.append(f'<node id="A{k}" x="{ax:.4f}" y="{ay:.4f}"/>')
        edges.append(f'<edge id="in{k}" from="A{k}" to="R{k}" numLanes="1" width="3.5"/>')
        edges.append(f'<edge id="out{k}" from="R{k}" to="A{k}" numLanes="1" width="3.5"/>')
    for k, ang in enumerate((0, 90, 180, 270)):
        pts = _arc(0, 0, r, ang, ang + 90, step_deg=3.0)
        shape = _fmt(pts[:, :2])
        edges.append(
            f'<edge id="ring{k}" from="R{k}" to="R{(k + 1) % 4}" numLanes="1" width="4"'
            f' spreadType="center" shape="{shape}"/>'
        )
        ring.append(f"ring{k}")
    edges.append(f'<roundabout nodes="R0 R1 R2 R3" edges="{" ".join(ring)}"/>')
    return "".join(nodes), "".join(edges)


def test_roundabout_ring_radius(build_net):
    net = read_network(build_net(*roundabout_sources(16.0)))
    curves = extract_curves(net, ["roundabout"])
    # 4 entries x 4 exits (the U-turn round the ring included)
    assert len(curves) == 16
    through = next(c for c in curves if c.curve_id == "roundabout:R0:in0_0->out2_0")
    assert through.junction == "R0"
    assert through.turn_angle_deg == pytest.approx(0.0, abs=2.0)
    # on the ring lanes, the radius is the ring's
    ring_lanes = [k for k in through.core_lanes if k.startswith("ring")]
    assert ring_lanes
    s = through.profile_s_m
    mid = (s > through.core_start_m + 10) & (s < through.core_end_m - 10)
    ring_r = np.median(through.profile_radius_m[mid])
    assert ring_r == pytest.approx(16.0, rel=0.03)
    # first exit is a right turn, third a left turn, in right-hand traffic
    right = next(c for c in curves if c.curve_id == "roundabout:R0:in0_0->out1_0")
    left = next(c for c in curves if c.curve_id == "roundabout:R0:in0_0->out3_0")
    assert right.turn_angle_deg == pytest.approx(-90.0, abs=2.0)
    assert left.turn_angle_deg == pytest.approx(90.0, abs=2.0)
    # the entry and exit deflections are tighter than the ring
    assert through.min_radius_m < 16.0
    # no turns are reported at ring nodes (they belong to the roundabout curves)
    assert not [c for c in extract_curves(net, ["turn"]) if c.junction.startswith("R")]


CROSS_NODES = (
    '<node id="C" x="0" y="0" type="priority" radius="12"/>'
    '<node id="W" x="-100" y="0"/><node id="N" x="0" y="100"/>'
    '<node id="E" x="100" y="0"/><node id="S" x="0" y="-100"/>'
)
CROSS_EDGES = "".join(
    f'<edge id="{a}{b}" from="{a}" to="{b}" numLanes="1" width="3.5"/>'
    for a, b in (("W", "C"), ("C", "N"), ("C", "W"), ("N", "C"), ("E", "C"), ("C", "E"))
    + (("S", "C"), ("C", "S"))
)


def test_turn_with_exact_arc(build_net):
    first = read_network(build_net(CROSS_NODES, CROSS_EDGES, name="probe"))
    # connection shapes are given in input coordinates: undo netconvert's offset
    offset = np.array([*first.location.net_offset, 0.0])
    p1 = first.lanes["WC_0"].shape[-1] - offset  # approach lane end, heading east
    p2 = first.lanes["CN_0"].shape[0] - offset  # exit lane start, heading north
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    assert dx > 3 and dy > 3
    radius = min(dx, dy)
    # straight to the arc, a quarter circle (left turn), straight to the exit lane
    start = (p2[0] - radius, p1[1])
    arc = _arc(start[0], p1[1] + radius, radius, -90, 0, step_deg=7.5)
    pts = [tuple(p1[:2]), *map(tuple, arc[:, :2]), tuple(p2[:2])]
    con = f'<connection from="WC" to="CN" fromLane="0" toLane="0" shape="{_fmt(pts)}"/>'
    net = read_network(build_net(CROSS_NODES, CROSS_EDGES, con, name="arc"))
    (turn,) = [c for c in extract_curves(net, ["turn"]) if c.curve_id.startswith("turn:C:WC_0")]
    assert turn.curve_id == "turn:C:WC_0->CN_0"
    assert turn.min_radius_m == pytest.approx(radius, rel=0.03)
    assert turn.turn_angle_deg == pytest.approx(90.0, abs=2.0)
    assert turn.max_grade_pct == 0.0
    # approach and exit are long enough for the default 25 m
    assert turn.core_start_m == pytest.approx(25.0, abs=0.01)
    total = float(np.hypot(*np.diff(turn.centerline[:, :2], axis=0).T).sum())
    assert total - turn.core_end_m == pytest.approx(25.0, abs=0.01)
    # areas nest: own lanes within the roadway within the paved area (up to slivers)
    assert turn.own_lanes.difference(turn.roadway).area < 0.02 * turn.own_lanes.area
    assert turn.roadway.difference(turn.paved).area < 1e-6
    assert turn.paved.area > turn.roadway.area


def test_approach_extends_upstream_through_short_lanes(build_net):
    nodes = (
        '<node id="A" x="-100" y="0"/><node id="B" x="-8" y="0"/>'
        '<node id="C" x="0" y="0"/><node id="N" x="0" y="100"/>'
    )
    edges = (
        '<edge id="AB" from="A" to="B"/><edge id="BC" from="B" to="C"/>'
        '<edge id="CN" from="C" to="N"/>'
    )
    net = read_network(build_net(nodes, edges))
    opts = CurveOptions(approach_length_m=40.0)
    (turn,) = [c for c in extract_curves(net, ["turn"], opts) if c.curve_id == "turn:C:BC_0->CN_0"]
    assert turn.lanes[0] == "AB_0"
    assert turn.core_start_m == pytest.approx(40.0, abs=0.01)


def test_bend_inside_an_edge(build_net):
    arc = _arc(0, 30, 30, -90, 0, step_deg=3.0)  # a 30 m radius quarter circle, left
    pts = [(-60, 0), *map(tuple, arc[:, :2]), (30, 90)]
    nodes = '<node id="A" x="-60" y="0"/><node id="B" x="30" y="90"/>'
    edges = f'<edge id="E" from="A" to="B" numLanes="1" spreadType="center" shape="{_fmt(pts)}"/>'
    net = read_network(build_net(nodes, edges))
    (bend,) = extract_curves(net, ["bend"])
    assert bend.curve_id == "bend:E_0:0"
    assert bend.min_radius_m == pytest.approx(30.0, rel=0.03)
    assert bend.turn_angle_deg == pytest.approx(90.0, abs=2.0)
    # the stretch covers the arc, widened by at most the fitting window at either end
    assert math.pi * 15 - 1 < bend.length_m < math.pi * 15 + MAX_WINDOW_M


def test_network_without_internal_lanes_warns_and_has_no_turns(build_net, caplog):
    net = read_network(build_net(CROSS_NODES, CROSS_EDGES, None, "--no-internal-links"))
    assert not net.has_internal_lanes
    with caplog.at_level(logging.WARNING):
        curves = extract_curves(net, ["turn"])
    assert curves == []
    assert "without internal lanes" in caplog.text


def test_unknown_kind_is_an_input_error(build_net):
    net = read_network(build_net(CROSS_NODES, CROSS_EDGES))
    with pytest.raises(InputError, match="unknown curve kind.*spiral"):
        extract_curves(net, ["spiral"])


def test_ids_are_stable_and_unique(build_net):
    path = build_net(*roundabout_sources(18.0))
    a = [c.curve_id for c in extract_curves(read_network(path))]
    b = [c.curve_id for c in extract_curves(read_network(path))]
    assert a == b and len(set(a)) == len(a)


def test_turns_are_found_in_the_order_of_their_ids(small_grid):
    from clearance.networks.curves import find_turns

    net = read_network(small_grid)
    ids = [item[0] for item in find_turns(net, CurveOptions())]
    # one per connection through a junction (5 x 5 grid of two-lane streets), in the
    # order the curves are sorted in, so that a batch of them is final once measured
    assert len(ids) == len(set(ids)) > 100
    assert ids == sorted(ids)
    assert [c.curve_id for c in extract_curves(net, ["turn"], areas=False)] == ids


def test_automatic_uturns_are_a_kind_of_their_own_left_out_by_default(build_net):
    # netconvert adds a turnaround (dir "t") at each end of a two-way street by default
    nodes = '<node id="A" x="-100" y="0"/><node id="B" x="0" y="0"/><node id="C" x="100" y="0"/>'
    edges = (
        '<edge id="AB" from="A" to="B"/><edge id="BA" from="B" to="A"/>'
        '<edge id="BC" from="B" to="C"/><edge id="CB" from="C" to="B"/>'
    )
    net = read_network(build_net(nodes, edges))
    turnarounds = {(c.from_lane, c.to_lane) for c in net.connections
                   if c.direction == "t" and c.via}
    assert turnarounds, "netconvert made no turnaround"
    default = extract_curves(net, areas=False)
    assert all(c.kind != "uturn" and not c.curve_id.startswith("uturn:") for c in default)
    direction = {(c.from_lane, c.to_lane): c.direction for c in net.connections}
    for c in default:
        if c.kind == "turn":
            a, b = c.curve_id.split(":", 2)[2].split("->")
            assert direction[(a, b)] != "t", c.curve_id
    uturns = extract_curves(net, ["uturn"], areas=False)
    assert {tuple(c.curve_id.split(":", 2)[2].split("->")) for c in uturns} == turnarounds
    assert all(c.kind == "uturn" and abs(abs(c.turn_angle_deg) - 180) < 10 for c in uturns)
    # all kinds together: turns first, then U-turns, each sorted by id
    both = extract_curves(net, ["turn", "uturn"], areas=False)
    assert [c.kind for c in both] == sorted((c.kind for c in both), key=["turn", "uturn"].index)


def test_approach_and_exit_never_run_on_sidewalks_or_walking_areas(build_net):
    # a pedestrian zone open to deliveries (one shared lane each way, as OSM's
    # highway=pedestrian): its lanes connect to walking areas at both junctions
    zone = 'numLanes="1" allow="pedestrian delivery bicycle"'
    edges = "".join(
        f'<edge id="{a}{b}" from="{a}" to="{b}" {zone}/>'
        for a, b in (("W", "X"), ("X", "W"), ("X", "E"), ("E", "X"), ("S", "X"), ("X", "S"))
    )
    nodes = ('<node id="W" x="-30" y="0"/><node id="X" x="0" y="0" type="priority"/>'
             '<node id="E" x="30" y="0"/><node id="S" x="0" y="-30"/>')
    net = read_network(build_net(nodes, edges, None, "--walkingareas"))
    walk = {k for k, ln in net.lanes.items() if ln.function == "walkingarea"}
    assert walk
    # the street's lanes do lead into walking areas
    assert any(c.to_lane in walk for c in net.connections)
    from clearance.networks.paths import drivable

    curves = extract_curves(net, ["turn"], CurveOptions(approach_length_m=60.0), areas=False)
    assert curves
    for c in curves:
        bad = [k for k in c.lanes if not drivable(net, k)]
        assert not bad, (c.curve_id, bad)


def test_permissions_follow_the_lanes_allow(build_net):
    # a bus-only street from the west and an ordinary one from the south, into a junction
    nodes = ('<node id="W" x="-60" y="0"/><node id="X" x="0" y="0" type="priority"/>'
             '<node id="N" x="0" y="60"/><node id="S" x="0" y="-60"/>')
    edges = ('<edge id="WX" from="W" to="X" numLanes="1" allow="bus"/>'
             '<edge id="SX" from="S" to="X" numLanes="1"/>'
             '<edge id="XN" from="X" to="N" numLanes="1"/>')
    net = read_network(build_net(nodes, edges))
    from clearance.networks.permissions import permits, permitted_lanes

    by_id = {c.curve_id: c for c in extract_curves(net, ["turn"], areas=False)}
    from_w, from_s = by_id["turn:X:WX_0->XN_0"], by_id["turn:X:SX_0->XN_0"]
    assert permitted_lanes(from_s)[0] == "SX_0" and permitted_lanes(from_s)[-1] == "XN_0"
    assert permits(net, from_w, "bus") and not permits(net, from_w, "passenger")
    assert permits(net, from_s, "bus") and permits(net, from_s, "passenger")


def test_a_lead_in_starts_after_its_last_tight_corner(build_net):
    # the approach edge has a 6 m radius corner 20 m before junction B (an OSM service
    # road's), then runs straight east into B, where a right turn leads south
    arc = _arc(-20, -6, 6, 180, 90, step_deg=10.0)  # from (-26, -6) round to (-20, 0)
    shape = [(-26, -60), *map(tuple, arc[:, :2]), (0, 0)]
    nodes = ('<node id="A" x="-26" y="-60"/><node id="B" x="0" y="0" type="priority"/>'
             '<node id="C" x="0" y="-60"/><node id="D" x="60" y="0"/>')
    edges = (f'<edge id="AB" from="A" to="B" numLanes="1" shape="{_fmt(shape)}"/>'
             '<edge id="BC" from="B" to="C" numLanes="1"/>'
             '<edge id="BD" from="B" to="D" numLanes="1"/>')
    net = read_network(build_net(nodes, edges))
    from clearance.networks.paths import LEAD_KEEP_M

    by_id = {c.curve_id: c for c in extract_curves(net, ["turn"], CurveOptions(40.0),
                                                   areas=False)}
    from clearance.networks.geometry import curvature_profile, radius_from_curvature

    straight = by_id["turn:B:AB_0->BD_0"]
    # it starts after the corner, on the straight part (the corner is 20 m before B,
    # less B's junction radius), and nothing on the lead-in is tight any more
    assert LEAD_KEEP_M <= straight.core_start_m < 20.0
    _, k = curvature_profile(straight.centerline, 0.25, 3.0, 0.0,
                             straight.core_start_m - LEAD_KEEP_M, adaptive=False)
    assert radius_from_curvature(k).min() > 15.0
    # with the corner in it, the lead-in would have reached back the 40 m asked for
    assert sum(net.lanes[k].length_m for k in straight.lanes[:1]) > 40.0
