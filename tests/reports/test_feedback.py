"""Design feedback on the sample intersection: what each curve serves, where runs overreach."""

from __future__ import annotations

import json
import math

import pytest
import shapely

from clearance.analysis.clearance import Areas, classify
from clearance.analysis.turning import turning_metrics
from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.build import sample_networks
from clearance.reports.exports.geojson import origin_transformer, write_geojson
from clearance.reports.exports.study import envelope_records
from clearance.reports.results.feedback import (
    ENCROACHING,
    not_served_below,
    serves,
    serves_sentence,
    set_serves_up_to,
    size_order,
)
from clearance.reports.study.batch import Batch, detached, run_batch
from clearance.reports.study.run import NetworkCurves, Study
from clearance.vehicles.table import bundled_table, load_tables

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
VEHICLES = ["WB-62", "P", "SU-30"]  # not in size order: the order is the tool's


@pytest.fixture(scope="module")
def study():
    """Junction T of the sample intersection with P, SU-30 and WB-62 (model only, in this
    process), as :func:`clearance.reports.study.run.run_study` completes it."""
    net = read_network(NET)
    curves = [detached(c) for c in extract_curves(net) if c.junction == "T"]
    table = load_tables([bundled_table("aashto_green_book")], VEHICLES)
    vs = tuple(table.vehicles())
    pairs = tuple((v, c) for c in curves for v in range(len(vs)))
    records = run_batch(Batch("intersection", 0, "simulate", 0.0, vs, pairs, use_sumo=False),
                        (str(NET), None))
    set_serves_up_to(records, table)
    return Study(records, [NetworkCurves("intersection", NET, net, curves)], table,
                 "simulate", 0.0)


def _curve(study, cid):
    return next(c for c in study.networks[0].curves if c.curve_id == cid)


def test_vehicles_are_ordered_by_their_curb_to_curb_diameter():
    table = load_tables([bundled_table("aashto_green_book")], VEHICLES)
    d = dict(zip(turning_metrics(table)["vehicle"], turning_metrics(table)["curb_to_curb_m"],
                 strict=True))
    order = size_order(table)
    assert order == ["P", "SU-30", "WB-62"]
    assert [d[n] for n in order] == sorted(d.values())
    # WB-62 and WB-67 share a tractor (the same curb-to-curb): the longer is the larger
    both = load_tables([bundled_table("aashto_green_book")], ["WB-67", "WB-62"])
    assert size_order(both) == ["WB-62", "WB-67"]


def test_a_corner_that_p_clears_and_wb62_does_not_serves_up_to_p(study):
    cid = "turn:T:TS_in_0->TE_out_0"
    runs = {r.vehicle: r for r in study.records if r.curve_id == cid}
    # the sample's designed verdicts (networks/samples/golden_verdicts.csv)
    assert {v: r.verdict for v, r in runs.items()} == {
        "P": "clear", "SU-30": "encroaches", "WB-62": "fails"}
    assert {r.serves_up_to for r in runs.values()} == {"P"}  # on every row of the curve
    assert {r.serves_encroaching_up_to for r in runs.values()} == {"SU-30"}
    # a curve every vehicle clears serves the largest; none that no vehicle clears
    wide = {r.serves_up_to for r in study.records if r.curve_id == "turn:T:TE_in_0->TW_out_0"}
    assert wide == {"WB-62"}
    row = study.frame().set_index(["curve_id", "vehicle"]).loc[(cid, "WB-62")]
    assert (row.serves_up_to, row.serves_encroaching_up_to) == ("P", "SU-30")


def test_a_larger_vehicle_that_clears_where_a_smaller_fails_is_still_the_largest():
    order = ["P", "SU-30", "WB-62"]
    verdicts = {"P": "cannot-turn", "SU-30": "clear", "WB-62": "encroaches"}
    assert serves(verdicts, order) == "SU-30"
    assert serves(verdicts, order, ENCROACHING) == "WB-62"
    assert not_served_below(verdicts, order, "SU-30") == ["P"]
    assert "though the smaller P does not clear it" in serves_sentence(verdicts, order)
    # an error or a vehicle not run on the curve is not a vehicle it serves
    assert serves({"P": "clear"}, order) == "P"
    assert serves({}, order) == ""


