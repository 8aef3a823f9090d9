"""Loading and validating vehicle tables.

:func:`load_tables` reads one or several CSV tables, checks every row and reports every
problem at once (file, line, column, value, reason) as a
:class:`~clearance.vehicles.errors.TableError`.
The result is a :class:`VehicleTable`: a pandas DataFrame in SI units (lengths in metres,
angles in radians) with the steering lock resolved, plus the warnings found.

SI columns of the frame: ``name, category, source, table, line, units, length_m, width_m,
wheelbase_m, front_overhang_m, rear_overhang_m, track_m, steering, steered_axle,
max_inner_steer_rad, max_outer_steer_rad, max_steer_rad`` (the bicycle-equivalent lock),
``min_radius_m`` (rho at full lock), ``max_steer_rate_rad_s``, ``steering_ratio``,
``ackermann_pct``, ``steering_range_rad``, ``deadband_rad``, the optional dimensions in metres
or radians (``height_m``, ``ground_clearance_m``, ``approach_rad``, ...), and the trailer's
``hitch_offset_m, trailer_wheelbase_m, trailer_width_m, trailer_front_overhang_m,
trailer_rear_overhang_m, max_articulation_rad`` (NaN without a trailer).
"""

from __future__ import annotations

import csv
import difflib
import io
import logging
import math
import unicodedata
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

from clearance.vehicles.derive import LOCK_TOLERANCE, derive
from clearance.vehicles.errors import InputError, LimitError, OptionError, TableError
from clearance.vehicles.files import env_limit, open_regular
from clearance.vehicles.schema import (
    ALL_COLUMNS,
    REQUIRED,
    UNITS_TO_M,
    Column,
    default_vclass,
)
from clearance.vehicles.steering import Breakpoints, RackPinion, Schedule, Steering
from clearance.vehicles.underside import underside_from
from clearance.vehicles.vehicle import Trailer, Vehicle

__all__ = ["DEFAULT_MAX_TABLE_BYTES", "DEFAULT_MAX_VEHICLES", "LOCK_TOLERANCE",
           "MAX_TABLE_MB_ENV", "MAX_VEHICLES_ENV", "VehicleTable", "max_vehicles",
           "bundled_table", "bundled_table_paths", "load_tables", "max_table_bytes",
           "read_table_text", "steering_from_row", "unknown_name_message", "vehicle_from_row"]

log = logging.getLogger(__name__)


#: Default of :func:`max_table_bytes`: 100 MB, about 600,000 rows of the bundled tables'
#: width (the loader checks some 5,000 rows a second); a larger file is not a fleet.
DEFAULT_MAX_TABLE_BYTES = 100_000_000

#: The environment variable that raises the cap, in megabytes.
MAX_TABLE_MB_ENV = "CLEARANCE_MAX_TABLE_MB"


#: Default of :func:`max_vehicles`: rows of one table. The bundled tables have 40; a fleet
#: of 2,000 models takes about 0.4 s a row to check and derive, and as many runs per curve.
DEFAULT_MAX_VEHICLES = 2000

#: The environment variable that raises the cap on rows.
MAX_VEHICLES_ENV = "CLEARANCE_MAX_VEHICLES"


def max_vehicles() -> int:
    """How many vehicle rows one table may have: ``CLEARANCE_MAX_VEHICLES`` if set, else
    :data:`DEFAULT_MAX_VEHICLES`.

    >>> max_vehicles() >= 1
    True
    """
    return env_limit(MAX_VEHICLES_ENV, DEFAULT_MAX_VEHICLES)


def max_table_bytes() -> int:
    """How large a vehicle table may be: ``CLEARANCE_MAX_TABLE_MB`` megabytes if set, else
    :data:`DEFAULT_MAX_TABLE_BYTES`."""
    return env_limit(MAX_TABLE_MB_ENV, DEFAULT_MAX_TABLE_BYTES, 10**6)


