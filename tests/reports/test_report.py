"""`clearance report` as a user runs it: every output, determinism, atomicity."""

import base64
import csv
import html
import io
import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path

import ezdxf
import pyproj
import pytest
import sumo

from clearance.networks.reader import read_network
from clearance.networks.samples.build import sample_networks
from clearance.reports.cli.main import main
from clearance.reports.study.run import COLUMNS

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
VEHICLES = ["P", "CITY-BUS"]


def run_report(out: Path, *extra: str) -> int:
    args = ["report", "-n", str(NET), "-o", str(out)]
    for v in VEHICLES:
        args += ["--vehicle", v]
    return main(args + list(extra))


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("rep") / "report"
    assert run_report(out) == 0
    return out


@pytest.fixture(scope="module")
def rows(report) -> list[dict[str, str]]:
    with open(report / "clearance.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def test_clearance_csv_has_every_run_and_the_columns(report, rows):
    assert list(rows[0]) == COLUMNS
    curves = {r["curve_id"] for r in rows}
    assert len(rows) == len(curves) * len(VEHICLES) and len(curves) >= 10
    assert {r["vehicle"] for r in rows} == set(VEHICLES)
    assert {r["method"] for r in rows} == {"simulate"}
    by = {(r["vehicle"], r["curve_id"]): r for r in rows}
    # the designed corner of the four-leg junction: the car clears, the bus does not on
    # its lane; it swings into the two opposing lanes and stays paved
    assert by[("P", "turn:X:XN_in_0->XW_out_0")]["verdict"] == "clear"
    bus = by[("CITY-BUS", "turn:X:XN_in_0->XW_out_0")]
    assert (bus["lane_verdict"], bus["verdict"]) == ("fails", "encroaches")
    for r in rows:
        margin = float(r["margin_m"])
        assert (margin >= 0) == (r["verdict"] == "clear") or r["verdict"] == "cannot-turn"


def test_summary_json_counts_inputs_and_versions(report, rows):
    s = json.loads((report / "summary.json").read_text())
    assert s["runs"] == len(rows)
    assert sum(s["verdicts"].values()) == len(rows)
    by_vehicle = s["by_vehicle"]["P"]
    assert sum(by_vehicle.values()) == len(rows) // 2
    assert by_vehicle["clear"] == sum(1 for r in rows if r["vehicle"] == "P"
                                      and r["verdict"] == "clear")
    (net,) = s["inputs"]["networks"]
    import hashlib
    assert net["sha256"] == hashlib.sha256(NET.read_bytes()).hexdigest()
    assert all(len(t["sha256"]) == 64 for t in s["inputs"]["vehicle_tables"])
    assert s["versions"]["sumo"][0].isdigit()


def test_a_hand_drawn_network_rests_on_data_and_its_patches_touch_nothing(report, rows):
    """The intersection sample gives every width and draws its junctions: every verdict rests
    on data, the summary says so, and the fit patches propose nothing (no default to fit);
    the vTypes are still written, one per vehicle."""
    from lxml import etree

    assert {r["geometry"] for r in rows} == {"data"}
    bad = [r for r in rows if r["verdict"] in ("encroaches", "fails", "cannot-turn")]
    assert bad and all(r["conflict_at"] for r in bad)
    assert all(not r["conflict_at"] for r in rows if r["verdict"] == "clear")
    s = json.loads((report / "summary.json").read_text())
    assert s["geometry"]["intersection"]["not_clear"] == {
        "runs": len(bad), "on_data": len(bad), "on_defaults": 0}
    patches = report / "patches"
    assert sorted(p.name for p in patches.iterdir()) == [
        "intersection.fit.edg.xml", "intersection.fit.nod.xml",
        "intersection.restrict.con.xml", "intersection.vtypes.xml"]
    assert not etree.parse(str(patches / "intersection.fit.edg.xml")).getroot().findall("edge")
    assert not etree.parse(str(patches / "intersection.fit.nod.xml")).getroot().findall("node")
    types = etree.parse(str(patches / "intersection.vtypes.xml")).getroot().findall("vType")
    assert [t.get("id") for t in types] == list(VEHICLES)


def test_html_is_self_contained(report):
    html = (report / "report.html").read_text()
    refs = re.findall(r'(?:src|href)\s*=\s*"([^"]*)"', html)
    assert refs and all(r.startswith("data:") or r.startswith("#") for r in refs)
    assert "http://" not in html and "https://" not in html
    assert "<link" not in html and "<script" not in html
    assert "turn:X:XN_in_0-&gt;XW_out_0" in html


def test_html_contents_links_and_captions(report, rows):
    text = (report / "report.html").read_text()
    ids = set(re.findall(r'\sid="([^"]+)"', text))
    hrefs = re.findall(r'href="#([^"]+)"', text)
    assert set(hrefs) <= ids  # every link has its target
    assert '<nav class="toc"' in text and 'href="#net-intersection-' in text
    # every matrix row and cell links to its curve's section, and that section lists every
    # vehicle run on the curve, margins in words with the paved margin
    matrix = re.findall(r'<tr><td class="id" title="([^"]+)"><a href="#(curve-[^"]+)">[^<]+</a>'
                        r'</td>(.*?)</tr>', text)
    matrix = [(target, cid, cells) for cid, target, cells in matrix]  # the full id: title
    assert matrix
    for target, cid, cells in matrix:
        assert cells.count(f'href="#{target}"') == len(VEHICLES)
        section = text.split(f'id="{target}"', 1)[1].split("<h4", 1)[0]
        curve = html.unescape(cid)
        runs = [r for r in rows if r["curve_id"] == curve]
        assert len(runs) == len(VEHICLES)
        for r in runs:
            found = re.search(re.escape(f"{r['vehicle']}: {r['verdict']}, ")
                              + r"(?:([\d.]+) m (beyond|inside) its lanes|no margin)"
                              r"(?:, ([\d.]+) m (beyond|inside) the pavement)?", section)
            assert found, (curve, r["vehicle"])
            for value, side, column in ((found[1], found[2], "margin_m"),
                                        (found[3], found[4], "paved_margin_m")):
                m = float(r[column])
                if not math.isfinite(m):
                    assert value is None
                    continue
                signed = float(value) * (-1 if side == "beyond" else 1)
                assert signed == pytest.approx(m, abs=0.0051)
    assert not re.search(r"(?<![\d.])1 (vehicles|curves|runs|networks)\b", text)
    # compact figures, loaded lazily below the plan
    assert text.count('loading="lazy"') == text.count("<img") - 1
    assert len(text.encode()) < 1_000_000


def test_the_report_says_every_swung_path_and_what_each_curve_serves(report, rows):
    text = html.unescape(re.sub(r"<[^>]+>", " ", (report / "report.html").read_text()))
    swung = [r for r in rows if r["path"] == "swung"]
    assert swung, "the sample has swung runs"
    by_curve: dict[str, list[dict[str, str]]] = {}
    for r in rows:
        by_curve.setdefault(r["curve_id"], []).append(r)
    for r in swung:
        # the path in words: a swing out, a line of its own, or a corner cut
        assert r["reason"].startswith(("swings ", "takes its own line: ", "cuts the corner "))
        assert " m out" in r["reason"] or " m in" in r["reason"] or "inside" in r["reason"]
        # in its curve's section, or (a curve clear with room to spare) under the matrix
        assert f"{r['vehicle']}: {r['verdict']}" in text
        assert r["reason"] in " ".join(text.split())
    for r in rows:
        if r["verdict"] in ("fails", "encroaches"):
            assert float(r["extra_width_m"]) >= -float(
                r["paved_margin_m"] if r["verdict"] == "fails" else r["margin_m"])
            assert "worst at station" in r["reason"]
        else:
            assert r["extra_width_m"] == r["overreach_x"] == ""
    # the designed corner of the four-leg junction: the car clears it, the bus fails
    corner = by_curve["turn:X:XN_in_0->XW_out_0"]
    assert {r["serves_up_to"] for r in corner} == {"P"}
    assert "Serves up to P (clear)" in text
    assert "Design feedback: curves by what they serve up to" in text


def test_markdown_links_its_figures(report):
    md = (report / "report.md").read_text()
    links = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md)
    assert links
    for link in links:
        png = report / link
        assert png.is_file()
    assert not list((report / "figures").rglob("*.svg"))  # SVG only when asked (--svg)


