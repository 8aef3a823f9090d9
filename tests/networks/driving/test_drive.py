"""The libsumo driver on the sample networks: designed verdicts, SUMO agrees, errors isolated."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from clearance.analysis.clearance import VERDICTS
from clearance.networks.curves import extract_curves
from clearance.networks.driving import drive as driver
from clearance.networks.driving.drive import DriveOptions, drive
from clearance.networks.reader import read_network
from clearance.networks.samples import build as samples
from clearance.networks.sumo import placement
from clearance.vehicles.errors import GeometryError, InputError
from clearance.vehicles.table import bundled_table, load_tables

libsumo = pytest.importorskip("libsumo")


@pytest.fixture(scope="module")
def table():
    names = ["P", "SU-30", "CITY-BUS", "WB-40", "WB-62", "2008 Chrysler Town & Country"]
    return load_tables([bundled_table("aashto_green_book"), bundled_table("paper_table1")],
                       names)


KINDS = {"intersection": ["turn"], "roundabout": ["roundabout"], "parking_ramp": ["ramp"]}


@pytest.fixture(scope="module")
def nets():
    out = {}
    for name, kinds in KINDS.items():
        net = read_network(samples.SAMPLES_DIR / name / f"{name}.net.xml")
        out[name] = (net, extract_curves(net, kinds))
    return out


def _shown(n: int, every: int = 2) -> np.ndarray:
    """The model's samples SUMO shows: every ``every``-th and the last (0.2 s of 0.1 s)."""
    return np.unique(np.append(np.arange(0, n, every), n - 1))


def _curve(curves, start: str, end: str):
    """The curve whose id starts with ``start`` and contains ``end`` (lane indices vary)."""
    hits = [c for c in curves if c.curve_id.startswith(start) and end in c.curve_id]
    assert len(hits) == 1, (start, end, [c.curve_id for c in hits])
    return hits[0]


# What the samples were designed to show (networks/README.md, "Verdicts"; margins to the
# own lanes in metres as tabulated there by `python -m clearance.networks.samples.verdicts`).
VAN = "2008 Chrysler Town & Country"
DESIGNED = [
    ("intersection", "P", "turn:X:XN_in_0", "XW_out_0", "clear", 0.02),
    ("intersection", "CITY-BUS", "turn:X:XN_in_0", "XW_out_0", "fails", -2.01),
    ("intersection", "P", "turn:T:TW_in_0", "TS_out_0", "fails", -0.22),
    ("intersection", "SU-30", "turn:T:TW_in_0", "TS_out_0", "cannot-turn", -1.63),
    ("roundabout", "P", "roundabout:R0:R0_in_", "R2_out_", "clear", 0.26),
    ("roundabout", "SU-30", "roundabout:R0:R0_in_", "R2_out_", "encroaches", -0.77),
    ("roundabout", "WB-62", "roundabout:R0:R0_in_", "R1_out_", "fails", -3.47),
    ("roundabout", "WB-62", "roundabout:C0:C0_in_", "C3_out_", "cannot-turn", -5.73),
    ("parking_ramp", VAN, "ramp:", "helix", "clear", 0.09),
    ("parking_ramp", "P", "ramp:", "helix", "fails", -0.13),
]


@pytest.fixture(scope="module")
def driven(nets, table):
    results = {}
    for name in KINDS:
        net, curves = nets[name]
        rows = [d for d in DESIGNED if d[0] == name]
        pairs = [(table.vehicle(v), _curve(curves, a, b)) for _, v, a, b, _, _ in rows]
        for row, run in zip(rows, drive(net, pairs, options=DriveOptions(batch_size=3)),
                            strict=True):
            results[row] = run
    return results


