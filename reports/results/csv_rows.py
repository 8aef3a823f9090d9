"""Reading the small CSV files a user gives a command (golden verdicts, waivers).

The files are read with the csv module's quoting, so a field may hold anything, ``#``
and ``,`` included (SUMO ids of OpenStreetMap networks are full of ``#``). The first row
that is not a comment is the header. Comments are whole lines that start with ``#`` in
the first column *before* the header; after it every line is data (a curve id that
starts with ``#`` is data). Blank lines are skipped. Every problem names the file and the
line (the first line of a row, for a quoted field that spans lines).
"""

from __future__ import annotations

import csv
from collections.abc import Iterator, Sequence
from pathlib import Path

from clearance.vehicles.errors import InputError

__all__ = ["Row", "csv_line", "read_rows"]

#: A row of a file: its line number and its fields by column name.
Row = tuple[int, dict[str, str]]


def read_rows(path: Path, what: str, required: Sequence[str]) -> tuple[list[str], list[Row]]:
    """The header and the rows of a CSV file.

    Parameters
    ----------
    path
        The file.
    what
        What the file is, for messages (e.g. ``"golden file"``).
    required
        Columns the header must have (others are allowed and kept).

    Raises
    ------
    InputError
        No such file, not UTF-8 text, no header, a missing column, a row with more or
        fewer fields than the header, or a quoting error: the message names the file and
        the line.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = Path(d, "w.csv")
    ...     _ = p.write_text('# a note\\nid,n\\n"a#1,b",2\\n\\n#c,3\\n')
    ...     read_rows(p, "test file", ["id"])
    (['id', 'n'], [(3, {'id': 'a#1,b', 'n': '2'}), (5, {'id': '#c', 'n': '3'})])
    """
    if not path.is_file():
        raise InputError(f"{path}: no such {what}")
    try:
        with open(path, encoding="utf-8-sig", newline="") as fh:
            return _read(fh, path, what, required)
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not a UTF-8 text {what}: {exc}") from None


def _read(fh: Iterator[str], path: Path, what: str,
          required: Sequence[str]) -> tuple[list[str], list[Row]]:
    skipped = 0
    first = ""
    for line in fh:
        if line.startswith("#") or not line.strip():
            skipped += 1
            continue
        first = line
        break
    if not first:
        raise InputError(f"{path}: an empty {what} (no header row)")

    def lines() -> Iterator[str]:
        yield first
        yield from fh

    reader = csv.reader(lines(), strict=True)
    rows: list[Row] = []
    header: list[str] = []
    last = 0
    try:
        for fields in reader:
            start = skipped + last + 1
            last = reader.line_num
            if not header:
                header = [f.strip() for f in fields]
                missing = [c for c in required if c not in header]
                if missing:
                    raise InputError(f"{path}:{start}: missing column(s) "
                                     f"{', '.join(missing)} (the header has "
                                     f"{', '.join(header)})")
                dupes = sorted({c for c in header if header.count(c) > 1})
                if dupes:
                    raise InputError(f"{path}:{start}: column(s) {', '.join(dupes)} twice")
                continue
            if not fields or fields == [""]:
                continue  # a blank line
            if len(fields) != len(header):
                raise InputError(f"{path}:{start}: {len(fields)} fields, the header has "
                                 f"{len(header)}")
            rows.append((start, dict(zip(header, fields, strict=True))))
    except csv.Error as exc:
        raise InputError(f"{path}:{skipped + reader.line_num}: not a valid CSV row: "
                         f"{exc}") from None
    return header, rows


def csv_line(fields: Sequence[object]) -> str:
    """One CSV line (csv module quoting, ``\\n`` ending).

    Examples
    --------
    >>> csv_line(["n", 'a "b", c', "x#1"])
    'n,"a ""b"", c",x#1\\n'
    """
    import io

    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(fields)
    return out.getvalue()
