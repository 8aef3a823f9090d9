"""``clearance curves``: output, CSV, and exit status 2 on bad input."""

from __future__ import annotations

import csv
import gzip
import os
from pathlib import Path

import pytest

from clearance.networks.sumo.tools import netconvert_plain
from clearance.reports.cli.main import main
from clearance.reports.results.curve_rows import COLUMNS

NODES = (
    '<nodes><node id="C" x="0" y="0" type="traffic_light" radius="8"/>'
    '<node id="W" x="-80" y="0"/><node id="E" x="80" y="0"/><node id="N" x="0" y="80"/>'
    "</nodes>"
)
EDGES = (
    "<edges>"
    + "".join(
        f'<edge id="{a}{b}" from="{a}" to="{b}" numLanes="2" width="3.25"/>'
        for a, b in (("W", "C"), ("C", "W"), ("E", "C"), ("C", "E"), ("N", "C"), ("C", "N"))
    )
    + "</edges>"
)


@pytest.fixture(scope="module")
def tee_net(tmp_path_factory) -> Path:
    try:
        return netconvert_plain(tmp_path_factory.mktemp("tee"), "tee", NODES, EDGES)
    except FileNotFoundError as exc:  # pragma: no cover
        pytest.skip(f"netconvert not available: {exc}")


def test_prints_summary_and_writes_csv(tee_net, tmp_path, capsys):
    out = tmp_path / "curves.csv"
    assert main(["curves", "-n", str(tee_net), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "turn" in text and "R min [m]" in text
    with out.open() as fh:
        rows = list(csv.DictReader(fh))
    assert tuple(rows[0].keys()) == COLUMNS
    ids = [r["curve_id"] for r in rows]
    turns = [r for r in rows if r["kind"] == "turn"]
    assert len(turns) == len(ids) and len(set(ids)) == len(ids)

    # a right turn from the west arm into the north arm does not exist; W->N is a left turn
    def movement(a: str, b: str) -> list[dict[str, str]]:
        return [
            r
            for r in turns
            if r["curve_id"].startswith(f"turn:C:{a}_") and f"->{b}_" in r["curve_id"]
        ]

    left = movement("WC", "CN")
    assert left and all(float(r["turn_angle_deg"]) > 60 for r in left)
    right = [
        r for r in turns if r["curve_id"].startswith("turn:C:EC_") and "->CN_" in r["curve_id"]
    ]
    assert right and all(float(r["turn_angle_deg"]) < -60 for r in right)
    # the right turn hugs the 8 m corner: its centre line is tighter than the left turn's
    assert min(float(r["min_radius"]) for r in right) < min(float(r["min_radius"]) for r in left)
    assert not list(tmp_path.glob(".curves.csv.*"))  # no temporary file left behind


def test_kind_filter(tee_net, tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["curves", "-n", str(tee_net), "--kind", "roundabout", "-o", str(out)]) == 0
    assert "no curves" in capsys.readouterr().out
    assert out.read_text().strip() == ",".join(COLUMNS)


def _bad(tmp_path: Path, name: str, data: bytes) -> Path:
    p = tmp_path / name
    p.write_bytes(data)
    return p


@pytest.mark.parametrize(
    ("name", "data", "message"),
    [
        ("missing.net.xml", None, "no such file"),
        ("text.net.xml", b"hello\n", "not XML"),
        ("routes.xml", b"<routes/>", "not a SUMO network"),
        ("empty.net.xml", b"<net/>", "SUMO refuses to load this network: "),  # it crashes
        (
            "bomb.net.xml",
            b'<!DOCTYPE net [<!ENTITY a "x"><!ENTITY b "&a;&a;">]><net>&b;</net>',
            "refused",
        ),
        ("cut.net.xml", b'<net version="1.20"><edge id="e" from="a" to="b"><lane id="e_0" ',
         "SUMO refuses to load this network: "),
    ],
)
def test_bad_input_exits_2_without_traceback(tmp_path, capsys, name, data, message):
    path = tmp_path / name if data is None else _bad(tmp_path, name, data)
    assert main(["curves", "-n", str(path)]) == 2
    err = capsys.readouterr().err
    assert name in err and message in err
    assert "Traceback" not in err


def test_truncated_gzip_exits_2(tee_net, tmp_path, capsys):
    data = gzip.compress(tee_net.read_bytes())
    path = _bad(tmp_path, "cut.net.xml.gz", data[: len(data) // 2])
    assert main(["curves", "-n", str(path)]) == 2
    assert "cut.net.xml.gz" in capsys.readouterr().err


def test_output_into_missing_directory_exits_2(tee_net, tmp_path, capsys):
    assert main(["curves", "-n", str(tee_net), "-o", str(tmp_path / "no" / "x.csv")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_output_csv_gets_the_permissions_of_the_umask(tee_net, tmp_path):
    mask = os.umask(0o022)
    try:
        assert main(["curves", "-n", str(tee_net), "-o", str(tmp_path / "c.csv")]) == 0
    finally:
        os.umask(mask)
    assert os.stat(tmp_path / "c.csv").st_mode & 0o777 == 0o644  # mkstemp alone gave 0600
    assert not list(tmp_path.glob(".*.tmp"))


def test_straight_movements_are_said_in_words(capsys):
    from clearance.networks.samples.build import SAMPLES_DIR

    net = SAMPLES_DIR / "intersection" / "intersection.net.xml"
    assert main(["curves", "-n", str(net), "--limit", "100"]) == 0
    lines = capsys.readouterr().out.splitlines()
    straight = [ln for ln in lines if "XW_in_0->XE_out_0" in ln]
    assert len(straight) == 1 and "straight on" in straight[0] and "inf" not in straight[0]
    right = [ln for ln in lines if "TW_in_0->TS_out_0" in ln]
    assert "right 90°" in right[0]


def test_suspect_elevation_is_a_column_and_a_warning(tmp_path, capsys):
    from tests.networks.test_elevation import helix_sources

    nodes, edges = helix_sources(spike_at=40)
    net = netconvert_plain(tmp_path, "spike", f"<nodes>{nodes}</nodes>",
                           f"<edges>{edges}</edges>")
    out = tmp_path / "curves.csv"
    assert main(["curves", "-n", str(net), "--kind", "ramp", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "suspect elevation: lane helix_0 point" in err
    row = next(csv.DictReader(out.open()))
    assert row["suspect_elevation"].startswith("lane helix_0 point")
    assert float(row["max_grade_pct"]) < 6.5
