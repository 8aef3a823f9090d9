"""The design turn: the steered-axle centre on an arc of the CTR, and the inside radius it leaves.

The Green Book's minimum turning paths are drawn this way: the vehicle comes in straight
and aligned, the centre of its steered axle then follows a circular arc of the vehicle's
centre-line turning radius (CTR) through the turn angle (180° for the published minimum
inside radius), and leaves on a straight tangent. The minimum inside radius is the closest
the inner side of any unit comes to the arc's centre over the whole manoeuvre, exit included
(a trailer keeps cutting in after the tractor has straightened).

Kinematics
----------
The towing unit follows its steered-axle point exactly like a trailer hitched at that point
(hitch offset 0, trailer wheelbase ``l``) follows the point it is hitched to: with ``psi_1``
the angle between the steered axle's path and the body (the bicycle steering angle) and
``k`` the path's curvature per unit distance ``s`` of the steered axle::

    dpsi_1/ds = k - sin(psi_1) / l

(:func:`clearance.analysis.trailer.advance_articulation` with ``e = 0``, ``l_t = l``). On the arc,
``psi_1`` rises from 0 toward ``asin(l / CTR)``, the full-lock angle, and never exceeds it,
so the turn respects the lock. The rear axle travels ``cos(psi_1) ds`` on a path of
curvature ``tan(psi_1) / l``; a towed unit follows the rear axle by the same function with
the row's hitch offset and trailer wheelbase (midpoint values of ``psi_1`` over each step).

The inner side of each unit is the rectangle model's: the body side at ``B/2`` from the
centre line, from the rear of the body to its front. Its signed distance from the arc's
centre is negative where the body passes over the centre.

Rear-steered vehicles get NaN: their rear swings out and the Green Book has none.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from clearance.analysis.trailer import advance_articulation

__all__ = ["DEFAULT_STEP_M", "design_turn_inside_radius"]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

DEFAULT_STEP_M = 0.05
"""Largest distance the steered axle travels per integration step."""

_FRAME_COLUMNS = ("wheelbase_m", "width_m", "front_overhang_m", "rear_overhang_m",
                  "min_radius_m")


def _inner_side_distance(cx: FloatArray, cy: FloatArray, ax: FloatArray, ay: FloatArray,
                         bx: FloatArray, by: FloatArray, nx: FloatArray, ny: FloatArray
                         ) -> FloatArray:
    """Signed distance from ``(cx, cy)`` to the segment A-B; negative past it along ``n``.

    ``n`` is the segment's normal pointing away from the body, toward the centre; the
    distance is negative where the point lies abreast of the segment on the body's side.

    Examples
    --------
    >>> z, o = np.zeros(1), np.ones(1)
    >>> float(_inner_side_distance(z, 3 * o, -o, z, o, z, z, o)[0])      # 3 m inboard
    3.0
    >>> float(_inner_side_distance(z, -o, -o, z, o, z, z, o)[0])         # under the body
    -1.0
    >>> float(_inner_side_distance(z, z, -o, z, o, z, z, o)[0])          # on the side itself
    0.0
    """
    dx, dy = bx - ax, by - ay
    qx, qy = cx - ax, cy - ay
    t = (qx * dx + qy * dy) / (dx * dx + dy * dy)
    inside = (t > 0) & (t < 1)
    tc = np.clip(t, 0.0, 1.0)
    dist = np.hypot(qx - tc * dx, qy - tc * dy)
    lateral = qx * nx + qy * ny
    return np.where(inside & (lateral < 0), -dist, dist)


def design_turn_inside_radius(
    frame: pd.DataFrame,
    angle_deg: float = 180.0,
    ctr_m: float | FloatArray | None = None,
    step_m: float = DEFAULT_STEP_M,
) -> pd.DataFrame:
    """Inside radius of a left turn with the steered-axle centre on an arc of the CTR.

    Parameters
    ----------
    frame
        An SI vehicle frame (:attr:`clearance.vehicles.table.VehicleTable.frame`, or any frame with
        ``wheelbase_m, width_m, front_overhang_m, rear_overhang_m, min_radius_m`` and,
        for towed units, ``hitch_offset_m, trailer_wheelbase_m, trailer_width_m,
        trailer_front_overhang_m, trailer_rear_overhang_m``; ``steered_axle`` optional).
    angle_deg
        Angle of the arc (0 < angle <= 360).
    ctr_m
        Radius of the steered-axle centre's arc, one value or one per row; default each
        row's full-lock CTR ``sqrt(rho^2 + l^2)``. Smaller than the wheelbase is bad input.
    step_m
        Largest integration step of the steered axle (m).

    Returns
    -------
    DataFrame (same index) with ``ctr_m``, ``inside_radius_m`` (the whole vehicle: the
    smallest of the units), ``towing_inside_radius_m`` and ``trailer_inside_radius_m``
    (NaN without a trailer).

    Examples
    --------
    The AASHTO P car (ft; CTR 21, wheelbase 11, width 7): Green Book minimum inside
    radius 14.4.

    >>> f = pd.DataFrame(dict(wheelbase_m=[11.0], width_m=[7.0], front_overhang_m=[3.0],
    ...     rear_overhang_m=[5.0], min_radius_m=[np.sqrt(21.0**2 - 11.0**2)]))
    >>> round(float(design_turn_inside_radius(f).inside_radius_m[0]), 1)
    14.4

    Degenerate: a turn of almost no angle leaves the body straight, its inner side
    ``CTR - B/2`` from the centre.

    >>> round(float(design_turn_inside_radius(f, angle_deg=1e-9).inside_radius_m[0]), 9)
    17.5
    """
    _check_arguments(frame, angle_deg, step_m)
    col = {c: frame[c].to_numpy(float) for c in _FRAME_COLUMNS}
    R = _arc_radius(col, ctr_m, len(frame))
    v = _vehicle(frame, col)
    best_tow, best_trl = _sweep(v, R, math.radians(angle_deg), step_m)

    nan = np.nan
    towing = np.where(v.rear, nan, best_tow)
    trailer = np.where(v.has & ~v.rear, best_trl, nan)
    return pd.DataFrame(
        {
            "ctr_m": R,
            "inside_radius_m": np.fmin(towing, trailer),
            "towing_inside_radius_m": towing,
            "trailer_inside_radius_m": trailer,
        },
        index=frame.index,
    )


def _check_arguments(frame: pd.DataFrame, angle_deg: float, step_m: float) -> None:
    """Raise ValueError for a frame without the columns needed, a bad angle or a bad step."""
    missing = [c for c in _FRAME_COLUMNS if c not in frame]
    if missing:
        raise ValueError(f"design turn: the vehicle frame lacks {', '.join(missing)}")
    if not (0.0 < angle_deg <= 360.0):
        raise ValueError(f"design turn: angle_deg must be in (0, 360], got {angle_deg!r}")
    if not (math.isfinite(step_m) and step_m > 0):
        raise ValueError(f"design turn: step_m must be a positive number, got {step_m!r}")


def _arc_radius(col: dict[str, FloatArray], ctr_m: float | FloatArray | None, n_rows: int
                ) -> FloatArray:
    """Radius of each row's arc: ``ctr_m``, or the full-lock CTR when it is None.

    Raises ValueError where ``ctr_m`` is smaller than the wheelbase.
    """
    l = col["wheelbase_m"]
    if ctr_m is None:
        R: FloatArray = np.hypot(col["min_radius_m"], l)
        return R
    R = np.broadcast_to(np.asarray(ctr_m, dtype=float), (n_rows,)).copy()
    bad = ~(R >= l)
    if bad.any():
        raise ValueError(f"design turn: ctr_m {R[bad][0]!r} is smaller than the "
                         f"wheelbase {l[bad][0]!r}: no such arc can be driven")
    return R


@dataclass(frozen=True)
class _Vehicle:
    """Each row's dimensions (m) of the towing unit and of its towed unit, as arrays.

    Rows without a trailer have ``has`` False and harmless trailer values (``lt`` 1, the
    rest 0, ``bt`` the towing unit's width); ``rear`` marks rear-steered rows.
    """

    l: FloatArray
    B: FloatArray
    a_f: FloatArray
    a_r: FloatArray
    e: FloatArray
    lt: FloatArray
    bt: FloatArray
    a_tf: FloatArray
    a_tr: FloatArray
    has: BoolArray
    rear: BoolArray


def _vehicle(frame: pd.DataFrame, col: dict[str, FloatArray]) -> _Vehicle:
    """The units' dimensions of each row of ``frame`` (``col``: its frame columns as arrays)."""
    n_rows = len(frame)
    B = col["width_m"]

    def trailer_col(name: str, default: float) -> FloatArray:
        """Column ``name`` of the frame, or ``default`` in every row without it."""
        return frame[name].to_numpy(float) if name in frame else np.full(n_rows, default)

    lt = trailer_col("trailer_wheelbase_m", np.nan)
    has = np.isfinite(lt)
    e = np.where(has, trailer_col("hitch_offset_m", 0.0), 0.0)
    lt = np.where(has, lt, 1.0)
    bt = np.where(has, trailer_col("trailer_width_m", np.nan), 0.0)
    bt = np.where(np.isfinite(bt), bt, B)
    a_tf = np.where(has, trailer_col("trailer_front_overhang_m", 0.0), 0.0)
    a_tr = np.where(has, trailer_col("trailer_rear_overhang_m", 0.0), 0.0)
    rear = (frame["steered_axle"] == "rear").to_numpy() if "steered_axle" in frame else (
        np.zeros(n_rows, dtype=bool))
    return _Vehicle(col["wheelbase_m"], B, col["front_overhang_m"], col["rear_overhang_m"],
                    e, lt, bt, a_tf, a_tr, has, rear)


def _sweep(v: _Vehicle, R: FloatArray, angle: float, step_m: float
           ) -> tuple[FloatArray, FloatArray]:
    """Drive the arc of radius ``R`` through ``angle`` (rad), then the exit tangent.

    Returns the least signed distance of each unit's inner side from the arc's centre.
    """
    n_rows = len(R)
    arc = R * angle
    # Long enough an exit for the last unit to finish cutting in and straighten out.
    reach = v.a_f + v.l + np.where(v.has, np.abs(v.e) + v.lt + v.a_tr, v.a_r)
    exit_len = 3.0 * reach
    n_arc = max(1, math.ceil(float(np.nanmax(arc, initial=0.0)) / step_m))
    n_exit = max(1, math.ceil(float(np.nanmax(exit_len, initial=0.0)) / step_m))
    ds_arc, ds_exit = arc / n_arc, exit_len / n_exit
    centre = (np.zeros(n_rows), R)

    psi1 = np.zeros(n_rows)
    psi2 = np.zeros(n_rows)
    best_tow = np.full(n_rows, np.inf)
    best_trl = np.full(n_rows, np.inf)

    def measure(fx: FloatArray, fy: FloatArray, heading: FloatArray) -> None:
        """Lower the least distances to those of the current position."""
        d_tow, d_trl = _inner_distances(v, centre, fx, fy, heading, psi1, psi2)
        np.minimum(best_tow, d_tow, out=best_tow)
        np.minimum(best_trl, d_trl, out=best_trl)

    zero = np.zeros(n_rows)
    measure(zero, zero, zero)
    with np.errstate(divide="ignore", invalid="ignore"):
        k_arc = np.where(R > 0, 1.0 / R, 0.0)
    for i in range(1, n_arc + 1):
        psi1, psi2 = _advance(v, psi1, psi2, k_arc, ds_arc)
        a = i * ds_arc * k_arc
        measure(R * np.sin(a), R * (1 - np.cos(a)), a)
    ex, ey = R * math.sin(angle), R * (1 - math.cos(angle))
    for i in range(1, n_exit + 1):
        psi1, psi2 = _advance(v, psi1, psi2, zero, ds_exit)
        s = i * ds_exit
        measure(ex + s * math.cos(angle), ey + s * math.sin(angle), np.full(n_rows, angle))
    return best_tow, best_trl


def _inner_distances(v: _Vehicle, centre: tuple[FloatArray, FloatArray], fx: FloatArray,
                     fy: FloatArray, heading: FloatArray, psi1: FloatArray, psi2: FloatArray
                     ) -> tuple[FloatArray, FloatArray]:
    """Signed distances from ``centre`` to the towing unit's and the towed unit's inner sides.

    ``(fx, fy)`` is the steered-axle centre, ``heading`` its path's direction (rad).
    """
    cx, cy = centre
    theta = heading - psi1
    ux, uy = np.cos(theta), np.sin(theta)
    px, py = fx - v.l * ux, fy - v.l * uy
    h = v.B / 2
    d_tow = _inner_side_distance(cx, cy, px - v.a_r * ux - h * uy, py - v.a_r * uy + h * ux,
                                 fx + v.a_f * ux - h * uy, fy + v.a_f * uy + h * ux, -uy, ux)
    tt = theta - psi2
    vx, vy = np.cos(tt), np.sin(tt)
    hx, hy = px - v.e * ux, py - v.e * uy
    tx, ty = hx - v.lt * vx, hy - v.lt * vy
    ht = v.bt / 2
    d_trl = _inner_side_distance(cx, cy, tx - v.a_tr * vx - ht * vy,
                                 ty - v.a_tr * vy + ht * vx, hx + v.a_tf * vx - ht * vy,
                                 hy + v.a_tf * vy + ht * vx, -vy, vx)
    return d_tow, d_trl


def _advance(v: _Vehicle, psi1: FloatArray, psi2: FloatArray, k: FloatArray, ds: FloatArray
             ) -> tuple[FloatArray, FloatArray]:
    """The articulations after the steered axle travels ``ds`` on a path of curvature ``k``.

    ``psi1`` is the towing unit's (the bicycle steering angle), ``psi2`` the towed unit's.
    """
    new1 = advance_articulation(psi1, k, ds, 0.0, v.l)
    mid = 0.5 * (psi1 + new1)
    new2 = advance_articulation(psi2, np.tan(mid) / v.l, np.cos(mid) * ds, v.e, v.lt)
    return new1, new2
