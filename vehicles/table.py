"""Loading and validating vehicle tables.

:func:`load_tables` reads one or several CSV tables, checks every row and reports every
problem at once (file, line, column, value, reason) as a :class:`~vehicles.errors.TableError`.
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

from vehicles.errors import InputError, TableError
from vehicles.files import env_limit, open_regular
from vehicles.lock import rho_from_ctr, rho_from_curb_to_curb, rho_from_wall_to_wall
from vehicles.schema import (
    ALL_COLUMNS,
    LOCK_NAMES,
    RACK_NAMES,
    REQUIRED,
    TRAILER_NAMES,
    UNITS_TO_M,
    Column,
    default_vclass,
)
from vehicles.steering import Breakpoints, RackPinion, Schedule, Steering
from vehicles.vehicle import Trailer, Vehicle

log = logging.getLogger(__name__)

#: Relative disagreement allowed between two given lock columns (published values are
#: rounded, e.g. a CTR to 0.1 ft).
LOCK_TOLERANCE = 0.01

#: Default of :func:`max_table_bytes`: 100 MB, about 600,000 rows of the bundled tables'
#: width (the loader checks some 5,000 rows a second); a larger file is not a fleet.
DEFAULT_MAX_TABLE_BYTES = 100_000_000

#: The environment variable that raises the cap, in megabytes.
MAX_TABLE_MB_ENV = "CLEARANCE_MAX_TABLE_MB"


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
        """The :class:`~vehicles.vehicle.Vehicle` called ``name``."""
        rows = self.frame.index[self.frame["name"] == name]
        if len(rows) == 0:
            raise InputError(unknown_name_message(name, self.names))
        return vehicle_from_row(self.frame.loc[rows[0]])

    def vehicles(self) -> list[Vehicle]:
        """Every row as a :class:`~vehicles.vehicle.Vehicle`, in table order."""
        return [vehicle_from_row(row) for _, row in self.frame.iterrows()]

    def steering(self, name: str) -> Steering:
        """The steering mechanism of the vehicle called ``name``."""
        rows = self.frame.index[self.frame["name"] == name]
        if len(rows) == 0:
            raise InputError(unknown_name_message(name, self.names))
        return steering_from_row(self.frame.loc[rows[0]])


def bundled_table_paths() -> list[Path]:
    """The CSV tables shipped with the package, sorted by file name."""
    folder = resources.files("vehicles") / "tables"
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
    raise InputError(f"no bundled vehicle table {stem!r}; there are "
                     f"{', '.join(p.stem for p in bundled_table_paths())}")


def unknown_name_message(name: str, known: Sequence[str]) -> str:
    """The message for an unknown vehicle name, with close matches (case-insensitive).

    >>> unknown_name_message("p", ["P", "SU-30", "WB-62"])[:38]
    "unknown vehicle 'p'; did you mean 'P'?"
    """
    folded = {}
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
            raise InputError("; ".join(unknown_name_message(n, list(seen)) for n in missing))
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
            raise InputError(f"{path}: cannot read vehicle table: {exc.strerror}") from None
    if len(data) > limit:
        raise InputError(f"{path}: refused: the vehicle table is larger than {limit / 1e6:g} "
                         f"MB; to read it anyway, set the environment variable "
                         f"{MAX_TABLE_MB_ENV} higher")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise InputError(f"{path}:{line}: not UTF-8 text (byte {exc.start}: "
                         f"{data[exc.start:exc.start + 1]!r})") from None


def _read_file(path: Path, problems: list[str], warnings: list[str]) -> list[dict[str, object]]:
    text = read_table_text(path)
    if "\0" in text:
        raise InputError(f"{path}:{text[: text.index(chr(0))].count(chr(10)) + 1}: a NUL "
                         "character: not a CSV text file")
    # newline="": quoted line breaks stay inside their cell, and only \r and \n end a line
    # (str.splitlines also breaks at U+2028 and the like, inside cells too)
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = [h.strip() for h in next(reader)]
    except StopIteration:
        raise InputError(f"{path}: empty file, expected a CSV header") from None
    except csv.Error as exc:
        raise InputError(f"{path}: not a CSV table: {exc}") from None
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
    records = []
    line_no = reader.line_num + 1  # the line the next record starts on
    try:
        for values in reader:
            start, line_no = line_no, reader.line_num + 1
            if not any(v.strip() for v in values):
                continue
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
    except csv.Error as exc:
        problems.append(f"{path}: not a valid CSV table: {exc}")
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
    return _derive(v, where, problems, warnings, units, scale)


def _derive(v: dict[str, object], where: str, problems: list[str], warnings: list[str],
            units: str, scale: float) -> dict[str, object] | None:
    def f(key: str, default: float = math.nan) -> float:
        return float(v[key]) if key in v else default  # type: ignore[arg-type]

    l, B, a_f, L = f("wheelbase"), f("width"), f("front_overhang"), f("length")  # noqa: E741
    w = f("track", B)
    has_trailer = any(k in v for k in TRAILER_NAMES)
    unit = units
    n_before = len(problems)

    # Trailer and overhangs.
    trailer: dict[str, float] = {}
    if has_trailer:
        for key in ("hitch_offset", "trailer_wheelbase"):
            if key not in v:
                problems.append(f"{where}: column {key}: empty: a towed unit needs it")
        if len(problems) > n_before:
            return None
        e, lt = f("hitch_offset"), f("trailer_wheelbase")
        if e <= -l:
            problems.append(f"{where}: column hitch_offset: {e / scale:g} {unit}: puts the "
                            f"hitch at or ahead of the front axle (wheelbase {l / scale:g} "
                            f"{unit}); a towed unit is hitched behind it")
            return None
        a_tf = f("trailer_front_overhang", 0.0)
        rest = L - a_f - l - e - lt
        a_tr = f("trailer_rear_overhang", rest)
        if "trailer_rear_overhang" in v and abs(a_tr - rest) > 0.01 * L + 0.05:
            problems.append(
                f"{where}: column trailer_rear_overhang: {a_tr / scale:g} {unit}: disagrees "
                f"with length - front_overhang - wheelbase - hitch_offset - trailer_wheelbase "
                f"= {rest / scale:g} {unit}")
        if a_tr < 0:
            problems.append(f"{where}: column length: {L / scale:g} {unit}: too short for "
                            f"the combination: the trailer's rear overhang comes out "
                            f"{a_tr / scale:g} {unit}")
        if e + a_tf < -l - a_f + 1e-9 and a_tf > 0:
            pass  # a trailer nose ahead of the tractor's front is odd but not impossible
        a_r = f("rear_overhang", 0.0)
        trailer = dict(hitch_offset_m=e, trailer_wheelbase_m=lt,
                       trailer_width_m=f("trailer_width", B), trailer_front_overhang_m=a_tf,
                       trailer_rear_overhang_m=a_tr,
                       max_articulation_rad=f("max_articulation_deg", math.radians(90.0)))
    else:
        a_r = L - l - a_f
        if "rear_overhang" in v and abs(f("rear_overhang") - a_r) > 0.01 * L + 0.05:
            problems.append(f"{where}: column rear_overhang: {f('rear_overhang') / scale:g} "
                            f"{unit}: disagrees with length - wheelbase - front_overhang = "
                            f"{a_r / scale:g} {unit}")
        if a_r < 0:
            problems.append(f"{where}: column length: {L / scale:g} {unit}: shorter than "
                            f"wheelbase + front_overhang: the rear overhang comes out "
                            f"{a_r / scale:g} {unit}")
    if w > B + 1e-9:
        warnings.append(f"{where}: track {w / scale:g} {unit} is wider than the body "
                        f"width {B / scale:g} {unit}")

    # Steering mechanism.
    kind = str(v.get("steering", "ackermann"))
    axle = str(v.get("steered_axle", "front"))
    ratio: Schedule = v.get("steering_ratio", 16.0)  # type: ignore[assignment]
    pct: Schedule = v.get("ackermann_pct", 100.0)  # type: ignore[assignment]
    if kind != "ackermann" and "ackermann_pct" in v:
        problems.append(f"{where}: column ackermann_pct: given for {kind} steering, which "
                        "has no Ackermann percentage")
    rack = None
    if kind == "rack_pinion":
        missing = [k for k in RACK_NAMES if k not in v]
        if missing:
            problems.append(f"{where}: column steering: rack_pinion needs the linkage "
                            f"columns {', '.join(missing)}")
        else:
            try:
                rack = RackPinion(w, f("rack_length"), f("steering_arm"), f("tie_rod"),
                                  f("rack_offset"), f("pinion_radius"))
            except InputError as exc:
                problems.append(f"{where}: column steering: {exc}")
    if len(problems) > n_before:
        return None
    deadband = math.radians(f("deadband_deg", 0.0))
    user_range = "steering_range_deg" in v
    sw_range = math.radians(f("steering_range_deg")) if user_range else 8 * math.pi
    steering = Steering(kind, l, w, ratio, pct, sw_range, deadband, axle, rack)

    # Steering lock: each given form gives rho; they must agree.
    a_s = a_f if axle == "front" else (L - l - a_f if not has_trailer else f("rear_overhang", 0))
    rhos: dict[str, float] = {}
    given = [k for k in LOCK_NAMES if k in v]
    if not given:
        problems.append(f"{where}: column max_steer_deg: empty: the steering lock needs one "
                        f"of {', '.join(LOCK_NAMES)}")
        return None
    inner_given = f("max_steer_deg")
    if "max_steer_deg" in v:
        outer = float(steering.outer_for_inner(inner_given))
        if not math.isfinite(outer):
            problems.append(f"{where}: column max_steer_deg: {math.degrees(inner_given):g}: "
                            "beyond what the rack-and-pinion linkage can reach")
            return None
        phi = float(steering.max_bicycle_for_inner(inner_given))
        rhos["max_steer_deg"] = l / math.tan(phi)
    if "ctr" in v:
        rhos["ctr"] = float(rho_from_ctr(f("ctr"), l))
    if "curb_to_curb" in v:
        rhos["curb_to_curb"] = float(rho_from_curb_to_curb(f("curb_to_curb"), l, w))
    if "wall_to_wall" in v:
        rhos["wall_to_wall"] = float(rho_from_wall_to_wall(f("wall_to_wall"), l, B, a_s))
    for key, rho in rhos.items():
        if key == "max_steer_deg":
            continue
        shown = f"{f(key) / scale:g} {unit}"
        if not math.isfinite(rho) or rho <= 0:
            problems.append(f"{where}: column {key}: {shown}: too small for a wheelbase of "
                            f"{l / scale:g} {unit}: no such turning circle exists")
        elif rho <= w / 2 + 1e-9 and kind != "parallel":
            problems.append(f"{where}: column {key}: {shown}: implies an inner wheel lock of "
                            "90 degrees or more")
    if len(problems) > n_before:
        return None
    if len(rhos) > 1:
        lo, hi = min(rhos.values()), max(rhos.values())
        if hi - lo > LOCK_TOLERANCE * hi:
            detail = ", ".join(f"{k} gives {r / scale:.2f} {unit}" for k, r in rhos.items())
            problems.append(f"{where}: columns {', '.join(rhos)}: the steering lock columns "
                            f"disagree (radius of the rear-axle centre: {detail})")
            return None
    # The lock itself: prefer the inner-wheel angle when given, else the first radius.
    if "max_steer_deg" in v:
        inner = inner_given
        rho = rhos["max_steer_deg"]
    else:
        rho = rhos[given[0]]
        phi_target = math.atan(l / rho)
        inner = _inner_for_bicycle(steering, phi_target)
        if not math.isfinite(inner):
            problems.append(f"{where}: column {given[0]}: the mechanism cannot reach this lock")
            return None
    outer = float(steering.outer_for_inner(inner))
    if not 0.0 < outer < math.pi / 2:
        problems.append(f"{where}: column {'ackermann_pct' if 'ackermann_pct' in v else kind}: "
                        f"the outer wheel comes out at {math.degrees(outer):.1f} degrees at "
                        f"full lock (inner {math.degrees(inner):.1f}): it must turn the same "
                        "way, by less than 90 degrees")
        return None
    phi = math.atan(l / rho)
    sw_lock = float(steering.steering_for_inner(inner))
    if user_range and not math.isfinite(sw_lock):
        problems.append(f"{where}: column steering_range_deg: {f('steering_range_deg'):g}: "
                        "the steering wheel cannot reach the steering lock within this range")
        return None
    if not user_range:
        sw_range = sw_lock if math.isfinite(sw_lock) and sw_lock > 0 else sw_range
    if "max_steer_rate_deg_s" in v:
        rate = math.radians(f("max_steer_rate_deg_s"))
    else:
        rate = 2 * phi / f("lock_to_lock_s", 4.0)

    # Published w/l (Table 1 of the paper): a warning, never an error.
    if "w_l" in v:
        published = f("w_l")
        text = f"{published:g}"
        decimals = len(text.split(".")[1]) if "." in text else 0
        if abs(w / l - published) > 10.0 ** (-max(decimals, 2)) + 1e-9:
            warnings.append(f"{where}: column w_l: published {published:g} disagrees with "
                            f"track / wheelbase = {w / l:.3f}")

    out: dict[str, object] = {
        "name": v["name"], "category": v["category"], "source": v["source"], "units": units,
        "length_m": L, "width_m": B, "wheelbase_m": l, "front_overhang_m": a_f,
        "rear_overhang_m": a_r, "track_m": w, "steering": kind, "steered_axle": axle,
        "steering_ratio": _schedule_text(ratio), "ackermann_pct": _schedule_text(pct),
        "steering_range_rad": sw_range, "deadband_rad": deadband,
        "max_inner_steer_rad": inner, "max_outer_steer_rad": outer, "max_steer_rad": phi,
        "min_radius_m": rho, "max_steer_rate_rad_s": rate,
        "lock_given": ",".join(given),
        "vclass": v.get("vclass") or default_vclass(str(v["category"])),
    }
    for key in RACK_NAMES:
        out[f"{key}_m"] = f(key)
    for key, suffix in (("height", "_m"), ("ground_clearance", "_m"), ("approach_deg", ""),
                        ("departure_deg", ""), ("breakover_deg", ""),
                        ("ref_turning_radius", "_m"), ("ref_inside_radius", "_m"),
                        ("w_l", "")):
        out[key.replace("_deg", "_rad") + suffix] = f(key)
    for key in ("hitch_offset_m", "trailer_wheelbase_m", "trailer_width_m",
                "trailer_front_overhang_m", "trailer_rear_overhang_m", "max_articulation_rad"):
        out[key] = trailer.get(key, math.nan)
    return out


def _inner_for_bicycle(steering: Steering, phi: float) -> float:
    """Inner wheel angle whose mean-cotangent bicycle angle is ``phi`` (bisection)."""
    lo, hi = 0.0, math.radians(89.9)
    if steering.kind == "parallel":
        return phi
    for _ in range(80):
        mid = (lo + hi) / 2
        got = float(steering.max_bicycle_for_inner(mid))
        if not math.isfinite(got) or got > phi:
            hi = mid
        else:
            lo = mid
    return (lo + hi) / 2


def _schedule_text(value: Schedule) -> object:
    if isinstance(value, Breakpoints):
        return ";".join(f"{math.degrees(x):g}:{y:g}" for x, y in zip(value.x, value.y,
                                                                   strict=True))
    return float(value)


def _schedule_value(value: object) -> Schedule:
    if isinstance(value, str):
        return Breakpoints.parse(value, x_scale=math.pi / 180)
    return float(value)  # type: ignore[arg-type]


def steering_from_row(row: pd.Series) -> Steering:
    """The :class:`~vehicles.steering.Steering` of one row of a loaded table."""
    rack = None
    if row["steering"] == "rack_pinion":
        rack = RackPinion(row["track_m"], row["rack_length_m"], row["steering_arm_m"],
                          row["tie_rod_m"], row["rack_offset_m"], row["pinion_radius_m"])
    return Steering(row["steering"], row["wheelbase_m"], row["track_m"],
                    _schedule_value(row["steering_ratio"]), _schedule_value(row["ackermann_pct"]),
                    row["steering_range_rad"], row["deadband_rad"], row["steered_axle"], rack)


def vehicle_from_row(row: pd.Series) -> Vehicle:
    """A :class:`~vehicles.vehicle.Vehicle` from one row of a loaded table."""
    trailer = None
    if np.isfinite(row.get("trailer_wheelbase_m", np.nan)):
        trailer = Trailer(row["hitch_offset_m"], row["trailer_wheelbase_m"],
                          row["trailer_width_m"], row["trailer_front_overhang_m"],
                          row["trailer_rear_overhang_m"], row["max_articulation_rad"])
    height = row.get("height_m", np.nan)
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
        vclass=str(row.get("vclass") or default_vclass(str(row["category"]))),
    )
