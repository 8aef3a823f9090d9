"""Steering mechanisms: from the steering-wheel angle to the road-wheel angles.

Conventions (docs/design.md §3–§4): angles in radians, a left turn is positive. The *inner*
wheel is the one nearer the turning centre (the left wheel in a left turn). The
bicycle-equivalent angle ``phi`` is the angle of a single wheel at the steered-axle centre
giving the same path curvature, ``kappa = tan(phi) / wheelbase``. For ideal Ackermann
steering it is exact; for mechanisms whose wheels disagree on the turning centre
(parallel, part-Ackermann, rack-and-pinion) it is the paper's mean-cotangent angle
``cot(phi) = (cot(delta_i) + cot(delta_o)) / 2``.

Mechanisms (the reference page of a commercial "Kinematic Steering" block):

- steering ratio ``gamma``: road-wheel angle = steering-wheel angle / gamma; constant or a
  :class:`Breakpoints` table over the steering-wheel angle;
- steering range (default ±1.25π) and deadband applied to the steering-wheel input;
- Ackermann with percent Ackermann ``p`` (constant or table):
  ``delta_o = delta_i - p (delta_i - delta_o_ideal)``; ``p = 100 %`` is ideal, ``0 %`` parallel;
- parallel: both wheels at the steering-wheel angle / gamma;
- rack-and-pinion (:class:`RackPinion`): rack travel ``r * delta_in`` moving two tie rods;
- front or rear steered axle (a rear-steered vehicle turns left with its wheels to the right).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from clearance.vehicles.errors import InputError

__all__ = ["Breakpoints", "RackPinion", "Schedule", "Steering", "WheelAngles", "ackermann_angles",
           "angle_from_curvature", "bicycle_from_inner", "curvature_from_angle",
           "equivalent_bicycle", "evaluate", "ideal_outer_from_inner"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Breakpoints:
    """A 1-D look-up table with linear interpolation, holding the end values outside.

    Examples
    --------
    >>> table = Breakpoints.parse("-360:13.5; 0:13; 360:13.5", x_scale=math.pi / 180)
    >>> float(table(0.0)), round(float(table(math.pi)), 3)
    (13.0, 13.25)
    """

    x: tuple[float, ...]
    y: tuple[float, ...]

    def __post_init__(self) -> None:
        if len(self.x) != len(self.y) or len(self.x) < 2:
            raise InputError("a look-up table needs at least two 'x:y' breakpoints")
        if any(b <= a for a, b in zip(self.x, self.x[1:], strict=False)):
            raise InputError(f"look-up table breakpoints must increase strictly: {self.x}")

    @classmethod
    def parse(cls, text: str, x_scale: float = 1.0) -> Breakpoints:
        """Read ``"x:y; x:y; ..."``; ``x`` is multiplied by ``x_scale`` (degrees to radians)."""
        xs: list[float] = []
        ys: list[float] = []
        for item in text.replace(",", ";").split(";"):
            item = item.strip()
            if not item:
                continue
            try:
                a, b = item.split(":")
                xs.append(float(a) * x_scale)
                ys.append(float(b))
            except ValueError:
                raise InputError(f"bad look-up table entry {item!r}: expected 'x:y'") from None
        return cls(tuple(xs), tuple(ys))

    def __call__(self, x: ArrayLike) -> FloatArray:
        return np.interp(np.asarray(x, dtype=np.float64), self.x, self.y)


Schedule = float | Breakpoints
"""A parameter that is either constant or a table over the steering-wheel angle."""


def evaluate(value: Schedule, x: ArrayLike) -> FloatArray:
    """Evaluate a constant or a :class:`Breakpoints` table at ``x``.

    Examples
    --------
    >>> float(evaluate(16.0, 0.3))
    16.0
    """
    x = np.asarray(x, dtype=np.float64)
    if isinstance(value, Breakpoints):
        return value(x)
    return np.full_like(x, float(value))


class WheelAngles(NamedTuple):
    """Road-wheel angles (rad) for a steering input; arrays of one shape."""

    left: FloatArray
    right: FloatArray
    inner: FloatArray
    outer: FloatArray
    bicycle: FloatArray


def ackermann_angles(
    phi: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Ideal Ackermann inner and outer wheel angles for a bicycle angle ``phi``.

    ``delta_i = atan(2 l sin(phi) / (2 l cos(phi) - w sin(phi)))`` and the same with ``+ w``
    for the outer wheel: exact at ``phi = 0`` where the cotangent form is undefined. Signed:
    both follow the sign of ``phi``; ``|inner| >= |outer|``.

    Examples
    --------
    >>> i, o = ackermann_angles(0.0, 2.7, 1.5)          # straight ahead
    >>> float(i), float(o)
    (0.0, 0.0)
    >>> i, o = ackermann_angles(0.3, 2.7, 1.5)
    >>> bool(abs(1 / np.tan(o) - 1 / np.tan(i) - 1.5 / 2.7) < 1e-12)   # Ackermann condition
    True
    """
    phi = np.asarray(phi, dtype=np.float64)
    l = np.asarray(wheelbase_m, dtype=np.float64)  # noqa: E741
    w = np.asarray(track_m, dtype=np.float64)
    a = np.abs(phi)
    s = np.sign(phi)
    inner = np.arctan2(2 * l * np.sin(a), 2 * l * np.cos(a) - w * np.sin(a))
    outer = np.arctan2(2 * l * np.sin(a), 2 * l * np.cos(a) + w * np.sin(a))
    return s * inner, s * outer


