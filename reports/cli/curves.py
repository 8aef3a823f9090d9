"""``clearance curves``: list the curves of a SUMO network (turns, roundabouts, ramps, bends)."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path

from clearance.networks.curves import DEFAULT_KINDS, KINDS, CurveOptions, extract_curves
from clearance.networks.integrity import not_at_road_scale
from clearance.networks.loading import load_network
from clearance.networks.model import ROAD_VCLASSES
from clearance.reports.cli.options import add_net_option, add_output_option
from clearance.reports.results.curve_rows import curve_row, write_csv_atomic
from clearance.reports.results.text_table import format_table
from clearance.vehicles.errors import OptionError

__all__ = ["add_parser", "print_summary", "run"]


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
        raise OptionError(f"--approach must be a positive length in metres, not {args.approach}")
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


if __name__ == "__main__":  # pragma: no cover
    from clearance.reports.cli.main import main

    sys.exit(main(["curves", *sys.argv[1:]]))
