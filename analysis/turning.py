"""Steady-state turning geometry of every vehicle in a table, vectorised.

The docs/design.md §4 definitions, at full lock (:func:`full_lock_metrics`) and over the
steering range (:func:`steering_sweep`). Inputs are the SI columns of a loaded
:class:`clearance.vehicles.table.VehicleTable` frame; outputs are SI too (metres, radians).

For a rear-steered vehicle the roles of the axles swap: ``rho`` is the front (unsteered)
axle's radius and the overhang beyond the steered axle is the rear one.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from clearance.analysis.control_law import safe_pathway, theta_of_rho
from clearance.vehicles.table import VehicleTable, steering_from_row

__all__ = ["INPUT_COLUMNS", "ackermann_angle_at_lock", "articulation_limited_rho",
           "centre_line_radius", "curb_to_curb", "full_lock_metrics", "inside_radius",
           "steering_sweep", "trailer_steady_state", "turning_metrics", "wall_to_wall"]

FloatArray = NDArray[np.float64]

#: Columns :func:`full_lock_metrics` needs in its input frame.
INPUT_COLUMNS = ("wheelbase_m", "track_m", "width_m", "front_overhang_m", "rear_overhang_m",
                 "max_inner_steer_rad", "max_outer_steer_rad", "max_steer_rad")


def centre_line_radius(rho: ArrayLike, wheelbase_m: ArrayLike) -> FloatArray:
    """CTR: radius of the steered-axle centre, ``sqrt(rho^2 + l^2)``.

    Examples
    --------
    >>> round(float(centre_line_radius(np.sqrt(21.0**2 - 11.0**2), 11.0)), 9)   # AASHTO P
    21.0
    >>> float(centre_line_radius(np.inf, 2.7))                             # straight ahead
    inf
    """
    return np.hypot(np.asarray(rho, dtype=np.float64), np.asarray(wheelbase_m, dtype=np.float64))


def curb_to_curb(rho: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike) -> FloatArray:
    """Curb-to-curb turning diameter ``2 sqrt((rho + w/2)^2 + l^2)`` (SAE J695).

    Examples
    --------
    >>> round(float(curb_to_curb(5.0, 0.0, 1.5)), 9)   # zero wheelbase: a circle of rho + w/2
    11.5
    """
    r = np.asarray(rho, dtype=np.float64) + np.asarray(track_m, dtype=np.float64) / 2
    return 2 * np.hypot(r, np.asarray(wheelbase_m, dtype=np.float64))


def wall_to_wall(
    rho: ArrayLike, wheelbase_m: ArrayLike, width_m: ArrayLike, overhang_m: ArrayLike
) -> FloatArray:
    """Wall-to-wall turning diameter ``2 sqrt((rho + B/2)^2 + (l + a)^2)``.

    ``a`` is the overhang beyond the steered axle.

    Examples
    --------
    >>> round(float(wall_to_wall(5.0, 0.0, 2.0, 0.0)), 9)   # no reach: a circle of rho + B/2
    12.0
    """
    r = np.asarray(rho, dtype=np.float64) + np.asarray(width_m, dtype=np.float64) / 2
    reach = np.asarray(wheelbase_m, dtype=np.float64) + np.asarray(overhang_m, dtype=np.float64)
    return 2 * np.hypot(r, reach)


def inside_radius(rho: ArrayLike, width_m: ArrayLike) -> FloatArray:
    """Minimum inside radius ``rho - B/2`` (the inner body side at the unsteered axle).

    Examples
    --------
    >>> round(float(inside_radius(np.sqrt(38.0**2 - 20.0**2), 8.0)), 1)   # AASHTO SU-30, ft
    28.3
    """
    return np.asarray(rho, dtype=np.float64) - np.asarray(width_m, dtype=np.float64) / 2


def trailer_steady_state(
    rho: ArrayLike, hitch_offset_m: ArrayLike, trailer_wheelbase_m: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Steady-state trailer-axle radius and articulation angle.

    The hitch at ``e`` behind the towing unit's rear axle runs on a circle of radius
    ``sqrt(rho^2 + e^2)``; the trailer axle, ``l_t`` behind the hitch, on
    ``sqrt(rho^2 + e^2 - l_t^2)``. The articulation is
    ``psi = atan2(e, rho) + asin(l_t / sqrt(rho^2 + e^2))``. NaN where no steady state
    exists (``l_t`` longer than the hitch radius: the trailer would jackknife).

    Examples
    --------
    >>> r, psi = trailer_steady_state(np.inf, 0.0, 10.0)     # straight ahead
    >>> float(r), float(psi)
    (inf, 0.0)
    >>> r, psi = trailer_steady_state(12.0, 0.0, 5.0)        # hitch on the axle
    >>> round(float(r), 9), round(float(np.degrees(psi)), 4)
    (10.908712115, 24.6243)
    """
    r = np.asarray(rho, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        hitch = np.hypot(r, e)
        radius = np.sqrt(hitch**2 - lt**2)
        psi = np.arctan2(e, r) + np.arcsin(lt / hitch)
    psi = np.where(np.isinf(r), 0.0, psi)
    return radius, psi


def articulation_limited_rho(
    max_articulation_rad: ArrayLike, hitch_offset_m: ArrayLike, trailer_wheelbase_m: ArrayLike
) -> FloatArray:
    """Smallest towing-unit radius whose steady articulation stays within the limit.

    From ``rho sin(psi) - e cos(psi) = l_t``: ``rho = (l_t + e cos(psi)) / sin(psi)``.

    Examples
    --------
    >>> rho = articulation_limited_rho(np.radians(24.6243), 0.0, 5.0)
    >>> round(float(rho), 3)
    12.0
    """
    psi = np.asarray(max_articulation_rad, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    return (lt + e * np.cos(psi)) / np.sin(psi)


def full_lock_metrics(frame: pd.DataFrame) -> pd.DataFrame:
    """Turning metrics at full lock for every row of an SI vehicle frame.

    Returns a frame (same index) with ``max_steer_rad, outer_steer_rad,
    ackermann_angle_rad, min_radius_m`` (rho at lock), ``ctr_m, curb_to_curb_m,
    wall_to_wall_m, inside_radius_m, swept_width_m, offtracking_m``, and, where a row has a
    towed unit, ``steady_state, trailer_articulation_rad, articulation_limited,
    trailer_radius_m, trailer_inside_radius_m, trailer_offtracking_m,
    combination_inside_radius_m, combination_swept_width_m`` (NaN elsewhere).
    ``articulation_limited``: the steady state at full lock does not exist or exceeds the
    maximum articulation, so the steady columns are those of the tightest radius the
    articulation allows. ``steady_state`` is false, and the steady trailer columns NaN,
    where even that has none: no trailer-axle circle, or a trailer body that would pass
    over the turn's centre (:mod:`clearance.analysis.design_turn` gives such a combination's inside
    radius in a real, transient turn). Vectorised: a million rows take well under a second.

    Examples
    --------
    >>> f = pd.DataFrame(dict(wheelbase_m=[3.35], track_m=[1.8], width_m=[2.13],
    ...     front_overhang_m=[0.91], rear_overhang_m=[1.52], max_inner_steer_rad=[0.6],
    ...     max_outer_steer_rad=[0.45], max_steer_rad=[0.5]))
    >>> m = full_lock_metrics(f)
    >>> bool(np.isclose(m.ctr_m[0], 3.35 / np.sin(0.5)))
    True
    """
    l = frame["wheelbase_m"].to_numpy(float)  # noqa: E741
    w = frame["track_m"].to_numpy(float)
    B = frame["width_m"].to_numpy(float)
    phi = frame["max_steer_rad"].to_numpy(float)
    if "steered_axle" in frame:
        rear = (frame["steered_axle"] == "rear").to_numpy()
        a_s = np.where(rear, frame["rear_overhang_m"].to_numpy(float),
                       frame["front_overhang_m"].to_numpy(float))
    else:
        a_s = frame["front_overhang_m"].to_numpy(float)
    rho = l / np.tan(phi)
    inner = frame["max_inner_steer_rad"].to_numpy(float)
    outer = frame["max_outer_steer_rad"].to_numpy(float)
    ctr = centre_line_radius(rho, l)
    wall = wall_to_wall(rho, l, B, a_s)
    r_in = inside_radius(rho, B)
    out = pd.DataFrame(
        {
            "max_steer_rad": inner,
            "outer_steer_rad": outer,
            "ackermann_angle_rad": inner - outer,
            "min_radius_m": rho,
            "ctr_m": ctr,
            "curb_to_curb_m": curb_to_curb(rho, l, w),
            "wall_to_wall_m": wall,
            "inside_radius_m": r_in,
            "swept_width_m": safe_pathway(rho, l, B, a_s),
            "offtracking_m": ctr - rho,
        },
        index=frame.index,
    )
    if "trailer_wheelbase_m" in frame and frame["trailer_wheelbase_m"].notna().any():
        _trailer_metrics(frame, out, rho, l, B, a_s, ctr)
    return out


def _trailer_metrics(frame: pd.DataFrame, out: pd.DataFrame, rho: FloatArray,
                     l: FloatArray, B: FloatArray, a_s: FloatArray,  # noqa: E741
                     ctr: FloatArray) -> None:
    e = frame["hitch_offset_m"].to_numpy(float)
    lt = frame["trailer_wheelbase_m"].to_numpy(float)
    bt = frame["trailer_width_m"].to_numpy(float)
    a_tf = frame["trailer_front_overhang_m"].to_numpy(float)
    a_tr = frame["trailer_rear_overhang_m"].to_numpy(float)
    psi_max = frame["max_articulation_rad"].to_numpy(float)
    has = np.isfinite(lt)
    _, psi_lock = trailer_steady_state(rho, e, lt)
    rho_art = articulation_limited_rho(psi_max, e, lt)
    limited = has & ~(psi_lock <= psi_max)
    rho_eff = np.where(limited, np.maximum(rho, rho_art), rho)
    r_t, psi = trailer_steady_state(rho_eff, e, lt)
    ctr_eff = centre_line_radius(rho_eff, l)
    outer_tractor = np.hypot(rho_eff + B / 2, l + a_s)
    outer_nose = np.hypot(r_t + bt / 2, lt + a_tf)
    outer_tail = np.hypot(r_t + bt / 2, a_tr)
    outer = np.fmax(outer_tractor, np.fmax(outer_nose, outer_tail))
    inside = np.fmin(rho_eff - B / 2, r_t - bt / 2)
    # No steady state: the trailer axle's circle does not exist, or the trailer body would
    # sweep over the centre (the jackknife the articulation limit stops at, e.g. a WB-62
    # at full lock, whose trailer wheelbase is longer than the kingpin's radius).
    steady = has & np.isfinite(r_t) & (r_t - bt / 2 >= 0)
    nan = np.nan
    out["steady_state"] = steady | ~has
    out["trailer_articulation_rad"] = np.where(steady, psi, nan)
    out["articulation_limited"] = limited
    out["trailer_radius_m"] = np.where(steady, r_t, nan)
    out["trailer_inside_radius_m"] = np.where(steady, r_t - bt / 2, nan)
    out["trailer_offtracking_m"] = np.where(steady, ctr_eff - r_t, nan)
    out["combination_inside_radius_m"] = np.where(steady, inside, nan)
    out["combination_swept_width_m"] = np.where(steady, outer - inside, nan)


def turning_metrics(table: VehicleTable) -> pd.DataFrame:
    """Full-lock metrics of a loaded table, with the vehicle names, as a DataFrame (SI).

    Examples
    --------
    >>> from clearance.vehicles.table import bundled_table, load_tables
    >>> m = turning_metrics(load_tables([bundled_table("paper_table1")], ["2009 Smart Car"]))
    >>> m.loc[0, "vehicle"], round(float(m.loc[0, "curb_to_curb_m"] / 0.3048), 1)
    ('2009 Smart Car', 27.7)
    """
    frame = table.frame
    metrics = full_lock_metrics(frame)
    metrics.insert(0, "vehicle", frame["name"].to_numpy())
    for col in ("wheelbase_m", "track_m", "width_m", "length_m", "front_overhang_m",
                "rear_overhang_m"):
        metrics.insert(len(metrics.columns), col, frame[col].to_numpy())
    return metrics


def steering_sweep(table: VehicleTable, name: str, n: int = 50) -> pd.DataFrame:
    """One vehicle's geometry over its steering range, from straight ahead to full lock.

    Columns: ``steering_wheel_rad, inner_rad, outer_rad, bicycle_rad,
    ackermann_angle_rad, rho_m, ctr_m, swept_width_m`` (n rows; the first is straight
    ahead, where ``rho`` is infinite and the swept width is the body width).

    Examples
    --------
    >>> from clearance.vehicles.table import bundled_table, load_tables
    >>> t = load_tables([bundled_table("paper_table1")], ["2010 Honda Pilot"])
    >>> s = steering_sweep(t, "2010 Honda Pilot", 5)
    >>> float(s.rho_m.iloc[0]), round(float(np.degrees(s.inner_rad.iloc[-1])), 6)
    (inf, 40.0)
    """
    row = table.frame.loc[table.frame["name"] == name].iloc[0]
    steering = steering_from_row(row)
    sw = np.linspace(0.0, float(row["steering_range_rad"]), n)
    a = steering.wheel_angles(sw)
    l = float(row["wheelbase_m"])  # noqa: E741
    with np.errstate(divide="ignore"):
        rho = l / np.tan(np.abs(a.bicycle))
    a_s = row["front_overhang_m"] if row["steered_axle"] == "front" else row["rear_overhang_m"]
    return pd.DataFrame(
        {
            "steering_wheel_rad": sw,
            "inner_rad": np.abs(a.inner),
            "outer_rad": np.abs(a.outer),
            "bicycle_rad": np.abs(a.bicycle),
            "ackermann_angle_rad": np.abs(a.inner) - np.abs(a.outer),
            "rho_m": rho,
            "ctr_m": centre_line_radius(rho, l),
            "swept_width_m": safe_pathway(rho, l, row["width_m"], a_s),
        }
    )


def ackermann_angle_at_lock(rho: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike
                            ) -> FloatArray:
    """ϑ_max of an ideal Ackermann vehicle from its radius at lock (paper eq. 3).

    Examples
    --------
    >>> float(ackermann_angle_at_lock(np.inf, 2.7, 1.5))
    0.0
    """
    return theta_of_rho(rho, wheelbase_m, track_m)
