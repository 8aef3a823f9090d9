"""The paper's one-parameter control law: the Ackermann angle and the path it gives.

The control parameter is the Ackermann angle ``theta = delta_i - delta_o`` (inner minus
outer wheel angle) of an ideal Ackermann vehicle (the paper on invariant equations linking
the control of a vehicle, the Ackermann angle, to the trajectory of its movement: eqs. 1, 3
and 4):

- eq. 1: ``rho(theta) = l sqrt((w / 2l)^2 - 1 + (w / l) cot(theta))``, the radius of the
  rear-axle centre;
- eq. 3: ``theta(rho) = acot((rho^2 + l^2 - w^2 / 4) / (l w))``;
- eq. 4: the safe-pathway width ``dR = sqrt((rho + B/2)^2 + (l + a)^2) - (rho - B/2)``, with
  the body width ``B`` where the paper has the track ``w``.

Signed: a left turn has ``theta > 0`` and ``rho > 0``. Straight ahead, ``theta = 0`` and
``rho`` is infinite. Vectorised over numpy arrays.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def rho_of_theta(theta: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike) -> FloatArray:
    """Radius of the rear-axle centre for an Ackermann angle (paper eq. 1).

    Examples
    --------
    >>> float(rho_of_theta(0.0, 2.7, 1.5))                 # straight ahead
    inf
    >>> rho = 5.0; l, w = 2.7, 1.5
    >>> th = theta_of_rho(rho, l, w)
    >>> round(float(rho_of_theta(th, l, w)), 9)
    5.0
    """
    th = np.asarray(theta, dtype=float)
    l = np.asarray(wheelbase_m, dtype=float)  # noqa: E741
    w = np.asarray(track_m, dtype=float)
    a = np.abs(th)
    with np.errstate(divide="ignore", invalid="ignore"):
        cot = np.cos(a) / np.sin(a)
        rho = np.sign(th) * l * np.sqrt((w / (2 * l)) ** 2 - 1 + (w / l) * cot)
    return np.where(a == 0, np.inf, rho)


def theta_of_rho(rho: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike) -> FloatArray:
    """Ackermann angle giving a rear-axle radius ``rho`` (paper eq. 3).

    Examples
    --------
    >>> float(theta_of_rho(np.inf, 2.7, 1.5))             # straight ahead
    0.0
    >>> import math
    >>> th = theta_of_rho(-5.0, 2.7, 1.5)                  # a right turn mirrors a left
    >>> bool(math.isclose(float(th), -float(theta_of_rho(5.0, 2.7, 1.5))))
    True
    """
    r = np.asarray(rho, dtype=float)
    l = np.asarray(wheelbase_m, dtype=float)  # noqa: E741
    w = np.asarray(track_m, dtype=float)
    a = np.abs(r)
    with np.errstate(invalid="ignore"):
        th = np.arctan2(l * w, a**2 + l**2 - w**2 / 4)
    return np.where(np.isinf(a), 0.0, np.sign(r) * th)


def safe_pathway(
    rho: ArrayLike, wheelbase_m: ArrayLike, width_m: ArrayLike, overhang_m: ArrayLike
) -> FloatArray:
    """Steady-state swept width ``sqrt((rho + B/2)^2 + (l + a)^2) - (rho - B/2)`` (eq. 4).

    ``a`` is the overhang beyond the steered axle (the front overhang for front steering).
    Straight ahead (``rho`` infinite) the width is the body width.

    Examples
    --------
    >>> float(safe_pathway(np.inf, 2.7, 1.8, 0.9))        # straight ahead
    1.8
    >>> round(float(safe_pathway(5.0, 2.7, 1.8, 0.9)), 4)
    2.8116
    """
    r = np.abs(np.asarray(rho, dtype=float))
    B = np.asarray(width_m, dtype=float)
    reach = np.asarray(wheelbase_m, dtype=float) + np.asarray(overhang_m, dtype=float)
    with np.errstate(invalid="ignore"):
        # Written as a difference of squares over a sum: exact for very large rho.
        outer = np.sqrt((r + B / 2) ** 2 + reach**2)
        width = ((r + B / 2) ** 2 + reach**2 - (r - B / 2) ** 2) / (outer + (r - B / 2))
    return np.where(np.isinf(r), B, width)


def safe_pathway_of_theta(
    theta: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike, width_m: ArrayLike,
    overhang_m: ArrayLike,
) -> FloatArray:
    """Safe-pathway width as a function of the Ackermann angle (eq. 4 with eq. 1).

    Examples
    --------
    >>> float(safe_pathway_of_theta(0.0, 2.7, 1.5, 1.8, 0.9))
    1.8
    """
    return safe_pathway(rho_of_theta(theta, wheelbase_m, track_m), wheelbase_m, width_m,
                        overhang_m)