@dataclass
class VehicleTable:
    """A validated vehicle table in SI units, with the warnings found while loading."""

    frame: pd.DataFrame
    warnings: list[str] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.frame)

    @property
    def names(self) -> list[str]:
        return list(self.frame["name"])

    def vehicle(self, name: str) -> Vehicle:
        """The :class:`~clearance.vehicles.vehicle.Vehicle` called ``name``."""
        rows = self.frame.index[self.frame["name"] == name]
        if len(rows) == 0:
            raise OptionError(unknown_name_message(name, self.names))
        return vehicle_from_row(self.frame.loc[rows[0]])

    def vehicles(self) -> list[Vehicle]:
        """Every row as a :class:`~clearance.vehicles.vehicle.Vehicle`, in table order."""
        return [vehicle_from_row(row) for _, row in self.frame.iterrows()]

    def steering(self, name: str) -> Steering:
        """The steering mechanism of the vehicle called ``name``."""
        rows = self.frame.index[self.frame["name"] == name]
        if len(rows) == 0:
            raise OptionError(unknown_name_message(name, self.names))
        return steering_from_row(self.frame.loc[rows[0]])


def bundled_table_paths() -> list[Path]:
    """The CSV tables shipped with the package, sorted by file name."""
    folder = resources.files("clearance.vehicles") / "tables"
    return sorted(Path(str(p)) for p in folder.iterdir() if p.name.endswith(".csv"))


def bundled_table(stem: str) -> Path:
    """The bundled table called ``stem`` (e.g. ``"paper_table1"``).

    Examples
    --------
    >>> bundled_table("paper_table1").name
    'paper_table1.csv'
    """
    for path in bundled_table_paths():
        if path.stem == stem:
            return path
    raise OptionError(f"no bundled vehicle table {stem!r}; there are "
                     f"{', '.join(p.stem for p in bundled_table_paths())}")


def unknown_name_message(name: str, known: Sequence[str]) -> str:
    """The message for an unknown vehicle name, with close matches (case-insensitive).

    >>> unknown_name_message("p", ["P", "SU-30", "WB-62"])[:38]
    "unknown vehicle 'p'; did you mean 'P'?"
    """
    folded: dict[str, str] = {}
    for k in known:
        folded.setdefault(k.casefold(), k)
    same = [k for k in known if k.casefold() == name.casefold()]
    close = same + [folded[c] for c in difflib.get_close_matches(name.casefold(), list(folded),
                                                                 n=3, cutoff=0.5)
                    if folded[c] not in same]
    close = close[:3]
    hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
    return (f"unknown vehicle {name!r}{hint} (known: {len(known)} vehicles, "
            "see `clearance vehicles`)")


def load_tables(
    paths: Iterable[str | Path] | None = None, names: Sequence[str] | None = None,
    warn: bool = True,
) -> VehicleTable:
    """Read, validate and convert vehicle tables.

    Parameters
    ----------
    paths
        CSV files; ``None`` or empty means every bundled table.
    names
        Keep only these models (in this order); ``None`` keeps every row. Warnings are
        logged (and kept) for the rows kept only.
    warn
        Log the warnings (False: only keep them in the table, e.g. when the tables are read
        for their names).

    Raises
    ------
    InputError
        A missing or unreadable file, or an unknown name.
    TableError
        Every bad row of every table, listed together.

    Examples
    --------
    >>> t = load_tables([bundled_table("paper_table1")], names=["2009 Smart Car"])
    >>> round(float(t.frame["wheelbase_m"].iloc[0]), 4)
    1.8669
    """
    files = _distinct([Path(p) for p in paths]) if paths else bundled_table_paths()
    if names:
        names = list(dict.fromkeys(names))  # a name given twice is asked for once
    problems: list[str] = []
    warnings: list[str] = []
    records: list[dict[str, object]] = []
    for path in files:
        records.extend(_read_file(path, problems, warnings))
    seen: dict[str, str] = {}
    for rec in records:
        where = f"{rec['table']}:{rec['line']}"
        if rec["name"] in seen:
            problems.append(f"{where}: column name: {rec['name']!r}: duplicate name "
                            f"(first at {seen[rec['name']]})")
        else:
            seen[str(rec["name"])] = where
    if problems:
        raise TableError(problems)
    frame = pd.DataFrame.from_records(records)
    if names:
        missing = [n for n in names if n not in seen]
        if missing:
            raise OptionError("; ".join(unknown_name_message(n, list(seen)) for n in missing))
        frame = frame.set_index("name", drop=False).loc[list(names)].reset_index(drop=True)
        kept = [f"{t}:{n}" for t, n in zip(frame["table"], frame["line"], strict=True)]
        warnings = [w for w in warnings if any(w.startswith((f"{k} ", f"{k}:")) for k in kept)]
    for w in warnings if warn else ():
        log.warning(w)
    return VehicleTable(frame, warnings)


