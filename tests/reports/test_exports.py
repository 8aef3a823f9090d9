"""Exports of the clearance report: GeoJSON, SUMO additional polygons, DXF."""

from __future__ import annotations

import dataclasses
import datetime
import doctest
import importlib
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import ezdxf
import numpy as np
import pyproj
import pytest
from lxml import etree
from shapely.affinity import translate
from shapely.geometry import LineString, MultiPolygon, Point, Polygon
from shapely.ops import unary_union

from clearance.networks.model import Location
from clearance.networks.reader import read_network
from clearance.networks.sumo.tools import find_sumo_binary, sumo_home
from clearance.reports.exports.dxf import BASE_LAYERS, VERDICT_ACI, dxf_layer_name, write_dxf
from clearance.reports.exports.envelopes import EnvelopeRecord, conflict_parts
from clearance.reports.exports.geojson import (
    COORDS_LOCAL,
    COORDS_LONLAT,
    COORDS_MIXED,
    write_geojson,
)
from clearance.reports.exports.sumo import hole_free_pieces, write_sumo_additional
from clearance.vehicles.errors import GeometryError, InputError

SAMPLES = Path(__file__).resolve().parents[2] / "networks" / "samples"
INTERSECTION = SAMPLES / "intersection" / "intersection.net.xml"
# The right turn T_1_0 of the intersection sample (from its .net.xml).
TURN = LineString([(415.50, 1.75), (407.95, 0.67), (402.56, -2.56), (400.09, -6.69)])
NASTY = 'Bus 12 m & "Co" <art.>'
LOCAL = Location(
    net_offset=(0.0, 0.0),
    conv_boundary=(-120.0, -120.0, 520.0, 120.0),
    orig_boundary=(-120.0, -120.0, 520.0, 120.0),
    proj_parameter="!",
)


def signed_area(ring: list[list[float]]) -> float:
    x, y = np.asarray(ring).T
    return 0.5 * float(np.dot(x[:-1], y[1:]) - np.dot(x[1:], y[:-1]))


def records(network: str = "intersection") -> list[EnvelopeRecord]:
    """Three records: a turn envelope, a ring with a hole, two parts; given out of order."""
    turn = TURN.buffer(2.0)
    ring = Point(405.0, -3.0).buffer(6.0).difference(Point(405.0, -3.0).buffer(2.0))
    parts = MultiPolygon([Point(380.0, 0.0).buffer(1.0), Point(370.0, 5.0).buffer(1.5)])
    return [
        EnvelopeRecord(network, "Car", ":T_1_0", "turn", "clear", 0.41449, parts),
        EnvelopeRecord(network, NASTY, ":T_1_0", "turn", "encroaches", -0.123456, turn),
        EnvelopeRecord(network, NASTY, ":T_0_0", "turn", "cannot-turn", math.nan, ring),
    ]


# --------------------------------------------------------------------------- GeoJSON


def test_geojson_local_metres(tmp_path: Path):
    path = write_geojson(tmp_path / "swept.geojson", records(), {"intersection": LOCAL})
    doc = json.loads(path.read_text(encoding="utf-8"))
    assert doc["type"] == "FeatureCollection"
    assert doc["coordinate_system"] == COORDS_LOCAL
    assert "coordinates" not in doc  # RFC 7946 section 7.1
    assert doc["networks"] == {"intersection": {"net_offset": [0.0, 0.0], "proj_parameter": "!"}}
    feats = doc["features"]
    keys = [(f["properties"]["vehicle"], f["properties"]["curve_id"]) for f in feats]
    assert keys == [(NASTY, ":T_0_0"), (NASTY, ":T_1_0"), ("Car", ":T_1_0")]
    assert [f["properties"]["margin_m"] for f in feats] == [None, -0.123, 0.414]
    assert feats[1]["properties"] == {
        "network": "intersection",
        "vehicle": NASTY,
        "curve_id": ":T_1_0",
        "kind": "turn",
        "verdict": "encroaches",
        "margin_m": -0.123,
    }
    assert [f["geometry"]["type"] for f in feats] == ["Polygon", "Polygon", "MultiPolygon"]
    recs = sorted(records(), key=lambda r: (r.vehicle, r.curve_id))
    for feat, rec in zip(feats, recs, strict=True):
        geom = feat["geometry"]
        polys = [geom["coordinates"]] if geom["type"] == "Polygon" else geom["coordinates"]
        for rings in polys:
            for i, ring in enumerate(rings):
                assert len(ring) >= 4 and ring[0] == ring[-1]
                assert (signed_area(ring) > 0) == (i == 0)  # exterior CCW, holes CW
        back = unary_union([Polygon(p[0], p[1:]) for p in polys])
        # 1 mm rounding: the areas agree to well under a square centimetre per metre
        assert back.symmetric_difference(rec.envelope).area < 1e-3 * rec.envelope.length
    assert len(feats[0]["geometry"]["coordinates"]) == 2  # the ring keeps its hole
    assert pyproj.CRS(doc["crs"]["properties"]["name"]).is_engineering


