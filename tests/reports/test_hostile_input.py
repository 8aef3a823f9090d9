"""Hostile and broken input through the command line: exit 2, no traceback, the culprit named,
nothing written. The classes: XML (bombs, entities, DTDs, truncation, encodings), numbers
(NaN, inf, huge, tiny, negative), files (FIFO, device, directory, unreadable, symlink loop),
references SUMO refuses, and option values given twice."""

from __future__ import annotations

import gzip
import math
import os
import subprocess
from pathlib import Path

import pytest

from clearance.networks.samples.sources import SAMPLES_DIR
from clearance.reports.cli.main import main
from tests.cli import CLI
from tests.networks import damaged

REPO = Path(__file__).resolve().parents[2]
INTERSECTION = SAMPLES_DIR / "intersection" / "intersection.net.xml"
HEADER = "name,category,units,length,width,wheelbase,front_overhang,source,max_steer_deg\n"


def refused(capsys, argv: list[str], *expected: str) -> str:
    """Run the CLI: exit 2, no traceback, every expected piece in the message."""
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    for piece in expected:
        assert piece in err, (piece, err)
    return err


def run_cli(argv: list[str], env: dict[str, str] | None = None,
            timeout: float = 30) -> subprocess.CompletedProcess:
    """The CLI in its own process, which cannot hang the tests (``timeout`` s)."""
    return subprocess.run([*CLI, *argv], capture_output=True,
                          text=True, timeout=timeout, cwd=REPO,
                          env={**os.environ, **(env or {})}, check=False)


# -- networks


@pytest.mark.parametrize("case", sorted(damaged.REFUSED))
def test_curves_refuses_what_sumo_refuses_with_sumos_reason(tmp_path, capsys, case):
    path, expected = damaged.damage(case, tmp_path)
    out = tmp_path / "curves.csv"
    refused(capsys, ["curves", "-n", str(path), "-o", str(out)], expected)
    assert not out.exists()


