"""`clearance vehicles` as a user runs it: CSV columns, units, bad input exit status 2."""

import csv
import logging
import subprocess

import pytest

from clearance.reports.cli.main import main
from clearance.vehicles.table import bundled_table
from tests.cli import CLI

FT = 0.3048
REQUIRED = ["vehicle", "wheelbase", "track", "width", "max_steer_deg", "outer_steer_deg",
            "ackermann_angle_deg", "min_radius", "ctr", "curb_to_curb", "wall_to_wall",
            "inside_radius", "swept_width", "offtracking"]


def read(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_writes_csv_with_the_required_columns_in_metres_and_feet(tmp_path, capsys):
    paper = str(bundled_table("paper_table1"))
    assert main(["vehicles", "-t", paper, "-o", str(tmp_path / "m.csv")]) == 0
    assert main(["vehicles", "-t", paper, "--units", "ft", "-o", str(tmp_path / "f.csv")]) == 0
    out = capsys.readouterr().out
    assert "2009 Smart Car" in out and "curb to curb" in out
    m, f = read(tmp_path / "m.csv"), read(tmp_path / "f.csv")
    assert len(m) == len(f) == 24
    assert all(c in m[0] for c in REQUIRED)
    smart = next(r for r in f if r["vehicle"] == "2009 Smart Car")
    assert float(smart["wheelbase"]) == pytest.approx(6.125, rel=1e-5)
    assert float(smart["curb_to_curb"]) == pytest.approx(27.7, abs=0.05)
    assert float(smart["max_steer_deg"]) == pytest.approx(40.0)
    for rm, rf in zip(m, f, strict=True):
        assert float(rm["ctr"]) == pytest.approx(float(rf["ctr"]) * FT, rel=1e-5)
        assert float(rm["outer_steer_deg"]) == pytest.approx(float(rf["outer_steer_deg"]))


def test_selects_vehicles_by_name(tmp_path):
    out = tmp_path / "v.csv"
    assert main(["vehicles", "--vehicle", "2010 Honda Pilot", "--vehicle", "2009 Smart Car",
                 "-t", str(bundled_table("paper_table1")), "-o", str(out)]) == 0
    assert [r["vehicle"] for r in read(out)] == ["2010 Honda Pilot", "2009 Smart Car"]


def test_bundled_tables_by_default(tmp_path):
    out = tmp_path / "all.csv"
    assert main(["vehicles", "-o", str(out)]) == 0
    names = {r["vehicle"] for r in read(out)}
    assert "2009 Smart Car" in names and "SU-30" in names


def test_bad_table_exits_2_without_traceback_and_keeps_old_output(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("name,category,units,length,width,wheelbase,front_overhang,source,"
                   "max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,95\nB,car,m,x,1.8,2.7,0.9,t,30\n")
    out = tmp_path / "out.csv"
    out.write_text("previous\n")
    proc = subprocess.run([*CLI, "vehicles", "-t", str(bad),
                           "-o", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert "bad.csv:2 (A): column max_steer_deg: '95'" in proc.stderr
    assert "bad.csv:3 (B): column length: 'x': not a number" in proc.stderr
    assert out.read_text() == "previous\n"


def test_unknown_vehicle_and_missing_table_exit_2(capsys):
    assert main(["vehicles", "--vehicle", "Batmobile"]) == 2
    assert "unknown vehicle 'Batmobile'" in capsys.readouterr().err
    assert main(["vehicles", "-t", "/no/such/table.csv"]) == 2
    assert "/no/such/table.csv: no such vehicle table" in capsys.readouterr().err


def test_combinations_show_the_180_degree_turn_and_no_steady_state(tmp_path, capsys):
    out = tmp_path / "semis.csv"
    names = ["WB-40", "WB-62", "WB-67", "P"]
    args = ["vehicles", "-t", str(bundled_table("aashto_green_book")), "--units", "ft",
            "-o", str(out)]
    for n in names:
        args += ["--vehicle", n]
    assert main(args) == 0
    printed = capsys.readouterr().out
    lines = {line.split()[0]: line for line in printed.splitlines()[2:6]}
    assert "no steady state" in lines["WB-62"] and "no steady state" in lines["WB-67"]
    assert "no steady state" not in lines["WB-40"] and "-4.25" not in printed
    rows = {r["vehicle"]: r for r in read(out)}
    # Green Book minimum inside radii: WB-40 19.3, WB-62 7.4, P 14.4 ft
    assert float(rows["WB-40"]["inside_radius_180"]) == pytest.approx(19.3, abs=0.15)
    assert float(rows["WB-62"]["inside_radius_180"]) == pytest.approx(7.4, abs=0.15)
    assert float(rows["P"]["inside_radius_180"]) == pytest.approx(14.4, abs=0.15)
    assert float(rows["WB-67"]["inside_radius_180"]) < 3.0
    assert rows["WB-62"]["steady_state"] == "False" and rows["WB-40"]["steady_state"] == "True"
    assert rows["WB-62"]["combination_inside_radius"] == ""
    assert float(rows["WB-40"]["combination_inside_radius"]) == pytest.approx(18.12, abs=0.01)
    assert float(rows["WB-62"]["ctr"]) == pytest.approx(41.0, abs=0.05)


def test_the_smart_rows_w_l_warning_only_where_that_row_is_used(capsys, caplog):
    caplog.set_level(logging.WARNING, logger="clearance.vehicles")
    assert main(["vehicles", "--vehicle", "P"]) == 0
    assert "w_l" not in caplog.text
    assert "(1 vehicle;" in capsys.readouterr().out  # not "1 vehicles"
    assert main(["vehicles", "--vehicle", "2009 Smart Car", "--vehicle", "P"]) == 0
    assert caplog.text.count("column w_l: published 0.86") == 1
    caplog.clear()
    assert main(["vehicles"]) == 0  # every row: once
    assert caplog.text.count("column w_l: published 0.86") == 1


def test_an_unknown_name_suggests_the_one_of_another_case(capsys):
    assert main(["vehicles", "--vehicle", "p"]) == 2
    err = capsys.readouterr().err
    assert "unknown vehicle 'p'; did you mean 'P'" in err and "Traceback" not in err
    assert main(["vehicles", "--vehicle", "wb62"]) == 2
    assert "did you mean 'WB-62'" in capsys.readouterr().err