OGRINFO = "/usr/bin/ogrinfo"


@pytest.mark.skipif(not os.path.exists(OGRINFO), reason="GDAL's ogrinfo (Debian gdal-bin) "
                    "is not installed; .ci/run installs it")
def test_gdal_reads_local_metres_as_a_local_crs_and_lonlat_as_wgs84(tmp_path: Path,
                                                                      projected_net: Path):
    """As QGIS would: GDAL reads the local-metres file in a local engineering CRS (never on
    the globe, where metres read as degrees put a town in the South Atlantic), and a
    projected network's file in WGS 84."""
    local = write_geojson(tmp_path / "n.local-metres.geojson", records(),
                          {"intersection": LOCAL})
    said = subprocess.run([OGRINFO, "-so", "-al", str(local)], capture_output=True, text=True,
                          check=True).stdout
    assert "ENGCRS" in said and "SUMO network plane" in said and "WGS 84" not in said
    loc = read_network(projected_net).location
    x0, y0, x1, y1 = loc.conv_boundary
    rec = EnvelopeRecord(projected_net.stem, "Bus", "c1", "bend", "fails", -1.5,
                         Point((x0 + x1) / 2, (y0 + y1) / 2).buffer(5.0))
    lonlat = write_geojson(tmp_path / "p.geojson", [rec], {rec.network: loc})
    said = subprocess.run([OGRINFO, "-so", "-al", str(lonlat)], capture_output=True,
                          text=True, check=True).stdout
    assert "WGS 84" in said and "ENGCRS" not in said


def test_geojson_is_byte_identical_and_order_independent(tmp_path: Path):
    a = write_geojson(tmp_path / "a.geojson", records(), {"intersection": LOCAL})
    b = write_geojson(tmp_path / "b.geojson", records()[::-1], {"intersection": LOCAL})
    c = write_geojson(tmp_path / "a.geojson", records(), {"intersection": LOCAL})
    assert a.read_bytes() == b.read_bytes() == c.read_bytes()
    assert not list(tmp_path.glob(".*.tmp"))


@pytest.fixture(scope="module")
def projected_net() -> Path:
    game = sumo_home() / "tools" / "game"
    for rel in ("racing/spreewaldring.net.xml", "highway/highway.net.xml"):
        if (game / rel).is_file():
            return game / rel
    pytest.skip(f"no projected OSM network under {game} (eclipse-sumo without tools/game?)")


