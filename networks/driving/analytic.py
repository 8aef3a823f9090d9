"""The analytic method: each vehicle in steady state at every station of a curve.

Where the driven method (libsumo and the kinematic model) follows the transient, the
analytic method places the vehicle at each station of the centre line in the steady turn
of the local radius (docs/design.md §4): with the steered-axle centre on the centre line at
radius ``R``, the rear axle runs at ``rho = sqrt(R^2 - l^2)``, the body reaches
``R_out = sqrt((rho + B/2)^2 + (l + a)^2)`` outside and ``rho - B/2`` inside (a trailer:
``sqrt(rho^2 + e^2 - l_t^2) - B_t/2``). The envelope is the band between those offsets of
the designed line (the smoothed centre line the driven vehicle follows and the own lanes
are built on, :func:`clearance.networks.areas.designed_line`) over the feature and one vehicle
length either side (where some part of the vehicle can be while it is in the feature,
as the driven method judges). A curve whose feature is tighter than the vehicle's minimum
centre-line turning radius is ``cannot-turn``.

It is **not a bound** on the driven method, and it differs from it in two known ways:

- *more severe* where a turn is short: steady-state offtracking is the largest a turn can
  produce, and a short turn's transient never reaches it (on the samples 89 of 1,705 runs
  of the bundled vehicles, e.g. ``fails`` where the driven run ``encroaches``);
- *less severe* where the driven method's ``cannot-turn`` comes from the transient: the
  steering rate, or the overshoot after a tight stretch just before the feature, neither
  of which a steady state has. Its ``cannot-turn`` is only the radius test above;
- *less severe* where a long rear overhang (over 2.5 m) or a towed unit swings out at the
  start of a turn: the tail swing of the transient, outside the steady band.

On a curve with levels (docs/design.md §6, "Levels") the band is cut into the stretches of
its storeys by the centre line's height, each judged against its own storey's areas.

On the five samples with the AASHTO vehicles (819 runs) 482 are alike, 335 more severe
and 2 less severe: the S-BUS40 and the A-BUS at ``turn:T:TE_in_0->TS_out_0``, each
``fails`` driven and ``encroaches`` analytically.
``tests/reports/test_analytic.py`` checks that relation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from clearance.analysis.clearance import (
    END_SLACK_M,
    Areas,
    Clearance,
    classify,
    end_boxes,
    worst_level,
)
from clearance.analysis.levels import CORRIDOR_OVERLAP_M, path_segments
from clearance.analysis.polyline import prepare_path
from clearance.networks.areas import designed_line
from clearance.networks.curves import Curve
from clearance.networks.geometry import arc_length, clean_polyline, curvature_profile
from clearance.vehicles.errors import GeometryError
from clearance.vehicles.vehicle import Vehicle

__all__ = ["AnalyticRun", "STEP_M", "extents_m", "fill_small_holes", "minimum_ctr_m",
           "run_analytic"]

#: Stations every this many metres along the centre line.
STEP_M = 1.0


@dataclass(frozen=True)
class AnalyticRun:
    """One vehicle on one curve, analytically."""

    envelope: BaseGeometry
    clearance: Clearance
    swept_width_m: float
    max_offtracking_m: float
    vehicle_min_radius_m: float


def minimum_ctr_m(vehicle: Vehicle) -> float:
    """The vehicle's minimum centre-line turning radius (steered-axle centre).

    Examples
    --------
    >>> v = Vehicle("P", 3.35, 2.13, 2.13, 0.91, 1.52, math.atan(3.35 / 5.45), 0.7, 0.3)
    >>> round(minimum_ctr_m(v), 3)
    6.397
    """
    return math.hypot(vehicle.min_radius_m, vehicle.wheelbase_m)


def extents_m(vehicle: Vehicle, radius_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Steady-state body extents inside and outside a centre line of radius ``radius_m``.

    Returns ``(inside, outside)``: how far the body reaches to the inside and the outside
    of the centre line when the steered-axle centre runs on it. Straight ahead both are
    half the body width.

    Examples
    --------
    >>> v = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> i, o = extents_m(v, np.array([np.inf, 10.0]))
    >>> [round(float(x), 4) for x in i], [round(float(x), 4) for x in o]
    ([0.9, 1.2714], [0.9, 1.1271])
    """
    R = np.asarray(radius_m, dtype=float)
    l, B = vehicle.wheelbase_m, vehicle.width_m
    a = vehicle.front_overhang_m if vehicle.steered_axle == "front" else vehicle.rear_overhang_m
    straight = ~np.isfinite(R)
    Rf = np.where(straight, 1e9, np.maximum(R, l * 1.000001))
    rho = np.sqrt(Rf**2 - l**2)
    outer = np.hypot(rho + B / 2, l + a) - Rf
    inner = Rf - (rho - B / 2)
    t = vehicle.trailer
    if t is not None:
        rt2 = rho**2 + t.hitch_offset_m**2 - t.wheelbase_m**2
        r_t = np.sqrt(np.maximum(rt2, 0.0))
        inner = np.maximum(inner, Rf - (r_t - t.width_m / 2))
        outer = np.maximum(outer, np.hypot(r_t + t.width_m / 2,
                                           t.wheelbase_m + t.front_overhang_m) - Rf)
    inner = np.where(straight, max(B, t.width_m if t else 0.0) / 2, inner)
    outer = np.where(straight, max(B, t.width_m if t else 0.0) / 2, outer)
    return inner, outer