def bicycle_from_inner(inner: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike) -> FloatArray:
    """Bicycle angle of ideal Ackermann steering whose inner wheel is at ``inner``.

    ``cot(phi) = cot(delta_i) + w / (2 l)``, written to be exact at zero.

    Examples
    --------
    >>> float(bicycle_from_inner(0.0, 2.7, 1.5))
    0.0
    >>> round(float(bicycle_from_inner(ackermann_angles(0.4, 2.7, 1.5)[0], 2.7, 1.5)), 12)
    0.4
    """
    d = np.asarray(inner, dtype=np.float64)
    l = np.asarray(wheelbase_m, dtype=np.float64)  # noqa: E741
    w = np.asarray(track_m, dtype=np.float64)
    a = np.abs(d)
    return np.sign(d) * np.arctan2(2 * l * np.sin(a), 2 * l * np.cos(a) + w * np.sin(a))


def ideal_outer_from_inner(
    inner: ArrayLike, wheelbase_m: ArrayLike, track_m: ArrayLike
) -> FloatArray:
    """Outer wheel angle satisfying the Ackermann condition with the inner one.

    ``cot(delta_o) = cot(delta_i) + w / l``.

    Examples
    --------
    >>> float(ideal_outer_from_inner(0.0, 2.7, 1.5))
    0.0
    """
    d = np.asarray(inner, dtype=np.float64)
    l = np.asarray(wheelbase_m, dtype=np.float64)  # noqa: E741
    w = np.asarray(track_m, dtype=np.float64)
    a = np.abs(d)
    return np.sign(d) * np.arctan2(l * np.sin(a), l * np.cos(a) + w * np.sin(a))


def equivalent_bicycle(inner: ArrayLike, outer: ArrayLike) -> FloatArray:
    """Mean-cotangent bicycle angle ``cot(phi) = (cot(delta_i) + cot(delta_o)) / 2``.

    Exact for ideal Ackermann steering; equal to the wheel angle for parallel steering.

    Examples
    --------
    >>> float(equivalent_bicycle(0.0, 0.0))
    0.0
    >>> round(float(equivalent_bicycle(0.5, 0.5)), 12)
    0.5
    """
    i = np.abs(np.asarray(inner, dtype=np.float64))
    o = np.abs(np.asarray(outer, dtype=np.float64))
    s = np.sign(np.asarray(inner, dtype=np.float64))
    out: FloatArray = s * np.arctan2(2 * np.sin(i) * np.sin(o), np.sin(i + o))
    return out


def curvature_from_angle(phi: ArrayLike, wheelbase_m: ArrayLike) -> FloatArray:
    """Path curvature ``kappa = tan(phi) / l`` (1/m) of the rear-axle centre.

    Examples
    --------
    >>> float(curvature_from_angle(0.0, 2.7))
    0.0
    """
    return np.tan(np.asarray(phi, dtype=np.float64)) / np.asarray(wheelbase_m, dtype=np.float64)


def angle_from_curvature(kappa: ArrayLike, wheelbase_m: ArrayLike) -> FloatArray:
    """Bicycle angle ``phi = atan(l kappa)`` for a curvature command (no 1/r singularity).

    Examples
    --------
    >>> float(angle_from_curvature(0.0, 2.7))      # straight ahead: 1/r = 0
    0.0
    >>> round(float(angle_from_curvature(1 / 2.7, 2.7)), 12) == round(math.pi / 4, 12)
    True
    """
    l = np.asarray(wheelbase_m, dtype=np.float64)  # noqa: E741
    return np.arctan(l * np.asarray(kappa, dtype=np.float64))