def test_geojson_is_valid(report, rows):
    # the sample has no projection: a file named and described as local metres, no crs
    gj = json.loads((report / "exports" / "intersection.local-metres.geojson").read_text())
    assert gj["type"] == "FeatureCollection"
    assert "local metres" in gj["coordinate_system"]
    assert gj["crs"]["properties"]["name"].startswith("ENGCRS[")  # never read as WGS84
    envelopes = [f for f in gj["features"] if f["geometry"]["type"] != "Point"]
    points = [f for f in gj["features"] if f["geometry"]["type"] == "Point"]
    assert len(envelopes) == len(rows)
    # a point at the worst overreach of every run that fails or encroaches
    not_clear = {(r["vehicle"], r["curve_id"]) for r in rows
                 if r["verdict"] in ("fails", "encroaches")}
    assert {(f["properties"]["vehicle"], f["properties"]["curve_id"]) for f in points} == \
        not_clear and len(points) == len(not_clear)
    for f in envelopes:
        assert f["type"] == "Feature"
        assert f["geometry"]["type"] in ("Polygon", "MultiPolygon")
        polys = (f["geometry"]["coordinates"] if f["geometry"]["type"] == "MultiPolygon"
                 else [f["geometry"]["coordinates"]])
        for poly in polys:
            for ring in poly:
                assert len(ring) >= 4 and ring[0] == ring[-1]
        assert f["properties"]["verdict"] in ("clear", "encroaches", "fails", "cannot-turn")


