"""Steering-angle sensor: a look-up table between wheel angle and raw reading.

The steering subsystem of the ERTS autonomous vehicle reads the front wheels' pivot angle
through a linear potentiometer whose voltage is non-linear in the angle; a table of
``(angle, reading)`` pairs and an ``offset`` convert between the two:
``reading = table(angle) + offset``. Both directions interpolate linearly and refuse
values off the table (no extrapolation).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from clearance.vehicles.errors import InputError

__all__ = ["SteeringSensor"]

FloatArray = NDArray[np.float64]


class SteeringSensor:
    """Angle ↔ reading conversion through a monotone look-up table.

    Parameters
    ----------
    pairs
        ``(angle, reading)`` pairs in the sensor's own angle unit. Angles must not
        decrease and readings must increase strictly (a sensor that repeats a reading
        cannot be read back). Repeated angles, as in a table rounded to whole degrees,
        are merged by averaging their readings for the angle → reading direction.
    offset
        Added to the table's reading (a calibration offset).

    Examples
    --------
    >>> s = SteeringSensor([(-10, -1000), (0, 0), (10, 1200)], offset=-50)
    >>> float(s.reading(0.0)), float(s.angle(-50.0))      # straight ahead
    (-50.0, 0.0)
    >>> float(s.angle(s.reading(5.0)))
    5.0
    """

    def __init__(self, pairs: Iterable[tuple[float, float]], offset: float = 0.0):
        arr = np.asarray(list(pairs), dtype=np.float64)
        if arr.ndim != 2 or arr.shape[1] != 2 or len(arr) < 2:
            raise InputError("steering sensor table: needs at least two (angle, reading) pairs")
        if not np.all(np.isfinite(arr)):
            raise InputError("steering sensor table: has a value that is not a finite number")
        angles, readings = arr[:, 0], arr[:, 1]
        if np.any(np.diff(angles) < 0):
            raise InputError("steering sensor table: angles must not decrease")
        if np.any(np.diff(readings) <= 0):
            raise InputError("steering sensor table: readings must increase strictly")
        self.offset = float(offset)
        self._readings = readings
        self._angles_for_readings = angles
        unique, inverse = np.unique(angles, return_inverse=True)
        sums = np.bincount(inverse, weights=readings)
        counts = np.bincount(inverse)
        self._angles = unique
        self._mean_readings = sums / counts
        if len(unique) < 2:
            raise InputError("steering sensor table: needs at least two distinct angles")

    @property
    def angle_range(self) -> tuple[float, float]:
        return float(self._angles[0]), float(self._angles[-1])

    @property
    def reading_range(self) -> tuple[float, float]:
        return float(self._readings[0] + self.offset), float(self._readings[-1] + self.offset)

    def reading(self, angle: ArrayLike) -> FloatArray:
        """Raw reading for a wheel angle; refuses angles off the table."""
        a = np.asarray(angle, dtype=np.float64)
        lo, hi = self.angle_range
        if np.any((a < lo) | (a > hi)) or not np.all(np.isfinite(a)):
            raise InputError(f"steering sensor: angle off the table [{lo:g}, {hi:g}]")
        return np.interp(a, self._angles, self._mean_readings) + self.offset

    def angle(self, reading: ArrayLike) -> FloatArray:
        """Wheel angle for a raw reading; refuses readings off the table."""
        r = np.asarray(reading, dtype=np.float64) - self.offset
        lo, hi = self._readings[0], self._readings[-1]
        if np.any((r < lo) | (r > hi)) or not np.all(np.isfinite(r)):
            lo_o, hi_o = self.reading_range
            raise InputError(f"steering sensor: reading off the table [{lo_o:g}, {hi_o:g}]")
        return np.interp(r, self._readings, self._angles_for_readings)
