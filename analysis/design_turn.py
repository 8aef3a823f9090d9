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

(:func:`analysis.trailer.advance_articulation` with ``e = 0``, ``l_t = l``). On the arc,
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

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from analysis.trailer import advance_articulation
from vehicles.errors import InputError

__all__ = ["DEFAULT_STEP_M", "design_turn_inside_radius"]

FloatArray = NDArray[np.float64]

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
        An SI vehicle frame (:attr:`vehicles.table.VehicleTable.frame`, or any frame with
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
    missing = [c for c in _FRAME_COLUMNS if c not in frame]
    if missing:
        raise InputError(f"design turn: the vehicle frame lacks {', '.join(missing)}")
    if not (0.0 < angle_deg <= 360.0):
        raise InputError(f"design turn: angle_deg must be in (0, 360], got {angle_deg!r}")
    if not (math.isfinite(step_m) and step_m > 0):
        raise InputError(f"design turn: step_m must be a positive number, got {step_m!r}")
    n_rows = len(frame)
    col = {c: frame[c].to_numpy(float) for c in _FRAME_COLUMNS}
    l, B = col["wheelbase_m"], col["width_m"]  # noqa: E741
    a_f, a_r = col["front_overhang_m"], col["rear_overhang_m"]
    if ctr_m is None:
        R = np.hypot(col["min_radius_m"], l)
    else:
        R = np.broadcast_to(np.asarray(ctr_m, dtype=float), (n_rows,)).copy()
        bad = ~(R >= l)
        if bad.any():
            raise InputError(f"design turn: ctr_m {R[bad][0]!r} is smaller than the "
                             f"wheelbase {l[bad][0]!r}: no such arc can be driven")

    def trailer_col(name: str, default: float) -> FloatArray:
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

    angle = math.radians(angle_deg)
    arc = R * angle
    # Long enough an exit for the last unit to finish cutting in and straighten out.
    reach = a_f + l + np.where(has, np.abs(e) + lt + a_tr, a_r)
    exit_len = 3.0 * reach
    n_arc = max(1, math.ceil(float(np.nanmax(arc, initial=0.0)) / step_m))
    n_exit = max(1, math.ceil(float(np.nanmax(exit_len, initial=0.0)) / step_m))
    ds_arc, ds_exit = arc / n_arc, exit_len / n_exit
    cx, cy = np.zeros(n_rows), R

    psi1 = np.zeros(n_rows)
    psi2 = np.zeros(n_rows)
    best_tow = np.full(n_rows, np.inf)
    best_trl = np.full(n_rows, np.inf)

    def measure(fx: FloatArray, fy: FloatArray, heading: FloatArray) -> None:
        theta = heading - psi1
        ux, uy = np.cos(theta), np.sin(theta)
        px, py = fx - l * ux, fy - l * uy
        h = B / 2
        d = _inner_side_distance(cx, cy, px - a_r * ux - h * uy, py - a_r * uy + h * ux,
                                 fx + a_f * ux - h * uy, fy + a_f * uy + h * ux, -uy, ux)
        np.minimum(best_tow, d, out=best_tow)
        tt = theta - psi2
        vx, vy = np.cos(tt), np.sin(tt)
        hx, hy = px - e * ux, py - e * uy
        tx, ty = hx - lt * vx, hy - lt * vy
        ht = bt / 2
        d = _inner_side_distance(cx, cy, tx - a_tr * vx - ht * vy, ty - a_tr * vy + ht * vx,
                                 hx + a_tf * vx - ht * vy, hy + a_tf * vy + ht * vx, -vy, vx)
        np.minimum(best_trl, d, out=best_trl)

    def advance(k: FloatArray, ds: FloatArray) -> None:
        nonlocal psi1, psi2
        old = psi1
        psi1 = advance_articulation(psi1, k, ds, 0.0, l)
        mid = 0.5 * (old + psi1)
        psi2 = advance_articulation(psi2, np.tan(mid) / l, np.cos(mid) * ds, e, lt)

    zero = np.zeros(n_rows)
    measure(zero, zero, zero)
    with np.errstate(divide="ignore", invalid="ignore"):
        k_arc = np.where(R > 0, 1.0 / R, 0.0)
    for i in range(1, n_arc + 1):
        advance(k_arc, ds_arc)
        a = i * ds_arc * k_arc
        measure(R * np.sin(a), R * (1 - np.cos(a)), a)
    ex, ey = R * math.sin(angle), R * (1 - math.cos(angle))
    for i in range(1, n_exit + 1):
        advance(zero, ds_exit)
        s = i * ds_exit
        measure(ex + s * math.cos(angle), ey + s * math.sin(angle), np.full(n_rows, angle))

    nan = np.nan
    towing = np.where(rear, nan, best_tow)
    trailer = np.where(has & ~rear, best_trl, nan)
    return pd.DataFrame(
        {
            "ctr_m": R,
            "inside_radius_m": np.fmin(towing, trailer),
            "towing_inside_radius_m": towing,
            "trailer_inside_radius_m": trailer,
        },
        index=frame.index,
    )
