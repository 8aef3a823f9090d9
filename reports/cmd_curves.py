"""``clearance curves``: list the curves of a SUMO network (turns, roundabouts, ramps, bends)."""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
from collections.abc import Sequence
from pathlib import Path

from networks.curves import DEFAULT_KINDS, KINDS, Curve, CurveOptions, extract_curves
from networks.integrity import not_at_road_scale
from networks.loading import load_network
from networks.model import ROAD_VCLASSES
from reports.atomic import write_text_atomic
from reports.options import add_net_option, add_output_option
from reports.text_table import format_table
from vehicles.errors import InputError

__all__ = ["COLUMNS", "add_parser", "curve_row", "movement", "print_summary", "run",
           "write_csv_atomic"]

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


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``curves`` with the ``clearance`` command."""
    parser = subparsers.add_parser(
        "curves",
        help="list the curves of a SUMO network",
        description=(
            "Find the junction turns, roundabout paths, ramps and tight bends of a SUMO "
            "network and print their radius, turn angle, length, lane width and grade. "
            "Lengths in metres, angles in degrees (left turns positive)."
        ),
    )
    add_net_option(parser, required=True, type=Path)
    parser.add_argument(
        "--kind",
        action="append",
        choices=KINDS,
        help="only curves of this kind (repeat for several; default: all but uturn, "
        "netconvert's automatic turnarounds)",
    )
    add_output_option(parser, folder=False, metavar="OUT.csv", type=Path,
                      help="write the table as CSV here")
    parser.add_argument(
        "--approach",
        type=float,
        default=CurveOptions.approach_length_m,
        metavar="M",
        help="approach and exit length of each centre line (default %(default)s m)",
    )
    parser.add_argument(
        "--limit", type=int, default=40, metavar="N", help="print at most N rows (default 40)"
    )
    parser.set_defaults(run=run)
    return parser


def run(args: argparse.Namespace) -> int:
    """Read the network, extract the curves, print a summary and write the CSV."""
    if not (args.approach > 0 and math.isfinite(args.approach)):
        raise InputError(f"--approach must be a positive length in metres, not {args.approach}")
    net = load_network(args.net)
    if why := not_at_road_scale(net.lanes, ROAD_VCLASSES):  # listed, but warned of
        print(f"clearance curves: warning: {args.net}: {why}", file=sys.stderr)
    options = CurveOptions(approach_length_m=args.approach)
    curves = extract_curves(net, args.kind or DEFAULT_KINDS, options, areas=False)
    rows = [curve_row(c) for c in curves]
    print_summary(args.net, rows, args.limit)
    for c in curves:
        if c.suspect_elevation:
            print(f"clearance curves: warning: {c.curve_id}: suspect elevation: "
                  f"{c.suspect_elevation}", file=sys.stderr)
    if args.output is not None:
        write_csv_atomic(args.output, rows)
        print(f"wrote {len(rows)} curve(s) to {args.output}")
    return 0


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


def print_summary(net_path: Path, rows: Sequence[dict[str, str]], limit: int) -> None:
    """Print counts per kind and the tightest curves as an aligned table."""
    counts = {k: sum(1 for r in rows if r["kind"] == k) for k in KINDS}
    summary = ", ".join(f"{n} {k}" for k, n in counts.items() if n) or "no curves"
    print(f"{net_path}: {summary}")
    if not rows:
        return
    shown = sorted(rows, key=lambda r: (float(r["min_radius"]), r["curve_id"]))[: max(limit, 0)]
    shown = [dict(r, min_radius="straight" if r["min_radius"] == "inf" else r["min_radius"])
             for r in shown]
    cols = ("curve_id", "kind", "movement", "min_radius", "turn_angle_deg", "length",
            "lane_width", "max_grade_pct")
    heads = ("curve", "kind", "movement", "R min [m]", "turn [deg]", "length [m]", "width [m]",
             "grade [%]")
    print("\n".join(format_table(shown, cols, heads, 3)))
    if len(rows) > len(shown):
        print(f"... {len(rows) - len(shown)} more (the tightest are shown; see --output)")



def write_csv_atomic(path: Path, rows: Sequence[dict[str, str]]) -> None:
    """Write rows as CSV atomically (:func:`reports.atomic.write_text_atomic`)."""
    directory = path.resolve().parent
    if not directory.is_dir():
        raise InputError(f"{path}: the directory {directory} does not exist")
    buf = io.StringIO(newline="")
    writer = csv.DictWriter(buf, fieldnames=COLUMNS)
    writer.writeheader()
    writer.writerows(rows)
    write_text_atomic(path, buf.getvalue())


if __name__ == "__main__":  # pragma: no cover
    from reports.cli import main

    sys.exit(main(["curves", *sys.argv[1:]]))
