"""The vertical findings of a study: a 15 % ramp with no transition, in the CSV and the gate."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.sumo.tools import find_sumo_binary, netconvert_plain
from clearance.reports.cli.main import main
from clearance.reports.results.records import COLUMNS
from clearance.reports.results.vertical import grade_limit_pct, vertical_check, vertical_words
from clearance.vehicles.table import load_tables

CARS = "\n".join([
    "name,category,units,length,width,wheelbase,front_overhang,max_steer_deg,"
    "ground_clearance,grade_limit_pct,source",
    "LowCar,passenger car,m,4.6,1.8,2.7,0.9,35,0.10,,test: a low car",
    "SUV,passenger car,m,4.6,1.8,2.7,0.9,35,0.22,20,test: an SUV", ""])


@pytest.fixture(scope="module")
def ramp_net(tmp_path_factory) -> Path:
    """A level street turning at B onto a straight 15 % ramp with no transition."""
    try:
        find_sumo_binary("netconvert")
    except FileNotFoundError as exc:  # pragma: no cover - depends on the install
        pytest.skip(f"netconvert is not available: {exc}")
    nodes = ('<nodes><node id="A" x="-60" y="0" z="0"/><node id="B" x="0" y="0" z="0" '
             'radius="12"/><node id="C" x="0" y="20" z="3"/><node id="D" x="0" y="50" '
             'z="3"/></nodes>')
    edges = ('<edges><edge id="in" from="A" to="B" numLanes="1" speed="8"/>'
             '<edge id="ramp" from="B" to="C" numLanes="1" speed="8"/>'
             '<edge id="top" from="C" to="D" numLanes="1" speed="8"/></edges>')
    return netconvert_plain(tmp_path_factory.mktemp("ramp"), "ramp", nodes, edges)


@pytest.fixture(scope="module")
def cars(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("cars") / "cars.csv"
    path.write_text(CARS)
    return path


def test_low_car_scrapes_at_the_foot_and_the_suv_does_not(ramp_net, cars):
    net = read_network(ramp_net)
    foot = next(c for c in extract_curves(net, areas=False) if c.junction == "B")
    assert foot.max_grade_pct == pytest.approx(15.0, abs=0.3)
    low, suv = load_tables([str(cars)]).vehicles()
    a, b = vertical_check(low, foot), vertical_check(suv, foot)
    assert a["vertical"] == "scrapes" and a["vertical_margin_m"] < -0.02  # type: ignore[operator]
    assert a["vertical_part"] in ("front overhang", "rear overhang")
    assert b["vertical"] == "clear" and b["vertical_margin_m"] > 0.05  # type: ignore[operator]
    # the SUV's own limit (20 %) is above the ramp; a study limit of 12 % is not
    assert vertical_check(suv, foot, 12.0)["vertical"] == "too-steep"
    assert grade_limit_pct(suv, 12.0) == 12.0 and grade_limit_pct(suv, None) == 20.0


def test_gate_and_csv_carry_the_vertical_finding(ramp_net, cars, tmp_path, capsys):
    args = ["check", "-n", str(ramp_net), "-t", str(cars), "--design-vehicle", "LowCar",
            "--design-vehicle", "SUV", "--method", "analytic",
            "--allow", "cannot-turn", "--allow", "fails", "--allow", "encroaches"]
    assert main(args) == 1
    out = capsys.readouterr().out
    assert "LowCar: scrapes: the" in out and "into the ground" in out
    assert "SUV: scrapes" not in out
    assert main([*args, "--allow", "scrapes"]) == 0
    assert main([*args, "--allow", "scrapes", "--max-grade-pct", "12"]) == 1
    assert "too-steep: 15.0 % against a limit of 12 %" in capsys.readouterr().out
    out_dir = tmp_path / "out"
    assert main(["report", "-n", str(ramp_net), "-t", str(cars), "--method", "analytic",
                 "-o", str(out_dir)]) == 0
    rows = list(csv.DictReader((out_dir / "clearance.csv").open()))
    assert list(rows[0])[-6:] == COLUMNS[-6:]
    foot = [r for r in rows if r["junction"] == "B"]
    assert {r["vehicle"]: r["vertical"] for r in foot} == {"LowCar": "scrapes", "SUV": "clear"}
    summary = json.loads((out_dir / "summary.json").read_text())["vertical"]
    assert summary["findings"]["scrapes"] == sum("scrapes" in r["vertical"] for r in rows) >= 1
    html = (out_dir / "report.html").read_text()
    assert "Vertical checks" in html and "LowCar" in html
    figures = [p.name for p in (out_dir / "figures").iterdir()]
    assert any("__profile__" in n and n.endswith(".png") for n in figures)
    assert not [n for n in figures if n.endswith(".svg")]  # SVG only with --svg


def test_words_of_a_level_clear_run_are_empty():
    class R:
        vertical, vertical_margin_m, vertical_station_m = "clear", 0.1, math.nan
        vertical_part, max_grade_pct, grade_limit_pct, suspect_elevation = "", 0.0, math.nan, ""

    assert vertical_words(R()) == ""
