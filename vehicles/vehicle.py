"""One vehicle's geometry in SI units, as the kinematics and the simulation use it.

The table loader (:mod:`clearance.vehicles.table`) turns each validated row into a :class:`Vehicle`;
tests and scripts may also build one directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from clearance.vehicles.underside import Underside, underside_from

__all__ = ["Trailer", "Vehicle"]


@dataclass(frozen=True)
class Trailer:
    """A towed unit: a semitrailer on a kingpin or a trailer on a drawbar hitch.

    Attributes
    ----------
    hitch_offset_m
        Distance of the hitch (kingpin) behind the towing unit's rear axle; negative when
        the hitch is ahead of that axle (the usual fifth wheel of a tractor).
    wheelbase_m
        Hitch to the trailer's axle (or tandem) centre.
    width_m
        Body width of the trailer.
    front_overhang_m
        Body ahead of the hitch (a semitrailer's nose); 0 for a drawbar trailer whose body
        starts at the hitch.
    rear_overhang_m
        Body behind the trailer's axle centre.
    max_articulation_rad
        Largest angle between the towing unit and the trailer (jackknife limit).
    """

    hitch_offset_m: float
    wheelbase_m: float
    width_m: float
    front_overhang_m: float = 0.0
    rear_overhang_m: float = 0.0
    max_articulation_rad: float = math.radians(90.0)

    @property
    def length_m(self) -> float:
        """Body length of the trailer from its front to its rear."""
        return self.front_overhang_m + self.wheelbase_m + self.rear_overhang_m


@dataclass(frozen=True)
class Vehicle:
    """A vehicle for kinematics: lengths in metres, angles in radians.

    Attributes
    ----------
    name
        Unique model name.
    wheelbase_m
        Front axle to rear axle (for a tandem, to its centre).
    track_m
        Between the steered wheels' contact centres.
    width_m
        Body width.
    front_overhang_m, rear_overhang_m
        Body ahead of the front axle and behind the rear axle.
    max_steer_rad
        Bicycle-equivalent steering angle φ at full lock (the front-axle centre's angle;
        ``rho = wheelbase / tan(phi)`` is the rear-axle centre's radius).
    max_inner_steer_rad
        Inner road-wheel angle at full lock.
    max_steer_rate_rad_s
        Largest rate of change of φ.
    steered_axle
        ``"front"`` or ``"rear"``.
    height_m
        Overall height, or ``None`` when unknown.
    trailer
        The towed unit, or ``None``.
    category, source
        Free text from the table.
    vclass
        SUMO vehicle class: which lanes admit it (``allow``/``disallow``).
    underside
        Ground clearance and ramp angles (:class:`~clearance.vehicles.underside.Underside`), or
        ``None``: the vertical checks then take the class default
        (:func:`clearance.vehicles.underside.underside_from` with nothing given).
    grade_limit_pct
        The steepest grade the vehicle is to climb (percent), or ``None``: no limit of its own.
    """

    name: str
    wheelbase_m: float
    track_m: float
    width_m: float
    front_overhang_m: float
    rear_overhang_m: float
    max_steer_rad: float
    max_inner_steer_rad: float
    max_steer_rate_rad_s: float
    steered_axle: str = "front"
    height_m: float | None = None
    trailer: Trailer | None = None
    category: str = ""
    source: str = ""
    vclass: str = "passenger"
    params: dict[str, str] = field(default_factory=dict, compare=False)
    underside: Underside | None = None
    grade_limit_pct: float | None = None

    @property
    def length_m(self) -> float:
        """Body length of the (towing) unit."""
        return self.front_overhang_m + self.wheelbase_m + self.rear_overhang_m

    @property
    def min_radius_m(self) -> float:
        """Radius of the rear-axle centre at full lock, ``l / tan(phi_max)``."""
        return self.wheelbase_m / math.tan(self.max_steer_rad)

    @property
    def overall_length_m(self) -> float:
        """Front of the towing unit to the rear of the last unit, driving straight."""
        if self.trailer is None:
            return self.length_m
        t = self.trailer
        rear_of_trailer = self.wheelbase_m + t.hitch_offset_m + t.wheelbase_m + t.rear_overhang_m
        return max(self.front_overhang_m + rear_of_trailer, self.length_m)

    def underside_or_default(self) -> Underside:
        """:attr:`underside`, or the class default where the vehicle has none.

        Examples
        --------
        >>> v = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.7, 0.4)
        >>> u = v.underside_or_default()
        >>> u.ground_clearance_m, u.defaulted
        (0.1, True)
        """
        if self.underside is not None:
            return self.underside
        return underside_from(None, None, None, None, self.wheelbase_m, self.front_overhang_m,
                              self.rear_overhang_m, self.vclass)