@pytest.mark.parametrize("row", DESIGNED, ids=lambda r: f"{r[1]}@{r[2]}->{r[3]}")
def test_designed_verdicts(driven, row):
    # the samples' designed verdicts are those of the lane's centre line
    run = driven[row]
    assert run.error == ""
    assert run.lane_verdict == run.lane_result.verdict == row[4], run.lane_result.clearance.reason
    margin = run.lane_margin_m
    assert (margin >= 0) == (row[4] == "clear")
    assert margin == pytest.approx(row[5], abs=0.015)
    lane_reason = run.lane_result.clearance.reason
    if row[4] == "cannot-turn":  # a verdict with its reason, not an error
        assert "front axle left the centre line" in lane_reason or "articulation" in lane_reason
    # the path taken is never worse than the lane's, and says what it was on the lane
    assert VERDICTS.index(run.verdict) >= VERDICTS.index(run.lane_verdict)
    if run.path == "swung":
        assert run.verdict != run.lane_verdict or run.result.clearance.paved_margin_m > (
            run.lane_result.clearance.paved_margin_m)
        assert f"on the lane centre line: {row[4]}" in run.reason
    else:
        assert run.result.verdict == row[4]
        assert run.result.margin_m == run.lane_margin_m


def test_sumo_positions_agree_with_the_model(driven):
    for row, run in driven.items():
        assert run.sumo_steps == len(_shown(len(run.run.trajectory))), row
        assert run.sumo_max_deviation_m < 1e-6, row