@pytest.mark.parametrize("case", sorted(damaged.LOADED))
def test_curves_reads_what_sumo_loads_and_names_what_it_left_out(tmp_path, capsys, caplog,
                                                                 case):
    path, expected = damaged.damage(case, tmp_path)
    out = tmp_path / "curves.csv"
    code = main(["curves", "-n", str(path), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert any(w.startswith(expected) for w in warnings), (expected, warnings)
    assert out.exists()


@pytest.mark.parametrize("case", ["via-to-a-missing-lane", "lane-length-nan",
                                  "roundabout-unknown-edge"])
@pytest.mark.parametrize("command", ["report-simulate", "report-analytic", "simulate",
                                     "check"])
def test_every_command_refuses_before_any_run(tmp_path, capsys, case, command):
    path, expected = damaged.damage(case, tmp_path)
    out = tmp_path / "out"
    argv = {
        "report-simulate": ["report", "-n", str(path), "--vehicle", "P", "-o", str(out)],
        "report-analytic": ["report", "-n", str(path), "--vehicle", "P", "-o", str(out),
                            "--method", "analytic"],
        "simulate": ["simulate", "-n", str(path), "--vehicle", "P", "-o", str(out)],
        "check": ["check", "-n", str(path), "--design-vehicle", "P"],
    }[command]
    refused(capsys, argv, expected)
    assert not out.exists()


def test_a_fifo_as_the_network_or_its_dtd_never_hangs(tmp_path):
    fifo = tmp_path / "n.net.xml"
    os.mkfifo(fifo)
    proc = run_cli(["curves", "-n", str(fifo)])
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert f"{fifo}: is a FIFO, not a regular file" in proc.stderr
    net = tmp_path / "dtd.net.xml"
    net.write_text(INTERSECTION.read_text().replace(
        "<net ", f'<!DOCTYPE net SYSTEM "{fifo}">\n<net ', 1))
    proc = run_cli(["curves", "-n", str(net)])
    assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("kind", ["device", "directory", "symlink-loop", "under-a-file"])
def test_special_files_as_the_network(tmp_path, capsys, kind):
    p = tmp_path / "n.net.xml"
    if kind == "device":
        p, expected = Path("/dev/zero"), "is a character device, not a regular file"
    elif kind == "directory":
        p.mkdir()
        expected = "is a directory, not a regular file"
    elif kind == "symlink-loop":
        os.symlink(p, p)
        expected = "cannot be read (Too many levels of symbolic links)"
    else:
        (tmp_path / "f").write_text("x")
        p, expected = tmp_path / "f" / "n.net.xml", "cannot be read (Not a directory)"
    refused(capsys, ["curves", "-n", str(p)], f"{p}: {expected}")


def test_a_decompression_bomb_stops_at_the_cap_named_with_its_variable(tmp_path):
    bomb = tmp_path / "bomb.net.xml.gz"
    row = b'<connection from="a" to="a" fromLane="0" toLane="0" dir="t"/>\n'
    with gzip.open(bomb, "wb") as fh:
        fh.write(b'<net><edge id="a" from="J" to="K"><lane id="a_0" index="0" '
                 b'shape="0,0 10,0"/></edge>')
        for _ in range(30):
            fh.write(row * 10000)
        fh.write(b"</net>")
    proc = run_cli(["curves", "-n", str(bomb)], env={"CLEARANCE_MAX_ELEMENTS": "100000"})
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "the number of elements exceeds the limit of 100,000 elements" in proc.stderr
    assert "set the environment variable CLEARANCE_MAX_ELEMENTS higher" in proc.stderr


@pytest.mark.parametrize("text", [
    b"",
    b"\xef\xbb\xbf",
    b"<net",
    b'<?xml version="1.0"?><net><edge id="a"><lane id="a_0" shape="0,0 1,1"/>',
    b'<?xml version="1.0"?><!DOCTYPE net [<!ENTITY a "x"><!ENTITY b "&a;&a;">]><net/>',
    b'<?xml version="1.0" encoding="klingon"?><net/>',
    b"\xff\xfe<\x00n\x00e\x00t\x00",
    b"<net>\x00</net>",
    gzip.compress(b"<net><edge id='a'>")[:-5],
])
def test_broken_xml(tmp_path, capsys, text):
    p = tmp_path / "b.net.xml"
    p.write_bytes(text)
    refused(capsys, ["curves", "-n", str(p)], f"{p}: ")


# -- vehicle tables


def test_a_fifo_as_the_table_never_hangs(tmp_path):
    fifo = tmp_path / "t.csv"
    os.mkfifo(fifo)
    proc = run_cli(["vehicles", "-t", str(fifo)])
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert f"{fifo}: is a FIFO, not a regular file" in proc.stderr


@pytest.mark.parametrize("row, expected", [
    ("A,car,m,4.5,1.8,2.7,0.9,test,1e-300", "column max_steer_deg: '1e-300': outside the range"),
    ("A,car,m,4.5,1e300,2.7,0.9,test,35", "column width: '1e300': outside the range"),
    ("A,car,m,4.5,nan,2.7,0.9,test,35", "column width: 'nan': not a finite number"),
    ("A,car,m,inf,1.8,2.7,0.9,test,35", "column length: 'inf': not a finite number"),
    ("A,car,m,4.5,1.8,-2.7,0.9,test,35", "column wheelbase: '-2.7': outside the range"),
    ("A,car,m,4.5,1.8,2.7,0.9,test,0", "column max_steer_deg: '0': outside the range"),
    ('"A\nB",car,m,4.5,1.8,2.7,0.9,test,35', "column name: 'A\\nB': holds a line"),
    ("A\u2028B,car,m,4.5,1.8,2.7,0.9,test,35", "holds a line or paragraph separator (U+2028)"),
])
def test_bad_numbers_and_cells_in_a_table(tmp_path, capsys, row, expected):
    p = tmp_path / "t.csv"
    p.write_text(HEADER + row + "\n")
    refused(capsys, ["vehicles", "-t", str(p), "-o", str(tmp_path / "out.csv")],
            f"{p}:2", expected)
    assert not (tmp_path / "out.csv").exists()


def test_dev_zero_and_a_directory_as_the_table(tmp_path, capsys):
    refused(capsys, ["vehicles", "-t", "/dev/zero"], "/dev/zero: is a character device")
    refused(capsys, ["vehicles", "-t", str(tmp_path)], f"{tmp_path}: is a directory")


def test_a_vehicle_given_twice_runs_once(tmp_path, capsys):
    # it crashed after the whole study had run
    out = tmp_path / "r"
    code = main(["simulate", "-n", str(INTERSECTION), "--vehicle", "P", "--vehicle", "SU-30",
                 "--vehicle", "P", "--curve", "turn:T:TW_in_0->TS_out_0", "--no-sumo",
                 "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    rows = (out / "results.csv").read_text().splitlines()[1:]
    assert [r.split(",")[0] for r in rows] == ["P", "SU-30"]
    code = main(["vehicles", "--vehicle", "P", "--vehicle", "P", "-o", str(tmp_path / "v.csv")])
    assert code == 0
    assert (tmp_path / "v.csv").read_text().count("\nP,") == 1


# -- ids and names as SUMO and a spreadsheet have them

HOSTILE_IDS = REPO / "tests" / "data" / "sumo_corpus" / "hostile_ids.net.xml"
HOSTILE_NAME = '<script>alert(1)</script> & "Q" a:b'


def test_ids_with_xml_characters_are_the_networks_own(tmp_path, capsys):
    # they were read as `&#38;`: SUMO refused the route ("Unknown edge") and the runs were errors
    import sumolib

    from clearance.networks.reader import read_network

    net = read_network(HOSTILE_IDS)
    theirs = sumolib.net.readNet(str(HOSTILE_IDS), withInternal=True)
    assert set(net.edges) == {e.getID() for e in theirs.getEdges(withInternal=True)}
    assert {'in&<a>:1', 'out"b\'c', "up:&"} <= set(net.edges)
    assert set(net.junctions) == {n.getID() for n in theirs.getNodes()}
    table = tmp_path / "t.csv"
    bundled = (REPO / "vehicles" / "tables" / "aashto_green_book.csv").read_text().splitlines()
    row = next(r for r in bundled if r.startswith("P,"))
    table.write_text(bundled[0] + "\n" + f'"{HOSTILE_NAME.replace(chr(34), 2 * chr(34))}"'
                     + row[1:] + "\n")
    out = tmp_path / "r"
    code = main(["report", "-n", str(HOSTILE_IDS), "-t", str(table), "-o", str(out),
                 "--workers", "1"])
    assert code == 0, capsys.readouterr().err
    import pandas as pd

    frame = pd.read_csv(out / "clearance.csv", keep_default_na=False)
    assert set(frame.verdict) <= {"clear", "encroaches", "fails"}  # no error: SUMO drove them
    assert set(frame.vehicle) == {HOSTILE_NAME}
    assert "turn:C<x>:in&<a>:1_0->up:&_0" in set(frame.curve_id)
    md = (out / "report.md").read_text()
    assert "<script>" not in md and "&lt;script&gt;" in md
    import re

    prose = re.sub(r"(`+).+?\1", "", md)  # outside code spans, every < and & is escaped
    assert "<" not in prose and not re.search(r"&(?!amp;|lt;|gt;)", prose)
    html_text = (out / "report.html").read_text()
    assert "<script>" not in html_text


# -- scale, heights

def _tiny(tmp_path: Path) -> Path:
    p = tmp_path / "tiny.net.xml"
    p.write_text(damaged.scaled(INTERSECTION.read_text(), 1e-4))  # a junction 5 mm across
    return p


@pytest.mark.parametrize("command", ["report", "check", "simulate"])
def test_a_network_drawn_10000_times_too_small_is_not_driven(tmp_path, capsys, command):
    # every run was `clear` with a margin of `inf` ("stays inf m inside its own lanes")
    net = _tiny(tmp_path)
    out = tmp_path / "out"
    argv = {"report": ["report", "-n", str(net), "--vehicle", "P", "-o", str(out)],
            "check": ["check", "-n", str(net), "--design-vehicle", "P"],
            "simulate": ["simulate", "-n", str(net), "--vehicle", "P", "-o", str(out)]}
    refused(capsys, argv[command], f"{net}: not drivable at road scale: its widest road lane "
            "is 0.00035 m wide")
    assert not out.exists()
    assert main(["curves", "-n", str(net)]) == 0  # SUMO loads it: listed, with the warning
    assert "not drivable at road scale" in capsys.readouterr().err


def test_a_run_that_sweeps_nothing_is_never_clear(tmp_path):
    from clearance.networks.curves import CurveOptions, extract_curves
    from clearance.networks.driving.drive import DriveOptions, drive
    from clearance.networks.reader import read_network
    from clearance.vehicles.table import bundled_table, load_tables

    net = read_network(_tiny(tmp_path))
    curves = extract_curves(net, options=CurveOptions(approach_length_m=30.0))
    car = load_tables([bundled_table("aashto_green_book")], names=["P"]).vehicles()[0]
    runs = drive(net, [(car, c) for c in curves[:3]], options=DriveOptions(use_sumo=False))
    for r in runs:
        assert r.verdict == "cannot-turn" and "nothing was swept" in r.reason, r.reason
        assert r.result is None or not math.isfinite(r.result.clearance.margin_m)


def test_a_lone_height_of_1e6_m_is_answered_in_seconds_with_a_warning(tmp_path):
    # the report hung building 760,766 storeys; `curves` warned in 3 s
    text = INTERSECTION.read_text()
    old = 'shape="520.00,1.75 415.50,1.75"'
    p = tmp_path / "spike.net.xml"
    p.write_text(text.replace(old, 'shape="520.00,1.75 415.50,1.75,1000000"'))
    proc = run_cli(["report", "-n", str(p), "--vehicle", "P", "-o", str(tmp_path / "r"),
                    "--workers", "1"], timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert "lane TE_in_0 point 1: z 1000000.00 m" in proc.stderr


# -- scale of the study: said at once, capped

def test_a_table_of_100000_rows_is_refused_at_once_naming_the_variable(tmp_path):
    # it ran for minutes without a word
    bundled = (REPO / "vehicles" / "tables" / "aashto_green_book.csv").read_text().splitlines()
    row = next(r for r in bundled if r.startswith("P,"))
    table = tmp_path / "fleet.csv"
    table.write_text(bundled[0] + "\n" + "".join(f"CAR{i}{row[1:]}\n" for i in range(100_000)))
    proc = run_cli(["check", "-n", str(INTERSECTION), "-t", str(table), "--design-vehicle",
                    "CAR1"], timeout=20)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert (f"{table}: refused: 100,000 vehicle rows, more than the limit of 2,000"
            in proc.stderr) and "CLEARANCE_MAX_VEHICLES" in proc.stderr


def test_a_study_says_its_runs_and_time_first_and_refuses_above_the_cap(tmp_path, capsys):
    out = tmp_path / "r"
    argv = ["report", "-n", str(INTERSECTION), "--vehicle", "P", "--vehicle", "SU-30",
            "-o", str(out), "--lane-only", "--workers", "1"]
    proc = run_cli(argv, env={"CLEARANCE_MAX_RUNS": "10"})
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "refused: the study has 40 runs (2 vehicles on 20 curves), more than the limit " \
           "of 10" in proc.stderr and "CLEARANCE_MAX_RUNS" in proc.stderr
    assert not out.exists()
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "clearance report: 40 runs (2 vehicles on 20 curves of 1 network(s)): about " in err


# -- what works stays working

HEBREW_CAR = "מכונית פרטית"  # a right-to-left name, as a spreadsheet in Hebrew saves it
ARABIC_STREET = "شارع_الملك"


def test_a_spreadsheet_table_and_right_to_left_names_and_ids(tmp_path, capsys):
    # "CSV UTF-8" from a spreadsheet: a byte-order mark and CRLF line ends; a vehicle named
    # in Hebrew; a network whose street is named in Arabic
    bundled = (REPO / "vehicles" / "tables" / "aashto_green_book.csv").read_text().splitlines()
    row = next(r for r in bundled if r.startswith("P,"))
    table = tmp_path / "fleet.csv"
    table.write_bytes(("\ufeff" + bundled[0] + "\r\n" + HEBREW_CAR + row[1:] + "\r\n")
                      .encode("utf-8"))
    net = tmp_path / "rtl.net.xml"
    net.write_text(HOSTILE_IDS.read_text(encoding="utf-8").replace(
        "up:&amp;", ARABIC_STREET), encoding="utf-8")
    out = tmp_path / "r"
    assert main(["report", "-n", str(net), "-t", str(table), "-o", str(out),
                 "--workers", "1"]) == 0, capsys.readouterr().err
    import pandas as pd

    frame = pd.read_csv(out / "clearance.csv", keep_default_na=False)
    assert set(frame.vehicle) == {HEBREW_CAR}
    assert f"turn:C<x>:in&<a>:1_0->{ARABIC_STREET}_0" in set(frame.curve_id)
    assert HEBREW_CAR in (out / "report.md").read_text(encoding="utf-8")
    assert HEBREW_CAR in (out / "report.html").read_text(encoding="utf-8")


@pytest.mark.parametrize("command", ["report", "simulate"])
def test_o_naming_an_existing_file_is_refused_and_the_file_kept(tmp_path, capsys, command):
    target = tmp_path / "notes.txt"
    target.write_text("my notes")
    argv = {"report": ["report", "-n", str(INTERSECTION), "--vehicle", "P", "-o", str(target)],
            "simulate": ["simulate", "-n", str(INTERSECTION), "--vehicle", "P", "--no-sumo",
                         "-o", str(target)]}[command]
    refused(capsys, argv, f"{target}: ")
    assert target.read_text() == "my notes"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]
