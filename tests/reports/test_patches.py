"""Patches SUMO takes: netconvert accepts them, they widen only defaults, the restriction
takes exactly the failing vehicle's class off exactly its failing connections, and sumo
loads the vTypes."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from lxml import etree

from clearance.networks.paths import via_lanes
from clearance.networks.reader import read_network
from clearance.networks.selection import Selection
from clearance.networks.sumo.tools import find_sumo_binary, netconvert_plain, run_sumo_tool
from clearance.reports.exports.patches import FAILING, Fit, restrict_xml, write_patches
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table_paths, load_tables

# A junction of one-lane one-way streets (no opposing lanes to swing into) with a tight
# computed corner; the exit JB has its width as data.
NODES = ('<nodes><node id="A" x="-150" y="0"/><node id="J" x="0" y="0"/>'
         '<node id="B" x="150" y="0"/><node id="C" x="0" y="-150"/></nodes>')
EDGES = ('<edges><edge id="AJ" from="A" to="J" numLanes="1"/>'
         '<edge id="JB" from="J" to="B" numLanes="1" width="3.4"/>'
         '<edge id="JC" from="J" to="C" numLanes="1"/></edges>')


@pytest.fixture(scope="module")
def studied(tmp_path_factory):
    folder = tmp_path_factory.mktemp("patch")
    net_path = netconvert_plain(folder, "tee", NODES, EDGES)
    table = load_tables(bundled_table_paths(), ["P", "CITY-BUS", "WB-62"], warn=False)
    study = run_study([net_path], table, workers=1)
    [nc] = study.networks
    paths = write_patches(folder / "patches", nc.name, nc.network, nc.curves, study.records,
                          table)
    return folder, net_path, study, paths


def _run(*args):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=300)


def test_fit_widens_only_defaults_and_netconvert_builds_it(studied):
    folder, net_path, study, paths = studied
    assert any(r.verdict in FAILING for r in study.records), "the bus must fail somewhere"
    fitted = folder / "fitted.net.xml"
    run_sumo_tool("netconvert", ["-s", str(net_path), "-e", str(paths["edges"]), "-n",
                                 str(paths["nodes"]), "-o", str(fitted)])
    before, after = read_network(net_path), read_network(fitted)
    widened = {k for k in before.lanes if not before.lanes[k].is_internal
               and after.lanes[k].width_m > before.lanes[k].width_m + 1e-6}
    assert widened, "a default lane of the failing turn is widened"
    for k, lane in before.lanes.items():
        if lane.is_internal:
            continue
        assert after.lanes[k].width_m >= lane.width_m - 1e-6, f"{k} narrowed"
        if lane.width_given:  # data: never touched
            assert after.lanes[k].width_m == pytest.approx(lane.width_m), k
    assert "JB_0" not in widened
    radii = etree.parse(str(paths["nodes"])).getroot().findall("node")
    assert [n.get("id") for n in radii] == ["J"]  # the one computed corner of a failing turn
    assert float(radii[0].get("radius")) > 4.0
    # the fitted network says which widths and corners are the patch's proposals
    from clearance.networks.curves import extract_curves
    from clearance.networks.provenance import (
        CORNER_FITTED,
        LANE_WIDTH_FITTED,
        curve_assumptions,
        read_header,
    )

    header = read_header(fitted)
    assert header.fitted() == (frozenset(widened), frozenset({"J"}))
    [turn] = [c for c in extract_curves(after, ("turn",), areas=False)
              if "AJ_0->JC_0" in c.curve_id]
    assert {LANE_WIDTH_FITTED, CORNER_FITTED} <= set(curve_assumptions(after, turn, header))
    head = paths["edges"].read_text()
    assert "proposal for a designer to check" in head and "netconvert -s" in head


NEWER_CLASSES = frozenset({"subway", "cable_car"})


def assert_restriction_exact(folder, net_path, study, restrict):
    """Applied with netconvert, the restriction takes each failing vehicle's class off
    exactly the connections of its failing turns, and changes no other permission (compared
    with the same network rebuilt by netconvert without the patch)."""
    restricted = folder / "restricted.net.xml"
    same = folder / "same.net.xml"
    run_sumo_tool("netconvert", ["-s", str(net_path), "-x", str(restrict), "-o", str(restricted)])
    run_sumo_tool("netconvert", ["-s", str(net_path), "-o", str(same)])
    nets = {name: read_network(p) for name, p in (("same", same), ("restricted", restricted))}
    curves = {c.curve_id: c for c in study.networks[0].curves}
    vclass = {v.name: v.vclass for v in study.table.vehicles()}
    failing: dict[tuple[str, str, int, int], set[str]] = {}
    for r in study.records:
        c = curves[r.curve_id]
        if r.verdict in FAILING and c.kind in ("turn", "uturn"):
            a, b = c.lanes[c.lanes.index(c.core_lanes[0]) - 1], c.lanes[
                c.lanes.index(c.core_lanes[-1]) + 1]
            key = (a.rsplit("_", 1)[0], b.rsplit("_", 1)[0], int(a.rsplit("_", 1)[1]),
                   int(b.rsplit("_", 1)[1]))
            failing.setdefault(key, set()).add(vclass[r.vehicle])
    after = {c[:4]: c for c in nets["restricted"].connections}
    changed = 0
    for conn in nets["same"].connections:
        if not conn.via or conn.from_edge.startswith(":"):
            continue
        off = failing.get(conn[:4], set())
        # every internal lane of the connection (a left turn's waiting point splits it)
        lanes = zip(via_lanes(nets["same"], conn), via_lanes(nets["restricted"], after[conn[:4]]),
                    strict=True)
        for a, b in lanes:
            # classes SUMO added after an older file's version (1.20: subway, cable_car) are
            # disallowed by netconvert's rebuild of a lane listing what it disallows; the
            # reader, and so the patch, takes them as allowed: compared without them
            was = nets["same"].lanes[a].allowed - NEWER_CLASSES
            now = nets["restricted"].lanes[b].allowed - NEWER_CLASSES
            assert now == was - off, (conn, off)
        changed += bool(off & nets["same"].lanes[conn.via].allowed)
    return failing, changed


def test_restriction_takes_off_exactly_the_failing_connections(studied):
    folder, net_path, study, paths = studied
    failing, changed = assert_restriction_exact(folder, net_path, study, paths["restrict"])
    assert "trailer" in set().union(*failing.values()), "the WB-62 fails a turn"
    assert changed == len(failing)


REAL_NET = Path(__file__).resolve().parents[3] / "shared" / "realnets" / "doerpfeldstr.net.xml.gz"


@pytest.mark.skipif(not REAL_NET.exists(), reason="../shared/realnets/ is absent")
def test_restriction_on_a_real_network_takes_the_trailer_off_where_the_wb62_fails(tmp_path):
    """Doerpfeldstr, the junctions of a bus line, the WB-62 alone: the trailer class leaves
    exactly the connections where it fails or cannot turn, nothing else changes."""
    table = load_tables(bundled_table_paths(), ["WB-62"], warn=False)
    junctions = ("1625633828", "1906421964", "6366092613", "clusterJ1_J2", "220496738",
                 "1978634893")
    study = run_study([REAL_NET], table, workers=1, swing=False,
                      selection=Selection(junctions=junctions))
    [nc] = study.networks
    paths = write_patches(tmp_path / "patches", nc.name, nc.network, nc.curves, study.records,
                          table)
    failing, changed = assert_restriction_exact(tmp_path, REAL_NET, study, paths["restrict"])
    assert failing and changed == len(failing)
    assert {c for classes in failing.values() for c in classes} == {"trailer"}


def test_vtypes_load_in_sumo(studied):
    folder, net_path, study, paths = studied
    proc = _run(find_sumo_binary("sumo"), "-n", net_path, "-a", paths["vtypes"], "--end", "1",
                "--no-step-log")
    assert proc.returncode == 0, proc.stderr
    types = {t.get("id"): t for t in etree.parse(str(paths["vtypes"])).getroot().iter("vType")}
    assert set(types) == {"P", "CITY-BUS", "WB-62"}
    wb = types["WB-62"]
    assert wb.get("vClass") == "trailer" and wb.get("guiShape") == "truck/semitrailer"
    # the carriages add up to the whole vehicle
    parts = [float(wb.get(k)) for k in ("locomotiveLength", "carriageLength", "carriageGap")]
    assert sum(parts) == pytest.approx(float(wb.get("length")), abs=0.02)
    assert float(types["CITY-BUS"].get("length")) == pytest.approx(40 * 0.3048, abs=0.01)


def test_a_connection_left_with_no_class_is_closed_as_netconvert_takes_it(studied):
    """A bus lane's connection closed to buses admits nothing: ``disallow="all"`` (netconvert
    refuses an empty ``allow``)."""
    folder, net_path, _, _ = studied
    fit = Fit(restrict={("AJ", "JC", 0, 0): (frozenset({"bus"}), {"bus"}, ["CITY-BUS fails"])})
    text = restrict_xml(fit, "tee", net_path.name)
    assert 'disallow="all"' in text and 'allow=""' not in text
    patch = folder / "closed.con.xml"
    patch.write_text(text)
    closed = folder / "closed.net.xml"
    run_sumo_tool("netconvert", ["-s", str(net_path), "-x", str(patch), "-o", str(closed)])
    net = read_network(closed)
    [conn] = [c for c in net.connections if (c.from_edge, c.to_edge) == ("AJ", "JC")]
    assert net.lanes[conn.via].allowed == frozenset()