def test_geojson_lonlat_for_a_projected_network(tmp_path: Path, projected_net: Path):
    loc = read_network(projected_net).location
    assert loc.proj_parameter.startswith("+proj=utm")
    x0, y0, x1, y1 = loc.conv_boundary
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    env = Point(cx, cy).buffer(10.0).difference(Point(cx, cy).buffer(3.0))
    rec = EnvelopeRecord(projected_net.stem, "Bus", "c1", "bend", "fails", -1.5, env)
    doc = json.loads(
        write_geojson(tmp_path / "s.geojson", [rec], {rec.network: loc}).read_text("utf-8")
    )
    assert doc["coordinate_system"] == COORDS_LONLAT
    outer, hole = doc["features"][0]["geometry"]["coordinates"]
    assert signed_area(outer) > 0 > signed_area(hole)
    lon0, lat0, lon1, lat1 = loc.orig_boundary  # OSM imports: the lon/lat box
    for lon, lat in outer + hole:
        assert -180 <= lon <= 180 and -90 <= lat <= 90
        assert lon0 < lon < lon1 and lat0 < lat < lat1
    # back through the projection: the same SUMO points to about a centimetre
    proj = pyproj.Proj(loc.proj_parameter)
    x, y = proj(*np.asarray(outer).T)
    xy = np.column_stack([x + loc.net_offset[0], y + loc.net_offset[1]])
    assert np.hypot(*(xy - np.asarray(orient_ccw(env.exterior.coords))).T).max() < 0.02
    assert math.hypot(xy[:, 0].mean() - cx, xy[:, 1].mean() - cy) < 0.5


def test_dxf_of_a_projected_network_lies_in_its_crs(tmp_path: Path, projected_net: Path):
    """Drawn in the projected CRS: each vertex is SUMO's less netOffset, which PROJ takes back to
    the network's own lon/lat box; the header names the CRS and the extents follow."""
    net = read_network(projected_net)
    loc = net.location
    x0, y0, x1, y1 = loc.conv_boundary
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    env = Point(cx, cy).buffer(10.0)
    rec = EnvelopeRecord(projected_net.stem, "Bus", "c1", "bend", "fails", -1.5, env)
    doc = ezdxf.readfile(write_dxf(tmp_path / "p.dxf", [rec], net))
    assert doc.header.custom_vars.get("CRS") == loc.proj_parameter
    msp = doc.modelspace()
    [outline] = [e for e in msp.query("LWPOLYLINE") if e.dxf.layer.endswith("-ENVELOPE")]
    pts = np.asarray(outline.get_points("xy"))
    sumo = np.asarray(orient_ccw(env.exterior.coords))[:-1]
    shifted = sumo - np.asarray(loc.net_offset)
    assert min(np.hypot(*(pts - p).T).min() for p in shifted) < 1e-3  # to the millimetre
    lon, lat = pyproj.Proj(loc.proj_parameter)(*pts.T, inverse=True)
    lon0, lat0, lon1, lat1 = loc.orig_boundary
    assert ((lon0 < lon) & (lon < lon1) & (lat0 < lat) & (lat < lat1)).all()
    lo, hi = doc.header["$EXTMIN"], doc.header["$EXTMAX"]
    assert lo[0] <= pts[:, 0].min() and hi[1] >= pts[:, 1].max()
    assert hi[0] - lo[0] < 1e4  # the base plan near the envelope, not the globe


def orient_ccw(coords) -> list[tuple[float, float]]:
    pts = list(coords)
    x, y = np.asarray(pts).T
    return pts if np.dot(x[:-1], y[1:]) - np.dot(x[1:], y[:-1]) > 0 else pts[::-1]


def test_geojson_mixed_networks_are_local_metres(tmp_path: Path, projected_net: Path):
    loc = read_network(projected_net).location
    recs = records() + [
        EnvelopeRecord("osm", "Car", "c", "bend", "clear", 0.2, Point(50, 50).buffer(2))
    ]
    path = write_geojson(tmp_path / "m.geojson", recs, {"intersection": LOCAL, "osm": loc})
    doc = json.loads(path.read_text("utf-8"))
    assert doc["coordinate_system"] == COORDS_MIXED
    osm = [f for f in doc["features"] if f["properties"]["network"] == "osm"][0]
    x, y = np.asarray(osm["geometry"]["coordinates"][0]).T
    assert x.min() == pytest.approx(48.0, abs=1e-3) and y.max() == pytest.approx(52.0, abs=1e-3)


