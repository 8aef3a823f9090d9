r"""A towed unit (semitrailer on a kingpin, trailer on a drawbar) behind a bicycle model.

Derivation of the trailer heading rate
--------------------------------------
Let ``P = (x, y)`` be the towing unit's rear-axle centre, ``theta`` its heading,
``u = (cos theta, sin theta)`` and ``n = (-sin theta, cos theta)``. The rear axle does not
slip sideways, so ``P' = v u`` and ``theta' = (v / l) tan(phi)``. The hitch (kingpin) lies
on the centre line a distance ``e`` behind the rear axle (``e < 0``: ahead of it)::

    H = P - e u          =>   H' = v u - e theta' n

The trailer's axle centre lies ``l_t`` behind the hitch along the trailer heading
``theta_t`` (``u_t``, ``n_t`` as above)::

    T = H - l_t u_t      =>   T' = H' - l_t theta_t' n_t

The trailer axle does not slip sideways either: ``T' . n_t = 0``, hence
``theta_t' = (H' . n_t) / l_t``. With ``u . n_t = sin(theta - theta_t)`` and
``n . n_t = cos(theta - theta_t)``, and the articulation ``psi = theta - theta_t``::

    theta_t' = (v / l_t) (sin psi - (e / l) tan(phi) cos psi)

which is the formula of docs/design.md §5. Per unit distance ``s`` of the rear axle
(``ds = v dt``) and with the tractor's path curvature ``k = tan(phi) / l``, the articulation
obeys an autonomous equation while ``phi`` is held::

    dpsi/ds = k - (sin psi - e k cos psi) / l_t

Steady state
------------
``dpsi/ds = 0`` gives ``rho sin psi - e cos psi = l_t`` with ``rho = 1 / k``. Writing
``rho sin psi - e cos psi = R_h sin(psi - atan2(e, rho))`` with ``R_h = sqrt(rho^2 + e^2)``
(the hitch's radius: it sits ``e`` along the tangent from the rear-axle centre)::

    psi_ss = atan2(e, rho) + asin(l_t / R_h)            (rho > 0; odd in rho)

The trailer axle moves on a circle about the same centre, perpendicular to its radius, so
``R_t^2 + l_t^2 = R_h^2``::

    R_t = sqrt(rho^2 + e^2 - l_t^2)

A steady state exists only when ``l_t < R_h``; beyond it, or when ``|psi|`` exceeds the
trailer's maximum articulation, the combination jackknifes.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["advance_articulation", "hitch_point", "steady_articulation_rad",
           "steady_trailer_radius_m", "trailer_axle_point", "trailer_heading_rate"]

FloatArray = NDArray[np.float64]


def trailer_heading_rate(
    speed_m_s: ArrayLike,
    phi_rad: ArrayLike,
    psi_rad: ArrayLike,
    wheelbase_m: ArrayLike,
    hitch_offset_m: ArrayLike,
    trailer_wheelbase_m: ArrayLike,
) -> FloatArray:
    """Trailer heading rate ``(v / l_t)(sin psi - (e / l) tan(phi) cos psi)`` (rad/s).

    Parameters
    ----------
    speed_m_s
        Rear-axle speed of the towing unit.
    phi_rad
        Towing unit's bicycle-equivalent steering angle.
    psi_rad
        Articulation ``theta - theta_t`` (positive: tractor turned left of the trailer).
    wheelbase_m
        Towing unit's wheelbase ``l``.
    hitch_offset_m
        Hitch behind the rear axle ``e`` (negative ahead of it).
    trailer_wheelbase_m
        Hitch to trailer axle centre ``l_t``.

    Examples
    --------
    Straight and aligned, the trailer keeps its heading:

    >>> float(trailer_heading_rate(2.0, 0.0, 0.0, 4.0, -0.5, 10.0))
    0.0

    A hitch on the rear axle (``e = 0``) makes the trailer turn toward the tractor:

    >>> round(float(trailer_heading_rate(2.0, 0.0, np.pi / 2, 4.0, 0.0, 10.0)), 12)
    0.2
    """
    psi = np.asarray(psi_rad, dtype=np.float64)
    k = np.tan(np.asarray(phi_rad, dtype=np.float64)) / np.asarray(wheelbase_m, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    v = np.asarray(speed_m_s, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    return (v / lt) * (np.sin(psi) - e * k * np.cos(psi))


def _dpsi_ds(psi: FloatArray, k: FloatArray, e: FloatArray, lt: FloatArray) -> FloatArray:
    return k - (np.sin(psi) - e * k * np.cos(psi)) / lt


def advance_articulation(
    psi_rad: ArrayLike,
    curvature_1_m: ArrayLike,
    ds_m: ArrayLike,
    hitch_offset_m: ArrayLike,
    trailer_wheelbase_m: ArrayLike,
    substeps: int = 1,
) -> FloatArray:
    """Advance the articulation while the tractor's rear axle travels ``ds`` on one arc.

    Classical fourth-order Runge-Kutta on ``dpsi/ds = k - (sin psi - e k cos psi) / l_t``
    (see the module docstring), ``substeps`` equal sub-steps. The equation is autonomous
    while the steering is held, so a steady state of the equation is a fixed point of the
    update: steady-state runs converge to the closed form, not to a discretisation of it.
    The local error is ``O((ds / l_t)^5)``; one sub-step per 0.1 m is ample for
    ``l_t`` of a metre or more.

    Examples
    --------
    Straight ahead and aligned, nothing changes:

    >>> float(advance_articulation(0.0, 0.0, 0.1, -0.5, 10.0))
    0.0

    Straight ahead, an articulation decays as ``tan(psi/2) ~ exp(-s / l_t)``:

    >>> psi = advance_articulation(0.5, 0.0, 10.0, 0.0, 10.0, substeps=100)
    >>> round(float(np.tan(psi / 2) / np.tan(0.25)), 6), round(float(np.exp(-1.0)), 6)
    (0.367879, 0.367879)
    """
    if substeps < 1:
        raise ValueError(f"advance_articulation: substeps must be >= 1, got {substeps!r}")
    psi = np.asarray(psi_rad, dtype=np.float64)
    k = np.asarray(curvature_1_m, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    h = np.asarray(ds_m, dtype=np.float64) / substeps
    for _ in range(substeps):
        k1 = _dpsi_ds(psi, k, e, lt)
        k2 = _dpsi_ds(psi + 0.5 * h * k1, k, e, lt)
        k3 = _dpsi_ds(psi + 0.5 * h * k2, k, e, lt)
        k4 = _dpsi_ds(psi + h * k3, k, e, lt)
        psi = psi + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return psi


def hitch_point(
    x_m: ArrayLike, y_m: ArrayLike, theta_rad: ArrayLike, hitch_offset_m: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Hitch position, ``e`` behind the rear-axle centre on the towing unit's centre line.

    Examples
    --------
    >>> hx, hy = hitch_point(10.0, 5.0, 0.0, 1.0)
    >>> float(hx), float(hy)
    (9.0, 5.0)
    """
    theta = np.asarray(theta_rad, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    return (np.asarray(x_m, dtype=np.float64) - e * np.cos(theta),
            np.asarray(y_m, dtype=np.float64) - e * np.sin(theta))


def trailer_axle_point(
    x_m: ArrayLike,
    y_m: ArrayLike,
    theta_rad: ArrayLike,
    trailer_theta_rad: ArrayLike,
    hitch_offset_m: ArrayLike,
    trailer_wheelbase_m: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Trailer axle centre from the tractor's rear-axle state and the trailer heading.

    Examples
    --------
    Straight and aligned, the axle is ``e + l_t`` behind the tractor's rear axle:

    >>> tx, ty = trailer_axle_point(0.0, 0.0, 0.0, 0.0, -0.5, 10.0)
    >>> float(tx), float(ty)
    (-9.5, 0.0)
    """
    hx, hy = hitch_point(x_m, y_m, theta_rad, hitch_offset_m)
    tt = np.asarray(trailer_theta_rad, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    return hx - lt * np.cos(tt), hy - lt * np.sin(tt)


def steady_articulation_rad(
    rho_m: ArrayLike, hitch_offset_m: ArrayLike, trailer_wheelbase_m: ArrayLike
) -> FloatArray:
    """Steady-state articulation ``psi_ss = atan2(e, |rho|) + asin(l_t / sqrt(rho^2 + e^2))``.

    Signed like ``rho`` (left turns positive); ``inf`` radius (straight) gives 0; NaN where
    no steady state exists (``l_t >= sqrt(rho^2 + e^2)``: the trailer jackknifes).

    Examples
    --------
    >>> float(steady_articulation_rad(np.inf, -0.5, 10.0))
    0.0
    >>> round(float(np.degrees(steady_articulation_rad(10.0, 0.0, 5.0))), 9)
    30.0
    >>> round(float(np.degrees(steady_articulation_rad(-10.0, 0.0, 5.0))), 9)
    -30.0
    """
    rho = np.asarray(rho_m, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    r = np.abs(rho)
    with np.errstate(invalid="ignore", divide="ignore"):
        rh = np.hypot(r, e)
        ratio = np.where(rh > lt, lt / rh, np.nan)
        psi = np.arctan2(e, r) + np.arcsin(ratio)
    psi = np.where(np.isinf(r), 0.0, psi)
    out: FloatArray = np.sign(rho) * psi
    return out


def steady_trailer_radius_m(
    rho_m: ArrayLike, hitch_offset_m: ArrayLike, trailer_wheelbase_m: ArrayLike
) -> FloatArray:
    """Steady-state radius of the trailer axle centre, ``sqrt(rho^2 + e^2 - l_t^2)``.

    Unsigned; NaN where no steady state exists.

    Examples
    --------
    >>> float(steady_trailer_radius_m(13.0, 0.0, 5.0))
    12.0
    >>> float(steady_trailer_radius_m(3.0, 0.0, 5.0))
    nan
    """
    rho = np.asarray(rho_m, dtype=np.float64)
    e = np.asarray(hitch_offset_m, dtype=np.float64)
    lt = np.asarray(trailer_wheelbase_m, dtype=np.float64)
    sq = rho * rho + e * e - lt * lt
    with np.errstate(invalid="ignore"):
        return np.where(sq > 0, np.sqrt(np.where(sq > 0, sq, 0.0)), np.nan)
