"""Route studies (clearance.reports.study.routes, clearance.reports.results.routes) on the
real bus lines of ../shared/realnets/: every bus passage studied, verdicts equal to a
whole-network study of the same junctions, the baseline comparison, the CLI's outputs."""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path

import pytest

from clearance.networks.loading import load_network
from clearance.networks.routes import RouteSelection, read_routes
from clearance.networks.selection import Selection
from clearance.reports.cli.main import main
from clearance.reports.results.routes import compare_runs
from clearance.reports.study.routes import run_route_study
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table_paths, load_tables
from tests.reports.pdf import pdf_text

REAL = Path(__file__).resolve().parents[3] / "shared" / "realnets"
needs_real = pytest.mark.skipif(not REAL.is_dir(), reason="../shared/realnets/ is absent")
NET = REAL / "doerpfeldstr.net.xml.gz"
LINES = REAL / "doerpfeldstr.pt_lines.rou.xml"
TYPES = REAL / "doerpfeldstr.vtypes.xml"


@pytest.fixture(scope="module")
def buses():
    return load_tables(bundled_table_paths(), ["CITY-BUS", "A-BUS"], warn=False)


@pytest.fixture(scope="module")
def doerpfeld(buses):
    return run_route_study(NET, [LINES], buses, [TYPES], RouteSelection(vclasses=("bus",)),
                           baseline="CITY-BUS", workers=2)


@needs_real
def test_every_bus_passage_is_studied_once(doerpfeld):
    # the bus routes' consecutive edges, read here from the file on its own
    net = load_network(NET)
    bus_routes = [r for r in read_routes([LINES], [TYPES]) if r.vclass == "bus"]
    steps = {(a, b) for r in bus_routes for a, b in zip(r.edges, r.edges[1:], strict=False)
             if net.edges[a].to_junction == net.edges[b].from_junction}
    rows = doerpfeld.rows
    turned = {(r.passage.from_edge, r.passage.to_edge) for r in rows if len(r.passage.edges) > 1}
    assert steps <= turned | {(a, b) for r in rows for a, b in zip(
        r.passage.edges, r.passage.edges[1:], strict=False)}
    assert sum(doerpfeld.uncovered.values()) == 0
    assert not any(r.record is not None and r.record.verdict == "error" for r in rows)
    # each curve driven once per vehicle, however many routes and passages use it
    runs = [(r.vehicle, r.curve_id) for r in doerpfeld.study.records]
    assert len(runs) == len(set(runs))


@needs_real
def test_a_passage_gets_the_verdict_of_a_whole_network_study(doerpfeld, buses):
    junctions = tuple(sorted({r.passage.junction for r in doerpfeld.rows
                              if r.passage.kind == "turn"}))[:4]
    whole = run_study([NET], buses, selection=Selection(junctions=junctions), workers=2)
    by_run = {(r.vehicle, r.curve_id): r for r in whole.records}
    compared = 0
    for r in doerpfeld.study.records:
        if (r.vehicle, r.curve_id) in by_run:
            w = by_run[(r.vehicle, r.curve_id)]
            assert (r.verdict, r.margin_m, r.paved_margin_m) == (w.verdict, w.margin_m,
                                                                 w.paved_margin_m)
            compared += 1
    assert compared >= 4


@needs_real
def test_the_longer_bus_is_never_better_than_the_baseline_where_it_needs_more_room(doerpfeld):
    for r in doerpfeld.rows:
        if r.vehicle == "A-BUS" and r.vs_baseline == "better":
            assert r.more_room_m < 0 or math.isnan(r.more_room_m)
        if r.vehicle == "CITY-BUS":
            assert r.vs_baseline == "baseline"


def test_compare_runs_by_verdict_then_room():
    from types import SimpleNamespace as Run
    base = Run(verdict="encroaches", margin_m=-0.3, paved_margin_m=0.5)
    assert compare_runs(Run(verdict="fails", margin_m=-2, paved_margin_m=-0.1), base, 0.1)[0] \
        == "worse"
    assert compare_runs(Run(verdict="clear", margin_m=0.2, paved_margin_m=1), base, 0.1)[0] \
        == "better"
    assert compare_runs(Run(verdict="encroaches", margin_m=-0.35, paved_margin_m=0.5), base,
                        0.1)[0] == "same"
    assert compare_runs(None, base, 0.1) == ("", compare_runs(None, base, 0.1)[1])


