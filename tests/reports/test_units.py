"""Output units: one unit system throughout an output, the reasons' lengths included."""

from __future__ import annotations

import csv
import html
import io
import math
import re

import numpy as np
import pandas as pd
import pytest
import shapely

from clearance.analysis.clearance import Areas, Clearance, classify, worst_level
from clearance.analysis.feature import feature_mask, feature_reason
from clearance.analysis.levels import Level
from clearance.analysis.overreach import Overreach
from clearance.analysis.polyline import prepare_path
from clearance.analysis.tracking import simulate
from clearance.networks.driving.candidates import Candidate
from clearance.networks.driving.judging import swing_reason
from clearance.networks.elevation import repair_suspect_heights
from clearance.networks.samples import build as samples
from clearance.networks.selection import Selection
from clearance.reports.cli.main import main
from clearance.reports.results.feedback import overreach_words
from clearance.reports.results.records import COLUMNS
from clearance.reports.results.tables import clearance_csv
from clearance.reports.results.units import TEXT_COLUMNS, text_in_units, to_output_units
from clearance.reports.results.vertical import vertical_words
from clearance.reports.study.run import run_study
from clearance.vehicles.errors import InputError
from clearance.vehicles.schema import FOOT_M
from clearance.vehicles.table import load_tables
from clearance.vehicles.vehicle import Vehicle

NUMBER = re.compile(r"\d+(?:\.\d+)?")
#: A metre length left in a text: a digit, a space, ``m`` as a word (not ``m/s``, ``m²``).
METRE_LENGTH = re.compile(r"\d m(?![\w/²])")


def aligned_lengths(metres: str, feet: str) -> list[tuple[str, str]]:
    """The (metre, foot) number pairs of the lengths of two versions of one text, checking
    that everything else (words, signs, coordinates, percentages, times) is the same."""
    a, b = NUMBER.split(metres), NUMBER.split(feet)
    na, nb = NUMBER.findall(metres), NUMBER.findall(feet)
    assert len(na) == len(nb), (metres, feet)
    pairs = []
    for i, (x, y) in enumerate(zip(na, nb, strict=True)):
        after_a, after_b = a[i + 1], b[i + 1]
        # a length: the number has " m" after it, or starts a range whose end has it
        ends = re.match(r" m(?![\w/²])", after_a)
        starts = after_a in ("-", " to ") and i + 1 < len(na) and re.match(
            r" m(?![\w/²])", a[i + 2])
        if ends:
            assert after_b.startswith(" ft") and after_b[3:] == after_a[2:], (metres, feet)
        else:
            assert after_b == after_a, (metres, feet)
        if ends or starts:
            pairs.append((x, y))
        else:
            assert x == y, (metres, feet)  # not a length: as written
    assert a[0] == b[0]
    return pairs


def assert_converted(metres: str, feet: str) -> None:
    """Each foot figure is its metre figure / 0.3048, rounded to as many decimals."""
    for x, y in aligned_lengths(metres, feet):
        step = 10.0 ** -len(x.partition(".")[2])
        assert len(y.partition(".")[2]) == len(x.partition(".")[2])
        assert abs(float(y) - float(x) / FOOT_M) <= step / 2 + 1e-9, (x, y)


CAR = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)


def produced_reasons() -> list[str]:
    """A reason of every form analysis/ and networks/ write (each made by its function)."""
    out = []
    for c in (Clearance("clear", 0.41, 0.9, None, 0.0, ""),
              Clearance("fails", -3.0, -0.62, -2.0, 0.0, ""),
              Clearance("encroaches", -1.1, 0.5, 0.4, 0.0, ""),
              Clearance("encroaches", -2.0, 0.5, -1.4, 0.0, "")):
        out.append(swing_reason(2.25, 0.3, c))
    z = prepare_path([(0.0, 0.0), (1.0, 0.0)])
    zeros = np.zeros(1)
    out += [Candidate(2.0, 0.0, zeros, z, (0.0, 1.0), zeros).how,
            Candidate(3.5, 0.3, zeros, z, (0.0, 1.0), zeros, "fitted", 0.5).how,
            Candidate(0.0, 0.0, zeros, z, (0.0, 1.0), zeros, "inside", inside_m=1.25).how]
    out.append(overreach_words(Overreach(0.62, 405.114, -10.649, 52.13, 0.56), "fails"))
    lanes = shapely.box(0, 0, 20, 3.5)
    areas = Areas(lanes, shapely.box(0, -1, 20, 4.5))
    for env in (shapely.box(2, 0.5, 10, 3.0), shapely.box(2, 0.5, 10, 4.0),
                shapely.box(2, 0.5, 10, 5.2)):
        out.append(classify(env, areas, 0.25).reason)
    out.append(worst_level([(Level(2.5, 3.5, None), (10.0, 20.5),
                             Clearance("fails", -0.4, -0.3, None, 0.0, "leaves"))]).reason)
    run = simulate(CAR, [(0.0, 0.0), (20.0, 0.0), (20.0, 3.0), (0.0, 3.0)])
    out += [run.reason, feature_reason(run, feature_mask(run, (15.0, 30.0)))]
    from clearance.networks.model import Edge, Lane, Location, Network

    line = np.array([[0, 0, 40.0], [50, 0, 40.2], [122, 0, 218], [200, 0, 40.6]])
    net = Network("n", {"m_0": Lane("m_0", "m", 0, 3.5, "normal", frozenset(), line, 200, 9)},
                  {"m": Edge("m", "a", "b", "normal", 1, ["m_0"])}, [], {}, [], Location())
    repair_suspect_heights(net)
    out.append(net.suspect_heights["m_0"][0])
    assert all(out) and all(METRE_LENGTH.search(r) for r in out), out
    return out