def _distinct(paths: list[Path]) -> list[Path]:
    """``paths`` without repeats of one file (the same path twice, or two names of it).

    Examples
    --------
    >>> _distinct([Path("a.csv"), Path("./a.csv"), Path("b.csv")])
    [PosixPath('a.csv'), PosixPath('b.csv')]
    """
    seen: set[object] = set()
    out = []
    for p in paths:
        try:
            st = p.stat()
            key: object = (st.st_dev, st.st_ino)
        except (OSError, ValueError):
            key = p
        if key not in seen:
            seen.add(key)
            out.append(p)
    return out


def read_table_text(path: Path) -> str:
    """The text of a vehicle table: a regular file of at most :func:`max_table_bytes`,
    UTF-8 (with or without a byte-order mark).

    Raises
    ------
    InputError
        Missing, not a regular file (a FIFO, a device, a directory, a symlink loop),
        unreadable, too large, or not UTF-8.
    """
    limit = max_table_bytes()
    with open_regular(path, "vehicle table") as fh:
        try:
            data = fh.read(limit + 1)
        except OSError as exc:
            raise TableError(f"{path}: cannot read vehicle table: {exc.strerror}",
                             file=path) from None
    if len(data) > limit:
        raise LimitError(f"{path}: refused: the vehicle table is larger than {limit / 1e6:g} "
                         f"MB; to read it anyway, set the environment variable "
                         f"{MAX_TABLE_MB_ENV} higher")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise TableError(f"{path}:{line}: not UTF-8 text (byte {exc.start}: "
                         f"{data[exc.start:exc.start + 1]!r})", file=path) from None


def _read_file(path: Path, problems: list[str], warnings: list[str]) -> list[dict[str, object]]:
    text = read_table_text(path)
    if "\0" in text:
        raise TableError(f"{path}:{text[: text.index(chr(0))].count(chr(10)) + 1}: a NUL "
                         "character: not a CSV text file", file=path)
    # newline="": quoted line breaks stay inside their cell, and only \r and \n end a line
    # (str.splitlines also breaks at U+2028 and the like, inside cells too)
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = [h.strip() for h in next(reader)]
    except StopIteration:
        raise TableError(f"{path}: empty file, expected a CSV header", file=path) from None
    except csv.Error as exc:
        raise TableError(f"{path}: not a CSV table: {exc}", file=path) from None
    bad_header = False
    for col in REQUIRED:
        if col.name not in header:
            problems.append(f"{path}: header: missing required column {col.name!r}")
            bad_header = True
    for h in header:
        if h not in ALL_COLUMNS:
            close = difflib.get_close_matches(h, list(ALL_COLUMNS), n=1, cutoff=0.6)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            problems.append(f"{path}: header: unknown column {h!r}{hint}")
            bad_header = True
    dupes = {h for h in header if header.count(h) > 1}
    for h in sorted(dupes):
        problems.append(f"{path}: header: column {h!r} appears more than once")
        bad_header = True
    if bad_header:
        return []
    rows: list[tuple[int, list[str]]] = []
    line_no = reader.line_num + 1  # the line the next record starts on
    try:
        for values in reader:
            start, line_no = line_no, reader.line_num + 1
            if any(v.strip() for v in values):
                rows.append((start, values))
    except csv.Error as exc:
        problems.append(f"{path}: not a valid CSV table: {exc}")
    limit = max_vehicles()
    if len(rows) > limit:  # said at once: checking them all would take minutes
        raise LimitError(f"{path}: refused: {len(rows):,} vehicle rows, more than the limit "
                         f"of {limit:,} (a fleet, not a catalogue: every row is a run on "
                         f"every curve); to read it anyway, set the environment variable "
                         f"{MAX_VEHICLES_ENV} higher")
    records = []
    for start, values in rows:
        if len(values) != len(header):
            problems.append(f"{path}:{start}: has {len(values)} fields, the header has "
                            f"{len(header)}")
            continue
        raw = {h: v.strip() for h, v in zip(header, values, strict=True)}
        rec = _row(raw, f"{path}:{start}", problems, warnings)
        if rec is not None:
            rec["table"] = str(path)
            rec["line"] = start
            records.append(rec)
    if not records and not problems:
        problems.append(f"{path}: no vehicle rows")
    return records


