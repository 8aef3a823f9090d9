"""The vehicle table's turning geometry at full lock as ``clearance vehicles`` shows and writes it.

Beside the steady-state figures at full lock (docs/design.md §4), every vehicle is driven through
the Green Book's design turn (:mod:`clearance.analysis.design_turn`): 180° with the steered-axle
centre on its full-lock CTR. That turn's inside radius is what the Green Book publishes as the
minimum inside radius, and the only one a combination without a steady state at full lock
(a WB-62: its trailer would jackknife) has."""

from __future__ import annotations

import pandas as pd

from clearance.analysis.design_turn import design_turn_inside_radius
from clearance.analysis.turning import turning_metrics
from clearance.reports.results.units import to_output_units
from clearance.vehicles.table import load_tables

__all__ = ["COLUMNS", "NO_STEADY_STATE", "TRAILER_COLUMNS", "steady_inside_radius",
           "vehicles_frame"]


#: CSV columns, in this order (lengths in the chosen units, angles in degrees).
COLUMNS = ["vehicle", "wheelbase", "track", "width", "length", "front_overhang",
           "rear_overhang", "max_steer_deg", "outer_steer_deg", "ackermann_angle_deg",
           "min_radius", "ctr", "curb_to_curb", "wall_to_wall", "inside_radius",
           "swept_width", "offtracking", "inside_radius_180"]


TRAILER_COLUMNS = ["steady_state", "trailer_articulation_deg", "articulation_limited",
                   "trailer_radius", "trailer_inside_radius", "trailer_offtracking",
                   "combination_inside_radius", "combination_swept_width"]


NO_STEADY_STATE = "no steady state"
"""Shown instead of a steady inside radius where a combination has none at full lock."""


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
