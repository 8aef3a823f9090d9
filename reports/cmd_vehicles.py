"""``clearance vehicles``: turning circles and swept widths of every vehicle at full lock."""

from __future__ import annotations

import argparse

import pandas as pd

from analysis.turning import turning_metrics
from reports.atomic import write_text_atomic
from reports.options import add_table_option, add_units_option, add_vehicle_option
from reports.units import to_output_units
from vehicles.table import load_tables

#: CSV columns, in this order (lengths in the chosen units, angles in degrees).
COLUMNS = ["vehicle", "wheelbase", "track", "width", "length", "front_overhang",
           "rear_overhang", "max_steer_deg", "outer_steer_deg", "ackermann_angle_deg",
           "min_radius", "ctr", "curb_to_curb", "wall_to_wall", "inside_radius",
           "swept_width", "offtracking"]
TRAILER_COLUMNS = ["trailer_articulation_deg", "articulation_limited", "trailer_radius",
                   "trailer_inside_radius", "trailer_offtracking", "combination_inside_radius",
                   "combination_swept_width"]
SHOWN = ["vehicle", "wheelbase", "width", "max_steer_deg", "outer_steer_deg",
         "ackermann_angle_deg", "min_radius", "ctr", "curb_to_curb", "wall_to_wall",
         "inside_radius", "swept_width", "offtracking"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "vehicles",
        help="turning circles and swept widths of the vehicle table(s)",
        description="Full-lock turning geometry of every vehicle: lock angles, Ackermann "
                    "angle, turning radii and diameters, inside radius, steady-state swept "
                    "width and offtracking (DESIGN.md §4).",
    )
    add_table_option(p)
    add_vehicle_option(p)
    add_units_option(p)
    p.add_argument("-o", "--output", metavar="OUT.csv", help="write the table as CSV")
    p.set_defaults(run=run)


def vehicles_frame(tables: list[str] | None, names: list[str] | None, units: str
                   ) -> pd.DataFrame:
    """The ``clearance vehicles`` table as a DataFrame in the chosen units."""
    table = load_tables(tables, names)
    metrics = to_output_units(turning_metrics(table), units)
    columns = list(COLUMNS)
    if "trailer_radius" in metrics:
        columns += TRAILER_COLUMNS
    out = metrics[columns].copy()
    out.insert(len(out.columns), "units", units)
    out.insert(len(out.columns), "source", table.frame["source"].to_numpy())
    return out


def run(args: argparse.Namespace) -> int:
    frame = vehicles_frame(args.table, args.vehicle, args.units)
    shown = frame[SHOWN].copy()
    shown.columns = [c.replace("_deg", " °").replace("_", " ") for c in SHOWN]
    with pd.option_context("display.width", 250, "display.max_columns", 40,
                           "display.max_rows", 500):
        print(f"Full-lock turning geometry ({len(frame)} vehicles; lengths in {args.units})")
        print(shown.round(2).to_string(index=False))
    if args.output:
        text = frame.to_csv(index=False, float_format="%.6g", lineterminator="\n", na_rep="")
        path = write_text_atomic(args.output, text)
        print(f"wrote {path}")
    return 0
