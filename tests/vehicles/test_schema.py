"""Every number column has a physical range: just inside passes, just outside is refused."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from clearance.vehicles.errors import TableError
from clearance.vehicles.schema import ALL_COLUMNS, FOOT_M, Column
from clearance.vehicles.table import load_tables

BASE = {"name": "A", "category": "car", "units": "m", "length": "12", "width": "1.8",
        "wheelbase": "2.7", "front_overhang": "0.9", "source": "test", "max_steer_deg": "35"}
TRAILER = {"hitch_offset": "0.5", "trailer_wheelbase": "6"}
RANGED = [c for c in ALL_COLUMNS.values() if c.low is not None]
README = Path(__file__).resolve().parents[2] / "README.md"


def test_every_number_column_has_a_range_and_a_reason():
    numbers = [c for c in ALL_COLUMNS.values() if c.kind not in ("text", "choice")]
    assert numbers == RANGED
    for c in RANGED:
        assert c.high is not None and c.low < c.high and len(c.why) > 5, c.name


def _row(col: Column, text: str) -> dict[str, str]:
    row = dict(BASE)
    if col.name in ALL_COLUMNS and col.name.startswith(("trailer_", "max_articulation",
                                                        "hitch")):
        row.update(TRAILER)
    if col.name in ("curb_to_curb", "wall_to_wall", "ctr"):
        del row["max_steer_deg"]
    row[col.name] = text
    return row


def _problems(tmp_path: Path, row: dict[str, str]) -> list[str]:
    p = tmp_path / "t.csv"
    p.write_text(",".join(row) + "\n" + ",".join(row.values()) + "\n")
    try:
        load_tables([p])
    except TableError as exc:
        return exc.problems
    return []


def _inside(col: Column) -> list[float]:
    eps = 1e-6 * max(1.0, abs(col.high))
    low = col.low + eps if (col.positive is True and col.low == 0) else col.low
    high = col.high - eps if col.high_open else col.high
    return [low, high]


def _outside(col: Column) -> list[float]:
    eps = 1e-6 * max(1.0, abs(col.high))
    low = col.low if (col.positive is True and col.low == 0) else col.low - eps
    high = col.high if col.high_open else col.high + eps
    return [low, high]


def _text(value: float) -> str:
    return repr(round(value, 9))


@pytest.mark.parametrize("col", RANGED, ids=[c.name for c in RANGED])
def test_just_inside_the_range_is_accepted(tmp_path, col):
    for value in _inside(col):
        text = _text(value)
        probs = _problems(tmp_path, _row(col, text))
        # other columns may disagree with an extreme value; the range itself is not at fault
        assert not [s for s in probs if "outside the range" in s], (text, probs)


@pytest.mark.parametrize("col", RANGED, ids=[c.name for c in RANGED])
def test_just_outside_the_range_is_refused_naming_file_line_column_value(tmp_path, col):
    for value in _outside(col):
        text = _text(value)
        probs = _problems(tmp_path, _row(col, text))
        expected = (f"{tmp_path / 't.csv'}:2 (A): column {col.name}: {text!r}: outside the "
                    f"range {col.range_text()} ({col.why})")
        assert expected in probs, (text, probs)


def test_lengths_are_bounded_in_metres_whatever_the_units(tmp_path):
    row = dict(BASE, units="ft", length="40", width="6", wheelbase="9", front_overhang="3")
    assert _problems(tmp_path, dict(row, length="196.8")) == []  # 59.98 m
    probs = _problems(tmp_path, dict(row, length="196.9"))  # 60.02 m
    assert probs == [f"{tmp_path / 't.csv'}:2 (A): column length: '196.9': outside the range "
                     f"[1.64, 196.9] ft = [0.5, 60] m ({ALL_COLUMNS['length'].why})"]
    assert 196.9 * FOOT_M > 60 > 196.8 * FOOT_M


def test_values_that_broke_the_arithmetic_are_refused(tmp_path):
    # a lock of 1e-300 degrees and a width of 1e300 m raised ZeroDivisionError
    for column, text in (("max_steer_deg", "1e-300"), ("width", "1e300"), ("length", "1e300"),
                         ("wheelbase", "1e-300")):
        probs = _problems(tmp_path, dict(BASE, **{column: text}))
        assert len(probs) == 1 and f"column {column}: {text!r}: outside the range" in probs[0]


def test_the_documented_default_articulation_is_accepted(tmp_path):
    # 90 degrees is the documented default, and was refused when written out
    p = tmp_path / "t.csv"
    row = dict(BASE, **TRAILER, max_articulation_deg="90")
    p.write_text(",".join(row) + "\n" + ",".join(row.values()) + "\n")
    t = load_tables([p])
    assert t.frame["max_articulation_rad"].iloc[0] == pytest.approx(math.pi / 2)
    assert ALL_COLUMNS["max_articulation_deg"].default == 90.0


def test_readme_states_every_range():
    # the README's table of ranges is the schema's
    text = README.read_text().split("| column | range | why |\n", 1)[1].split("\n\n", 1)[0]
    for col in RANGED:
        m = re.search(rf"^\| `{col.name}` \| ([^|]+) \| ([^|]+) \|$", text, re.M)
        assert m, f"{col.name} is missing from the README's ranges"
        assert m.group(1).strip() == col.range_text(), col.name
        assert m.group(2).strip() == col.why, col.name
