"""The vehicle table's columns: names, kinds, units and documented defaults.

A table is a CSV file with one row per vehicle model. Lengths are in the row's ``units``
(``m`` or ``ft``) and converted to metres on loading; angles are in degrees and converted to
radians; every other column is unit-free.
"""

from __future__ import annotations

from dataclasses import dataclass

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
    """

    name: str
    kind: str
    positive: bool | str = True
    choices: tuple[str, ...] = ()
    default: object = None
    doc: str = ""


# ---------------------------------------------------------------- SUMO vehicle class

VCLASSES: tuple[str, ...] = (
    "passenger", "private", "taxi", "bus", "coach", "delivery", "truck", "trailer",
    "emergency", "authority", "army", "vip", "hov", "evehicle", "motorcycle", "moped",
    "custom1", "custom2",
)
"""SUMO vehicle classes a table row may name (those that drive on roads)."""

#: Category words and the SUMO class they mean, the first match winning (lower case).
_CATEGORY_VCLASS: tuple[tuple[str, str], ...] = (
    ("semitrailer", "trailer"), ("combination", "trailer"), ("trailer", "trailer"),
    ("coach", "coach"), ("bus", "bus"), ("truck", "truck"), ("lorry", "truck"),
    ("van", "delivery"), ("delivery", "delivery"), ("motorcycle", "motorcycle"),
    ("emergency", "emergency"), ("fire", "emergency"), ("passenger", "passenger"),
    ("car", "passenger"), ("suv", "passenger"),
)


def default_vclass(category: str) -> str:
    """The SUMO vehicle class a row's ``category`` means when ``vclass`` is empty.

    Examples
    --------
    >>> [default_vclass(c) for c in ("passenger car", "single-unit truck", "school bus",
    ...                              "semitrailer combination", "Coach", "")]
    ['passenger', 'truck', 'bus', 'trailer', 'coach', 'passenger']
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
    Column("length", "length", doc="overall length (of the whole combination with a trailer)"),
    Column("width", "length", doc="body width"),
    Column("wheelbase", "length", doc="front axle to rear axle (tandem centre)"),
    Column("front_overhang", "length", positive="nonneg", doc="body ahead of the front axle"),
    Column("source", "text", doc="where the numbers come from"),
)

LOCK: tuple[Column, ...] = (
    Column("max_steer_deg", "angle", doc="inner road-wheel angle at full lock"),
    Column("curb_to_curb", "length", doc="curb-to-curb turning diameter (outer front wheel)"),
    Column("wall_to_wall", "length", doc="wall-to-wall turning diameter (outer front corner)"),
    Column("ctr", "length", doc="centre-line turning radius of the steered-axle centre"),
)

OPTIONAL: tuple[Column, ...] = (
    Column("rear_overhang", "length", positive="nonneg",
           doc="body behind the rear axle; default length - wheelbase - front_overhang "
               "(0 for the towing unit of a combination)"),
    Column("track", "length", doc="steered-axle track; default: the body width (the paper's "
                                  "rectangle model)"),
    Column("steering", "choice", choices=("ackermann", "parallel", "rack_pinion"),
           default="ackermann", doc="steering mechanism"),
    Column("ackermann_pct", "table", positive="nonneg", default=100.0,
           doc="percent Ackermann, constant or 'angle_deg:pct;...' over steering-wheel angle"),
    Column("steering_ratio", "table", default=16.0,
           doc="steering-wheel / road-wheel angle, constant or 'angle_deg:ratio;...'"),
    Column("lock_to_lock_s", "number", default=4.0,
           doc="time from full left to full right lock; gives the steering rate"),
    Column("max_steer_rate_deg_s", "number", doc="road-wheel steering rate (overrides "
                                                 "lock_to_lock_s)"),
    Column("steering_range_deg", "number",
           doc="steering-wheel input range, +/-; default: exactly what reaches the lock"),
    Column("deadband_deg", "number", positive="nonneg", default=0.0,
           doc="steering-wheel deadband before the mechanism engages"),
    Column("steered_axle", "choice", choices=("front", "rear"), default="front",
           doc="which axle steers"),
    Column("pinion_radius", "length", doc="rack-and-pinion: pinion radius"),
    Column("rack_length", "length", doc="rack-and-pinion: rack casing length"),
    Column("steering_arm", "length", doc="rack-and-pinion: steering arm length"),
    Column("tie_rod", "length", doc="rack-and-pinion: tie rod length"),
    Column("rack_offset", "length", doc="rack-and-pinion: distance from the axle to the rack"),
    Column("height", "length", doc="overall height"),
    Column("ground_clearance", "length", positive="nonneg", doc="ground clearance"),
    Column("approach_deg", "angle", doc="approach angle"),
    Column("departure_deg", "angle", doc="departure angle"),
    Column("breakover_deg", "angle", doc="ramp breakover angle"),
    Column("w_l", "number", doc="published track/wheelbase ratio, checked (warning only)"),
    Column("ref_turning_radius", "length",
           doc="published design turning radius, kept for comparison only"),
    Column("ref_inside_radius", "length",
           doc="published minimum inside radius, kept for comparison only"),
    Column("vclass", "choice", choices=VCLASSES,
           doc="SUMO vehicle class (allow/disallow decide which curves it is checked on); "
               "default from the category: passenger car -> passenger, bus -> bus, coach "
               "-> coach, truck -> truck, semitrailer/combination -> trailer, van -> "
               "delivery"),
)

TRAILER: tuple[Column, ...] = (
    Column("hitch_offset", "length", positive=False,
           doc="hitch (kingpin) behind the towing unit's rear axle; negative ahead of it"),
    Column("trailer_wheelbase", "length", doc="hitch to the trailer's axle (tandem) centre"),
    Column("trailer_width", "length", doc="trailer body width; default: the towing unit's"),
    Column("trailer_front_overhang", "length", positive="nonneg", default=0.0,
           doc="trailer body ahead of the hitch"),
    Column("trailer_rear_overhang", "length", positive="nonneg",
           doc="trailer body behind its axle; default from the overall length"),
    Column("max_articulation_deg", "angle", default=90.0,
           doc="largest angle between towing unit and trailer"),
)

ALL_COLUMNS: dict[str, Column] = {c.name: c for c in REQUIRED + LOCK + OPTIONAL + TRAILER}
LOCK_NAMES: tuple[str, ...] = tuple(c.name for c in LOCK)
TRAILER_NAMES: tuple[str, ...] = tuple(c.name for c in TRAILER)
RACK_NAMES: tuple[str, ...] = ("pinion_radius", "rack_length", "steering_arm", "tie_rod",
                               "rack_offset")
