"""The vehicle table's columns: names, kinds, units and documented defaults.

A table is a CSV file with one row per vehicle model. Lengths are in the row's ``units``
(``m`` or ``ft``) and converted to metres on loading; angles are in degrees and converted to
radians; every other column is unit-free.

Every number has a physical range (:attr:`Column.low`, :attr:`Column.high`, in metres for
lengths, whatever the row's units), wide enough for any road vehicle from a microcar to a
road train and an oversize load, narrow enough that the geometry stays well-conditioned
(a lock of 1e-300 degrees or a width of 1e300 m broke the arithmetic): a value outside is
an error naming the file, line, column and value, with the range and its reason
(:attr:`Column.why`). Text cells may not hold line breaks or control characters.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ALL_COLUMNS", "Column", "FOOT_M", "LOCK", "LOCK_NAMES", "OPTIONAL", "RACK_NAMES",
           "REQUIRED", "TRAILER", "TRAILER_NAMES", "UNITS_TO_M", "VCLASSES", "default_vclass"]

FOOT_M = 0.3048
"""One international foot in metres."""

UNITS_TO_M = {"m": 1.0, "ft": FOOT_M}


@dataclass(frozen=True)
class Column:
    """One column of the vehicle table.

    Attributes
    ----------
    name
        The column's spelling in the CSV header.
    kind
        ``"text"``, ``"length"`` (converted with the row's units), ``"angle"`` (degrees),
        ``"number"`` (unit-free or with its unit in the name), ``"choice"`` or ``"table"``
        (a constant or ``x:y;x:y`` breakpoints).
    positive
        ``True`` when the value must be > 0, ``"nonneg"`` when it must be >= 0, ``False``
        when any sign is allowed.
    choices
        Allowed values of a ``"choice"`` column.
    default
        What an empty cell means (documented in the README and in ``clearance vehicles``).
    low, high
        The physical range of a number (SI: metres for lengths, degrees for angles, the
        column's own unit otherwise), both ends included except ``low`` when ``positive``
        is ``True`` and ``low`` is 0 (must be greater), and ``high`` when ``high_open``.
        For a ``"table"`` column, every value of the table.
    why
        The reason for the range, given with the error.
    """

    name: str
    kind: str
    positive: bool | str = True
    choices: tuple[str, ...] = ()
    default: object = None
    doc: str = ""
    low: float | None = None
    high: float | None = None
    high_open: bool = False
    why: str = ""

    def range_text(self, scale: float = 1.0, unit: str = "") -> str:
        """The range as an interval in units of ``scale`` metres (lengths only).

        Examples
        --------
        >>> ALL_COLUMNS["width"].range_text()
        '[0.3, 6] m'
        >>> ALL_COLUMNS["max_articulation_deg"].range_text()
        '(0, 90] deg'
        """
        if self.low is None or self.high is None:
            return ""
        k = scale if self.kind == "length" else 1.0
        unit = unit or {"length": "m", "angle": "deg"}.get(self.kind, self.unit)
        lo = "(" if self.positive is True and self.low == 0 else "["
        hi = ")" if self.high_open else "]"
        return f"{lo}{self.low / k:.4g}, {self.high / k:.4g}{hi} {unit}".rstrip()

    @property
    def unit(self) -> str:
        """The unit of a ``"number"`` or ``"table"`` column, from its name."""
        for suffix, unit in (("_pct", "%"), ("_deg_s", "deg/s"), ("_deg", "deg"), ("_s", "s")):
            if self.name.endswith(suffix):
                return unit
        return ""

    def in_range(self, value: float) -> bool:
        """True when ``value`` (SI) lies in the column's range (NaN never does)."""
        if self.low is None or self.high is None:
            return value == value
        above = value > self.low if self.positive is True and self.low == 0 else value >= self.low
        below = value < self.high if self.high_open else value <= self.high
        return above and below


# ---------------------------------------------------------------- SUMO vehicle class

VCLASSES: tuple[str, ...] = (
    "passenger", "private", "taxi", "bus", "coach", "delivery", "truck", "trailer",
    "emergency", "authority", "army", "vip", "hov", "evehicle", "motorcycle", "moped",
    "custom1", "custom2",
)
"""SUMO vehicle classes a table row may name (those that drive on roads)."""

#: Category words and the SUMO class they mean, the first match winning (lower case). A car
#: or a motor home towing a trailer stays a passenger vehicle (SUMO's ``trailer`` is a truck
#: with a trailer, the class truck bans keep out).
_CATEGORY_VCLASS: tuple[tuple[str, str], ...] = (
    ("passenger", "passenger"), ("motor home", "passenger"), ("car", "passenger"),
    ("suv", "passenger"), ("semitrailer", "trailer"), ("combination", "trailer"),
    ("trailer", "trailer"), ("coach", "coach"), ("bus", "bus"), ("truck", "truck"),
    ("lorry", "truck"), ("van", "delivery"), ("delivery", "delivery"),
    ("motorcycle", "motorcycle"), ("emergency", "emergency"), ("fire", "emergency"),
)


def default_vclass(category: str) -> str:
    """The SUMO vehicle class a row's ``category`` means when ``vclass`` is empty.

    Examples
    --------
    >>> [default_vclass(c) for c in ("passenger car", "single-unit truck", "school bus",
    ...                              "semitrailer combination", "Coach", "")]
    ['passenger', 'truck', 'bus', 'trailer', 'coach', 'passenger']
    >>> [default_vclass(c) for c in ("articulated bus", "truck and full trailer",
    ...                              "passenger car and boat trailer", "motor home")]
    ['bus', 'trailer', 'passenger', 'passenger']
    """
    text = category.lower()
    for word, vclass in _CATEGORY_VCLASS:
        if word in text:
            return vclass
    return "passenger"


REQUIRED: tuple[Column, ...] = (
    Column("name", "text", doc="unique model name"),
    Column("category", "text", doc="free text, e.g. passenger car, bus, semitrailer"),
    Column("units", "choice", choices=("m", "ft"), doc="units of every length in the row"),
    Column("length", "length", doc="overall length (of the whole combination with a trailer)",
           low=0.5, high=60, why='from a microcar to the longest road train (53.5 m)'),
    Column("width", "length", doc="body width",
           low=0.3, high=6, why='legal widths are 2.5-2.6 m; wide loads reach 5-6 m'),
    Column("wheelbase", "length", doc="front axle to rear axle (tandem centre)",
           low=0.3, high=20, why='a rigid 15 m coach has about 7-8 m; no road vehicle has 20 m'),
    Column("front_overhang", "length", positive="nonneg", doc="body ahead of the front axle",
           low=0, high=10, why='buses reach 2.7 m, crane booms a few metres more'),
    Column("source", "text", doc="where the numbers come from"),
)

LOCK: tuple[Column, ...] = (
    Column("max_steer_deg", "angle", doc="inner road-wheel angle at full lock",
           low=1, high=80, why='below 1 degree a car turns on a circle of several hundred metres '
                               '(no lock); road vehicles reach 30-60 degrees; near 90 the inner '
                               'wheel stands across the road and the geometry degenerates'),
    Column("curb_to_curb", "length", doc="curb-to-curb turning diameter (outer front wheel)",
           low=1, high=200, why='cars 9-13 m, the largest trucks about 30 m'),
    Column("wall_to_wall", "length", doc="wall-to-wall turning diameter (outer front corner)",
           low=1, high=200, why='cars 10-14 m, the largest trucks about 32 m'),
    Column("ctr", "length", doc="centre-line turning radius of the steered-axle centre",
           low=0.5, high=100, why='cars about 6 m, the largest design vehicles about 20 m'),
)

OPTIONAL: tuple[Column, ...] = (
    Column("rear_overhang", "length", positive="nonneg",
           doc="body behind the rear axle; default length - wheelbase - front_overhang "
               "(0 for the towing unit of a combination)",
           low=0, high=20, why='cars about 1 m, a rigid bus 3-4 m'),
    Column("track", "length", doc="steered-axle track; default: the body width (the paper's "
                                  "rectangle model)",
           low=0.3, high=6, why='as the body width'),
    Column("steering", "choice", choices=("ackermann", "parallel", "rack_pinion"),
           default="ackermann", doc="steering mechanism"),
    Column("ackermann_pct", "table", positive="nonneg", default=100.0,
           doc="percent Ackermann, constant or 'angle_deg:pct;...' over steering-wheel angle",
           low=0, high=150, why='real linkages lie between parallel (0) and about 120 %; more '
                                'turns the outer wheel back towards straight ahead'),
    Column("steering_ratio", "table", default=16.0,
           doc="steering-wheel / road-wheel angle, constant or 'angle_deg:ratio;...'",
           low=1, high=50, why='cars 12-20, heavy trucks up to about 36'),
    Column("lock_to_lock_s", "number", default=4.0,
           doc="time from full left to full right lock; gives the steering rate",
           low=0.5, high=60, why='power steering takes 1-4 s, a heavy manual truck about 10 s'),
    Column("max_steer_rate_deg_s", "number", doc="road-wheel steering rate (overrides "
                                                 "lock_to_lock_s)",
           low=1, high=360, why='road wheels turn at about 10-60 degrees per second'),
    Column("steering_range_deg", "number",
           doc="steering-wheel input range, +/-; default: exactly what reaches the lock",
           low=10, high=1800, why='cars about 540, trucks up to about 1080 degrees each way'),
    Column("deadband_deg", "number", positive="nonneg", default=0.0,
           doc="steering-wheel deadband before the mechanism engages",
           low=0, high=90, why='a steering-wheel play of a few degrees; 90 is a broken linkage'),
    Column("steered_axle", "choice", choices=("front", "rear"), default="front",
           doc="which axle steers"),
    Column("pinion_radius", "length", doc="rack-and-pinion: pinion radius",
           low=0, high=0.2, why='pinions have radii of a few centimetres'),
    Column("rack_length", "length", doc="rack-and-pinion: rack casing length",
           low=0, high=3, why='shorter than the track'),
    Column("steering_arm", "length", doc="rack-and-pinion: steering arm length",
           low=0, high=1, why='steering arms are 0.1-0.3 m'),
    Column("tie_rod", "length", doc="rack-and-pinion: tie rod length",
           low=0, high=2, why='tie rods are 0.2-0.6 m'),
    Column("rack_offset", "length", doc="rack-and-pinion: distance from the axle to the rack",
           low=0, high=1, why='racks sit within 0.3 m of the axle'),
    Column("height", "length", doc="overall height",
           low=0, high=6, why='legal heights are 4-4.3 m; 6 m covers any load'),
    Column("ground_clearance", "length",
           doc="lowest point of the body above level ground; default: from breakover_deg, "
               "else the class default of vehicles/underside.py (no source, flagged)",
           low=0, high=2, why='cars 0.1-0.2 m, off-road vehicles under 1 m; a body on the '
                              'ground (0) scrapes at any change of grade'),
    Column("approach_deg", "angle",
           doc="approach angle; default: atan(ground_clearance / front_overhang)",
           low=0, high=90, why='an angle to the ground, under 90 degrees', high_open=True),
    Column("departure_deg", "angle",
           doc="departure angle; default: atan(ground_clearance / rear_overhang)",
           low=0, high=90, why='an angle to the ground, under 90 degrees', high_open=True),
    Column("breakover_deg", "angle",
           doc="ramp breakover angle; default: 2 atan(2 ground_clearance / wheelbase)",
           low=0, high=90, why='an angle to the ground, under 90 degrees', high_open=True),
    Column("grade_limit_pct", "number",
           doc="steepest grade the vehicle is to climb; default: none (a study's "
               "--max-grade-pct applies to every vehicle)",
           low=0, high=100, why='100 % is 45 degrees, beyond any road vehicle on a paved '
                                'ramp; parking ramps are built at 5-20 %'),
    Column("w_l", "number", doc="published track/wheelbase ratio, checked (warning only)",
           low=0, high=2, why='track over wheelbase: cars about 0.6'),
    Column("ref_turning_radius", "length",
           doc="published design turning radius, kept for comparison only",
           low=0, high=100, why='as ctr'),
    Column("ref_inside_radius", "length",
           doc="published minimum inside radius, kept for comparison only",
           low=0, high=100, why='as ctr'),
    Column("vclass", "choice", choices=VCLASSES,
           doc="SUMO vehicle class (allow/disallow decide which curves it is checked on); "
               "default from the category: passenger car -> passenger, bus -> bus, coach "
               "-> coach, truck -> truck, semitrailer/combination -> trailer, van -> "
               "delivery"),
)

TRAILER: tuple[Column, ...] = (
    Column("hitch_offset", "length", positive=False,
           doc="hitch (kingpin) behind the towing unit's rear axle; negative ahead of it",
           low=-15, high=15, why='a fifth wheel sits within 1 m of the rear axle, a drawbar up to '
                                 'a few metres behind; it must also lie behind the front axle'),
    Column("trailer_wheelbase", "length", doc="hitch to the trailer's axle (tandem) centre",
           low=0.5, high=25, why='a 16 m semitrailer has about 12.5 m from kingpin to axles'),
    Column("trailer_width", "length", doc="trailer body width; default: the towing unit's",
           low=0.3, high=6, why='as the body width'),
    Column("trailer_front_overhang", "length", positive="nonneg", default=0.0,
           doc="trailer body ahead of the hitch",
           low=0, high=10, why="a semitrailer's nose is about 1 m ahead of the kingpin"),
    Column("trailer_rear_overhang", "length", positive="nonneg",
           doc="trailer body behind its axle; default from the overall length",
           low=0, high=20, why="a semitrailer's body reaches about 4 m behind its axles"),
    Column("max_articulation_deg", "angle", default=90.0,
           doc="largest angle between towing unit and trailer",
           low=0, high=90, why='a jackknife limit beyond 90 degrees would fold the trailer into '
                               'the towing unit'),
)

ALL_COLUMNS: dict[str, Column] = {c.name: c for c in REQUIRED + LOCK + OPTIONAL + TRAILER}
LOCK_NAMES: tuple[str, ...] = tuple(c.name for c in LOCK)
TRAILER_NAMES: tuple[str, ...] = tuple(c.name for c in TRAILER)
RACK_NAMES: tuple[str, ...] = ("pinion_radius", "rack_length", "steering_arm", "tie_rod",
                               "rack_offset")