@dataclass(frozen=True)
class RackPinion:
    """Rack-and-pinion linkage geometry (all lengths in metres).

    The pinion turns with the steering wheel and moves the rack by ``r * delta_in``; each
    end of the rack pulls a tie rod (``tie_rod_m``) attached to a steering arm
    (``arm_length_m``) at the wheel's kingpin. Per side ``l1 = (TW - l_rack)/2 -/+ dP``,
    ``l2 = sqrt(l1^2 + D^2)``,
    ``beta = pi/2 - atan(D / l1) - acos((l_arm^2 + l2^2 - l_rod^2) / (2 l_arm l2))`` and
    the wheel angle is the change of ``beta`` from its value with the rack centred.
    """

    track_m: float
    rack_length_m: float
    arm_length_m: float
    tie_rod_m: float
    rack_offset_m: float
    pinion_radius_m: Schedule

    def __post_init__(self) -> None:
        l1 = (self.track_m - self.rack_length_m) / 2
        if l1 <= 0:
            raise InputError(
                f"rack-and-pinion: rack casing {self.rack_length_m:.3f} m is not shorter than "
                f"the track {self.track_m:.3f} m"
            )
        if not np.isfinite(self._beta(np.array([l1])))[0]:
            raise InputError("rack-and-pinion: tie rod and steering arm cannot meet "
                             "with the rack centred")

    def _beta(self, l1: FloatArray) -> FloatArray:
        l2 = np.hypot(l1, self.rack_offset_m)
        c = (self.arm_length_m**2 + l2**2 - self.tie_rod_m**2) / (2 * self.arm_length_m * l2)
        with np.errstate(invalid="ignore"):
            return np.pi / 2 - np.arctan2(self.rack_offset_m, l1) - np.arccos(c)

    def wheel_angles(self, steering_wheel_rad: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Left and right wheel angles (rad, left turn positive) for a steering-wheel angle.

        Returns NaN where the linkage cannot reach (rod and arm cannot meet).

        Examples
        --------
        >>> rp = RackPinion(1.0, 0.5, 0.1, 0.248, 0.2, 0.0057)   # the reference defaults
        >>> left, right = rp.wheel_angles(0.0)
        >>> abs(float(left)), abs(float(right))
        (0.0, 0.0)
        """
        d = np.asarray(steering_wheel_rad, dtype=np.float64)
        travel = evaluate(self.pinion_radius_m, d) * d
        base = (self.track_m - self.rack_length_m) / 2
        beta0 = self._beta(np.asarray(base))
        left = self._beta(base + travel) - beta0
        right = -(self._beta(base - travel) - beta0)
        return left, right


@dataclass(frozen=True)
class Steering:
    """A steering mechanism from steering-wheel angle to road-wheel angles.

    Examples
    --------
    >>> s = Steering("ackermann", wheelbase_m=2.7, track_m=1.5, ratio=10.0)
    >>> a = s.wheel_angles(0.0)                         # straight ahead
    >>> float(a.left), float(a.right), float(a.bicycle)
    (0.0, 0.0, 0.0)
    >>> a = s.wheel_angles(10 * 0.3)                    # 0.3 rad bicycle angle, left
    >>> round(float(a.bicycle), 12), bool(a.left > a.right > 0)
    (0.3, True)
    """

    kind: str
    wheelbase_m: float
    track_m: float
    ratio: Schedule = 16.0
    ackermann_pct: Schedule = 100.0
    steering_range_rad: float = 1.25 * math.pi
    deadband_rad: float = 0.0
    steered_axle: str = "front"
    rack: RackPinion | None = field(default=None)

    def __post_init__(self) -> None:
        if self.kind not in ("ackermann", "parallel", "rack_pinion"):
            raise InputError(f"unknown steering mechanism {self.kind!r}")
        if self.kind == "rack_pinion" and self.rack is None:
            raise InputError("rack_pinion steering needs the linkage geometry")
        if self.steered_axle not in ("front", "rear"):
            raise InputError(f"steered axle must be 'front' or 'rear', not {self.steered_axle!r}")

    def effective_input(self, steering_wheel_rad: ArrayLike) -> FloatArray:
        """The steering-wheel angle after the steering range and the deadband.

        Examples
        --------
        >>> s = Steering("parallel", 2.7, 1.5, deadband_rad=0.1, steering_range_rad=5.0)
        >>> [round(float(v), 12) for v in s.effective_input([0.05, -0.3, 7.0])]
        [0.0, -0.2, 4.9]
        """
        d = np.clip(np.asarray(steering_wheel_rad, dtype=np.float64),
                    -self.steering_range_rad, self.steering_range_rad)
        return np.sign(d) * np.maximum(np.abs(d) - self.deadband_rad, 0.0)

    def wheel_angles(self, steering_wheel_rad: ArrayLike) -> WheelAngles:
        """Road-wheel angles for a steering-wheel angle (rad).

        For a rear-steered axle the wheels turn the other way for the same turn direction;
        ``bicycle`` keeps the sign of the vehicle's turn (left positive).
        """
        raw = np.asarray(steering_wheel_rad, dtype=np.float64)
        d = self.effective_input(raw)
        if self.kind == "rack_pinion":
            assert self.rack is not None
            left, right = self.rack.wheel_angles(d)
            turn_left = d >= 0
            inner = np.where(turn_left, left, right)
            outer = np.where(turn_left, right, left)
        else:
            road = d / evaluate(self.ratio, raw)
            if self.kind == "parallel":
                inner = outer = road
            else:
                inner, ideal_outer = ackermann_angles(road, self.wheelbase_m, self.track_m)
                p = evaluate(self.ackermann_pct, raw) / 100.0
                outer = inner - p * (inner - ideal_outer)
            left = np.where(road >= 0, inner, outer)
            right = np.where(road >= 0, outer, inner)
        bicycle = equivalent_bicycle(inner, outer)
        if self.steered_axle == "rear":
            left, right, inner, outer = -left, -right, -inner, -outer
        return WheelAngles(left, right, inner, outer, bicycle)

    def outer_for_inner(self, inner: ArrayLike) -> FloatArray:
        """Outer wheel angle (rad) when the inner wheel is at ``inner`` (both >= 0).

        Ackermann and parallel are closed forms; rack-and-pinion inverts the linkage
        through a dense monotone table over the steering range (NaN beyond its reach).

        Examples
        --------
        >>> s = Steering("parallel", 2.7, 1.5)
        >>> float(s.outer_for_inner(0.5))
        0.5
        """
        i = np.asarray(inner, dtype=np.float64)
        if self.kind == "parallel":
            return i.copy()
        if self.kind == "ackermann":
            p: FloatArray | float
            if isinstance(self.ackermann_pct, Breakpoints):
                sw = self.steering_for_inner(i)
                p = evaluate(self.ackermann_pct, sw) / 100.0
            else:
                p = float(self.ackermann_pct) / 100.0
            return i - p * (i - ideal_outer_from_inner(i, self.wheelbase_m, self.track_m))
        sw = np.linspace(0.0, self.steering_range_rad, 4001)
        a = self.wheel_angles(sw)
        ok = np.isfinite(a.inner) & np.isfinite(a.outer)
        return np.interp(i, np.abs(a.inner[ok]), np.abs(a.outer[ok]), left=np.nan, right=np.nan)

    def steering_for_inner(self, inner: ArrayLike) -> FloatArray:
        """Steering-wheel angle (rad) that puts the inner wheel at ``inner`` (>= 0).

        NaN where the steering range does not reach that wheel angle.

        Examples
        --------
        >>> s = Steering("ackermann", 2.7, 1.5, ratio=16.0)
        >>> float(s.steering_for_inner(0.0))
        0.0
        """
        sw = np.linspace(0.0, self.steering_range_rad, 4001)
        a = np.abs(self.wheel_angles(sw).inner)
        ok = np.isfinite(a)
        return np.interp(np.asarray(inner, dtype=np.float64), a[ok], sw[ok], left=np.nan,
                         right=np.nan)

    def max_bicycle_for_inner(self, inner: ArrayLike) -> FloatArray:
        """Bicycle-equivalent angle when the inner wheel is at ``inner`` (>= 0).

        Examples
        --------
        >>> s = Steering("ackermann", 2.7, 1.5)
        >>> round(float(s.max_bicycle_for_inner(ackermann_angles(0.5, 2.7, 1.5)[0])), 12)
        0.5
        """
        i = np.asarray(inner, dtype=np.float64)
        return equivalent_bicycle(i, self.outer_for_inner(i))