def _number(col: Column, text: str, where: str, problems: list[str]) -> float | None:
    try:
        value = float(text)
    except ValueError:
        problems.append(f"{where}: column {col.name}: {text!r}: not a number")
        return None
    if not math.isfinite(value):
        problems.append(f"{where}: column {col.name}: {text!r}: not a finite number")
        return None
    return value  # its range is checked by the caller (in SI units)


def _check_range(col: Column, value_si: float, text: str, where: str, problems: list[str],
                 scale: float, unit: str) -> bool:
    """False (and the problem noted) when ``value_si`` is outside the column's range."""
    if col.in_range(value_si):
        return True
    shown = col.range_text(scale, unit if col.kind == "length" else "")
    if col.kind == "length" and scale != 1.0:
        shown += f" = {col.range_text()}"
    problems.append(f"{where}: column {col.name}: {text!r}: outside the range {shown} "
                    f"({col.why})")
    return False


def _text_problem(text: str) -> str | None:
    """What makes ``text`` unfit for a text cell (a line break, a control character).

    Examples
    --------
    >>> _text_problem("Car One") is None
    True
    >>> _text_problem("Car\u2028Two")
    'holds a line or paragraph separator (U+2028)'
    """
    for ch in text:
        cat = unicodedata.category(ch)
        if cat in ("Zl", "Zp") or ch in "\n\r\x0b\x0c\x1c\x1d\x1e\x85":
            return f"holds a line or paragraph separator (U+{ord(ch):04X})"
        if cat == "Cc":
            return f"holds a control character (U+{ord(ch):04X})"
    return None


def _schedule(col: Column, text: str, where: str, problems: list[str]) -> Schedule | None:
    if ":" not in text:
        return _number(col, text, where, problems)
    try:
        table = Breakpoints.parse(text, x_scale=math.pi / 180)
    except InputError as exc:
        problems.append(f"{where}: column {col.name}: {text!r}: {exc}")
        return None
    limit = ALL_COLUMNS["steering_range_deg"].high  # the steering wheel turns no further
    odd = [x for x in np.degrees(table.x) if not abs(x) <= limit]  # NaN too
    if odd:
        problems.append(f"{where}: column {col.name}: {text!r}: breakpoint angle {odd[0]:g} "
                        f"outside +/-{limit:g} degrees of steering-wheel angle")
        return None
    bad = [y for y in table.y if not col.in_range(float(y))]
    if bad:
        problems.append(f"{where}: column {col.name}: {text!r}: table value {bad[0]:g} "
                        f"outside the range {col.range_text()} ({col.why})")
        return None
    return table