def test_each_run_not_clear_has_its_worst_overreach_and_the_width_that_holds_it(study):
    checked = 0
    for r in study.records:
        curve = _curve(study, r.curve_id)
        if r.verdict in ("clear", "cannot-turn"):
            assert math.isnan(r.extra_width_m) and math.isnan(r.overreach_x)
            continue
        area = curve.paved if r.verdict == "fails" else curve.own_lanes
        decisive = r.paved_margin_m if r.verdict == "fails" else r.margin_m
        point = shapely.Point(r.overreach_x, r.overreach_y)
        # the point lies on the envelope, on its part outside the area, as far out as the
        # verdict's margin says (to the search's tolerances)
        assert shapely.distance(point, shapely.difference(r.envelope, area)) < 2e-3
        assert shapely.distance(point, area) == pytest.approx(-decisive, abs=0.03)
        assert r.extra_width_m >= -decisive
        # its station is where it projects onto the curve's centre line
        line = shapely.LineString(curve.centerline[:, :2])
        assert r.overreach_station_m == pytest.approx(line.project(point), abs=2e-3)
        assert 0.0 <= r.overreach_station_m <= line.length
        # the invariant: the area widened by the extra width holds the envelope
        wider = shapely.buffer(area, r.extra_width_m, quad_segs=32)
        areas = (Areas(curve.own_lanes, wider) if r.verdict == "fails"
                 else Areas(wider, curve.paved))
        c = classify(r.envelope, areas)
        assert (c.paved_margin_m if r.verdict == "fails" else c.margin_m) >= 0.0
        assert f"worst at station {r.overreach_station_m:.1f} m" in r.reason
        assert f"{r.extra_width_m:.2f} m more width there" in r.reason
        checked += 1
    assert checked >= 6  # SU-30 encroaches and WB-62 fails on three curves each


def test_the_geojson_has_a_point_at_each_worst_overreach_inside_the_network(study, tmp_path):
    records = envelope_records(study)
    net = study.networks[0].network
    path = write_geojson(tmp_path / "x.geojson", records, {"intersection": net.location})
    doc = json.loads(path.read_text(encoding="utf-8"))
    points = [f for f in doc["features"] if f["geometry"]["type"] == "Point"]
    not_clear = [r for r in study.records if r.verdict in ("fails", "encroaches")]
    assert len(points) == len(not_clear)
    lanes = [shapely.LineString(ln.shape[:, :2]) for ln in net.lanes.values()
             if len(ln.shape) >= 2]
    x0, y0, x1, y1 = shapely.total_bounds(lanes)  # the network's bounds
    by_key = {(r.vehicle, r.curve_id): r for r in not_clear}
    for f in points:
        p = f["properties"]
        r = by_key[(p["vehicle"], p["curve_id"])]
        x, y = f["geometry"]["coordinates"]
        assert x0 <= x <= x1 and y0 <= y <= y1
        assert (x, y) == pytest.approx((r.overreach_x, r.overreach_y), abs=1e-3)
        assert p["feature"] == "worst overreach"
        assert p["beyond"] == ("paved area" if r.verdict == "fails" else "own lanes")
        assert (p["station_m"], p["extra_width_m"]) == pytest.approx(
            (r.overreach_station_m, r.extra_width_m), abs=1e-3)
    # placed on the globe by an origin: lon/lat that map back to the same network point
    origin = (52.0, 13.0)
    path = write_geojson(tmp_path / "y.geojson", records, {"intersection": net.location},
                         origin)
    doc = json.loads(path.read_text(encoding="utf-8"))
    back = origin_transformer(origin)
    off = net.location.net_offset
    for f in (f for f in doc["features"] if f["geometry"]["type"] == "Point"):
        lon, lat = f["geometry"]["coordinates"]
        assert abs(lon - 13.0) < 0.1 and abs(lat - 52.0) < 0.1
        x, y = back.transform(lon, lat, direction="INVERSE")
        r = by_key[(f["properties"]["vehicle"], f["properties"]["curve_id"])]
        assert (x + off[0], y + off[1]) == pytest.approx((r.overreach_x, r.overreach_y),
                                                         abs=0.02)