@needs_real
def test_report_and_check_along_a_line(tmp_path, capsys):
    out = tmp_path / "r"
    args = ["-n", str(NET), "--routes", str(LINES), "--additional", str(TYPES),
            "--line", "bus_162", "--vehicle", "CITY-BUS", "--vehicle", "A-BUS",
            "--baseline", "CITY-BUS", "--lane-only", "--workers", "1"]
    assert main(["report", *args, "-o", str(out), "--max-sheets", "2"]) == 0
    with open(out / "routes.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    # the baseline is the ghost of the other vehicles' sheets
    sheets = " ".join(pdf_text(out / "sheets" / f"{NET.name.split('.')[0]}.pdf").split())
    assert "A-BUS" in sheets and "CITY-BUS for comparison" in sheets
    assert {r["route_id"] for r in rows} == {"bus_162"}
    assert {r["vs_baseline"] for r in rows if r["vehicle"] == "CITY-BUS"} == {"baseline"}
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["routes"]["bus_162"]) == {"CITY-BUS", "A-BUS"}
    worse = [r for r in rows if r["vs_baseline"] == "worse"]
    capsys.readouterr()
    code = main(["check", "-n", str(NET), "--routes", str(LINES), "--additional", str(TYPES),
                 "--line", "bus_162", "--design-vehicle", "CITY-BUS", "--design-vehicle",
                 "A-BUS", "--baseline", "CITY-BUS", "--lane-only", "--workers", "1"])
    printed = capsys.readouterr().out
    assert code == (1 if worse else 0)
    assert sum(ln.startswith("bus_162: passage") and "worse than CITY-BUS" in ln
               for ln in printed.splitlines()) == len(worse)
    assert f"A-BUS: {len(worse)} worse than CITY-BUS" in printed


@needs_real
def test_a_route_file_naming_what_the_network_lacks_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.rou.xml"
    bad.write_text('<routes><route id="r" edges="nowhere"/></routes>')
    assert main(["check", "-n", str(NET), "--routes", str(bad), "--design-vehicle",
                 "CITY-BUS"]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "route 'r'" in err and "Traceback" not in err


@needs_real
def test_simulate_drives_the_passages_of_a_line(tmp_path, doerpfeld):
    out = tmp_path / "sim"
    assert main(["simulate", "-n", str(NET), "--routes", str(LINES), "--additional",
                 str(TYPES), "--line", "bus_162", "--vehicle", "A-BUS", "--no-sumo",
                 "-o", str(out)]) == 0
    with open(out / "results.csv", newline="") as fh:
        driven = {r["curve_id"] for r in csv.DictReader(fh)}
    line = {c for r in doerpfeld.rows if r.route.route_id == "bus_162"
            for c in r.passage.curve_ids}
    assert driven == line


#: The three shared bus networks: network, route files, additional files.
BUS_NETWORKS = {
    "wildau": ("wildau.net.xml.gz", ["wildau.bus.rou.xml"], []),
    "tavf_hamburg": ("tavf_hamburg.net.xml.gz", ["tavf_hamburg.bus.rou.xml"],
                     ["tavf_hamburg.vtypes.xml"]),
    "doerpfeldstr": ("doerpfeldstr.net.xml.gz", ["doerpfeldstr.pt_lines.rou.xml"],
                     ["doerpfeldstr.vtypes.xml"]),
}


@needs_real
@pytest.mark.skipif(not os.environ.get("CLEARANCE_BUS_NETWORKS"),
                    reason="about 5 minutes: set CLEARANCE_BUS_NETWORKS=1")
@pytest.mark.parametrize("name", sorted(BUS_NETWORKS))
def test_every_bus_line_of_the_shared_networks(name, buses):
    net, routes, additional = BUS_NETWORKS[name]
    rs = run_route_study(REAL / net, [REAL / f for f in routes], buses,
                         [REAL / f for f in additional], RouteSelection(vclasses=("bus",)),
                         baseline="CITY-BUS", workers=2)
    assert not any(r.verdict == "error" for r in rs.study.records)
    # every step of every bus route, read here on its own, is inside one of its passages
    network = load_network(REAL / net)
    for route in read_routes([REAL / f for f in routes], [REAL / f for f in additional]):
        if route.vclass != "bus":
            continue
        covered = {(p.edges[k], p.edges[k + 1]) for _, p in rs.passages[route.route_id]
                   for k in range(len(p.edges) - 1)}
        for a, b in zip(route.edges, route.edges[1:], strict=False):
            assert network.edges[a].to_junction == network.edges[b].from_junction
            assert (a, b) in covered, (route.route_id, a, b)


@needs_real
def test_the_networks_own_buses_are_evidence_where_the_bus_fails(doerpfeld):
    """Every failing bus passage of a bus line is driven by that line's own buses: each one
    says so, naming the line and SUMO's bus size; no clear passage does."""
    rows = doerpfeld.rows
    for r in rows:
        failing = r.record is not None and r.record.verdict in ("fails", "cannot-turn")
        assert bool(r.own_traffic) == failing, (r.route.route_id, r.passage.junction)
        if failing:
            assert r.route.route_id in r.own_traffic and "12.0 × 2.5 m" in r.own_traffic
        if r.record is not None:
            assert r.record.geometry  # data, or the defaults it rests on


def test_own_traffic_needs_the_same_class():
    from clearance.networks.passages import Passage
    from clearance.networks.routes import Route
    from clearance.reports.results.routes import own_traffic_words

    p = Passage(("a", "b"), "J", "roundabout", ("c",))
    trucks = [Route(f"t{i}", ("a", "b"), "HGV", "truck", "", "f", (), (16.5, 2.55))
              for i in range(7)]
    words = own_traffic_words(p, "truck", trucks)
    assert "own trucks take this roundabout passage" in words and "and 2 more" in words
    assert own_traffic_words(p, "bus", trucks) == ""