def test_trailer_and_tractor_both_checked(nets, table):
    net, curves = nets["roundabout"]
    curve = _curve(curves, "roundabout:R0:R0_in_", "R2_out_")
    wb = table.vehicle("WB-40")
    placed: dict[str, int] = {}
    real = libsumo.vehicle.moveToXY

    def spy(vid, *args, **kwargs):
        placed[vid] = placed.get(vid, 0) + 1
        return real(vid, *args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(libsumo.vehicle, "moveToXY", spy)
    try:
        (run,) = drive(net, [(wb, curve)], options=DriveOptions())
    finally:
        mp.undo()
    n = len(_shown(len(run.run.trajectory)))
    assert placed["v0"] == n
    # the trailer joins once its front is on the curve's lanes, and stays to the end
    assert 0 < placed["v0.trailer"] <= n
    assert run.sumo_max_deviation_m < 1e-6


@pytest.mark.parametrize("sumo_step_s, every", [(0.2, 2), (None, 1), (0.5, 5)])
def test_fcd_output_replays_the_model(nets, table, tmp_path, sumo_step_s, every):
    net, curves = nets["intersection"]
    curve = _curve(curves, "turn:X:XN_in_0", "XW_out_0")
    fcd = tmp_path / "fcd.xml"
    car = table.vehicle("P")
    (run,) = drive(net, [(car, curve)],
                   options=DriveOptions(fcd_output=fcd, sumo_step_s=sumo_step_s))
    root = ET.parse(fcd).getroot()
    steps = root.findall("timestep")
    at = _shown(len(run.run.trajectory), every)
    assert len(steps) == len(at)
    assert float(steps[1].get("time")) - float(steps[0].get("time")) == pytest.approx(
        every * 0.1)
    x, y = placement.front_bumper(run.run)
    for k in (0, len(steps) // 2, len(steps) - 1):
        (veh,) = steps[k].findall("vehicle")
        assert veh.get("id") == "v0"
        assert float(veh.get("x")) == pytest.approx(x[at[k]], abs=0.01)
        assert float(veh.get("y")) == pytest.approx(y[at[k]], abs=0.01)
        heading = math.radians(90.0 - float(veh.get("angle")))
        theta = run.run.trajectory.theta_rad[at[k]]
        assert math.remainder(heading - theta, 2 * math.pi) == pytest.approx(0.0, abs=1e-3)


def _fcd_points(fcd) -> dict[str, np.ndarray]:
    """Each FCD vehicle's (x, y), step by step."""
    points: dict[str, list[tuple[float, float]]] = {}
    for step in ET.parse(fcd).getroot().iter("timestep"):
        for veh in step.iter("vehicle"):
            points.setdefault(veh.get("id"), []).append((float(veh.get("x")),
                                                         float(veh.get("y"))))
    return {vid: np.array(p) for vid, p in points.items()}


@pytest.mark.parametrize("name, vehicle, start, end", [
    ("intersection", "CITY-BUS", "turn:X:XN_in_0", "XW_out_0"),
    ("roundabout", "WB-62", "roundabout:R0:R0_in_", "R1_out_"),
], ids=["bus", "semitrailer"])
def test_fcd_output_follows_the_swung_path(nets, table, tmp_path, name, vehicle, start, end):
    # a run whose verdict rests on a swung path is shown in SUMO along that path
    net, curves = nets[name]
    curve = _curve(curves, start, end)
    fcd = tmp_path / "fcd.xml"
    hints: list[str] = []
    real = libsumo.vehicle.moveToXY

    def spy(vid, edge, lane, *args, **kwargs):
        if vid == "v0" and (not hints or hints[-1] != edge):
            hints.append(edge)
        return real(vid, edge, lane, *args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(libsumo.vehicle, "moveToXY", spy)
    try:
        (run,) = drive(net, [(table.vehicle(vehicle), curve)],
                       options=DriveOptions(fcd_output=fcd))
    finally:
        mp.undo()
    assert run.error == "" and run.path == "swung" and run.lane_verdict == "fails"
    chosen = run.chosen_run
    assert chosen is run.result.run and chosen is not run.run
    at = _shown(len(chosen.trajectory))
    assert run.sumo_vehicle == "v0"
    assert run.sumo_steps == len(at) and run.sumo_max_deviation_m < 1e-6
    shown = _fcd_points(fcd)
    x, y = placement.front_bumper(chosen)
    assert np.abs(shown["v0"] - np.column_stack([x[at], y[at]])).max() < 0.006  # 2 decimals
    # ... which is not the lane's: the swing is there to see
    lane = LineString(np.column_stack(placement.front_bumper(run.run)))
    assert max(lane.distance(Point(p)) for p in shown["v0"]) > 0.3
    if chosen.vehicle.trailer is not None:  # the trailer joins later, and swings too
        tx, ty, _ = placement.trailer_front(chosen)
        tail = at[len(at) - len(shown["v0.trailer"]):]
        assert np.abs(shown["v0.trailer"] - np.column_stack([tx[tail], ty[tail]])).max() < 0.006
    # the swung path's placements are hinted with the curve's edges, in order
    edges = list(dict.fromkeys(placement.edge_of_lane(k) for k in curve.lanes))
    assert hints == edges


def test_without_fcd_sumo_checks_the_lane_path(nets, table):
    net, curves = nets["intersection"]
    (run,) = drive(net, [(table.vehicle("CITY-BUS"), _curve(curves, "turn:X:XN_in_0",
                                                             "XW_out_0"))])
    assert run.path == "swung" and run.chosen_run is run.result.run
    assert run.sumo_steps == len(_shown(len(run.run.trajectory)))
    assert run.sumo_steps != len(_shown(len(run.chosen_run.trajectory)))


def test_sumo_step_changes_neither_paths_nor_verdicts(nets, table, driven):
    net, curves = nets["roundabout"]
    rows = [d for d in DESIGNED if d[0] == "roundabout"]
    pairs = [(table.vehicle(v), _curve(curves, a, b)) for _, v, a, b, _, _ in rows]
    coarse = drive(net, pairs, options=DriveOptions(sumo_step_s=0.5))
    for row, run in zip(rows, coarse, strict=True):
        fine = driven[row]  # SUMO at its default step
        assert run.error == "" and run.verdict == fine.verdict
        assert run.result.margin_m == fine.result.margin_m
        assert run.sumo_max_deviation_m < 1e-6
        assert run.sumo_steps == len(_shown(len(run.run.trajectory), 5))


def test_sumo_step_must_fit_the_model_step(nets, table):
    net, pairs = _pairs(nets, table, 1)
    for bad in (0.25, 0.05, 0.0, -0.2, math.nan):
        with pytest.raises(InputError, match="SUMO step"):
            drive(net, pairs, options=DriveOptions(sumo_step_s=bad))


def test_without_sumo_same_verdicts(nets, table, driven):
    net, curves = nets["intersection"]
    rows = [d for d in DESIGNED if d[0] == "intersection"]
    pairs = [(table.vehicle(v), _curve(curves, a, b)) for _, v, a, b, _, _ in rows]
    plain = drive(net, pairs, options=DriveOptions(use_sumo=False))
    for row, run in zip(rows, plain, strict=True):
        assert run.verdict == driven[row].verdict
        assert run.result.margin_m == driven[row].result.margin_m
        assert math.isnan(run.sumo_max_deviation_m) and run.sumo_steps == 0


def test_edge_hints_follow_the_curve(nets, table):
    net, curves = nets["intersection"]
    curve = _curve(curves, "turn:X:XN_in_0", "XW_out_0")
    car = table.vehicle("P")
    hints: list[str] = []
    real = libsumo.vehicle.moveToXY

    def spy(vid, edge, lane, *args, **kwargs):
        if not hints or hints[-1] != edge:
            hints.append(edge)
        return real(vid, edge, lane, *args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(libsumo.vehicle, "moveToXY", spy)
    try:
        drive(net, [(car, curve)])
    finally:
        mp.undo()
    assert hints == [placement.edge_of_lane(k) for k in curve.lanes]
    assert placement.route_edges(curve) == ["XN_in", "XW_out"]


def _pairs(nets, table, n: int):
    net, curves = nets["intersection"]
    straight = _curve(curves, "turn:X:XN_in_0", "XS_out_0")
    return net, [(table.vehicle("P"), straight)] * n


def test_vehicle_removed_behind_the_drivers_back(nets, table):
    net, pairs = _pairs(nets, table, 4)
    real = libsumo.vehicle.moveToXY
    calls = {"n": 0}

    def sabotage(vid, *args, **kwargs):
        if vid == "v1":
            calls["n"] += 1
            if calls["n"] == 20:
                libsumo.vehicle.remove("v1")
        return real(vid, *args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(libsumo.vehicle, "moveToXY", sabotage)
    try:
        runs = drive(net, pairs, options=DriveOptions(batch_size=2))
    finally:
        mp.undo()
    assert runs[1].verdict == "error"
    assert "v1" in runs[1].error and "sample 38" in runs[1].error  # SUMO step 19
    assert runs[1].sumo_steps == 19
    for i in (0, 2, 3):
        assert runs[i].error == "" and runs[i].verdict == "clear"
        assert runs[i].sumo_steps == len(_shown(len(runs[i].run.trajectory)))
    # the model's result is kept for the failed run too
    assert runs[1].result.verdict == "clear"


def test_failed_simulation_step_restarts_sumo(nets, table):
    net, pairs = _pairs(nets, table, 3)
    real = libsumo.simulationStep
    calls = {"n": 0}

    def flaky(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 5:
            raise libsumo.TraCIException("injected failure")
        return real(*args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(libsumo, "simulationStep", flaky)
    try:
        runs = drive(net, pairs, options=DriveOptions(batch_size=1))
    finally:
        mp.undo()
    assert "injected failure" in runs[0].error and runs[0].sumo_steps == 4
    assert [r.verdict for r in runs[1:]] == ["clear", "clear"]
    assert all(r.sumo_max_deviation_m < 1e-6 for r in runs[1:])


def test_sumo_failing_every_step_never_hangs(nets, table):
    net, pairs = _pairs(nets, table, 5)

    def broken(*args, **kwargs):
        raise libsumo.TraCIException("always broken")

    mp = pytest.MonkeyPatch()
    mp.setattr(libsumo, "simulationStep", broken)
    try:
        runs = drive(net, pairs, options=DriveOptions(batch_size=2, max_restarts=1))
    finally:
        mp.undo()
    assert all(r.verdict == "error" for r in runs)
    assert "always broken" in runs[0].error
    assert "not driven" in runs[4].error
    assert all(r.result is not None for r in runs)  # the model still ran


def test_vtype_parameters_carry_the_trailer(table):
    p = placement.vtype_parameters(table.vehicle("WB-62"))
    assert float(p["wheelbase_m"]) == pytest.approx(19.5 * 0.3048, abs=1e-4)
    assert float(p["trailer_wheelbase_m"]) == pytest.approx(41.0 * 0.3048, abs=1e-4)
    assert placement.shape_class("semitrailer combination") == "truck"
    assert placement.shape_class("single-unit truck") == "truck"


def test_lane_boundaries_on_a_helix_use_elevation():
    net = read_network(samples.SAMPLES_DIR / "parking_ramp" / "parking_ramp.net.xml")
    (ramp,) = extract_curves(net, ["ramp"], areas=False)
    from clearance.analysis.polyline import prepare_path

    path = prepare_path(ramp.centerline, 0.25, name=ramp.curve_id)
    ends = [net.lanes[k].shape[-1] for k in ramp.lanes]
    bounds = placement.lane_boundaries_m(ramp, path, ends)
    assert np.all(np.diff(bounds) >= 0) and bounds[0] == pytest.approx(25.0, abs=0.3)
    # the helix lane ends at the top, not where the plan view first passes over its end
    helix = ramp.lanes.index("helix_0")
    assert bounds[helix] > ramp.core_end_m - 1.0


def test_docstring_examples():
    import doctest

    from clearance.networks.sumo import placement

    failures, tried = doctest.testmod(placement, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried >= 7 and failures == 0


def test_a_failing_verdict_keeps_the_other_runs(nets, table, monkeypatch):
    net, pairs = _pairs(nets, table, 3)
    real = driver.evaluate
    calls = {"n": 0}

    def flaky(run, *args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 2:
            raise GeometryError("clearance areas: own_lanes is not a valid polygon")
        return real(run, *args, **kwargs)

    monkeypatch.setattr(driver, "evaluate", flaky)
    runs = drive(net, pairs, options=DriveOptions(use_sumo=False))
    assert runs[1].verdict == "error" and runs[1].result is None
    assert "envelope or verdict failed: clearance areas" in runs[1].reason
    assert [runs[0].verdict, runs[2].verdict] == ["clear", "clear"]


def test_a_network_sumo_refuses_is_an_input_error_naming_sumos_message(nets, table, tmp_path):
    # read from the sample, handed to SUMO damaged (a via to a missing lane, which the
    # reader refuses itself): SUMO's refusal at start is bad input, with SUMO's words
    import dataclasses

    from tests.networks import damaged

    net, pairs = _pairs(nets, table, 1)
    bad, _ = damaged.damage("via-to-a-missing-lane", tmp_path)
    with pytest.raises(InputError) as info:
        drive(dataclasses.replace(net, path=bad), pairs, options=DriveOptions())
    msg = str(info.value)
    assert msg.startswith(f"{bad}: SUMO cannot load the network: ")
    assert "':nope_0'" in msg and "via-lane" in msg


def test_a_lead_in_over_a_lane_the_class_may_not_use_is_driven(build_net, table):
    # a bus-only street W-A, then a short general one A-X before the turn at X: a car's
    # 30 m lead-in runs back over the bus lane, where SUMO will not let a car depart
    from clearance.networks.curves import CurveOptions, extract_curves

    net_path = build_net(
        '<node id="W" x="-80" y="0"/><node id="A" x="-10" y="0"/>'
        '<node id="X" x="0" y="0" type="priority"/><node id="N" x="0" y="60"/>',
        '<edge id="WA" from="W" to="A" numLanes="1" allow="bus"/>'
        '<edge id="AX" from="A" to="X" numLanes="1"/>'
        '<edge id="XN" from="X" to="N" numLanes="1"/>',
        None, "--no-turnarounds", name="buslead")
    net = read_network(net_path)
    [turn] = [c for c in extract_curves(net, ["turn"],
                                       options=CurveOptions(approach_length_m=30.0))
              if c.curve_id.startswith("turn:X:")]
    assert any(lane.startswith("WA_") for lane in turn.lanes)  # the lead-in reaches WA
    (run,) = drive(net, [(table.vehicle("P"), turn)])
    assert run.error == "" and run.verdict != "error", run.reason
    assert run.sumo_steps > 0
