"""A vehicle's underside in side view: ground clearance and the three ramp angles.

The vertical checks (:mod:`clearance.analysis.vertical`) need, per vehicle, how high its body sits
above the chord between the tyre contacts of its axles:

- between the axles, the **breakover** height ``(l / 2) tan(beta / 2)`` (the two lines from
  the tyre contacts at half the breakover angle meet there);
- ahead of the front axle, the line from the front tyre's contact at the **approach**
  angle ``alpha``; behind the rear axle, the line from the rear contact at the
  **departure** angle ``delta``.

A table row may give any of ``ground_clearance``, ``approach_deg``, ``departure_deg`` and
``breakover_deg``; what it does not give is derived (:func:`underside_from`):

- the clearance ``c``, when not given: from the breakover angle, ``c = (l / 2) tan(beta /
  2)``; with neither, the stated default of the vehicle's class (:data:`DEFAULT_CLEARANCE_M`,
  *no source*, flagged in :attr:`Underside.note`);
- approach ``atan(c / a_f)`` and departure ``atan(c / a_r)``: the underside at the ground
  clearance reaching to the body's front and rear ends (90 degrees without an overhang);
- breakover ``2 atan(2 c / l)``: a flat underside at the clearance between the axles.

Derived angles are the smallest a body of that clearance and those overhangs can have, so a
vehicle without published angles is checked as a low one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["DEFAULT_CLEARANCE_M", "UNDERSIDE_COLUMNS", "Underside", "underside_from"]

#: The table columns an underside is made from.
UNDERSIDE_COLUMNS = ("ground_clearance", "approach_deg", "departure_deg", "breakover_deg")

#: Ground clearance (m) assumed by SUMO vehicle class where a row gives neither a clearance
#: nor a breakover angle. *Not from a source*: the low end of each class (a low saloon
#: about 0.10 m, vans 0.15 m, buses and coaches 0.20 m, trucks 0.25 m), so that a vehicle
#: without data errs towards scraping; :attr:`Underside.note` says when it was used.
DEFAULT_CLEARANCE_M: dict[str, float] = {
    "passenger": 0.10, "private": 0.10, "taxi": 0.10, "hov": 0.10, "vip": 0.10,
    "evehicle": 0.10, "emergency": 0.15, "authority": 0.10, "army": 0.25,
    "delivery": 0.15, "bus": 0.20, "coach": 0.20, "truck": 0.25, "trailer": 0.25,
    "motorcycle": 0.10, "moped": 0.10, "custom1": 0.10, "custom2": 0.10,
}


@dataclass(frozen=True)
class Underside:
    """A vehicle's underside: clearance (m) and the three angles (rad) to the ground.

    Attributes
    ----------
    ground_clearance_m
        The lowest point of the body above level ground.
    approach_rad, departure_rad, breakover_rad
        The approach, departure and breakover angles (``pi / 2`` where an overhang is 0:
        nothing of the body ahead of or behind the axle).
    given
        Which of :data:`UNDERSIDE_COLUMNS` the table gave.
    note
        ``given`` when every value was given, else what was derived or assumed, e.g.
        ``approach, departure derived from the ground clearance`` or ``ground clearance:
        default 0.10 m for passenger (no source)``.
    """

    ground_clearance_m: float
    approach_rad: float
    departure_rad: float
    breakover_rad: float
    given: tuple[str, ...] = ()
    note: str = ""

    def mid_height_m(self, wheelbase_m: float) -> float:
        """The breakover height: where the lines from the two tyre contacts at half the
        breakover angle meet, ``(l / 2) tan(beta / 2)``.

        Examples
        --------
        >>> u = underside_from(0.10, None, None, None, 2.7, 0.9, 1.0, "passenger")
        >>> round(u.mid_height_m(2.7), 6)   # a flat underside at the clearance
        0.1
        """
        return 0.5 * wheelbase_m * math.tan(0.5 * self.breakover_rad)

    @property
    def defaulted(self) -> bool:
        """True when the clearance is a class default (no source)."""
        return "default" in self.note


def underside_from(clearance_m: float | None, approach_rad: float | None,
                   departure_rad: float | None, breakover_rad: float | None,
                   wheelbase_m: float, front_overhang_m: float, rear_overhang_m: float,
                   vclass: str) -> Underside:
    """The underside of a vehicle from what its row gives (``None``: not given).

    Examples
    --------
    The Hummer H3's published figures, all given:

    >>> import math
    >>> r = math.radians
    >>> u = underside_from(0.216, r(37.5), r(34.6), r(23.5), 2.842, 0.781, 1.140, "passenger")
    >>> u.note, round(u.mid_height_m(2.842), 3)
    ('given', 0.296)

    Only a clearance: the angles of a body at that height to its ends:

    >>> u = underside_from(0.10, None, None, None, 2.7, 0.9, 1.0, "passenger")
    >>> [round(math.degrees(a), 2) for a in (u.approach_rad, u.departure_rad, u.breakover_rad)]
    [6.34, 5.71, 8.47]
    >>> u.note
    'approach, departure, breakover derived from the ground clearance'

    Nothing given, no front overhang (the degenerate case): the class default, and nothing
    ahead of the front axle to scrape:

    >>> u = underside_from(None, None, None, None, 6.0, 0.0, 2.0, "bus")
    >>> u.ground_clearance_m, u.approach_rad == math.pi / 2, u.defaulted
    (0.2, True, True)
    >>> u.note.split("; ")  # doctest: +NORMALIZE_WHITESPACE
    ['ground clearance: default 0.20 m for bus (no source)',
     'approach, departure, breakover derived from the ground clearance']
    """
    given = tuple(name for name, value in zip(
        UNDERSIDE_COLUMNS, (clearance_m, approach_rad, departure_rad, breakover_rad),
        strict=True) if value is not None)
    notes: list[str] = []
    if clearance_m is None:
        if breakover_rad is not None:
            clearance_m = 0.5 * wheelbase_m * math.tan(0.5 * breakover_rad)
            notes.append("ground clearance derived from the breakover angle")
        else:
            clearance_m = DEFAULT_CLEARANCE_M.get(vclass, 0.10)
            notes.append(f"ground clearance: default {clearance_m:.2f} m for {vclass} "
                         f"(no source)")
    derived = []

    def angle(value: float | None, name: str, run_m: float) -> float:
        if value is not None:
            return value
        derived.append(name)
        return math.pi / 2 if run_m <= 0 else math.atan2(clearance_m, run_m)

    approach = angle(approach_rad, "approach", front_overhang_m)
    departure = angle(departure_rad, "departure", rear_overhang_m)
    breakover = angle(breakover_rad, "breakover", 0.5 * wheelbase_m)
    if breakover_rad is None:
        breakover = 2.0 * breakover
    if derived:
        notes.append(f"{', '.join(derived)} derived from the ground clearance")
    return Underside(clearance_m, approach, departure, breakover, given,
                     "; ".join(notes) or "given")
