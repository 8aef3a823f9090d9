"""Kinematic bicycle model: exact arc steps, explicit Euler, steering limits, speed profiles.

The model (rear-axle reference, front axle steered)::

    x' = v cos(theta),   y' = v sin(theta),   theta' = (v / l) tan(phi)

with ``(x, y)`` the rear-axle centre, ``theta`` the heading (rad, counter-clockwise from +x),
``v`` the rear-axle speed, ``l`` the wheelbase and ``phi`` the bicycle-equivalent steering
angle at the front-axle centre (left turns positive). Holding ``v`` and ``phi`` constant over
a step, the rear-axle centre moves on a circular arc of signed radius ``rho = l / tan(phi)``
(a straight line when ``phi = 0``); :func:`arc_step` integrates that arc exactly, so a run at
constant lock closes its circle. A steering wheel turns at a finite rate: over a step of the
path follower the steering ramps linearly from its value at the step's start to the new one,
and :func:`ramp_step` integrates that step to second order (Simpson's rule for the turn, one
arc for the position; exact when the steering is held). :func:`euler_step` is kept only to
reproduce the explicit Euler exercise of the robotics article (its points lie on a circle of radius
``ds / (2 sin(k ds / 2))``, slightly too large, whose centre is shifted by ``ds / 2``).

Every function works on numpy arrays: one element per vehicle, so a whole batch advances in
one call. Scalars broadcast.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["CRAWL_SPEED_M_S", "SpeedProfile", "arc_step", "as_speed_profile",
           "curvature_from_steer", "euler_step", "integrate", "limit_steering", "ramp_arc",
           "ramp_step"]

CRAWL_SPEED_M_S = 2.0
"""Default speed of the steering point for design checks (walking pace, no dynamics)."""

FloatArray = NDArray[np.float64]


def curvature_from_steer(phi_rad: ArrayLike, wheelbase_m: ArrayLike) -> FloatArray:
    """Curvature of the rear-axle centre's path, ``tan(phi) / l`` (1/m, left positive).

    Examples
    --------
    >>> float(curvature_from_steer(0.0, 3.0))           # straight ahead
    0.0
    >>> round(float(curvature_from_steer(math.atan(0.5), 3.0)), 6)  # rho = 6 m
    0.166667
    """
    return np.tan(np.asarray(phi_rad, dtype=np.float64)) / np.asarray(wheelbase_m, dtype=np.float64)


def arc_step(
    x_m: ArrayLike,
    y_m: ArrayLike,
    theta_rad: ArrayLike,
    speed_m_s: ArrayLike,
    phi_rad: ArrayLike,
    wheelbase_m: ArrayLike,
    dt_s: ArrayLike,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Advance the rear-axle state exactly over one step of constant speed and steering.

    The rear-axle centre travels ``ds = v dt`` along an arc of curvature
    ``k = tan(phi) / l``; the heading turns by ``k ds``. The chord is written with
    ``sinc`` so that ``phi -> 0`` gives the straight line without a division by zero::

        x1 = x0 + ds cos(theta0 + k ds / 2) sinc(k ds / 2)
        y1 = y0 + ds sin(theta0 + k ds / 2) sinc(k ds / 2)

    Parameters
    ----------
    x_m, y_m, theta_rad
        Rear-axle centre and heading at the start of the step.
    speed_m_s
        Rear-axle speed (negative reverses along the same arc).
    phi_rad
        Bicycle-equivalent steering angle, held over the step.
    wheelbase_m
        Wheelbase ``l``.
    dt_s
        Step length in seconds.

    Returns
    -------
    x_m, y_m, theta_rad
        State at the end of the step (heading not wrapped).

    Examples
    --------
    Straight ahead moves along the heading:

    >>> x, y, th = arc_step(0.0, 0.0, 0.0, 2.0, 0.0, 3.0, 0.5)
    >>> float(x), float(y), float(th)
    (1.0, 0.0, 0.0)

    A quarter of the circle of radius ``rho = l / tan(phi) = 6 m`` ends at (6, 6):

    >>> phi = math.atan(3.0 / 6.0)
    >>> x, y, th = arc_step(0.0, 0.0, 0.0, 1.0, phi, 3.0, 6.0 * math.pi / 2)
    >>> round(float(x), 9), round(float(y), 9), round(float(th), 9)
    (6.0, 6.0, 1.570796327)
    """
    x = np.asarray(x_m, dtype=np.float64)
    y = np.asarray(y_m, dtype=np.float64)
    theta = np.asarray(theta_rad, dtype=np.float64)
    ds = np.asarray(speed_m_s, dtype=np.float64) * np.asarray(dt_s, dtype=np.float64)
    dtheta = curvature_from_steer(phi_rad, wheelbase_m) * ds
    half = 0.5 * dtheta
    chord = ds * np.sinc(half / np.pi)
    mid = theta + half
    return x + chord * np.cos(mid), y + chord * np.sin(mid), theta + dtheta