def test_sumo_loads_the_polygons(report):
    env = dict(os.environ, SUMO_HOME=sumo.SUMO_HOME)
    proc = subprocess.run([str(Path(sumo.SUMO_HOME) / "bin" / "sumo"), "-n", str(NET),
                           "-a", str(report / "exports" / "intersection.add.xml"), "--end", "1",
                           "--no-step-log", "true"], capture_output=True, text=True, env=env,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "Error" not in proc.stderr


def test_dxf_reopens_with_the_base_plan_and_layers_per_vehicle(report, rows):
    doc = ezdxf.readfile(report / "exports" / "intersection.dxf")
    auditor = doc.audit()
    assert not auditor.has_errors and not auditor.has_fixes
    layers = {layer.dxf.name for layer in doc.layers}
    assert {"BASE-PAVEMENT-EDGE", "BASE-LANE-LINE", "BASE-JUNCTION", "P-ENVELOPE",
            "P-LABEL", "CITY-BUS-ENVELOPE", "CITY-BUS-CONFLICT-LANE"} <= layers
    msp = doc.modelspace()
    labels = [t.dxf.text for t in msp.query('TEXT[layer=="P-LABEL"]')]
    assert set(labels) == {r["curve_id"] for r in rows if r["vehicle"] == "P"}
    assert len(msp.query('LWPOLYLINE[layer=="BASE-PAVEMENT-EDGE"]')) >= 1
    # the bus encroaches somewhere (the sample's design): its conflict is hatched
    assert any(r["verdict"] != "clear" for r in rows if r["vehicle"] == "CITY-BUS")
    assert len(msp.query('HATCH[layer=="CITY-BUS-CONFLICT-LANE"]')) >= 1
    # the worst run of each curve is drawn with its body at intervals and its wheel paths:
    # seven outlines of four corners, and the paths of the outer front and inner rear wheel
    bodies = msp.query('LWPOLYLINE[layer=="CITY-BUS-BODY"]')
    assert len(bodies) >= 7 and all(len(b) == 4 for b in bodies)
    assert len(msp.query('LWPOLYLINE[layer=="CITY-BUS-WHEEL-PATH"]')) >= 2


def test_exports_per_network_in_each_networks_coordinates(tmp_path):
    nets = [NET, next(p for p in sample_networks() if p.stem.startswith("roundabout"))]
    out = tmp_path / "two"
    args = ["report", "-o", str(out), "--vehicle", "P", "--method", "analytic"]
    assert main(args + [a for n in nets for a in ("-n", str(n))]) == 0
    names = sorted(p.name for p in (out / "exports").iterdir())
    assert names == sorted(f"{n}{s}" for n in ("intersection", "roundabout")
                           for s in (".add.xml", ".dxf", ".local-metres.geojson"))
    env = dict(os.environ, SUMO_HOME=sumo.SUMO_HOME)
    for net in nets:
        name = net.name.removesuffix(".net.xml")
        gj = json.loads((out / "exports" / f"{name}.local-metres.geojson").read_text())
        assert {f["properties"]["network"] for f in gj["features"]} == {name}
        # every envelope lies on its own network (within its boundary, plus a car length)
        x0, y0, x1, y1 = read_network(net).location.conv_boundary
        for f in gj["features"]:
            xy = [p for poly in ([f["geometry"]["coordinates"]]
                                 if f["geometry"]["type"] == "Polygon"
                                 else f["geometry"]["coordinates"]) for ring in poly
                  for p in ring]
            assert all(x0 - 6 < x < x1 + 6 and y0 - 6 < y < y1 + 6 for x, y in xy)
        add = out / "exports" / f"{name}.add.xml"
        proc = subprocess.run([str(Path(sumo.SUMO_HOME) / "bin" / "sumo"), "-n", str(net),
                               "-a", str(add), "--end", "1", "--no-step-log", "true"],
                              capture_output=True, text=True, env=env, timeout=120)
        assert proc.returncode == 0 and "Error" not in proc.stderr, proc.stderr
        assert f"swept:{name}:" in add.read_text()
        doc = ezdxf.readfile(out / "exports" / f"{name}.dxf")
        assert not doc.audit().has_errors


def test_origin_places_a_network_without_projection(tmp_path):
    geo, local = tmp_path / "geo", tmp_path / "local"
    assert run_report(geo, "--method", "analytic", "--origin", "48.137,11.575") == 0
    assert run_report(local, "--method", "analytic") == 0
    gj = json.loads((geo / "exports" / "intersection.geojson").read_text())
    plain = json.loads((local / "exports" / "intersection.local-metres.geojson").read_text())
    assert gj["coordinate_system"].startswith("WGS84") and "crs" not in gj
    assert gj["networks"]["intersection"]["origin_lat_lon"] == [48.137, 11.575]
    off = read_network(NET).location.net_offset
    geod = pyproj.Geod(ellps="WGS84")
    assert len(gj["features"]) == len(plain["features"]) > 0
    for f, g in zip(gj["features"], plain["features"], strict=True):
        def first(geometry):  # a vertex: of a Point, a Polygon or a MultiPolygon
            c = geometry["coordinates"]
            if geometry["type"] == "Point":
                return c
            return c[0][0] if geometry["type"] == "Polygon" else c[0][0][0]
        assert f["geometry"]["type"] == g["geometry"]["type"]
        lon, lat = first(f["geometry"])
        x, y = first(g["geometry"])
        # a vertex's distance from the origin is its distance from the input's 0,0
        azimuth, _, dist = geod.inv(11.575, 48.137, lon, lat)
        assert dist == pytest.approx(math.hypot(x - off[0], y - off[1]), abs=0.05)
        # and its direction (north = 0, east = 90°) its direction there, to a centimetre
        assert math.radians(azimuth) == pytest.approx(math.atan2(x - off[0], y - off[1]),
                                                      abs=0.03 / max(dist, 1.0))
    assert main(["report", "-n", str(NET), "--vehicle", "P", "-o", str(tmp_path / "x"),
                 "--origin", "95,11"]) == 2


def test_identical_inputs_give_identical_files(report, tmp_path):
    again = tmp_path / "again"
    assert run_report(again) == 0
    names = ["clearance.csv", "summary.json", "exports/intersection.local-metres.geojson",
             "exports/intersection.dxf", "exports/intersection.add.xml"]
    for name in names:
        assert (again / name).read_bytes() == (report / name).read_bytes(), name


def test_a_failing_run_leaves_the_previous_report(report, tmp_path, capsys):
    out = tmp_path / "kept"
    shutil.copytree(report, out)
    before = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    bad = tmp_path / "broken.net.xml"
    bad.write_text("<net><edge id='e'><lane id='e_0' shape='0,0 1,")  # truncated
    assert main(["report", "-n", str(bad), "-o", str(out), "--vehicle", "P"]) == 2
    assert "broken.net.xml" in capsys.readouterr().err
    after = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert after == before and Path(".clearance-report") in after
    assert sorted(p.name for p in tmp_path.iterdir()) == ["broken.net.xml", "kept"]


def test_a_folder_that_is_not_a_report_is_refused(tmp_path, capsys):
    # the case: a report over a folder of one's own deleted its files
    mine = tmp_path / "d"
    mine.mkdir()
    (mine / "thesis.txt").write_text("x")
    assert run_report(mine) == 2
    err = capsys.readouterr().err
    assert str(mine) in err and "thesis.txt" in err and "Traceback" not in err
    assert [p.name for p in mine.iterdir()] == ["thesis.txt"]
    assert (mine / "thesis.txt").read_text() == "x"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d"]


def test_a_report_replaces_its_own_report_and_one_from_before_markers(report, tmp_path):
    # a report folder as this tool wrote it before markers: its files, no marker
    old = tmp_path / "old"
    shutil.copytree(report, old)
    (old / ".clearance-report").unlink()
    (old / "summary.json").write_text("{}")
    os.chmod(old, 0o700)  # as mkdtemp left it
    mask = os.umask(0o022)
    try:
        assert run_report(old) == 0
    finally:
        os.umask(mask)
    assert (old / "summary.json").read_bytes() == (report / "summary.json").read_bytes()
    assert (old / ".clearance-report").read_text().startswith("clearance report output")
    # the ordinary permissions of umask 022, folders and files alike
    assert os.stat(old).st_mode & 0o777 == 0o755
    assert os.stat(old / "figures").st_mode & 0o777 == 0o755
    for f in ("clearance.csv", "report.html", "exports/intersection.dxf", ".clearance-report"):
        assert os.stat(old / f).st_mode & 0o777 == 0o644, f
    pngs = list((old / "figures").glob("*.png"))
    assert pngs and all(os.stat(p).st_mode & 0o777 == 0o644 for p in pngs)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old"]


def test_analytic_method_and_feet(tmp_path):
    out = tmp_path / "a"
    assert run_report(out, "--method", "analytic", "--units", "ft", "--svg") == 0
    pngs = sorted((out / "figures").rglob("*.png"))
    assert pngs and all(p.with_suffix(".svg").is_file() for p in pngs)  # --svg: each
    with open(out / "clearance.csv", newline="") as fh:
        got = list(csv.DictReader(fh))
    assert {r["method"] for r in got} == {"analytic"}
    assert "Margins in feet" in (out / "report.md").read_text()
    # one unit system: the lengths of the columns and of the reasons in feet
    assert "margin_ft" in got[0] and "margin_m" not in got[0]
    assert all(" ft" in r["reason"] for r in got)
    assert not [r["reason"] for r in got if re.search(r"\d m(?![\w/²])", r["reason"])]


def test_a_real_osm_network_with_a_projection(tmp_path):
    # a network nobody here drew: OSM import shipped with eclipse-sumo (UTM projection)
    net = Path(sumo.SUMO_HOME) / "tools" / "game" / "fkk_in" / "ingolstadt.net.xml.gz"
    if not net.is_file():
        pytest.skip(f"{net} is not in this eclipse-sumo package")
    out = tmp_path / "osm"
    assert main(["report", "-n", str(net), "--vehicle", "P", "-o", str(out)]) == 0
    with open(out / "clearance.csv", newline="") as fh:
        got = list(csv.DictReader(fh))
    assert len(got) > 50
    assert {r["verdict"] for r in got} <= {"clear", "encroaches", "fails", "cannot-turn"}
    gj = json.loads((out / "exports" / "ingolstadt.geojson").read_text())
    assert gj["coordinate_system"].startswith("WGS84")
    lon, lat = gj["features"][0]["geometry"]["coordinates"][0][0][:2]
    assert 11.2 < lon < 11.6 and 48.6 < lat < 48.9  # Ingolstadt


def test_waivers_and_a_selection(tmp_path):
    w = tmp_path / "waivers.csv"
    w.write_text("curve_id,vehicle,verdict,reason\n"
                 'turn:T:*,CITY-BUS,fails,"bus stop layout, agreed 2026-11"\n'
                 "roundabout:*,*,fails,no roundabout here\n")
    out = tmp_path / "rep"
    assert run_report(out, "--method", "analytic", "--junction", "T", "--waivers", str(w)) == 0
    with open(out / "clearance.csv", newline="") as fh:
        got = list(csv.DictReader(fh))
    assert list(got[0]) == COLUMNS + ["waived"]
    assert {r["curve_id"].split(":")[1] for r in got} == {"T"} and len(got) == 4 * 2
    expected = [r for r in got if r["vehicle"] == "CITY-BUS"
                and r["verdict"] in ("encroaches", "fails")]
    assert expected, "the bus should fail or encroach somewhere at T"
    assert [r for r in got if r["waived"]] == expected
    assert {r["waived"] for r in expected} == {"bus stop layout, agreed 2026-11"}
    s = json.loads((out / "summary.json").read_text())
    assert s["waived"]["runs"] == len(expected)
    assert s["waived"]["verdicts"]["fails"] == sum(r["verdict"] == "fails" for r in expected)
    assert s["waived"]["unused_waivers"] == [f"{w}:3"]
    assert s["waived"]["not_clear_and_not_waived"] == sum(
        r["verdict"] != "clear" and not r["waived"] for r in got)
    md = (out / "report.md").read_text()
    assert f"### Waived runs ({len(expected)})" in md
    assert "| CITY-BUS |" in md and "bus stop layout, agreed 2026-11 |" in md
    assert "(waived)" in md
    html_text = (out / "report.html").read_text()
    assert f"<h3>Waived runs ({len(expected)})</h3>" in html_text
    # without --waivers the file keeps its columns
    assert run_report(out, "--method", "analytic", "--kind", "turn") == 0
    with open(out / "clearance.csv", newline="") as fh:
        assert list(next(csv.DictReader(fh))) == COLUMNS
    assert "waived" not in json.loads((out / "summary.json").read_text())


def test_embedded_figures_are_compact_copies(report):
    from PIL import Image

    from clearance.reports.documents.html_images import (
        HTML_IMAGE_COLOURS,
        HTML_IMAGE_WIDTH_PX,
        compact_png,
    )

    text = (report / "report.html").read_text()
    embedded = re.findall(r'src="data:image/png;base64,([^"]+)"', text)
    pngs = sorted((report / "figures").glob("*.png"))
    assert embedded and pngs
    for png in pngs[:4]:
        small = compact_png(png)
        with Image.open(io.BytesIO(small)) as im, Image.open(png) as full:
            assert im.width == min(full.width, HTML_IMAGE_WIDTH_PX)
            assert im.mode == "P" and len(im.getcolors(256)) <= HTML_IMAGE_COLOURS
            # the same picture: aspect kept
            assert abs(im.height / im.width - full.height / full.width) < 0.01
        assert len(small) < png.stat().st_size
    # what the page embeds is those copies, not the full figures
    sizes = sorted(len(base64.b64decode(e)) for e in embedded)
    assert sizes[-1] < max(p.stat().st_size for p in pngs)


def test_a_report_drawn_in_workers_is_the_one_drawn_here(tmp_path):
    """The curve figures, sheets and exports drawn in worker processes (clearance report)
    are the same files, byte for byte, as those drawn in the report's own process."""
    from clearance.reports.documents.writer import write_report
    from clearance.reports.study.executor import LocalExecutor
    from clearance.reports.study.run import run_study
    from clearance.vehicles.table import bundled_table_paths, load_tables

    tables = bundled_table_paths()
    with LocalExecutor(2) as ex:
        study = run_study([NET], load_tables(tables, VEHICLES), executor=ex)
        (tmp_path / "workers").mkdir()
        write_report(study, tmp_path / "workers", tables, executor=ex)
    (tmp_path / "here").mkdir()
    write_report(study, tmp_path / "here", tables)
    here = sorted(p.relative_to(tmp_path / "here") for p in (tmp_path / "here").rglob("*")
                  if p.is_file())
    there = sorted(p.relative_to(tmp_path / "workers")
                   for p in (tmp_path / "workers").rglob("*") if p.is_file())
    assert here == there
    assert sum(p.parts[0] == "figures" for p in here) >= 4
    assert any(p.suffix == ".pdf" for p in here) and any(p.suffix == ".dxf" for p in here)
    for rel in here:
        assert (tmp_path / "workers" / rel).read_bytes() == (tmp_path / "here" / rel
                                                             ).read_bytes(), rel
