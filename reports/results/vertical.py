"""The vertical checks of a study's runs: scraping at crests and sags, and the grade.

Each run gets, beside its plan verdict, a **vertical finding** (``RunRecord.vertical``):
``clear``, ``scrapes`` (the ground cuts into the body somewhere while it is over the
feature: :func:`clearance.analysis.vertical.body_clearance` on the curve's centre-line profile),
``too-steep`` (the curve's ``max_grade_pct`` exceeds the grade limit: the vehicle's own
``grade_limit_pct`` or the study's ``--max-grade-pct``, the lower of the two), or both as
``scrapes, too-steep``. ``vertical_margin_m`` is the least gap under the body (negative:
how deep the ground cuts in), ``vertical_station_m`` where along the centre line, from the
feature's start, and ``vertical_part`` which part of the body (``underside``, ``front
overhang``, ``rear overhang``). The finding does not depend on the path the plan verdict
took: the profile is the centre line's (a swung path crosses the same grades).

The checks are cheap (a level curve is skipped) and run in the study's process after the
runs come back, for every record, ``error`` runs too: they need no simulation.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from clearance.analysis.vertical import Body, VerticalResult, body_clearance
from clearance.networks.curves import Curve
from clearance.networks.geometry import arc_length
from clearance.reports.results.records import RunRecord
from clearance.vehicles.vehicle import Vehicle

__all__ = ["FINDINGS", "add_vertical", "grade_limit_pct", "profile_of", "vertical_check",
           "vertical_result", "vertical_words"]

#: The vertical findings that fail a gate (``clearance check`` exits 1 on them).
FINDINGS = ("scrapes", "too-steep")


def grade_limit_pct(vehicle: Vehicle, study_limit_pct: float | None) -> float:
    """The grade limit of a vehicle in a study: the lower of its own and the study's (NaN:
    none).

    Examples
    --------
    >>> v = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.7, 0.4, grade_limit_pct=25.0)
    >>> grade_limit_pct(v, 15.0), grade_limit_pct(v, None)
    (15.0, 25.0)
    >>> math.isnan(grade_limit_pct(Vehicle("x", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.7, 0.4), None))
    True
    """
    limits = [x for x in (vehicle.grade_limit_pct, study_limit_pct) if x is not None]
    return min(limits) if limits else math.nan


def profile_of(curve: Curve) -> tuple[object, object]:
    """Stations (plane arc length along the centre line) and heights of a curve."""
    return arc_length(curve.centerline), curve.centerline[:, 2]


def vertical_result(vehicle: Vehicle, curve: Curve) -> VerticalResult:
    """:func:`clearance.analysis.vertical.body_clearance` of ``vehicle`` over ``curve``'s
    feature."""
    s, z = profile_of(curve)
    return body_clearance(s, z, Body.of(vehicle),  # type: ignore[arg-type]
                          span_m=(curve.core_start_m, curve.core_end_m))


def vertical_check(vehicle: Vehicle, curve: Curve,
                   study_limit_pct: float | None = None) -> dict[str, object]:
    """The vertical fields of one run (the names of
    :class:`~clearance.reports.results.records.RunRecord`)."""
    r = vertical_result(vehicle, curve)
    limit = grade_limit_pct(vehicle, study_limit_pct)
    found = []
    if r.scrapes:
        found.append("scrapes")
    if math.isfinite(limit) and curve.max_grade_pct > limit:
        found.append("too-steep")
    station = r.station_m - curve.core_start_m if math.isfinite(r.station_m) else math.nan
    return {"vertical": ", ".join(found) or "clear", "vertical_margin_m": r.margin_m,
            "vertical_station_m": station, "vertical_part": r.part,
            "grade_limit_pct": limit, "suspect_elevation": curve.suspect_elevation}


def add_vertical(records: Iterable[RunRecord], curves: dict[tuple[str, str], Curve],
                 vehicles: Sequence[Vehicle], study_limit_pct: float | None = None) -> None:
    """Set the vertical fields of every record in place (``curves`` by network and id)."""
    by_name = {v.name: v for v in vehicles}
    for rec in records:
        curve = curves[(rec.network, rec.curve_id)]
        for key, value in vertical_check(by_name[rec.vehicle], curve,
                                         study_limit_pct).items():
            setattr(rec, key, value)


def vertical_words(r: object, units: str = "m") -> str:
    """A run's vertical finding in words (``""`` when there is nothing to say: level and
    clear).

    Examples
    --------
    >>> from types import SimpleNamespace as N
    >>> vertical_words(N(vertical="scrapes", vertical_margin_m=-0.05, vertical_station_m=3.2,
    ...                  vertical_part="rear overhang", max_grade_pct=15.0,
    ...                  grade_limit_pct=float("nan"), suspect_elevation=""))
    'scrapes: the rear overhang 0.05 m into the ground at 3.2 m into the feature'
    >>> vertical_words(N(vertical="too-steep", vertical_margin_m=0.1, vertical_station_m=1.0,
    ...                  vertical_part="underside", max_grade_pct=18.0, grade_limit_pct=15.0,
    ...                  suspect_elevation=""))
    'too-steep: 18.0 % against a limit of 15 %; 0.10 m under the underside'
    >>> vertical_words(N(vertical="clear", vertical_margin_m=0.1, vertical_station_m=math.nan,
    ...                  vertical_part="", max_grade_pct=0.0, grade_limit_pct=math.nan,
    ...                  suspect_elevation=""))
    ''
    """
    from clearance.reports.results.units import length_scale, text_in_units

    k = length_scale(units)
    finding = str(getattr(r, "vertical", ""))
    parts: list[str] = []
    m = float(getattr(r, "vertical_margin_m", math.nan))
    part = str(getattr(r, "vertical_part", ""))
    station = float(getattr(r, "vertical_station_m", math.nan))
    grade = float(getattr(r, "max_grade_pct", math.nan))
    limit = float(getattr(r, "grade_limit_pct", math.nan))
    if "too-steep" in finding:
        parts.append(f"{grade:.1f} % against a limit of {limit:g} %")
    if part and math.isfinite(m):
        where = f" at {station / k:.1f} {units} into the feature" if math.isfinite(station) else ""
        depth = abs(m) / k
        amount = f"{depth:.2f}" if depth >= 0.005 else f"{depth:.3f}"
        if m < 0:
            parts.insert(0, f"the {part} {amount} {units} into the ground{where}")
        else:
            parts.append(f"{amount} {units} under the {part}")
    suspect = str(getattr(r, "suspect_elevation", ""))
    if suspect:
        parts.append(f"suspect elevation: {text_in_units(suspect, units)}")
    if finding in ("", "clear") and not suspect and not (part and math.isfinite(m)):
        return ""
    if finding in ("", "clear"):
        return "vertical clear: " + "; ".join(parts) if parts else ""
    return f"{finding}: " + "; ".join(parts)
