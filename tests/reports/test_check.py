"""`clearance check`: exit 0 when clear, 1 when not, 2 on bad input; the golden gate."""

import subprocess
import sys

import pytest

from reports.cli import main
from reports.cmd_check import compare, read_golden
from reports.cmd_report import sample_networks

NETS = {p.stem.split(".")[0]: str(p) for p in sample_networks()}


def test_passing_gate(capsys):
    # every roundabout path is clear for the large van (networks/README.md)
    assert main(["check", "-n", NETS["roundabout"], "--design-vehicle",
                 "2008 Chrysler Town & Country"]) == 0
    assert "0 not allowed" in capsys.readouterr().out


def test_failing_gate_lists_curve_vehicle_verdict_margin(capsys):
    assert main(["check", "-n", NETS["intersection"], "--design-vehicle", "CITY-BUS"]) == 1
    out = capsys.readouterr().out
    assert "intersection: turn:X:XN_in_0->XW_out_0: CITY-BUS: fails (-" in out


def test_allowed_verdicts_pass(capsys):
    # P on the parking helix: it scrapes the inner wall (fails) - allowing fails passes it
    args = ["check", "-n", NETS["parking_ramp"], "--design-vehicle", "P"]
    assert main(args) == 1
    capsys.readouterr()
    assert main(args + ["--allow", "fails", "--allow", "encroaches"]) == 0


def test_malformed_input_exits_2_without_traceback(tmp_path):
    bad = tmp_path / "bad.net.xml"
    bad.write_text("this is not a network")
    proc = subprocess.run([sys.executable, "-m", "reports.cli", "check", "-n", str(bad),
                           "--design-vehicle", "P"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "bad.net.xml" in proc.stderr and "Traceback" not in proc.stderr
    assert main(["check", "-n", NETS["roundabout"], "--design-vehicle", "Nobody"]) == 2


def test_golden_gate_detects_a_regression(tmp_path, capsys):
    golden = tmp_path / "golden.csv"
    args = ["check", "-n", NETS["parking_ramp"], "--design-vehicle", "P",
            "--design-vehicle", "2008 Chrysler Town & Country"]
    assert main(args + ["--write-golden", str(golden)]) == 1  # P fails on the helix
    assert main(args + ["--expect", str(golden)]) == 0
    assert "0 worse" in capsys.readouterr().out
    # a golden file that expects better than the network gives is a regression
    text = golden.read_text().replace("P,ramp:helix_0->helix_0,fails",
                                      "P,ramp:helix_0->helix_0,clear")
    assert text != golden.read_text()
    golden.write_text(text)
    assert main(args + ["--expect", str(golden)]) == 1
    assert "WORSE than expected: parking_ramp: ramp:helix_0->helix_0: P: fails" in (
        capsys.readouterr().out)


def test_bad_golden_files(tmp_path):
    g = tmp_path / "g.csv"
    g.write_text("network,vehicle,curve_id,verdict\nn,v,c,splendid\n")
    with pytest.raises(Exception, match="g.csv:2: unknown verdict 'splendid'"):
        read_golden(g)
    g.write_text("network,vehicle\nn,v\n")
    with pytest.raises(Exception, match="missing column"):
        read_golden(g)
    with pytest.raises(Exception, match="no such golden file"):
        read_golden(tmp_path / "none.csv")


def test_golden_errors_name_the_right_line(tmp_path):
    # the two comment lines a written golden file starts with, and a blank line, are
    # lines of the file too (the rows' numbers were two low)
    g = tmp_path / "g.csv"
    g.write_text("# comment\n# comment\nnetwork,vehicle,curve_id,verdict\nn,v,a,clear\n\n"
                 "n,v,b,splendid\n")
    with pytest.raises(Exception, match="g.csv:6: unknown verdict 'splendid'"):
        read_golden(g)
    g.write_text("# comment\nnetwork,vehicle,curve_id,verdict\nn,v,a,clear\n# x\n"
                 "n,v,a,fails\n")
    with pytest.raises(Exception, match="g.csv:5: the same network, vehicle and curve twice"):
        read_golden(g)


def test_compare_orders_verdicts():
    import pandas as pd
    golden = pd.DataFrame({"network": ["n", "n"], "vehicle": ["a", "b"],
                           "curve_id": ["c", "c"], "verdict": ["encroaches", "fails"]})
    found = pd.DataFrame({"network": ["n", "n"], "vehicle": ["a", "b"], "curve_id": ["c", "c"],
                          "verdict": ["fails", "clear"], "margin_m": [-0.3, 0.2]})
    worse, better = compare(found, golden)
    assert len(worse) == 1 and "a: fails" in worse[0]
    assert len(better) == 1 and "b: clear" in better[0]
