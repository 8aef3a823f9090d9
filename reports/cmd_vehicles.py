"""``clearance vehicles``: turning circles and swept widths of every vehicle at full lock.

Beside the steady-state figures at full lock (docs/design.md §4), every vehicle is driven through
the Green Book's design turn (:mod:`analysis.design_turn`): 180° with the steered-axle centre
on its full-lock CTR. That turn's inside radius is what the Green Book publishes as the
minimum inside radius, and the only one a combination without a steady state at full lock
(a WB-62: its trailer would jackknife) has.
"""

from __future__ import annotations

import argparse

import pandas as pd

from analysis.design_turn import design_turn_inside_radius
from analysis.turning import turning_metrics
from reports.atomic import write_text_atomic
from reports.options import (
    add_output_option,
    add_table_option,
    add_units_option,
    add_vehicle_option,
)
from reports.text_table import counted
from reports.units import to_output_units
from vehicles.table import load_tables

#: CSV columns, in this order (lengths in the chosen units, angles in degrees).
COLUMNS = ["vehicle", "wheelbase", "track", "width", "length", "front_overhang",
           "rear_overhang", "max_steer_deg", "outer_steer_deg", "ackermann_angle_deg",
           "min_radius", "ctr", "curb_to_curb", "wall_to_wall", "inside_radius",
           "swept_width", "offtracking", "inside_radius_180"]
TRAILER_COLUMNS = ["steady_state", "trailer_articulation_deg", "articulation_limited",
                   "trailer_radius", "trailer_inside_radius", "trailer_offtracking",
                   "combination_inside_radius", "combination_swept_width"]
SHOWN = ["vehicle", "wheelbase", "width", "max_steer_deg", "outer_steer_deg",
         "ackermann_angle_deg", "min_radius", "ctr", "curb_to_curb", "wall_to_wall",
         "steady_inside_radius", "inside_radius_180", "swept_width", "offtracking"]
NO_STEADY_STATE = "no steady state"
"""Shown instead of a steady inside radius where a combination has none at full lock."""


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


def vehicles_frame(tables: list[str] | None, names: list[str] | None, units: str
                   ) -> pd.DataFrame:
    """The ``clearance vehicles`` table as a DataFrame in the chosen units."""
    table = load_tables(tables, names)
    si = turning_metrics(table)
    si["inside_radius_180_m"] = design_turn_inside_radius(table.frame)["inside_radius_m"]
    metrics = to_output_units(si, units)
    columns = list(COLUMNS)
    if "trailer_radius" in metrics:
        columns += TRAILER_COLUMNS
    out = metrics[columns].copy()
    out.insert(len(out.columns), "units", units)
    out.insert(len(out.columns), "source", table.frame["source"].to_numpy())
    return out


def steady_inside_radius(frame: pd.DataFrame) -> pd.Series:
    """The steady inside radius at full lock as shown: the whole combination's, or text.

    A single unit's is ``inside_radius``; a combination's ``combination_inside_radius``,
    or :data:`NO_STEADY_STATE` where it has none (``steady_state`` false).

    Examples
    --------
    >>> f = pd.DataFrame({"inside_radius": [14.39, 29.64], "steady_state": [True, False],
    ...                   "combination_inside_radius": [float("nan"), float("nan")]})
    >>> steady_inside_radius(f).tolist()
    [14.39, 'no steady state']
    """
    values = frame["inside_radius"].astype(object)
    if "steady_state" in frame:
        combination = frame["combination_inside_radius"].notna()
        values[combination] = frame.loc[combination, "combination_inside_radius"]
        values[~frame["steady_state"].astype(bool)] = NO_STEADY_STATE
    return values


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
