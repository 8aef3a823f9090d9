"""The steering lock in its four published forms, and the radius it gives.

A spec sheet publishes a turning circle, a design manual a centre-line turning radius
(CTR), a steering drawing the inner wheel's angle. Each fixes ``rho``, the radius of the
unsteered axle's centre at full lock (the rear axle for front steering), through the
docs/design.md §4 relations. All functions are vectorised over numpy arrays.

Symbols: ``l`` wheelbase, ``w`` steered-axle track, ``B`` body width, ``a_s`` the body
overhang beyond the steered axle (the front overhang for a front-steered vehicle).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def rho_from_ctr(ctr_m: ArrayLike, wheelbase_m: ArrayLike) -> FloatArray:
    """Rear-axle radius from the steered-axle centre's radius: ``sqrt(CTR^2 - l^2)``.

    NaN when ``CTR <= l`` (impossible).

    Examples
    --------
    >>> round(float(rho_from_ctr(21.0, 11.0)), 3)        # AASHTO P car, feet
    17.889
    >>> float(rho_from_ctr(11.0, 11.0))                   # degenerate: steered axle at 90°
    0.0
    """
    c = np.asarray(ctr_m, dtype=float)
    l = np.asarray(wheelbase_m, dtype=float)  # noqa: E741
    with np.errstate(invalid="ignore"):
        return np.sqrt(c**2 - l**2)


def rho_from_curb_to_curb(
    diameter_m: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike
) -> FloatArray:
    """Rear-axle radius from the curb-to-curb diameter (outer steered wheel's path).

    ``D/2 = sqrt((rho + w/2)^2 + l^2)`` (SAE J695).

    Examples
    --------
    >>> round(float(rho_from_curb_to_curb(2 * np.hypot(5.0 + 0.75, 2.7), 2.7, 1.5)), 12)
    5.0
    """
    d = np.asarray(diameter_m, dtype=float)
    l = np.asarray(wheelbase_m, dtype=float)  # noqa: E741
    with np.errstate(invalid="ignore"):
        return np.sqrt((d / 2) ** 2 - l**2) - np.asarray(track_m, dtype=float) / 2


def rho_from_wall_to_wall(
    diameter_m: ArrayLike, wheelbase_m: ArrayLike, width_m: ArrayLike, overhang_m: ArrayLike
) -> FloatArray:
    """Rear-axle radius from the wall-to-wall diameter (outer front corner's path).

    ``D/2 = sqrt((rho + B/2)^2 + (l + a_s)^2)``.

    Examples
    --------
    >>> round(float(rho_from_wall_to_wall(2 * np.hypot(5.0 + 0.9, 2.7 + 0.9), 2.7, 1.8, 0.9)), 12)
    5.0
    """
    d = np.asarray(diameter_m, dtype=float)
    reach = np.asarray(wheelbase_m, dtype=float) + np.asarray(overhang_m, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.sqrt((d / 2) ** 2 - reach**2) - np.asarray(width_m, dtype=float) / 2


def rho_from_bicycle(phi: ArrayLike, wheelbase_m: ArrayLike) -> FloatArray:
    """Rear-axle radius ``l / tan(phi)``; infinite when straight ahead.

    Examples
    --------
    >>> float(rho_from_bicycle(0.0, 2.7))
    inf
    """
    phi = np.asarray(phi, dtype=float)
    with np.errstate(divide="ignore"):
        return np.asarray(wheelbase_m, dtype=float) / np.tan(np.abs(phi))


def solve_increasing(
    f: Callable[[FloatArray], FloatArray], target: ArrayLike, lo: float, hi: float,
    iterations: int = 60,
) -> FloatArray:
    """Vectorised bisection: ``x`` in ``[lo, hi]`` with ``f(x) = target``, ``f`` increasing.

    NaN where the target lies outside ``[f(lo), f(hi)]``.

    Examples
    --------
    >>> round(float(solve_increasing(np.sin, 0.5, 0.0, 1.5)), 12) == round(np.pi / 6, 12)
    True
    >>> abs(float(solve_increasing(np.sin, 0.0, 0.0, 1.5))) < 1e-15     # degenerate: zero
    True
    """
    t = np.asarray(target, dtype=float)
    a = np.full(t.shape, lo)
    b = np.full(t.shape, hi)
    f_lo, f_hi = f(a), f(b)
    bad = ~((t >= f_lo) & (t <= f_hi))
    for _ in range(iterations):
        m = (a + b) / 2
        below = f(m) < t
        a = np.where(below, m, a)
        b = np.where(below, b, m)
    x = (a + b) / 2
    return np.where(bad, np.nan, x)
