"""Route files as SUMO users have them (clearance.networks.routes): the three real layouts of
../shared/realnets/, trips routed by SUMO's duarouter, and bad input named by file and route."""

from __future__ import annotations

import gzip
import logging
from pathlib import Path

import pytest

from clearance.networks.loading import load_network
from clearance.networks.routes import (
    RouteSelection,
    check_routes,
    read_routes,
    select_routes,
)
from clearance.networks.samples.build import SAMPLES_DIR
from clearance.vehicles.errors import RouteError

REAL = Path(__file__).resolve().parents[3] / "shared" / "realnets"
INTERSECTION = SAMPLES_DIR / "intersection" / "intersection.net.xml"
needs_real = pytest.mark.skipif(not REAL.is_dir(), reason="../shared/realnets/ is absent")


def _write(path: Path, body: str) -> Path:
    path.write_text('<?xml version="1.0" encoding="UTF-8"?>\n<routes>\n' + body + "\n</routes>\n")
    return path


@needs_real
def test_duarouter_output_with_its_configuration_header():
    # Wildau: a duarouter output, vehicles naming routes, the type in the same file
    routes = read_routes([REAL / "wildau.bus.rou.xml"])
    assert len(routes) == 8 and {r.vclass for r in routes} == {"bus"}
    first = next(r for r in routes if r.route_id == "Bus738#1")
    assert first.line == "bus738#1" and first.users == ("738#1",) and first.edges[0] == \
        "26943536#1"
    check_routes(routes, load_network(REAL / "wildau.net.xml.gz"))


@needs_real
def test_line_flows_with_types_in_an_additional_file(caplog):
    # Doerpfeldstr: <route>s with stops (the bus stops' file is not given: not needed) and
    # flows with line= naming types that only the additional file defines
    files = [REAL / "doerpfeldstr.pt_lines.rou.xml"]
    with pytest.raises(RouteError, match="type 'pt_(tram|bus)' is not defined"):
        read_routes(files)
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="clearance.networks.routes"):
        routes = read_routes(files, [REAL / "doerpfeldstr.vtypes.xml"])
    (warned,) = [r.getMessage() for r in caplog.records]  # one warning for all the stops
    assert "stopping place(s) the files given do not define (bs_" in warned
    buses = select_routes(routes, RouteSelection(vclasses=("bus",)))
    assert sorted(r.line for r in buses) == ["bus_162", "bus_164"]
    check_routes(routes, load_network(REAL / "doerpfeldstr.net.xml.gz"))


@needs_real
def test_vehicles_with_nested_routes():
    # Hamburg: every vehicle carries its own route; each is a route named by the vehicle
    routes = read_routes([REAL / "tavf_hamburg.bus.rou.xml"], [REAL / "tavf_hamburg.vtypes.xml"])
    assert len(routes) == 189 and all(r.users == (r.route_id,) for r in routes)
    one = select_routes(routes, RouteSelection(route_ids=("routeFlow_bus109H.0",)))
    assert [r.route_id for r in one] == ["routeFlow_bus109H.0"]


def test_trips_are_routed_by_duarouter_for_their_class(tmp_path):
    f = _write(tmp_path / "t.rou.xml",
               '<vType id="coach" vClass="coach"/>'
               '<trip id="a" type="coach" depart="0" from="XS_in" to="XW_out" line="7"/>'
               '<flow id="f" begin="0" end="10" number="1" from="XN_in" to="XE_out"/>')
    routes = {r.route_id: r for r in read_routes([f], net_path=INTERSECTION)}
    assert routes["a"].edges == ("XS_in", "XW_out") and routes["a"].vclass == "coach"
    assert routes["a"].line == "7" and routes["f"].vclass == "passenger"


def test_route_distributions_and_gzip(tmp_path):
    body = ('<routeDistribution id="d"><route id="r1" edges="XS_in XN_out" probability="1"/>'
            '<route id="r2" edges="XS_in XE_out" probability="2"/></routeDistribution>'
            '<vehicle id="v" depart="0" route="d"/>')
    plain = _write(tmp_path / "d.rou.xml", body)
    packed = tmp_path / "d.rou.xml.gz"
    packed.write_bytes(gzip.compress(plain.read_bytes()))
    routes = read_routes([packed])
    assert sorted((r.route_id, r.edges[-1]) for r in routes) == [("r1", "XN_out"),
                                                                   ("r2", "XE_out")]
    check_routes(routes, load_network(INTERSECTION))


@pytest.mark.parametrize("body, message", [
    ('<route id="r" edges="XS_in nowhere"/>', "route 'r': the edge 'nowhere' within the route "
                                              "is not known"),
    ('<route id="r" edges="XS_in TE_out"/>', "No connection between edge 'XS_in' and edge "
                                             "'TE_out' found."),
])
def test_routes_the_network_cannot_drive_are_named(tmp_path, body, message):
    f = _write(tmp_path / "bad.rou.xml", body)
    with pytest.raises(RouteError) as info:
        check_routes(read_routes([f]), load_network(INTERSECTION))
    assert message in str(info.value) and info.value.file == str(f)
    assert info.value.element == "route 'r'"


@pytest.mark.parametrize("body, message", [
    ("<route id='r' edges='a'", "malformed XML"),
    ('<vehicle id="v" depart="0" route="missing"/>', "vehicle 'v': route 'missing' is not "
                                                     "defined"),
    ('<vehicle id="v" depart="0"/>', "vehicle 'v': no route"),
])
def test_bad_route_files_are_named(tmp_path, body, message):
    f = tmp_path / "bad.rou.xml"
    f.write_text("<routes>" + body + ("</routes>" if body.endswith(">") else ""))
    with pytest.raises(RouteError, match=message) as info:
        read_routes([f])
    assert str(f) in str(info.value)


def test_a_selection_that_matches_nothing_is_refused(tmp_path):
    f = _write(tmp_path / "r.rou.xml", '<route id="r" edges="XS_in XN_out"/>')
    with pytest.raises(RouteError, match="no route matches the selection.*--line 14"):
        select_routes(read_routes([f]), RouteSelection(lines=("14",)))


@needs_real
def test_route_types_carry_their_size_or_sumo_defaults():
    """Doerpfeldstr's pt_bus gives no size: SUMO's bus default (12 x 2.5 m); Hamburg's
    types give their own, as the file says."""
    routes = read_routes([REAL / "doerpfeldstr.pt_lines.rou.xml"],
                         [REAL / "doerpfeldstr.vtypes.xml"])
    assert {r.size_m for r in routes if r.vclass == "bus"} == {(12.0, 2.5)}
    from lxml import etree

    files = [REAL / "tavf_hamburg.bus.rou.xml", REAL / "tavf_hamburg.vtypes.xml"]
    types = {t.get("id"): t for f in files for t in etree.parse(str(f)).iter("vType")}
    hamburg = read_routes(files[:1], files[1:])
    assert hamburg
    for r in hamburg:
        if r.vtype:
            t = types[r.vtype]
            default = {"bus": (12.0, 2.5), "passenger": (5.0, 1.8), "truck": (7.1, 2.4)}[r.vclass]
            assert r.size_m == (float(t.get("length", default[0])),
                                float(t.get("width", default[1]))), r.vtype