def ramp_arc(
    phi0_rad: ArrayLike,
    phi1_rad: ArrayLike,
    wheelbase_m: ArrayLike,
    distance_m: ArrayLike,
    front_steered: ArrayLike = True,
) -> tuple[FloatArray, FloatArray]:
    """Reference-axle travel and heading change over a step whose steering ramps linearly.

    Over the step the steering point (the front-axle centre) travels ``distance_m`` at a
    constant speed while the steering moves linearly in time from ``phi0`` to ``phi1`` (a
    wheel turned at a finite rate, not a wheel that jumps at the step's start). For a
    front-steered vehicle the reference (rear) axle moves ``cos(phi)`` as fast as the front
    axle and the body turns at ``v_f sin(phi) / l``; for a rear-steered one the reference
    axle is the front axle itself and the body turns at ``v_f tan(phi) / l``. Both
    integrals are taken by Simpson's rule over the ramp (``phi_m`` its middle)::

        ds = d (f(phi0) + 4 f(phi_m) + f(phi1)) / 6,   f = cos (front-steered) or 1
        dtheta = d (g(phi0) + 4 g(phi_m) + g(phi1)) / (6 l),   g = sin or tan

    The step is then the arc of length ``ds`` turning by ``dtheta``
    (:func:`ramp_step`): the steering acts at the step's middle, so the integration is
    second order in the time step, where holding ``phi0`` over the step is first order.

    Returns
    -------
    ds_m, dtheta_rad
        Distance travelled by the reference axle's centre and the heading change.

    Examples
    --------
    A held steering (``phi0 == phi1``) gives the exact arc of :func:`arc_step`:

    >>> ds, dth = ramp_arc(0.3, 0.3, 3.0, 2.0)
    >>> bool(np.isclose(ds, 2.0 * math.cos(0.3))), bool(np.isclose(dth, ds * math.tan(0.3) / 3))
    (True, True)

    Straight ahead (the degenerate case) nothing turns:

    >>> [float(v) for v in ramp_arc(0.0, 0.0, 3.0, 1.5, front_steered=False)]
    [1.5, 0.0]
    """
    p0 = np.asarray(phi0_rad, dtype=np.float64)
    p1 = np.asarray(phi1_rad, dtype=np.float64)
    pm = 0.5 * (p0 + p1)
    d = np.asarray(distance_m, dtype=np.float64)
    l = np.asarray(wheelbase_m, dtype=np.float64)  # noqa: E741
    front = np.asarray(front_steered, dtype=bool)

    def simpson(f: Callable[[FloatArray], FloatArray]) -> FloatArray:
        return (f(p0) + 4.0 * f(pm) + f(p1)) / 6.0

    ds = np.where(front, d * simpson(np.cos), d)
    dtheta = np.where(front, d * simpson(np.sin), d * simpson(np.tan)) / l
    return ds, dtheta


