"""`clearance check`: exit 0 when clear, 1 when not, 2 on bad input; the golden gate."""

import csv
import subprocess
from pathlib import Path

import pytest

from clearance.networks.samples.build import sample_networks
from clearance.reports.cli.main import main
from clearance.reports.results.csv_rows import csv_line
from clearance.reports.results.golden import compare, read_golden
from tests.cli import CLI

NETS = {p.stem.split(".")[0]: str(p) for p in sample_networks()}


def test_passing_gate(capsys):
    # every roundabout path is clear for the large van (networks/README.md)
    assert main(["check", "-n", NETS["roundabout"], "--design-vehicle",
                 "2008 Chrysler Town & Country"]) == 0
    assert "0 not allowed" in capsys.readouterr().out


def test_failing_gate_lists_curve_vehicle_verdict_margin(capsys):
    assert main(["check", "-n", NETS["intersection"], "--design-vehicle", "CITY-BUS",
                 "--design-vehicle", "WB-62"]) == 1
    out = capsys.readouterr().out
    # the semitrailer cannot turn right from T's west arm without leaving the pavement
    assert "intersection: turn:T:TW_in_0->TS_out_0: WB-62: fails (-" in out
    # at X's NW corner the bus swings into the two opposing lanes and stays paved
    assert "intersection: turn:X:XN_in_0->XW_out_0: CITY-BUS: encroaches (-" in out


def test_allowed_verdicts_pass(capsys):
    # P on the parking helix: it scrapes the inner wall (fails) - allowing fails passes it
    args = ["check", "-n", NETS["parking_ramp"], "--design-vehicle", "P", "--lane-only"]
    assert main(args) == 1
    capsys.readouterr()
    assert main(args + ["--allow", "fails", "--allow", "encroaches"]) == 0