def _row(raw: dict[str, str], where: str, problems: list[str],
         warnings: list[str]) -> dict[str, object] | None:
    n_before = len(problems)
    name = raw.get("name", "")
    if not name:
        problems.append(f"{where}: column name: empty: every row needs a name")
    where = f"{where} ({name})" if name and _text_problem(name) is None else where
    units = raw.get("units", "")
    if units not in UNITS_TO_M:
        problems.append(f"{where}: column units: {units!r}: must be 'm' or 'ft'")
        scale = 1.0
    else:
        scale = UNITS_TO_M[units]
    v: dict[str, object] = {}
    for cname, text in raw.items():
        col = ALL_COLUMNS[cname]
        if cname == "units":
            continue  # checked above
        if text == "":
            if col in REQUIRED:
                problems.append(f"{where}: column {cname}: empty: a required value")
            continue
        if col.kind == "text":
            problem = _text_problem(text)
            if problem:
                problems.append(f"{where}: column {cname}: {text[:40]!r}: {problem}")
            else:
                v[cname] = text
        elif col.kind == "choice":
            if text.lower() not in col.choices:
                problems.append(f"{where}: column {cname}: {text!r}: must be one of "
                                f"{', '.join(col.choices)}")
            else:
                v[cname] = text.lower()
        elif col.kind == "table":
            sched = _schedule(col, text, where, problems)
            if isinstance(sched, float) and not _check_range(col, sched, text, where,
                                                             problems, 1.0, ""):
                continue
            if sched is not None:
                v[cname] = sched
        else:
            num = _number(col, text, where, problems)
            if num is None:
                continue
            si = num * scale if col.kind == "length" else num
            if not _check_range(col, si, text, where, problems, scale, units):
                continue
            if col.kind == "angle":
                v[cname] = math.radians(num)
            else:
                v[cname] = si
    if len(problems) > n_before:
        return None
    return derive(v, where, problems, warnings, units, scale)


def _schedule_value(value: object) -> Schedule:
    if isinstance(value, str):
        return Breakpoints.parse(value, x_scale=math.pi / 180)
    return float(value)  # type: ignore[arg-type]


def steering_from_row(row: pd.Series) -> Steering:
    """The :class:`~clearance.vehicles.steering.Steering` of one row of a loaded table."""
    rack = None
    if row["steering"] == "rack_pinion":
        rack = RackPinion(row["track_m"], row["rack_length_m"], row["steering_arm_m"],
                          row["tie_rod_m"], row["rack_offset_m"], row["pinion_radius_m"])
    return Steering(row["steering"], row["wheelbase_m"], row["track_m"],
                    _schedule_value(row["steering_ratio"]), _schedule_value(row["ackermann_pct"]),
                    row["steering_range_rad"], row["deadband_rad"], row["steered_axle"], rack)


def vehicle_from_row(row: pd.Series) -> Vehicle:
    """A :class:`~clearance.vehicles.vehicle.Vehicle` from one row of a loaded table."""
    trailer = None
    if np.isfinite(row.get("trailer_wheelbase_m", np.nan)):
        trailer = Trailer(row["hitch_offset_m"], row["trailer_wheelbase_m"],
                          row["trailer_width_m"], row["trailer_front_overhang_m"],
                          row["trailer_rear_overhang_m"], row["max_articulation_rad"])
    height = row.get("height_m", np.nan)

    def given(key: str) -> float | None:
        value = row.get(key, np.nan)
        return float(value) if np.isfinite(value) else None

    vclass = str(row.get("vclass") or default_vclass(str(row["category"])))
    underside = underside_from(given("ground_clearance_m"), given("approach_rad"),
                               given("departure_rad"), given("breakover_rad"),
                               float(row["wheelbase_m"]), float(row["front_overhang_m"]),
                               float(row["rear_overhang_m"]), vclass)
    return Vehicle(
        name=str(row["name"]), wheelbase_m=float(row["wheelbase_m"]),
        track_m=float(row["track_m"]), width_m=float(row["width_m"]),
        front_overhang_m=float(row["front_overhang_m"]),
        rear_overhang_m=float(row["rear_overhang_m"]),
        max_steer_rad=float(row["max_steer_rad"]),
        max_inner_steer_rad=float(row["max_inner_steer_rad"]),
        max_steer_rate_rad_s=float(row["max_steer_rate_rad_s"]),
        steered_axle=str(row["steered_axle"]),
        height_m=float(height) if np.isfinite(height) else None,
        trailer=trailer, category=str(row["category"]), source=str(row["source"]),
        vclass=vclass, underside=underside, grade_limit_pct=given("grade_limit_pct"),
    )
