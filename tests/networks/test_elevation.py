"""Grades of a helix built with netconvert, and a lone suspect height on it."""

from __future__ import annotations

import math

import numpy as np

from networks.curves import extract_curves
from networks.elevation import drop_suspect_elevation
from networks.reader import read_network

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
    lane = net.lanes["helix_0"]
    z = lane.shape[:, 2]
    spike = int(np.argmax(z - np.interp(np.arange(len(z)), [0, len(z) - 1], [z[0], z[-1]])))
    ramp = extract_curves(net, kinds=("ramp",), areas=False)[0]
    assert f"lane helix_0 point {spike}" in ramp.suspect_elevation
    assert "suspect geometry" in ramp.suspect_elevation
    assert abs(ramp.max_grade_pct - DESIGN_GRADE_PCT) < 0.5  # not thousands of per cent
    assert float(np.max(ramp.centerline[:, 2])) < RISE_M * TURNS + 1e-6


def test_clean_line_is_left_alone():
    line = np.array([[0.0, 0, 0], [20, 0, 0], [40, 0, 3], [60, 0, 3]])
    clean, note = drop_suspect_elevation(None, (), line)  # type: ignore[arg-type]
    assert note == "" and clean is line
