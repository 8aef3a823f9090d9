"""User CSV files: csv quoting, '#' comments only before the header, exact line numbers."""

from __future__ import annotations

import pytest

from clearance.reports.results.csv_rows import csv_line, read_rows
from clearance.vehicles.errors import InputError


def test_hash_in_fields_and_after_the_header_is_data(tmp_path):
    p = tmp_path / "f.csv"
    p.write_text("# note one\n#note two\nid,verdict\n"
                 "turn:123:156775056#13_0->-27149243_1,clear\n"
                 "#starts-with-hash,fails\n"
                 '"quoted, with comma # and ""quote""",clear\n')
    header, rows = read_rows(p, "test file", ["id"])
    assert header == ["id", "verdict"]
    assert [(line, r["id"]) for line, r in rows] == [
        (4, "turn:123:156775056#13_0->-27149243_1"),
        (5, "#starts-with-hash"),
        (6, 'quoted, with comma # and "quote"'),
    ]


def test_written_lines_read_back_whatever_the_text(tmp_path):
    ids = ["a#1", "#b", 'c,"d"', "e\nf", " g ", "h*[i]?"]
    p = tmp_path / "f.csv"
    with open(p, "w", newline="") as fh:
        fh.write("id,n\n" + "".join(csv_line([x, k]) for k, x in enumerate(ids)))
    header, rows = read_rows(p, "test file", ["id"])
    assert [r["id"] for _, r in rows] == ids
    assert [r["n"] for _, r in rows] == [str(k) for k in range(len(ids))]
    # the row after a field spanning two lines starts on the right line
    assert [line for line, _ in rows] == [2, 3, 4, 5, 7, 8]


@pytest.mark.parametrize("text, message", [
    ("", "f.csv: an empty test file"),
    ("# only a comment\n", "f.csv: an empty test file"),
    ("# c\nname,verdict\n", r"f.csv:2: missing column\(s\) id"),
    ("id,id\n", "f.csv:1: column.s. id twice"),
    ("id,n\n\na,1\nb,2,3\n", "f.csv:4: 3 fields, the header has 2"),
    ('id,n\na,1\n"b,2\n', "f.csv:3: not a valid CSV row"),
])
def test_errors_name_file_and_line(tmp_path, text, message):
    p = tmp_path / "f.csv"
    p.write_text(text)
    with pytest.raises(InputError, match=message):
        read_rows(p, "test file", ["id"])


def test_missing_and_binary_files(tmp_path):
    with pytest.raises(InputError, match="none.csv: no such test file"):
        read_rows(tmp_path / "none.csv", "test file", ["id"])
    p = tmp_path / "b.csv"
    p.write_bytes(b"id\n\xff\xfe\n")
    with pytest.raises(InputError, match="b.csv: not a UTF-8"):
        read_rows(p, "test file", ["id"])