def test_geojson_bad_inputs(tmp_path: Path):
    out = tmp_path / "bad.geojson"
    empty = EnvelopeRecord("intersection", "Van", "c9", "turn", "clear", 0.1, Polygon())
    with pytest.raises(GeometryError, match="intersection/Van/c9.*empty"):
        write_geojson(out, [empty], {"intersection": LOCAL})
    point = EnvelopeRecord("intersection", "Van", "c9", "turn", "clear", 0.1, Point(0, 0))
    with pytest.raises(ValueError, match="Polygon or MultiPolygon, got Point"):
        write_geojson(out, [point], {"intersection": LOCAL})
    wrong = EnvelopeRecord("intersection", "Van", "c9", "turn", "ok", 0.1, TURN.buffer(1))
    with pytest.raises(ValueError, match="unknown verdict 'ok'"):
        write_geojson(out, [wrong], {"intersection": LOCAL})
    with pytest.raises(InputError, match="no location given for network.*intersection"):
        write_geojson(out, records(), {})
    bad = Location(proj_parameter="+proj=nonsense +zone=99")
    with pytest.raises(InputError, match="network intersection: cannot use its projParameter"):
        write_geojson(out, records(), {"intersection": bad})
    assert not out.exists()


# --------------------------------------------------------------------------- SUMO


def test_sumo_additional_loads_in_sumo(tmp_path: Path):
    try:
        sumo = find_sumo_binary("sumo")
    except FileNotFoundError as exc:  # pragma: no cover - depends on the install
        pytest.skip(f"sumo is not available: {exc}")
    recs = records()
    path = write_sumo_additional(tmp_path / "swept.add.xml", recs)
    root = etree.parse(str(path)).getroot()
    polys = root.findall("poly")
    ids = [p.get("id") for p in polys]
    assert len(set(ids)) == len(ids) == 1 + 2 + 2  # turn, two parts, a ring cut in two
    assert "swept:intersection:Bus_12_m_Co_art.:T_1_0:0" in ids
    assert not any(c in i for i in ids for c in " &\"<>',;|")
    by_vehicle: dict[str, list[Polygon]] = {}
    for p in polys:
        params = {q.get("key"): q.get("value") for q in p.findall("param")}
        assert p.get("type") == f"swept:{params['verdict']}"
        assert p.get("fill") == "1"
        pts = [tuple(map(float, xy.split(","))) for xy in p.get("shape").split()]
        by_vehicle.setdefault(f"{params['vehicle']}|{params['curve_id']}", []).append(Polygon(pts))
        if params["verdict"] == "encroaches":
            assert params["vehicle"] == NASTY and params["margin_m"] == "-0.123"
            assert p.get("color") == "255,140,0,128"
        if params["verdict"] == "cannot-turn":
            assert "margin_m" not in params
    for rec in recs:
        pieces = by_vehicle[f"{rec.vehicle}|{rec.curve_id}"]
        assert unary_union(pieces).symmetric_difference(rec.envelope).area < 0.01

    env = dict(os.environ, SUMO_HOME=str(sumo_home()))
    # --fcd-output.filter-shapes fails on a shape id SUMO did not load: this proves that
    # every polygon was read, not merely that the file parsed.
    cmd = [
        str(sumo),
        "-n",
        str(INTERSECTION),
        "-a",
        str(path),
        "--end",
        "1",
        "--no-step-log",
        "--fcd-output",
        str(tmp_path / "fcd.xml"),
        "--fcd-output.filter-shapes",
        ",".join(ids),
    ]
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "Error" not in run.stderr and "Invalid characters" not in run.stderr, run.stderr
    cmd[-1] = "swept:not-there"  # the control: SUMO does complain about an unknown shape
    control = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=60)
    assert "'swept:not-there' for filtering fcd-output could not be found" in control.stderr


