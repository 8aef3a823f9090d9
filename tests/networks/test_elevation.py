"""Grades of a helix built with netconvert, and a lone suspect height on it."""

from __future__ import annotations

import math

import numpy as np

from clearance.networks.area_book import network_is_flat
from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.sources import SAMPLES_DIR

RADIUS_M, RISE_M, TURNS = 9.0, 3.2, 2.0
DESIGN_GRADE_PCT = 100 * RISE_M / (2 * math.pi * RADIUS_M)  # 5.66 %


def helix_sources(spike_at: int | None = None, spike_m: float = 30.0) -> tuple[str, str]:
    """Nodes and edges of a two-turn helix (radius 9 m, 3.2 m a turn) with straight lead-in
    and exit; ``spike_at`` raises that shape point of the helix by ``spike_m``."""
    lead = 15.0
    top = RISE_M * TURNS
    angles = np.linspace(-90.0, -90.0 + 360.0 * TURNS, int(360 * TURNS / 5) + 1)
    pts = [(RADIUS_M * math.cos(math.radians(a)), RADIUS_M * math.sin(math.radians(a)),
            top * (a + 90.0) / (360.0 * TURNS)) for a in angles]
    if spike_at is not None:
        x, y, z = pts[spike_at]
        pts[spike_at] = (x, y, z + spike_m)
    end = pts[-1]
    out = (end[0] + lead, end[1], top)  # the helix ends heading east (+x) at -90 + 720 deg
    shape = [(-lead, -RADIUS_M, 0.0), *pts, out]
    text = " ".join(f"{x:.3f},{y:.3f},{z:.3f}" for x, y, z in shape)
    nodes = (f'<node id="A" x="{-lead - 30:.3f}" y="{-RADIUS_M:.3f}" z="0"/>'
             f'<node id="H0" x="{-lead:.3f}" y="{-RADIUS_M:.3f}" z="0"/>'
             f'<node id="H1" x="{out[0]:.3f}" y="{out[1]:.3f}" z="{top:.3f}"/>'
             f'<node id="B" x="{out[0] + 30:.3f}" y="{out[1]:.3f}" z="{top:.3f}"/>')
    attrs = 'numLanes="1" width="3.5" speed="4.17" spreadType="center"'
    edges = (f'<edge id="approach" from="A" to="H0" {attrs}/>'
             f'<edge id="helix" from="H0" to="H1" {attrs} shape="{text}"/>'
             f'<edge id="exit" from="H1" to="B" {attrs}/>')
    return nodes, edges


def test_helix_grade_is_its_design_grade(build_net):
    net = read_network(build_net(*helix_sources(), name="helix"))
    ramps = extract_curves(net, kinds=("ramp",), areas=False)
    assert len(ramps) == 1
    assert abs(ramps[0].max_grade_pct - DESIGN_GRADE_PCT) < 0.5
    assert ramps[0].suspect_elevation == ""


def test_lone_height_is_flagged_not_reported_as_a_grade(build_net):
    net = read_network(build_net(*helix_sources(spike_at=40), name="spike"))
    z = net.lanes["helix_0"].shape[:, 2]
    spike = 41  # the helix's point 40, after the lane's first point
    assert abs(z[spike] - 0.5 * (z[spike - 1] + z[spike + 1])) < 1e-3  # on the line again
    ramp = extract_curves(net, kinds=("ramp",), areas=False)[0]
    assert f"lane helix_0 point {spike}: z 31.78 m, 30.0 m off" in ramp.suspect_elevation
    assert "suspect geometry" in ramp.suspect_elevation
    assert abs(ramp.max_grade_pct - DESIGN_GRADE_PCT) < 0.5  # not thousands of per cent
    assert float(np.max(ramp.centerline[:, 2])) < RISE_M * TURNS + 1e-6


def test_a_network_without_lone_heights_is_left_alone(build_net):
    net = read_network(build_net(*helix_sources(), name="helix"))
    assert net.suspect_heights == {} and net.repairs == []


def test_a_lone_height_at_a_lanes_junction_end_is_repaired_in_the_network(tmp_path):
    # z = 1e6 at the junction end of a two-point lane: the lead-in of the curves through it
    # interpolated heights of 760,000 m into their centre lines, and the report hung
    # building 760,766 storeys; now the network's own shape is repaired on reading
    text = (SAMPLES_DIR / "intersection" / "intersection.net.xml").read_text()
    old = 'shape="520.00,1.75 415.50,1.75"'
    assert text.count(old) == 1
    p = tmp_path / "spike.net.xml"
    p.write_text(text.replace(old, 'shape="520.00,1.75 415.50,1.75,1000000"'))
    net = read_network(p)
    assert net.lanes["TE_in_0"].shape[:, 2].tolist() == [0.0, 0.0]
    assert network_is_flat(net)
    [note] = net.suspect_heights["TE_in_0"]
    assert note.startswith("lane TE_in_0 point 1: z 1000000.00 m") and note in net.repairs
    curves = {c.curve_id: c for c in extract_curves(net, areas=False)}
    through = curves["turn:T:TE_in_0->TW_out_0"]
    assert float(np.abs(through.centerline[:, 2]).max()) == 0.0
    assert through.suspect_elevation == note and through.max_grade_pct == 0.0
    assert curves["turn:X:XE_in_0->XN_out_0"].suspect_elevation == ""
