"""The committed sample networks: rebuilt from their sources they match; curves as designed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples import build as samples
from clearance.networks.samples import sources


@pytest.mark.parametrize("name", samples.SAMPLES)
def test_rebuilt_sample_matches_committed(name, tmp_path, netconvert):
    committed = read_network(samples.SAMPLES_DIR / name / f"{name}.net.xml")
    rebuilt = read_network(samples.build(name, tmp_path))
    assert rebuilt.lanes.keys() == committed.lanes.keys()
    for k, lane in committed.lanes.items():
        other = rebuilt.lanes[k]
        assert other.width_m == lane.width_m and other.allowed == lane.allowed
        np.testing.assert_allclose(other.shape, lane.shape, atol=0.011, err_msg=k)
    assert rebuilt.junctions.keys() == committed.junctions.keys()
    for k, j in committed.junctions.items():
        np.testing.assert_allclose(rebuilt.junctions[k].shape, j.shape, atol=0.011, err_msg=k)
    assert [(c.from_lane, c.to_lane, c.via) for c in rebuilt.connections] == [
        (c.from_lane, c.to_lane, c.via) for c in committed.connections
    ]
    assert rebuilt.roundabouts == committed.roundabouts


def _sample(name: str):
    return read_network(samples.SAMPLES_DIR / name / f"{name}.net.xml")


def test_intersection_right_turns_follow_their_corners():
    curves = {c.curve_id: c for c in extract_curves(_sample("intersection"), ["turn"])}
    corners = sources.INTERSECTION_CORNERS
    half_lane = 3.25 / 2
    expected = {
        "turn:X:XN_in_0->XW_out_0": corners.nw,
        "turn:X:XE_in_0->XN_out_0": corners.ne,
        "turn:X:XS_in_0->XE_out_0": corners.se,
        "turn:X:XW_in_0->XS_out_0": corners.sw,
        "turn:T:TW_in_0->TS_out_0": sources.TEE_TIGHT_CORNER_M + 3.5 / 2 - half_lane,
    }
    for cid, corner in expected.items():
        turn = curves[cid]
        assert turn.min_radius_m == pytest.approx(corner + half_lane, rel=0.03), cid
        assert turn.turn_angle_deg == pytest.approx(-90.0, abs=2.0), cid
    # the T's tight corner is tighter than a passenger car's 6.4 m turning radius
    assert curves["turn:T:TW_in_0->TS_out_0"].min_radius_m < 6.4
    # the X's NW corner is tighter than a bus's (11.5 m) and an SU-30's (11.6 m)
    assert curves["turn:X:XN_in_0->XW_out_0"].min_radius_m < 11.5
    assert curves["turn:X:XE_in_0->XN_out_0"].min_radius_m > 11.6


def test_roundabouts_entry_and_ring_radii():
    net = _sample("roundabout")
    curves = extract_curves(net, ["roundabout"])
    assert len(curves) == 32
    for design in sources.ROUNDABOUTS:
        mine = [c for c in curves if c.junction.startswith(design.rid)]
        assert len(mine) == 16
        smallest = min(design.entry_radius_m, design.exit_radius_m)
        for c in mine:
            assert c.min_radius_m == pytest.approx(smallest, rel=0.03), c.curve_id
        through = next(c for c in mine if abs(c.turn_angle_deg) < 1 and c.junction.endswith("0"))
        s = through.profile_s_m
        ring_lanes = [k for k in through.lanes if "ring" in k]
        assert ring_lanes
        # somewhere along the ring the radius is the ring lane's centre radius
        rc = design.ring_centre_radius_m
        mid = (s > through.core_start_m) & (s < through.core_end_m)
        assert np.any(np.abs(through.profile_radius_m[mid] - rc) < 0.03 * rc)
    # the truck apron is paved but not roadway
    big = next(c for c in curves if c.junction == "R0" and abs(c.turn_angle_deg) < 1)
    assert big.curve_id == "roundabout:R0:R0_in_1->R2_out_1"  # lane 0 is the shoulder
    apron = net.lanes["Rring0_1"]
    assert "passenger" not in apron.allowed
    from shapely.geometry import Point

    probe = Point(0.0, 7.5)  # on the apron, 7.5 m from the centre
    assert big.paved.covers(probe) and not big.roadway.covers(probe)
    # so are the arms' shoulders
    shoulder = Point(30.0, 4.5)  # east arm, 1 m outside the inbound lane
    assert "passenger" not in net.lanes["R0_in_0"].allowed
    assert big.paved.covers(shoulder) and not big.roadway.covers(shoulder)


def test_parking_ramp_helix():
    net = _sample("parking_ramp")
    (ramp,) = extract_curves(net, ["ramp"])
    assert ramp.min_radius_m == pytest.approx(sources.HELIX_RADIUS_M, rel=0.03)
    grade = 100 * sources.HELIX_RISE_PER_TURN_M / (2 * math.pi * sources.HELIX_RADIUS_M)
    assert ramp.max_grade_pct == pytest.approx(grade, abs=0.5)
    assert ramp.turn_angle_deg == pytest.approx(360 * sources.HELIX_TURNS, abs=2.0)
    assert ramp.lane_width_m == sources.HELIX_LANE_M


def test_helix_sample_turns_on_itself():
    net = _sample("helix")
    (ramp,) = extract_curves(net, ["ramp"])
    assert ramp.min_radius_m == pytest.approx(sources.LEVEL_HELIX_RADIUS_M, rel=0.03)
    grade = 100 * sources.LEVEL_HELIX_RISE_PER_TURN_M / (2 * math.pi * sources.LEVEL_HELIX_RADIUS_M)
    assert ramp.max_grade_pct == pytest.approx(grade, abs=0.5)
    assert ramp.turn_angle_deg == pytest.approx(360 * sources.LEVEL_HELIX_TURNS, abs=2.0)
    z = ramp.centerline[:, 2]
    top = sources.LEVEL_HELIX_RISE_PER_TURN_M * sources.LEVEL_HELIX_TURNS
    assert z.min() == pytest.approx(0.0, abs=0.01) and z.max() == pytest.approx(top, abs=0.01)
    # the run ends where it began in plan, 9.6 m higher (the exit over the first turn)
    start = ramp.centerline[np.argmin(np.hypot(*(ramp.centerline[:, :2] - [0.0, -9.0]).T))]
    assert start[2] < 0.5


def test_garage_sample_deck_lies_above_the_aisle():
    net = _sample("garage")
    (ramp,) = extract_curves(net, ["ramp"])
    assert ramp.min_radius_m == pytest.approx(sources.GARAGE_CORNER_M, rel=0.03)
    assert ramp.lane_width_m == sources.GARAGE_RAMP_M
    assert ramp.lanes[0] == "aisle_0" and ramp.lanes[-1] == "deck_0"
    aisle, deck = net.lanes["aisle_0"], net.lanes["deck_0"]
    assert aisle.width_m == sources.GARAGE_AISLE_M and deck.width_m == sources.GARAGE_DECK_M
    # the deck's centre line is the aisle's, a storey up
    assert np.allclose(aisle.shape[:, 0], deck.shape[0, 0], atol=0.01)
    assert np.allclose(deck.shape[:, 2] - aisle.shape[:, 2].max(), sources.GARAGE_STOREY_M,
                       atol=0.01)


def test_plan_figure_is_drawn(tmp_path):
    from clearance.networks.plot import save_plan

    png = save_plan(
        samples.SAMPLES_DIR / "parking_ramp" / "parking_ramp.net.xml",
        tmp_path / "plan.png",
        [("helix", None), ("zoom", (-15.0, 15.0, -15.0, 15.0))],
    )
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