def ramp_step(
    x_m: ArrayLike,
    y_m: ArrayLike,
    theta_rad: ArrayLike,
    distance_m: ArrayLike,
    phi0_rad: ArrayLike,
    phi1_rad: ArrayLike,
    wheelbase_m: ArrayLike,
    front_steered: ArrayLike = True,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Advance the reference-axle state over a step whose steering ramps from phi0 to phi1.

    ``distance_m`` is the steering point's travel (front-axle speed times the step); see
    :func:`ramp_arc` for the travel and turn of the reference axle, which then follows one
    arc. Exact for a held steering; second order in the step for a ramp.

    Examples
    --------
    Held steering: the rear axle of a front-steered vehicle, whose front axle moves
    ``d``, goes ``d cos(phi)`` along the arc of radius ``l / tan(phi)``:

    >>> x, y, th = ramp_step(0.0, 0.0, 0.0, 1.0, 0.2, 0.2, 3.0)
    >>> xa, ya, tha = arc_step(0.0, 0.0, 0.0, math.cos(0.2), 0.2, 3.0, 1.0)
    >>> bool(np.allclose([x, y, th], [xa, ya, tha]))
    True

    Straight ahead:

    >>> [float(v) for v in ramp_step(0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 3.0)]
    [2.0, 0.0, 0.0]
    """
    ds, dtheta = ramp_arc(phi0_rad, phi1_rad, wheelbase_m, distance_m, front_steered)
    theta = np.asarray(theta_rad, dtype=np.float64)
    half = 0.5 * dtheta
    chord = ds * np.sinc(half / np.pi)
    mid = theta + half
    return (np.asarray(x_m, dtype=np.float64) + chord * np.cos(mid),
            np.asarray(y_m, dtype=np.float64) + chord * np.sin(mid), theta + dtheta)


def euler_step(
    x_m: ArrayLike,
    y_m: ArrayLike,
    theta_rad: ArrayLike,
    speed_m_s: ArrayLike,
    phi_rad: ArrayLike,
    wheelbase_m: ArrayLike,
    dt_s: ArrayLike,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """One explicit Euler step of the bicycle model (for the robotics-article exercise only).

    Same arguments as :func:`arc_step`. The position moves along the heading at the start of
    the step, so a constant-lock run traces equal chords turning by equal angles: a circle of
    radius ``ds / (2 sin(k ds / 2))`` instead of ``1 / k``, its centre shifted by ``ds / 2``.

    Examples
    --------
    Straight ahead, Euler and the exact arc agree:

    >>> x, y, th = euler_step(0.0, 0.0, 0.0, 2.0, 0.0, 3.0, 0.5)
    >>> float(x), float(y), float(th)
    (1.0, 0.0, 0.0)

    Turning, the position ignores the rotation within the step:

    >>> x, y, th = euler_step(0.0, 0.0, 0.0, 1.0, math.atan(0.5), 3.0, 1.0)
    >>> float(x), float(y), round(float(th), 6)
    (1.0, 0.0, 0.166667)
    """
    x = np.asarray(x_m, dtype=np.float64)
    y = np.asarray(y_m, dtype=np.float64)
    theta = np.asarray(theta_rad, dtype=np.float64)
    ds = np.asarray(speed_m_s, dtype=np.float64) * np.asarray(dt_s, dtype=np.float64)
    dtheta = curvature_from_steer(phi_rad, wheelbase_m) * ds
    return x + ds * np.cos(theta), y + ds * np.sin(theta), theta + dtheta


def integrate(
    x0_m: ArrayLike,
    y0_m: ArrayLike,
    theta0_rad: ArrayLike,
    speed_m_s: ArrayLike,
    phi_rad: ArrayLike,
    wheelbase_m: ArrayLike,
    dt_s: float,
    n_steps: int,
    method: Literal["arc", "euler"] = "arc",
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Drive at constant speed and steering for ``n_steps`` steps (open loop).

    Parameters
    ----------
    x0_m, y0_m, theta0_rad
        Initial rear-axle states, one per vehicle (scalars broadcast).
    speed_m_s, phi_rad, wheelbase_m
        Rear-axle speed, steering angle and wheelbase, one per vehicle.
    dt_s
        Step length (s), > 0.
    n_steps
        Number of steps, >= 0.
    method
        ``"arc"`` (exact) or ``"euler"`` (explicit Euler).

    Returns
    -------
    x_m, y_m, theta_rad
        Arrays of shape ``(n_steps + 1,) + broadcast shape``, row 0 the initial state.

    Examples
    --------
    Straight ahead for 10 steps of 0.1 s at 1 m/s:

    >>> x, y, th = integrate(0.0, 0.0, 0.0, 1.0, 0.0, 2.5, 0.1, 10)
    >>> round(float(x[-1]), 12), float(y[-1])
    (1.0, 0.0)

    Zero steps returns the initial state only:

    >>> integrate(1.0, 2.0, 0.0, 1.0, 0.2, 2.5, 0.1, 0)[0].shape
    (1,)
    """
    if not dt_s > 0 or not math.isfinite(dt_s):
        raise ValueError(f"integrate: time step dt_s must be a positive number, got {dt_s!r}")
    if n_steps < 0:
        raise ValueError(f"integrate: n_steps must be >= 0, got {n_steps!r}")
    step = {"arc": arc_step, "euler": euler_step}.get(method)
    if step is None:
        raise ValueError(f"integrate: method must be 'arc' or 'euler', got {method!r}")
    x, y, th, v, phi, wb = np.broadcast_arrays(
        *(np.asarray(a, dtype=np.float64) for a in (x0_m, y0_m, theta0_rad, speed_m_s, phi_rad,
                                                 wheelbase_m))
    )
    out = np.empty((3, n_steps + 1) + x.shape)
    out[0, 0], out[1, 0], out[2, 0] = x, y, th
    for k in range(n_steps):
        out[0, k + 1], out[1, k + 1], out[2, k + 1] = step(
            out[0, k], out[1, k], out[2, k], v, phi, wb, dt_s
        )
    return out[0], out[1], out[2]


def limit_steering(
    phi_prev_rad: ArrayLike,
    phi_cmd_rad: ArrayLike,
    max_steer_rad: ArrayLike,
    max_steer_rate_rad_s: ArrayLike,
    dt_s: ArrayLike,
) -> FloatArray:
    """Apply the steering-rate limit, then the lock, to a commanded steering angle.

    ``|phi - phi_prev| <= max_steer_rate * dt`` and ``|phi| <= max_steer``. An infinite
    rate means no rate limit.

    Examples
    --------
    Nothing to limit when driving straight:

    >>> float(limit_steering(0.0, 0.0, 0.6, 0.4, 0.05))
    0.0

    The rate allows 0.02 rad per step of 0.05 s, the lock stops at 0.6 rad:

    >>> round(float(limit_steering(0.1, 0.5, 0.6, 0.4, 0.05)), 12)
    0.12
    >>> float(limit_steering(0.59, 0.9, 0.6, math.inf, 0.05))
    0.6
    """
    prev = np.asarray(phi_prev_rad, dtype=np.float64)
    max_change = (np.asarray(max_steer_rate_rad_s, dtype=np.float64)
                  * np.asarray(dt_s, dtype=np.float64))
    lock = np.asarray(max_steer_rad, dtype=np.float64)
    # np.minimum / np.maximum: np.clip's overhead dominates on the model's small arrays
    change = np.minimum(np.maximum(np.asarray(phi_cmd_rad, dtype=np.float64) - prev, -max_change),
                        max_change)
    return np.minimum(np.maximum(prev + change, -lock), lock)


@dataclass(frozen=True)
class SpeedProfile:
    """Speed of the steering point (front-axle centre) as a function of station or time.

    Linear interpolation between breakpoints, constant beyond the first and last one.

    Attributes
    ----------
    by
        ``"station"`` (breakpoints are arc lengths along the path, m) or ``"time"`` (s).
    at
        Increasing breakpoints.
    speed_m_s
        Speed at each breakpoint, all > 0 (the design check drives forward).

    Examples
    --------
    >>> p = SpeedProfile.constant(2.0)
    >>> float(p.speed(station_m=35.0, time_s=3.0))
    2.0
    >>> q = SpeedProfile("station", (0.0, 10.0), (4.0, 2.0))
    >>> float(q.speed(station_m=5.0, time_s=0.0)), float(q.min_speed_m_s)
    (3.0, 2.0)
    """

    by: Literal["station", "time"]
    at: tuple[float, ...]
    speed_m_s: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.by not in ("station", "time"):
            raise ValueError(f"speed profile: 'by' must be 'station' or 'time', got {self.by!r}")
        at = np.asarray(self.at, dtype=np.float64)
        v = np.asarray(self.speed_m_s, dtype=np.float64)
        if at.ndim != 1 or at.shape != v.shape or at.size == 0:
            raise ValueError(
                f"speed profile: breakpoints and speeds must be equal-length, non-empty "
                f"lists, got {at.size} breakpoints and {v.size} speeds"
            )
        if not (np.all(np.isfinite(at)) and np.all(np.isfinite(v))):
            raise ValueError("speed profile: breakpoints and speeds must be finite numbers")
        if np.any(np.diff(at) <= 0):
            raise ValueError(f"speed profile: breakpoints must increase strictly, got {self.at}")
        if np.any(v <= 0):
            raise ValueError(
                "speed profile: every speed must be > 0 m/s (forward driving), "
                f"got {self.speed_m_s}"
            )

    @classmethod
    def constant(cls, speed_m_s: float = CRAWL_SPEED_M_S) -> SpeedProfile:
        """A constant speed (default: crawl speed for design checks)."""
        return cls("station", (0.0,), (float(speed_m_s),))

    @property
    def min_speed_m_s(self) -> float:
        """Lowest speed of the profile (bounds the number of steps of a run)."""
        return float(min(self.speed_m_s))

    @property
    def max_speed_m_s(self) -> float:
        """Highest speed of the profile."""
        return float(max(self.speed_m_s))

    def speed(self, station_m: ArrayLike, time_s: ArrayLike) -> FloatArray:
        """Speed (m/s) at the given stations or times (whichever ``by`` names)."""
        where = station_m if self.by == "station" else time_s
        return np.interp(np.asarray(where, dtype=np.float64), self.at, self.speed_m_s)


def as_speed_profile(speed: float | SpeedProfile) -> SpeedProfile:
    """Accept a constant speed (m/s) or a :class:`SpeedProfile`.

    Examples
    --------
    >>> as_speed_profile(1.5).speed_m_s
    (1.5,)
    """
    if isinstance(speed, SpeedProfile):
        return speed
    try:
        value = float(speed)
    except (TypeError, ValueError):
        raise ValueError(
            f"speed must be a number in m/s or a SpeedProfile, got {speed!r}"
        ) from None
    if not math.isfinite(value):
        raise ValueError(f"speed must be a finite number in m/s, got {speed!r}")
    return SpeedProfile.constant(value)