def test_malformed_input_exits_2_without_traceback(tmp_path):
    bad = tmp_path / "bad.net.xml"
    bad.write_text("this is not a network")
    proc = subprocess.run([*CLI, "check", "-n", str(bad),
                           "--design-vehicle", "P"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "bad.net.xml" in proc.stderr and "Traceback" not in proc.stderr
    assert main(["check", "-n", NETS["roundabout"], "--design-vehicle", "Nobody"]) == 2


def test_golden_gate_detects_a_regression(tmp_path, capsys):
    golden = tmp_path / "golden.csv"
    args = ["check", "-n", NETS["parking_ramp"], "--design-vehicle", "P",
            "--design-vehicle", "2008 Chrysler Town & Country", "--lane-only"]
    # P fails on the helix, but --write-golden exits 0 once it has written the file
    assert main(args + ["--write-golden", str(golden)]) == 0
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
    # after the header, '#' starts data (OSM ids hold it), never a comment
    g.write_text("# comment\nnetwork,vehicle,curve_id,verdict\nn,v,a,clear\n\n"
                 "n,v,a,fails\n")
    with pytest.raises(Exception, match="g.csv:5: the same network, vehicle and curve as line 3"):
        read_golden(g)


def test_compare_orders_verdicts():
    import pandas as pd
    golden = pd.DataFrame({"network": ["n", "n"], "vehicle": ["a", "b"],
                           "curve_id": ["c", "c"], "verdict": ["encroaches", "fails"]})
    found = pd.DataFrame({"network": ["n", "n"], "vehicle": ["a", "b"], "curve_id": ["c", "c"],
                          "verdict": ["fails", "clear"], "margin_m": [-0.3, 0.2]})
    result = compare(found, golden)
    assert len(result.worse) == 1 and "a: fails" in result.worse[0]
    assert len(result.better) == 1 and "b: clear" in result.better[0]
    assert result.as_expected == 0 and not result.new_curves and not result.gone_curves


RAMP_P = ["check", "-n", NETS["parking_ramp"], "--design-vehicle", "P"]


def test_new_and_gone_curves_fail_the_gate_unless_allowed(tmp_path, capsys):
    golden = tmp_path / "golden.csv"
    args = RAMP_P + ["--method", "analytic"]
    assert main(args + ["--write-golden", str(golden)]) == 0
    lines = golden.read_text().splitlines()
    dropped = next(x for x in lines if "turn:H0:approach_0->helix_0" in x)
    lines.remove(dropped)
    lines.append("parking_ramp,P,turn:H9:old#1_0->gone_0,clear,turn,H9,0.50")
    golden.write_text("\n".join(lines) + "\n")
    capsys.readouterr()
    assert main(args + ["--expect", str(golden)]) == 1
    out = capsys.readouterr().out
    assert ("NEW curve, not in the golden file: parking_ramp: turn:H0:approach_0->helix_0 "
            "(P ") in out
    assert ("GONE curve, in the golden file but not found: parking_ramp: "
            "turn:H9:old#1_0->gone_0 (expected P clear)") in out
    assert "1 new curves, 0 new runs, 1 gone curves" in out
    assert main(args + ["--expect", str(golden), "--allow-new"]) == 1  # still gone
    assert main(args + ["--expect", str(golden), "--allow-gone"]) == 1  # still new
    capsys.readouterr()
    assert main(args + ["--expect", str(golden), "--allow-new", "--allow-gone"]) == 0
    out = capsys.readouterr().out
    assert "new (allowed) curve" in out and "gone (allowed) curve" in out
    # a vehicle the golden file does not know: each of its runs is new
    assert main(args + ["--design-vehicle", "2008 Chrysler Town & Country", "--expect",
                        str(golden), "--allow-gone"]) == 1
    assert "NEW run, not in the golden file: parking_ramp: ramp:helix_0->helix_0: 2008" in (
        capsys.readouterr().out)
    assert main(args + ["--allow-new"]) == 2  # only with --expect


def test_waivers_pass_the_gate_and_are_listed(tmp_path, capsys):
    # P clears the turns at the helix's foot and top (judged on the junctions alone) and
    # fails the helix itself (simulate, on its lane's centre line)
    w = tmp_path / "w.csv"
    w.write_text("curve_id,vehicle,verdict,reason\n"
                 "turn:H*,P,fails,the helix turns are tight by design\n"
                 "ramp:helix_0->helix_0,*,encroaches,only encroaching is accepted\n"
                 "bend:*,*,fails,matches nothing\n")
    assert main(RAMP_P + ["--lane-only", "--waivers", str(w)]) == 1
    captured = capsys.readouterr()
    assert ("parking_ramp: ramp:helix_0->helix_0: P: fails (-0.13 m, worst on the ramp from "
            f"H0) (worse than {w}:3 accepts: encroaches)") in captured.out
    assert "3 runs, 0 waived, 1 not allowed" in captured.out
    assert f"{w}:4: waiver matches no run" in captured.err
    w.write_text(w.read_text().replace("*,encroaches,only encroaching is accepted",
                                       "P,fails,the wall is 0.13 m from the lane"))
    assert main(RAMP_P + ["--lane-only", "--waivers", str(w)]) == 0
    captured = capsys.readouterr()
    assert "3 runs, 1 waived, 0 not allowed" in captured.out
    assert ("waived: parking_ramp: ramp:helix_0->helix_0: P: fails (-0.13 m): the wall is "
            f"0.13 m from the lane ({w}:3)") in captured.out


def test_bad_waiver_files_exit_2_naming_file_and_line(tmp_path, capsys):
    w = tmp_path / "w.csv"
    for body, message in [("a,P,splendid,r\n", "w.csv:2: verdict 'splendid'"),
                          ("a,Nobody,fails,r\n", "w.csv:2: unknown vehicle 'Nobody'"),
                          ]:
        w.write_text("curve_id,vehicle,verdict,reason\n" + body)
        assert main(RAMP_P + ["--waivers", str(w)]) == 2
        assert message in capsys.readouterr().err
    w.write_text("curve,vehicle,verdict,reason\n")
    assert main(RAMP_P + ["--waivers", str(w)]) == 2
    assert "w.csv:1: missing column(s) curve_id" in capsys.readouterr().err
    # a waiver may name a vehicle of the tables that this check does not run
    w.write_text("curve_id,vehicle,verdict,reason\nturn:*,WB-62,fails,r\n")
    assert main(RAMP_P + ["--waivers", str(w), "--kind", "ramp", "--allow", "fails"]) == 0


def test_selection_checks_one_scheme(capsys):
    args = ["check", "-n", NETS["intersection"], "--design-vehicle", "P", "--method",
            "analytic"]
    main(args + ["--junction", "T"])
    out = capsys.readouterr().out
    assert "selection: junction T: 4 curves" in out and "4 runs" in out
    main(args + ["--kind", "turn"])
    assert "20 runs" in capsys.readouterr().out
    assert main(args + ["--junction", "Y"]) == 2
    err = capsys.readouterr().err
    assert "--junction 'Y': no such junction in" in err and "intersection.net.xml" in err
    assert main(args + ["--bbox", "0,0,1"]) == 2
    capsys.readouterr()
    # a selection of nothing is a mistake (another coordinate system?), not a pass
    assert main(args + ["--bbox=1e6,1e6,1e6,1e6"]) == 2
    assert "passes the selection (bbox 1e+06,1e+06,1e+06,1e+06)" in capsys.readouterr().err


def _realnet(name: str) -> str:
    """A network of ``shared/realnets`` beside the repository (or beside the folder of
    worktrees it is in); the test is skipped where there is none."""
    root = Path(__file__).resolve().parents[2]
    for up in (root.parent, root.parent.parent):
        path = up / "shared" / "realnets" / name
        if path.is_file():
            return str(path)
    pytest.skip(f"{name} is not in ../shared/realnets")


@pytest.mark.parametrize("net, selection, odd", [
    # OSM ids full of '#', in the junction's id too (27 turns of one cluster)
    ("doerpfeldstr.net.xml.gz",
     ["--junction", "cluster_1884227387_1884227390_1884227396_536402412_#2more"], "#"),
    # the 20 roundabout curves of Bologna, ids with '[' (a glob character)
    ("bologna_joined.net.xml.gz", ["--kind", "roundabout"], "["),
])
def test_real_network_golden_round_trip(tmp_path, capsys, net, selection, odd):
    path = _realnet(net)
    golden = tmp_path / "golden.csv"
    # analytic: the gate's bookkeeping is the subject here, not libsumo
    args = ["check", "-n", path, "--design-vehicle", "P", "--method", "analytic", *selection]
    assert main(args + ["--write-golden", str(golden)]) == 0
    capsys.readouterr()
    rows = read_golden(golden)
    assert len(rows) > 0 and rows.curve_id.str.contains(odd, regex=False).any()
    if odd == "#":
        assert rows.curve_id.str.contains("#").mean() > 0.5
    assert main(args + ["--expect", str(golden)]) == 0
    out = capsys.readouterr().out
    n = len(rows)
    assert (f"{n} expected verdicts: 0 worse, 0 worse but waived, 0 better, {n} as expected; "
            "0 new curves, 0 new runs, 0 gone curves") in out
    # one id removed, one added: both listed, exit 1
    text = golden.read_text().splitlines()
    removed = rows.curve_id.iloc[n // 2]
    kept = [x for x in text if removed not in x]
    assert len(kept) == len(text) - 1
    added = rows.curve_id.iloc[0] + "#gone"
    header = kept.index(next(x for x in kept if x.startswith("network,")))
    row = next(csv.reader([kept[header + 1]]))  # the first run, under another id
    row[2] = added
    golden.write_text("\n".join(kept) + "\n" + csv_line(row))
    assert main(args + ["--expect", str(golden)]) == 1
    out = capsys.readouterr().out
    assert f"NEW curve, not in the golden file: {rows.network.iloc[0]}: {removed} (P " in out
    assert f"GONE curve, in the golden file but not found: {rows.network.iloc[0]}: {added} " in out
    assert f"{n} expected verdicts" in out and "1 new curves, 0 new runs, 1 gone curves" in out


def test_check_builds_its_own_parser_without_the_drawing_modules():
    """A junction's check starts cold in seconds: parsing ``check`` imports neither
    matplotlib nor the report's drawing modules (``report`` needs them), and an unknown
    word still lists every sub-command."""
    import subprocess
    import sys

    code = ("import sys; from clearance.reports.cli.main import build_parser, chosen_command;"
            "p = build_parser(chosen_command(['-v', 'check', '-n', 'x.net.xml']));"
            "print(sorted(p._subparsers._group_actions[0].choices),"
            " 'matplotlib' in sys.modules, 'clearance.reports.documents.writer' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "['check'] False False"
    bad = subprocess.run([sys.executable, "-m", "clearance.reports.cli.main", "chekc"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "report" in bad.stderr and "check" in bad.stderr