@pytest.mark.parametrize("reason", produced_reasons())
def test_every_form_of_reason_comes_out_in_feet(reason):
    feet = text_in_units(reason, "ft")
    assert not METRE_LENGTH.search(feet), feet
    assert " ft" in feet
    assert_converted(reason, feet)
    # the metres are left as they are, and converting twice changes nothing more
    assert text_in_units(reason, "m") == reason
    assert text_in_units(feet, "ft") == feet


def test_what_is_not_a_length_is_left_alone():
    text = ("at t = 2.50 s, 45 deg, grades +12 % and -3 %, 2 m/s, 30 km/h, (x 405.11, "
            "y -10.65), in 300 samples, lane E2-3 m, 1e+07 m")
    assert text_in_units(text, "ft") == text
    # the range's end and start are both lengths; an area is in square feet
    assert text_in_units("stations 10.0-20.0 m, a hole of 1.00 m²", "ft") == (
        "stations 32.8-65.6 ft, a hole of 10.76 ft²")
    with pytest.raises(InputError, match="unknown units 'yd'"):
        text_in_units("1 m", "yd")


def test_the_reason_column_is_converted_with_the_lengths():
    frame = to_output_units(
        pd.DataFrame({"margin_m": [0.1524], "overreach_x": [405.114],
                      "reason": ["stays 0.15 m inside"], "suspect_elevation": [""]}),
        "ft", suffix=True)
    assert list(frame.columns) == ["margin_ft", "overreach_x", "reason", "suspect_elevation"]
    assert frame.margin_ft[0] == pytest.approx(0.5)
    assert frame.overreach_x[0] == 405.114  # network coordinates stay the network's
    assert frame.reason[0] == "stays 0.49 ft inside"


def test_vertical_words_give_the_suspect_heights_in_feet():
    note = "point at x 122.00, y 0.00: z 218.00 m, 177.6 m off the line (grades +247 %)"
    r = type("R", (), dict(vertical="clear", vertical_margin_m=math.nan,
                           vertical_station_m=math.nan, vertical_part="", max_grade_pct=0.0,
                           grade_limit_pct=math.nan, suspect_elevation=note))()
    words = vertical_words(r, "ft")
    assert "z 715.22 ft, 582.7 ft off the line" in words and "x 122.00, y 0.00" in words
    assert not METRE_LENGTH.search(words)


# --------------------------------------------------------------- a real study in feet

NET = samples.SAMPLES_DIR / "intersection" / "intersection.net.xml"
VEHICLES = ["P", "CITY-BUS", "WB-62"]


@pytest.fixture(scope="module")
def feet_report(tmp_path_factory):
    """``clearance report --units ft`` at the T junction, and the same study in metres."""
    pytest.importorskip("libsumo")
    out = tmp_path_factory.mktemp("ft") / "rep"
    args = ["report", "-n", str(NET), "--junction", "T", "-o", str(out), "--units", "ft",
            "--workers", "1"]
    for v in VEHICLES:
        args += ["--vehicle", v]
    assert main(args) == 0
    study = run_study([NET], load_tables(None, VEHICLES), workers=1,
                      selection=Selection(junctions=("T",)))
    metres = list(csv.DictReader(io.StringIO(clearance_csv(study))))
    with open(out / "clearance.csv", newline="") as fh:
        feet = list(csv.DictReader(fh))
    return out, metres, feet


def test_the_feet_csv_has_no_metre_length_and_agrees_with_the_metres(feet_report):
    _, metres, feet = feet_report
    assert list(feet[0]) == [c[:-2] + "_ft" if c.endswith("_m") else c for c in COLUMNS]
    assert [(r["vehicle"], r["curve_id"]) for r in feet] == [
        (r["vehicle"], r["curve_id"]) for r in metres]
    # the study has what the conversion must cover: swung paths, fails with an overreach
    assert {r["path"] for r in feet} == {"lane", "swung"}
    assert any(r["verdict"] == "fails" and r["extra_width_ft"] for r in feet)
    converted = 0
    for m, f in zip(metres, feet, strict=True):
        assert f["verdict"] == m["verdict"]
        assert not METRE_LENGTH.search(f["reason"]), f["reason"]
        assert_converted(m["reason"], f["reason"])
        converted += len(aligned_lengths(m["reason"], f["reason"]))
        for c in COLUMNS:
            if c.endswith("_m") and m[c]:
                # both rounded to three decimals from the same length
                tol = 0.0005 + 0.0005 / FOOT_M + 1e-9
                assert float(f[c[:-2] + "_ft"]) == pytest.approx(float(m[c]) / FOOT_M,
                                                                 abs=tol), c
            elif c in TEXT_COLUMNS:
                assert not METRE_LENGTH.search(f[c]), f[c]
                assert_converted(m[c], f[c])
            elif not c.endswith("_m"):
                assert f[c] == m[c], c  # coordinates, angles, grades, names as they are
    assert converted > 2 * len(feet)  # 24 lengths in 8 reasons


def test_the_feet_report_says_every_length_in_feet(feet_report):
    out, _, feet = feet_report
    for name in ("report.html", "report.md"):
        text = (out / name).read_text(encoding="utf-8")
        text = re.sub(r'src="data:[^"]*"', "", text)
        if name.endswith(".html"):
            text = html.unescape(re.sub(r"<[^>]+>", " ", text))
        assert not METRE_LENGTH.search(text), METRE_LENGTH.search(text)
        assert "clearance offset 0 ft" in text and "0.82 ft to spare" in text
        said = [r["reason"] for r in feet if r["verdict"] != "clear" or r["path"] == "swung"]
        assert said and all(r in text for r in said), name
