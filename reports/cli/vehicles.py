"""``clearance vehicles``: turning circles and swept widths of every vehicle at full lock.

The table is :func:`clearance.reports.results.vehicle_metrics.vehicles_frame`.
"""

from __future__ import annotations

import argparse

import pandas as pd

from clearance.reports.cli.options import (
    add_output_option,
    add_table_option,
    add_units_option,
    add_vehicle_option,
)
from clearance.reports.output.atomic import write_text_atomic
from clearance.reports.results.text_table import counted
from clearance.reports.results.vehicle_metrics import steady_inside_radius, vehicles_frame

__all__ = ["SHOWN", "add_parser", "run"]

SHOWN = ["vehicle", "wheelbase", "width", "max_steer_deg", "outer_steer_deg",
         "ackermann_angle_deg", "min_radius", "ctr", "curb_to_curb", "wall_to_wall",
         "steady_inside_radius", "inside_radius_180", "swept_width", "offtracking"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "vehicles",
        help="turning circles and swept widths of the vehicle table(s)",
        description="Full-lock turning geometry of every vehicle: lock angles, Ackermann "
                    "angle, turning radii and diameters, steady-state inside radius, swept "
                    "width and offtracking (docs/design.md §4), and the inside radius of a 180° "
                    "turn with the steered-axle centre on the full-lock CTR (the Green "
                    "Book's minimum inside radius; for a combination the trailer's, and the "
                    "only one where there is no steady state at full lock).",
    )
    add_table_option(p)
    add_vehicle_option(p)
    add_units_option(p)
    add_output_option(p, folder=False, metavar="OUT.csv", help="write the table as CSV")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    frame = vehicles_frame(args.table, args.vehicle, args.units)
    steady = [v if isinstance(v, str) else f"{v:.2f}" for v in steady_inside_radius(frame)]
    shown = frame.round(2).assign(steady_inside_radius=steady)[SHOWN]
    shown.columns = [c.replace("_deg", " °").replace("_", " ").replace(" 180", " 180°")
                     for c in SHOWN]
    with pd.option_context("display.width", 250, "display.max_columns", 40,
                           "display.max_rows", 500):
        print(f"Full-lock turning geometry ({counted(len(frame), 'vehicle')}; "
              f"lengths in {args.units})")
        print(shown.to_string(index=False))
    if args.output:
        text = frame.to_csv(index=False, float_format="%.6g", lineterminator="\n", na_rep="")
        path = write_text_atomic(args.output, text)
        print(f"wrote {path}")
    return 0