def test_hole_free_pieces_cover_the_same_area():
    two_holes = (
        Point(0, 0).buffer(10).difference(Point(-4, 0).buffer(2)).difference(Point(4, 3).buffer(1))
    )
    pieces = hole_free_pieces(two_holes)
    assert all(not p.interiors for p in pieces) and len(pieces) >= 3
    assert sum(p.area for p in pieces) == pytest.approx(two_holes.area, rel=1e-9)
    assert unary_union(pieces).symmetric_difference(two_holes).area < 1e-6


def test_sumo_additional_bad_input(tmp_path: Path):
    ctrl = EnvelopeRecord("intersection", "Car\x01", "c", "turn", "clear", 0.1, TURN.buffer(1))
    with pytest.raises(ValueError, match="cannot be written as XML"):
        write_sumo_additional(tmp_path / "bad.add.xml", [ctrl])


# --------------------------------------------------------------------------- DXF


def test_dxf_reopens_with_layers_and_vertices(tmp_path: Path):
    recs = records()
    path = write_dxf(tmp_path / "swept.dxf", recs)
    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 6
    names = {layer.dxf.name for layer in doc.layers} - {"0", "Defpoints"}
    nasty = dxf_layer_name(NASTY)
    assert nasty != NASTY
    assert names == {f"{v}-{s}" for v in ("Car", nasty) for s in ("ENVELOPE", "LABEL")}
    assert doc.layers.get(f"{nasty}-ENVELOPE").description.startswith(NASTY + ": ")
    msp = doc.modelspace()
    for rec in recs:
        layer = f"{dxf_layer_name(rec.vehicle)}-ENVELOPE"
        lines = [
            e
            for e in msp.query(f'LWPOLYLINE[layer=="{layer}"]')
            if f"curve_id={rec.curve_id}" in [t.value for t in e.get_xdata("SUMO_CLEARANCE")]
        ]
        parts = list(getattr(rec.envelope, "geoms", [rec.envelope]))
        rings = [r for p in parts for r in [p.exterior, *p.interiors]]
        assert len(lines) == len(rings)
        for line in lines:
            assert line.closed and line.dxf.color == VERDICT_ACI[rec.verdict]
            pts = np.asarray(line.get_points("xy"))
            # every vertex is a vertex of the input, rounded to the millimetre
            match = [
                r
                for r in rings
                if len(r.coords) - 1 == len(pts)
                and np.abs(np.sort(np.asarray(r.coords)[:-1], axis=0) - np.sort(pts, axis=0)).max()
                <= 5e-4 + 1e-9
            ]
            assert len(match) == 1
            assert np.allclose(pts, np.round(pts, 3), rtol=0, atol=1e-9)
        label = f"{dxf_layer_name(rec.vehicle)}-LABEL"
        texts = [t.dxf.text for t in msp.query(f'TEXT[layer=="{label}"]')]
        assert rec.curve_id in texts