def fill_small_holes(geom: BaseGeometry, min_area_m2: float) -> BaseGeometry:
    """``geom`` with the holes smaller than ``min_area_m2`` filled (slivers between steps).

    Examples
    --------
    >>> ring = shapely.box(0, 0, 10, 10).difference(shapely.box(4, 4, 4.5, 4.5))
    >>> fill_small_holes(ring, 1.0).area
    100.0
    >>> fill_small_holes(ring, 0.1).area
    99.75
    """
    polys = []
    for p in shapely.get_parts(geom):
        if p.geom_type != "Polygon":
            continue
        holes = [h for h in p.interiors if shapely.Polygon(h).area >= min_area_m2]
        polys.append(shapely.Polygon(p.exterior, holes))
    return shapely.union_all(polys) if polys else geom


def run_analytic(vehicle: Vehicle, curve: Curve, offset_m: float = 0.0) -> AnalyticRun:
    """The analytic envelope and verdict of ``vehicle`` on ``curve``."""
    # the designed line (smoothed as the simulate method's vehicle follows it), on which
    # the own lanes are built too
    pts = clean_polyline(designed_line(np.asarray(curve.centerline), curve.curve_id))
    path = prepare_path(pts, name=curve.curve_id)  # refuses a line that turns back on itself
    s_pts = arc_length(pts)
    s, k = curvature_profile(pts, step_m=STEP_M)
    core = (s >= curve.core_start_m) & (s <= curve.core_end_m)
    with np.errstate(divide="ignore"):
        radius = np.where(np.abs(k) > 1e-9, 1.0 / np.abs(k), np.inf)
    # The fitted radius can dip below the curve's own minimum between fit windows; the
    # lead-in and run-out within the window keep their own radius (a helix before a
    # junction), never tighter than the vehicle can steer
    floor = np.where(core, curve.min_radius_m,
                     min(curve.min_radius_m, minimum_ctr_m(vehicle)))
    radius = np.maximum(radius, floor)
    inner, outer = extents_m(vehicle, radius)
    # judged by the feature, as the simulate method: the band where some part of the
    # vehicle can be while it is in the feature (the feature and a vehicle length either
    # side), not the whole lead-in and run-out
    reach = vehicle.overall_length_m
    window = (s >= curve.core_start_m - reach) & (s <= curve.core_end_m + reach)
    if window.sum() >= 2:
        s, k, inner, outer = s[window], k[window], inner[window], outer[window]
    left = np.where(k >= 0, inner, outer)
    right = np.where(k >= 0, outer, inner)
    x = np.interp(s, s_pts, pts[:, 0])
    y = np.interp(s, s_pts, pts[:, 1])
    hx, hy = np.gradient(x), np.gradient(y)
    norm = np.hypot(hx, hy)
    nx, ny = -hy / norm, hx / norm
    lx, ly = x + nx * left, y + ny * left
    rx, ry = x - nx * right, y - ny * right
    # The band as the union of one quadrilateral per step, not one ring: the plan of a
    # helix overlaps itself, and a self-overlapping ring is not a valid polygon.
    quads = np.stack([np.column_stack([lx[:-1], ly[:-1]]), np.column_stack([lx[1:], ly[1:]]),
                      np.column_stack([rx[1:], ry[1:]]), np.column_stack([rx[:-1], ry[:-1]])],
                     axis=1)
    parts = shapely.make_valid(shapely.polygons(quads))
    envelope = fill_small_holes(shapely.union_all(parts), 1.0)
    min_ctr = minimum_ctr_m(vehicle)
    reason = ""
    if curve.min_radius_m < min_ctr:
        reason = (f"curve radius {curve.min_radius_m:.2f} m is tighter than the minimum "
                  f"centre-line turning radius {min_ctr:.2f} m")
    measured = envelope.buffer(offset_m, quad_segs=8) if offset_m > 0 else envelope
    # The band ends on the lanes' end lines: those ends are not curbs (docs/design.md §6).
    boxes = end_boxes(path, float(np.max(inner + outer)) + offset_m + 1.0)
    measured = shapely.difference(measured, boxes)
    ignore = shapely.buffer(boxes, END_SLACK_M, quad_segs=1)
    own, paved = curve.own_lanes, curve.paved
    if own is None or paved is None:
        raise GeometryError(f"curve {curve.curve_id}: no areas (extract curves with areas=True)")
    areas = Areas(own, paved, curve.roadway)
    if curve.levels:  # each storey's stretch of the band against its own areas
        cl = np.asarray(curve.centerline, dtype=float)
        s_cl = arc_length(cl[:, :2])
        z = np.interp(s * s_cl[-1] / max(s_pts[-1], 1e-9), s_cl, cl[:, 2])
        found = []
        quads = np.asarray(parts, dtype=object)
        for a, b, i in path_segments(s, z, curve.levels):
            near = (s[:-1] <= b + CORRIDOR_OVERLAP_M) & (s[1:] >= a - CORRIDOR_OVERLAP_M)
            part = shapely.union_all(quads[near])
            part = part.buffer(offset_m, quad_segs=8) if offset_m > 0 else part
            part = shapely.difference(part, boxes)
            if shapely.area(part) >= 1e-6:
                lv = curve.levels[i]
                found.append((lv, (a, b), classify(part, lv.areas, 0.0, reason, ignore=ignore)))
        clearance = worst_level(found) if found else classify(measured, areas, 0.0, reason,
                                                               ignore=ignore)
    else:
        clearance = classify(measured, areas, 0.0, reason, ignore=ignore)
    width = float(np.max(inner + outer))
    r_min = max(curve.min_radius_m, min_ctr)
    rho = math.sqrt(max(r_min**2 - vehicle.wheelbase_m**2, 0.0))
    innermost = rho
    t = vehicle.trailer
    if t is not None:
        innermost = math.sqrt(max(rho**2 + t.hitch_offset_m**2 - t.wheelbase_m**2, 0.0))
    offtrack = r_min - innermost if math.isfinite(curve.min_radius_m) else 0.0
    return AnalyticRun(envelope, clearance, width, offtrack, min_ctr)
