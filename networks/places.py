"""Where along a curve a point lies: on the approach edge, in the feature, on the exit edge.

A verdict's worst conflict has a station on the curve's centre line
(:attr:`clearance.reports.results.records.RunRecord.overreach_station_m`). :func:`place_of`
names the part of the network that station is on, with its distance from the feature, so that
a conflict is charged to where it happens: a conflict on the approach edge a bus length before
the junction lies on that edge, not in the junction's turn, and where that edge bends there
(a ``bend`` curve of its own, or a kink of its drawn shape) the conflict is the bend's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clearance.networks.curves import Curve
from clearance.networks.model import Network
from clearance.networks.paths import junction_of_internal

__all__ = ["KINK_DEG", "Place", "core_span", "feature_ends", "kink_near", "place_of"]

#: A lane shape turning by more than this at one point (degrees) is a kink (a drawn corner
#: of the edge's own geometry, not a curve a driver follows).
KINK_DEG = 20.0

#: How far either side of a station a kink of the lane counts as "there" (m).
KINK_REACH_M = 4.0

#: Where in a feature the station is, by curve kind.
_FEATURE = {"turn": "in junction", "uturn": "in junction", "roundabout": "on the ring of",
            "ramp": "on the ramp from"}


@dataclass(frozen=True)
class Place:
    """A station's place on a curve.

    Attributes
    ----------
    part
        ``approach``, ``feature`` or ``exit``.
    lane
        The lane the station is on (the feature's first lane inside it).
    distance_m
        Along the centre line from the feature (before its start on the approach, after its
        end on the exit; 0 inside).
    kink_deg
        The largest turn of the lane's own drawn shape within :data:`KINK_REACH_M` of the
        station (degrees; 0 in the feature).
    words
        The place in words: ``approach E1 9.8 m before J5``, ``in junction J5``,
        ``exit E3 2.0 m after J5``; with ``, at a 35° kink of E1`` where the lane kinks there.
    """

    part: str
    lane: str
    distance_m: float
    kink_deg: float
    words: str


def core_span(curve: Curve) -> tuple[int, int] | None:
    """Indices in ``curve.lanes`` of the feature's first and last lane; None when no lane of
    the feature is among them.

    >>> from types import SimpleNamespace as C
    >>> core_span(C(lanes=("a_0", ":J_0_0", "b_0"), core_lanes=(":J_0_0",)))
    (1, 1)
    >>> core_span(C(lanes=("a_0",), core_lanes=("x_0",))) is None
    True
    """
    core = set(curve.core_lanes)
    idx = [i for i, k in enumerate(curve.lanes) if k in core]
    return (idx[0], idx[-1]) if idx else None


def feature_ends(net: Network, curve: Curve) -> tuple[str | None, str | None]:
    """The normal lanes the curve's feature is entered from and left onto (the approach
    lane and the exit lane; None where the curve has none).

    >>> from types import SimpleNamespace as S
    >>> lanes = {k: S(is_internal=k.startswith(":")) for k in ("a_0", ":J_0_0", "b_0")}
    >>> feature_ends(S(lanes=lanes), S(lanes=("a_0", ":J_0_0", "b_0"), core_lanes=(":J_0_0",)))
    ('a_0', 'b_0')
    """
    span = core_span(curve)
    if span is None:
        return None, None
    normal = [k in net.lanes and not net.lanes[k].is_internal for k in curve.lanes]
    before = [k for k, ok in zip(curve.lanes[:span[0]], normal, strict=False) if ok]
    after = [k for k, ok in zip(curve.lanes[span[1] + 1:], normal[span[1] + 1:], strict=True)
             if ok]
    return (before[-1] if before else None), (after[0] if after else None)


def place_of(net: Network, curve: Curve, station_m: float) -> Place | None:
    """The place of ``station_m`` (m along ``curve.centerline``); None for NaN.

    The lanes before the feature are walked back from its start by their lengths, those
    after it forward from its end, so the lane found is the network's even where the
    centre line's lead-in was cut.

    Examples
    --------
    >>> from clearance.networks.reader import read_network
    >>> from clearance.networks.curves import extract_curves
    >>> net = read_network("networks/samples/intersection/intersection.net.xml")
    >>> c = next(c for c in extract_curves(net, ("turn",), areas=False) if c.junction == "X")
    >>> place_of(net, c, c.core_start_m - 4.0).words.endswith("4.0 m before X")
    True
    >>> place_of(net, c, (c.core_start_m + c.core_end_m) / 2).words
    'in junction X'
    >>> place_of(net, c, math.nan) is None
    True
    """
    if not math.isfinite(station_m):
        return None
    first, last = core_span(curve) or (0, 0)
    feature = f"{_FEATURE.get(curve.kind, 'at')} {curve.junction}"
    if curve.kind == "bend":  # a bend is its lane's, not a junction's
        feature = f"in the bend of {_element(net, curve.lanes[first])}"
    if station_m < curve.core_start_m:
        d = curve.core_start_m - station_m
        lane, into = _walk(net, curve.lanes[:first][::-1], d)
        where = f"approach {_element(net, lane)}"
        words = f"{where} {d:.1f} m before {curve.junction}"
        return _with_kink(net, Place("approach", lane, d, 0.0, words), into, backwards=True)
    if station_m > curve.core_end_m:
        d = station_m - curve.core_end_m
        lane, into = _walk(net, curve.lanes[last + 1:], d)
        where = f"exit {_element(net, lane)}"
        words = f"{where} {d:.1f} m after {curve.junction}"
        return _with_kink(net, Place("exit", lane, d, 0.0, words), into, backwards=False)
    return Place("feature", curve.lanes[first], 0.0, 0.0, feature)


def _element(net: Network, lane_id: str) -> str:
    """A lane's edge, or for a junction's internal lane, ``through junction J``."""
    lane = net.lanes.get(lane_id)
    if lane is None:
        return lane_id
    return f"through junction {junction_of_internal(lane_id)}" if lane.is_internal else lane.edge


def _walk(net: Network, lanes: tuple[str, ...], d: float) -> tuple[str, float]:
    """The lane ``d`` metres along ``lanes`` (each walked whole, in the order given) and how
    far into it; the last lane when ``d`` is beyond them all."""
    if not lanes:
        return "", d
    for k in lanes:
        length = net.lane_line(k)[1] if k in net.lanes else 0.0
        if d <= length:
            return k, d
        d -= length
    return lanes[-1], d


def _with_kink(net: Network, place: Place, into_m: float, backwards: bool) -> Place:
    lane = net.lanes.get(place.lane)
    if lane is None or lane.is_internal:
        return place
    pts, length = net.lane_line(place.lane)
    at = length - into_m if backwards else into_m  # from the lane's start
    kink = kink_near(pts[:, :2], at, KINK_REACH_M)
    if kink < KINK_DEG:
        return Place(place.part, place.lane, place.distance_m, kink, place.words)
    return Place(place.part, place.lane, place.distance_m, kink,
                 f"{place.words}, at a {kink:.0f}° kink of {lane.edge}")


def kink_near(xy: np.ndarray, at_m: float, reach_m: float) -> float:
    """The largest turn (degrees) of a polyline at one of its inner points within
    ``reach_m`` of station ``at_m`` (0 when no inner point is that near).

    Examples
    --------
    >>> line = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 10.0]])
    >>> round(kink_near(line, 9.0, 2.0), 1), kink_near(line, 2.0, 2.0)
    (45.0, 0.0)
    >>> kink_near(np.array([[0.0, 0.0], [1.0, 0.0]]), 0.5, 2.0)  # no inner point
    0.0
    """
    if len(xy) < 3:
        return 0.0
    d = np.diff(xy, axis=0)
    s = np.concatenate(([0.0], np.cumsum(np.hypot(d[:, 0], d[:, 1]))))
    heading = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.degrees((np.diff(heading) + np.pi) % (2 * np.pi) - np.pi))
    near = np.abs(s[1:-1] - at_m) <= reach_m
    return float(turn[near].max()) if near.any() else 0.0