def test_dxf_base_plan_and_conflict_layers(tmp_path: Path):
    net = read_network(INTERSECTION)
    turn = translate(TURN, -400.0, 0.0)  # at the 2+2-lane crossing X of the sample
    lanes, paved = turn.buffer(1.6, cap_style="flat"), turn.buffer(4.0, cap_style="flat")
    env = turn.buffer(2.5, cap_style="flat")  # 0.9 m beyond its lanes each side, paved
    body = turn.buffer(2.2)
    wheel = turn.offset_curve(1.0)
    outside_lanes, outside_pavement = conflict_parts(env, lanes, paved)
    rec = EnvelopeRecord("intersection", "P", ":X_1_0", "turn", "encroaches", -0.9, env,
                         offset_m=0.3, body_envelope=body, outside_lanes=outside_lanes,
                         outside_pavement=outside_pavement, body_outlines=(turn.buffer(1.0),),
                         wheel_paths=(wheel,))
    path = write_dxf(tmp_path / "intersection.dxf", [rec], net)
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    assert not auditor.has_errors and not auditor.has_fixes
    names = {layer.dxf.name for layer in doc.layers} - {"0", "Defpoints"}
    assert names == set(BASE_LAYERS) | {
        "P-ENVELOPE", "P-CLEARANCE-ENVELOPE", "P-CONFLICT-LANE", "P-BODY", "P-WHEEL-PATH",
        "P-LABEL"}  # no conflict with the pavement: no such layer
    assert doc.layers.get("BASE-LANE-LINE").dxf.linetype == "DASHED"
    msp = doc.modelspace()

    def area(layer: str) -> float:
        return sum(Polygon(e.get_points("xy")).area
                   for e in msp.query(f'LWPOLYLINE[layer=="{layer}"]'))

    # the vertices to the millimetre: the area to half a millimetre times the perimeter
    assert area("P-CLEARANCE-ENVELOPE") == pytest.approx(env.area, abs=5e-4 * env.length)
    assert area("P-ENVELOPE") == pytest.approx(body.area, abs=5e-4 * body.length)
    conflict = env.difference(lanes)
    assert area("P-CONFLICT-LANE") == pytest.approx(conflict.area, abs=5e-4 * conflict.length)
    assert len(msp.query('HATCH[layer=="P-CONFLICT-LANE"]')) == 2  # one each side
    (wheel_line,) = msp.query('LWPOLYLINE[layer=="P-WHEEL-PATH"]')
    assert not wheel_line.closed
    assert LineString(wheel_line.get_points("xy")).length == pytest.approx(wheel.length,
                                                                          rel=1e-4)
    # the base plan: the pavement's edges enclose the lanes of the sample near the turn
    edges = [Polygon(e.get_points("xy"))
             for e in msp.query('LWPOLYLINE[layer=="BASE-PAVEMENT-EDGE"]')]
    probe = turn.interpolate(0.5, normalized=True)
    assert any(e.contains(probe) for e in edges)
    assert not any(e.contains(Point(probe.x + 40.0, probe.y - 40.0)) for e in edges)
    lines = msp.query('LWPOLYLINE[layer=="BASE-LANE-LINE"]')
    assert len(lines) > 0 and all(not e.closed for e in lines)
    assert len(msp.query('LWPOLYLINE[layer=="BASE-JUNCTION"]')) >= 1
    # the header's extents hold every vertex drawn (ezdxf's own bounding box of the
    # polylines' points, not our arithmetic), within a label's height
    from ezdxf import bbox

    ext = bbox.extents(msp.query("LWPOLYLINE"))
    lo, hi = doc.header["$EXTMIN"], doc.header["$EXTMAX"]
    assert lo[0] == pytest.approx(ext.extmin.x, abs=1e-6)
    assert lo[1] == pytest.approx(ext.extmin.y, abs=1e-6)
    assert hi[0] == pytest.approx(ext.extmax.x, abs=1e-6)
    assert hi[1] == pytest.approx(ext.extmax.y, abs=1e-6)
    assert doc.header["$INSUNITS"] == 6


def test_conflict_parts_doctest_and_plan():
    module = importlib.import_module("clearance.reports.exports.envelopes")
    failures, tried = doctest.testmod(module)
    assert tried > 0 and failures == 0


DXF_SCRIPT = """
import sys
sys.path.insert(0, sys.argv[2])
from test_exports import records
from clearance.reports.exports.dxf import write_dxf
write_dxf(sys.argv[1], records())
"""


def test_dxf_coordinates_are_written_to_the_millimetre(tmp_path: Path):
    """No coordinate of the drawing carries more than three decimals (a plan is never drawn
    finer than a millimetre), so the file is about half the size of one of 17-digit floats."""
    path = write_dxf(tmp_path / "mm.dxf", records(), read_network(INTERSECTION))
    lines = path.read_text(encoding="utf-8").splitlines()
    values = [lines[i + 1].strip() for i in range(len(lines) - 1)
              if lines[i].strip() in ("10", "20") and i % 2 == 0]
    assert len(values) > 100
    assert all(len(v.split(".", 1)[1]) <= 3 for v in values if "." in v and "e" not in v)


