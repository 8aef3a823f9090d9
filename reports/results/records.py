"""A study's result rows: one :class:`RunRecord` per network x vehicle x curve.

The columns of ``clearance.csv`` (:data:`COLUMNS`) are defined here once, and the ranks of
the verdicts (:data:`VERDICT_ORDER`: ``error`` before the order
:data:`clearance.analysis.clearance.VERDICTS` defines).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from shapely.geometry.base import BaseGeometry

from clearance.analysis.clearance import VERDICTS
from clearance.networks.driving.runs import SwungLine

__all__ = ["COLUMNS", "VERDICT_ORDER", "RunRecord"]

#: Columns of ``clearance.csv`` in order.
COLUMNS = ["network", "vehicle", "curve_id", "kind", "junction", "verdict", "margin_m",
           "paved_margin_m", "curve_radius_m", "vehicle_min_radius_m", "swept_width_m",
           "available_width_m", "max_offtracking_m", "trailer_offtracking_m",
           "max_tracking_error_m", "turn_angle_deg",
           "max_grade_pct", "method", "clearance_m", "lane_verdict", "lane_margin_m", "path",
           "encroaches_on", "reason", "geometry", "conflict_at",
           "vertical", "vertical_margin_m", "vertical_station_m", "vertical_part", "grade_limit_pct", "suspect_elevation",  # noqa: E501 - vertical checks
           "serves_up_to", "serves_encroaching_up_to", "overreach_station_m", "overreach_x",
           "overreach_y", "extra_width_m"]

#: Verdicts worst first, as ranks: ``error`` (a run the tool or SUMO could not complete; its
#: reason says why) before the run verdicts of :data:`clearance.analysis.clearance.VERDICTS`, which
#: define their order (``{"error": -1, "cannot-turn": 0, ..., "clear": 3}``).
VERDICT_ORDER = {v: rank for rank, v in enumerate(("error", *VERDICTS), start=-1)}


@dataclass
class RunRecord:
    """One vehicle on one curve of one network."""

    network: str
    vehicle: str
    curve_id: str
    kind: str
    junction: str
    verdict: str
    margin_m: float
    paved_margin_m: float
    curve_radius_m: float
    vehicle_min_radius_m: float
    swept_width_m: float
    available_width_m: float
    max_offtracking_m: float
    max_tracking_error_m: float
    turn_angle_deg: float
    max_grade_pct: float
    method: str
    clearance_m: float
    reason: str
    envelope: BaseGeometry | None = field(repr=False)
    #: The verdict and margin on the lane's centre line (the same as ``verdict`` and
    #: ``margin_m`` where the lane path was taken).
    lane_verdict: str = ""
    lane_margin_m: float = math.nan
    #: ``lane`` or ``swung``: the path the verdict judges (:mod:`clearance.networks.driving.swing`).
    path: str = "lane"
    #: What the path's envelope encroaches on: ``same-direction lanes``, ``opposing
    #: lanes``, ``shoulder`` (beyond the paved area), or empty.
    encroaches_on: str = ""
    #: The vertical finding (:mod:`clearance.reports.results.vertical`): ``clear``, ``scrapes``,
    #: ``too-steep``
    #: or ``scrapes, too-steep``; the least gap under the body (m, negative: into the
    #: ground), where (m from the feature's start) and which part; the grade limit applied
    #: (percent, NaN: none); the curve's suspect heights (``""``: none).
    vertical: str = ""
    vertical_margin_m: float = math.nan
    vertical_station_m: float = math.nan
    vertical_part: str = ""
    grade_limit_pct: float = math.nan
    suspect_elevation: str = ""
    #: The envelope's parts outside its own lanes (but paved) and outside the pavement
    #: (:func:`clearance.reports.exports.envelopes.conflict_parts`), computed where the curve's
    #: areas are (a
    #: worker); ``None`` when not computed.
    conflict: tuple[BaseGeometry | None, BaseGeometry | None] | None = field(
        default=None, repr=False)
    #: Design feedback (:mod:`clearance.reports.results.feedback`): the largest vehicle of the
    #: study that
    #: clears this curve, and that stays paved on it (clear or encroaches); ``""``: none.
    serves_up_to: str = ""
    serves_encroaching_up_to: str = ""
    #: A run not clear: its worst overreach (beyond the paved area for ``fails``, its own
    #: lanes for ``encroaches``): station along the curve's centre line (m), network x, y
    #: (m), and the extra width that area needs there (m); NaN otherwise.
    overreach_station_m: float = math.nan
    overreach_x: float = math.nan
    overreach_y: float = math.nan
    extra_width_m: float = math.nan
    #: An articulated vehicle's largest trailer offtracking (m): how far inside the steered
    #: axle's path the trailer axle runs (:attr:`clearance.analysis.envelope.SweptPath.
    #: max_trailer_offtracking_m`); NaN without a trailer or for the analytic method.
    trailer_offtracking_m: float = math.nan
    #: The netconvert defaults the verdict rests on, in words (``lane width default 3.2 m;
    #: corner computed (r 3.1 m)``), or ``data`` (:mod:`clearance.networks.provenance`).
    geometry: str = ""
    #: Where the worst conflict lies (:mod:`clearance.networks.places`): ``approach E1 9.8 m
    #: before J5``, ``in junction J5``, ``exit E3 2.0 m after J5``; ``""`` for a clear run.
    conflict_at: str = ""
    #: A swung run's line (:class:`clearance.networks.driving.runs.SwungLine`), with which a drawing
    #: drives it again without the search (:func:`clearance.reports.documents.drawing.rerun`);
    #: ``None`` on the
    #: lane, for the analytic method, and in a record made without it. Not an output
    #: column.
    line: SwungLine | None = field(default=None, repr=False, compare=False)

    def row(self) -> dict[str, object]:
        """The record's values by :data:`COLUMNS`."""
        return {c: getattr(self, c) for c in COLUMNS}
