"""File names made from ids: within 255 bytes, stable, unique, and usable end to end."""

from __future__ import annotations

import csv
import doctest
import hashlib
import os
import re

import pytest

from clearance.networks.samples import build as samples
from clearance.reports.cli.main import main
from clearance.reports.output import file_names
from clearance.reports.output.atomic import write_text_atomic
from clearance.reports.output.file_names import MAX_NAME_BYTES, file_name

# 250 characters, with the characters of real OSM-derived ids and some worse
LONG_ID = ("roundabout:cluster_25#3:/" + "ab#12/-3:>" * 23)[:250]


def test_a_250_character_id_gives_a_short_stable_name_that_can_be_written(tmp_path):
    assert len(LONG_ID) == 250 and "#" in LONG_ID and "/" in LONG_ID
    name = file_name(["CITY-BUS", LONG_ID], ".csv")
    assert len(name.encode()) <= MAX_NAME_BYTES < 255 - len(".X.12345678.tmp")
    assert re.fullmatch(r"[A-Za-z0-9._-]+~[0-9a-f]{16}\.csv", name)
    assert name.startswith("CITY-BUS__roundabout_cluster_25_3__ab_12_-3__")
    digest = hashlib.sha256(("CITY-BUS\0" + LONG_ID).encode()).hexdigest()[:16]
    assert name.endswith(f"~{digest}.csv")  # the hash of the exact ids
    assert file_name(["CITY-BUS", LONG_ID], ".csv") == name  # stable
    path = write_text_atomic(tmp_path / name, "x\n")  # its temporary name fits too
    assert path.read_text() == "x\n" and os.listdir(tmp_path) == [name]


def test_ids_differing_only_beyond_the_cut_or_in_replaced_characters_stay_apart():
    names = {file_name(["P", LONG_ID[:-1] + c]) for c in "abc#/"}
    assert len(names) == 5
    near = [["P", "a:b"], ["P", "a_b"], ["P", "a/b"], ["P", "a b"], ["P_", "b"], ["P", "_b"],
            ["P", "a", "b"], ["P__a", "b"], ["P", "a__b"], [".P", "a"], ["P", ".a"]]
    got = [file_name(p, ".png") for p in near]
    assert len(set(got)) == len(near)
    assert got[1] == "P__a_b.png" and got[6] == "P__a__b.png"  # left as they are
    assert all(not n.startswith(".") and "/" not in n for n in got)


def test_unicode_ids_are_ascii_names_with_a_hash():
    name = file_name(["Straße", "Kreisel:Süd"], ".svg")
    assert name.isascii() and name.startswith("Stra_e__Kreisel_S_d~")
    assert file_name(["Straße"]) != file_name(["Stra?e"])


def test_an_unsafe_suffix_is_a_programming_error():
    with pytest.raises(ValueError):
        file_name(["a"], "/../x")
    with pytest.raises(ValueError):
        file_name(["a"], room=-1)


def test_docstring_examples():
    result = doctest.testmod(file_names)
    assert result.attempted >= 4 and result.failed == 0


@pytest.fixture
def long_id_net(tmp_path):
    """The intersection sample with its north approach renamed to a 230-character id."""
    edge = ("osm/way#4711:" + "Hauptstraße#x/" * 20)[:230]
    text = (samples.SAMPLES_DIR / "intersection" / "intersection.net.xml").read_text()
    net = tmp_path / "long.net.xml"
    net.write_text(text.replace("XN_in", edge))
    return net, f"turn:X:{edge}_0->XW_out_0"


def test_simulate_and_report_write_runs_of_a_250_character_curve_id(long_id_net, tmp_path):
    pytest.importorskip("libsumo")
    net, curve = long_id_net
    assert len(curve) >= 249 and len(curve.encode()) > 255
    out = tmp_path / "sim"
    assert main(["simulate", "-n", str(net), "--vehicle", "CITY-BUS", "--vehicle", "P",
                 "--curve", curve, "--no-sumo", "-o", str(out)]) == 0
    with open(out / "results.csv", newline="") as fh:
        assert [r["curve_id"] for r in csv.DictReader(fh)] == [curve, curve]
    trajectories = sorted(p.name for p in (out / "trajectories").iterdir())
    assert trajectories == sorted(file_name([v, curve], ".csv") for v in ("CITY-BUS", "P"))
    assert all(len(n.encode()) <= MAX_NAME_BYTES for n in trajectories)

    rep = tmp_path / "rep"
    assert main(["report", "-n", str(net), "--vehicle", "CITY-BUS", "--method", "analytic",
                 "-o", str(rep), "--svg"]) == 0
    figures = sorted(p.name for p in (rep / "figures").iterdir())
    mine = file_name(["long", "curve", curve], room=4)
    assert f"{mine}.png" in figures and f"{mine}.svg" in figures  # the bus fails there
    assert max(len(n.encode()) for n in figures) <= MAX_NAME_BYTES
    assert f"(figures/{mine}.png)" in (rep / "report.md").read_text()
