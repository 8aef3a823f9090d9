"""A network's curves as rows: the columns of ``clearance curves -o CURVES.csv`` and the
movement in words."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence
from pathlib import Path

from clearance.networks.curves import Curve
from clearance.reports.output.atomic import write_text_atomic
from clearance.vehicles.errors import OptionError

__all__ = ["COLUMNS", "curve_row", "movement", "write_csv_atomic"]


#: CSV columns, in order.
COLUMNS = (
    "curve_id",
    "kind",
    "junction",
    "lanes",
    "min_radius",
    "turn_angle_deg",
    "length",
    "lane_width",
    "max_grade_pct",
    "max_grade_change_pct",
    "movement",
    "suspect_elevation",
)


def curve_row(curve: Curve) -> dict[str, str]:
    """One CSV row (values formatted: metres to 0.01, degrees to 0.1, grades to 0.01 %)."""
    return {
        "curve_id": curve.curve_id,
        "kind": curve.kind,
        "junction": curve.junction,
        "lanes": " ".join(curve.lanes),
        "min_radius": _num(curve.min_radius_m, 2),
        "turn_angle_deg": _num(curve.turn_angle_deg, 1),
        "length": _num(curve.length_m, 2),
        "lane_width": _num(curve.lane_width_m, 2),
        "max_grade_pct": _num(curve.max_grade_pct, 2),
        "max_grade_change_pct": _num(curve.max_grade_change_pct, 2),
        "movement": movement(curve.kind, curve.turn_angle_deg, curve.min_radius_m),
        "suspect_elevation": curve.suspect_elevation,
    }


def movement(kind: str, turn_angle_deg: float, min_radius_m: float) -> str:
    """The movement in words: ``straight on``, ``left 90°``, ``right 45°``, ``U-turn``.

    Left turns are positive (docs/design.md §3).

    Examples
    --------
    >>> movement("turn", 0.0, float("inf")), movement("turn", -90.0, 5.7)
    ('straight on', 'right 90°')
    >>> movement("turn", 178.0, 4.0), movement("uturn", 175.0, 3.0)
    ('U-turn', 'U-turn')
    >>> movement("roundabout", 270.4, 12.0)
    'left 270°'
    >>> movement("turn", 3.0, 150.0)  # a slight bend through the junction
    'left 3°'
    """
    if not math.isfinite(min_radius_m) or (abs(turn_angle_deg) < 0.5 and kind == "turn"):
        return "straight on"
    if kind == "uturn" or (kind == "turn" and abs(turn_angle_deg) >= 160.0):
        return "U-turn"
    side = "left" if turn_angle_deg > 0 else "right"
    return f"{side} {abs(turn_angle_deg):.0f}°"


def _num(value: float, digits: int) -> str:
    if math.isinf(value):
        return "inf"
    return f"{round(value, digits) + 0.0:.{digits}f}"  # + 0.0: no "-0.0"


def write_csv_atomic(path: Path, rows: Sequence[dict[str, str]]) -> None:
    """Write rows as CSV atomically (:func:`clearance.reports.output.atomic.write_text_atomic`)."""
    directory = path.resolve().parent
    if not directory.is_dir():
        raise OptionError(f"{path}: the directory {directory} does not exist")
    buf = io.StringIO(newline="")
    writer = csv.DictWriter(buf, fieldnames=COLUMNS)
    writer.writeheader()
    writer.writerows(rows)
    write_text_atomic(path, buf.getvalue())