def test_dxf_is_byte_identical_for_identical_inputs(tmp_path: Path):
    # Two processes with different string hashing (ezdxf collects the classes in use in a
    # set) at different clock times: the same bytes, and an audit finds nothing.
    here = str(Path(__file__).resolve().parent)
    files = []
    for seed in ("1", "2"):
        out = tmp_path / f"swept{seed}.dxf"
        env = dict(os.environ, PYTHONHASHSEED=seed)
        subprocess.run([sys.executable, "-c", DXF_SCRIPT, str(out), here], check=True,
                       env=env, timeout=120)
        files.append(out.read_bytes())
    assert files[0] == files[1]
    text = files[0].decode("utf-8")
    assert "{00000000-0000-0000-0000-000000000000}" in text  # no random GUID
    assert f"{datetime.date.today().year}-" not in text  # no clock time
    doc = ezdxf.readfile(tmp_path / "swept1.dxf")
    auditor = doc.audit()
    assert not auditor.has_errors and not auditor.has_fixes
    assert len(doc.modelspace().query("LWPOLYLINE")) == 5  # 2 parts + turn + ring and hole
    assert [c.dxf.name for c in doc.classes] == sorted(c.dxf.name for c in doc.classes)


def test_dxf_layer_names_are_sanitised():
    assert dxf_layer_name("a<b>c/d\\e\"f:g;h?i*j|k=l'm`n,o") == "a_b_c_d_e_f_g_h_i_j_k_l_m_n_o"
    assert dxf_layer_name("Bus 12 m") == "Bus 12 m"


@pytest.mark.parametrize("name", ["clearance.reports.exports.sumo", "clearance.reports.exports.dxf",
                                  "clearance.reports.exports.geojson"])
def test_docstring_examples(name: str):
    failures, tried = doctest.testmod(importlib.import_module(name))
    assert tried > 0 and failures == 0


# --------------------------------------------------------------------------- worst overreach


def _with_overreach() -> list[EnvelopeRecord]:
    recs = records()
    recs[1] = dataclasses.replace(recs[1], overreach=(407.95, 2.67, 38.5, 0.16))
    return recs


def test_geojson_and_dxf_mark_the_worst_overreach_as_a_point(tmp_path: Path):
    doc = json.loads(write_geojson(tmp_path / "a.geojson", _with_overreach(),
                                   {"intersection": LOCAL}).read_text(encoding="utf-8"))
    points = [f for f in doc["features"] if f["geometry"]["type"] == "Point"]
    assert len(doc["features"]) == 4 and doc["features"][-1] is points[0]
    assert points[0]["geometry"]["coordinates"] == [407.95, 2.67]
    assert points[0]["properties"] == {
        "network": "intersection", "vehicle": NASTY, "curve_id": ":T_1_0", "kind": "turn",
        "verdict": "encroaches", "feature": "worst overreach", "beyond": "own lanes",
        "margin_m": -0.123, "station_m": 38.5, "extra_width_m": 0.16}
    path = write_dxf(tmp_path / "a.dxf", _with_overreach())
    msp = ezdxf.readfile(path).modelspace()
    layer = f"{dxf_layer_name(NASTY)}-OVERREACH"
    [point] = msp.query(f'POINT[layer=="{layer}"]')
    assert tuple(point.dxf.location)[:2] == pytest.approx((407.95, 2.67))
    assert [t.dxf.text for t in msp.query(f'TEXT[layer=="{layer}"]')] == ["+0.16 m"]
    # no overreach, no point and no layer
    assert not ezdxf.readfile(write_dxf(tmp_path / "b.dxf", records())).modelspace().query(
        "POINT")


def test_an_overreach_that_is_not_four_finite_numbers_is_refused(tmp_path: Path):
    bad = records()
    bad[1] = dataclasses.replace(bad[1], overreach=(1.0, math.nan, 2.0, 0.1))
    with pytest.raises(ValueError, match="overreach must be four finite numbers"):
        write_geojson(tmp_path / "a.geojson", bad, {"intersection": LOCAL})
