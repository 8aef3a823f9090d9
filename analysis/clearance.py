"""Clearance of a swept envelope against the three nested areas, and the run's verdict.

Verdicts (docs/design.md §6), worst first:

``cannot-turn``
    The steering point could not follow the centre line within the tolerance (the curve is
    tighter than the lock or the steering rate allows), or the trailer jackknifed.
``fails``
    The (offset) envelope leaves the paved area.
``encroaches``
    It leaves its own lanes but stays paved.
``clear``
    It stays within its own lanes.

Margins are signed distances between the envelope (grown by the clearance offset) and an
area: ``>= 0`` is the smallest gap between the envelope and the area's boundary when the
envelope lies inside the area; ``< 0`` is minus how far the envelope reaches beyond it (the
largest distance from the area of any point of the envelope outside it, sought on that
outside part's boundary by branch and bound to within ``densify_m / 2``
(:func:`farthest_on_lines`), or at the pole of inaccessibility of a piece the envelope
covers whole, such as an island).
``margin_m`` is the margin to the own lanes, the one that decides between ``clear`` and
``encroaches``. An overreach smaller than :data:`PRECISION_M` counts as zero: SUMO writes
network coordinates to the centimetre, and its lanes kink where a smooth path does not.

A run starts with the front axle on the centre line's first point, so the body then hangs
back over whatever precedes the curve, and it ends with the front overhang past the last
point. :func:`evaluate` therefore trims the (grown) envelope at the centre line's end
normals before measuring (:func:`end_boxes`): only what is swept between the curve's ends
counts, and the areas' boundaries there (the lanes' ends, which the trimmed envelope
touches) do not count for the gap. A path that loops back across its own start within a
body length would lose that part too; pass ``trim_ends=False`` there.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from analysis.envelope import (
    DEFAULT_TOLERANCE_M,
    DEFAULT_WIDTH_STEP_M,
    SweptPath,
    ring_segments,
    swept_path,
)
from analysis.feature import feature_mask, feature_reason, slice_run
from analysis.kernels import farthest_from_segments, segments_distance
from analysis.levels import Level, finite_min, level_sweeps, worst_first
from analysis.polyline import Path
from analysis.tracking import TrackingRun
from vehicles.errors import InputError

__all__ = ["Areas", "Clearance", "DEFAULT_DENSIFY_M", "END_SLACK_M", "NEAR_M", "NOTHING_SWEPT",
           "PRECISION_M",
           "RunResult", "VERDICTS", "classify", "end_boxes", "evaluate", "evaluate_batch",
           "farthest_on_lines", "signed_margin_m", "worst_level"]

VERDICTS = ("cannot-turn", "fails", "encroaches", "clear")
"""Verdicts, worst first."""

DEFAULT_DENSIFY_M = 0.05
"""An overreach is found to within half this (m); also the pole-of-inaccessibility tolerance."""

NEAR_M = 5.0
"""Margins are first sought within this distance of the envelope's bounding box (m)."""

END_SLACK_M = 0.1
"""Boundaries this close to the trimmed ends of a run do not count (m): they are cuts."""

PRECISION_M = 0.01
"""Overreach below this (m) is within the network's precision and counts as a zero margin."""


def _within_precision(margin: float) -> float:
    """``margin``, with an overreach under :data:`PRECISION_M` taken as zero.

    Examples
    --------
    >>> _within_precision(-0.004), _within_precision(-0.02), _within_precision(0.3)
    (0.0, -0.02, 0.3)
    """
    return 0.0 if -PRECISION_M < margin < 0 else margin


def _check_area(name: str, geom: BaseGeometry | None, required: bool) -> None:
    if geom is None:
        if required:
            raise InputError(f"clearance areas: {name} is missing")
        return
    if not isinstance(geom, BaseGeometry) or geom.geom_type not in ("Polygon", "MultiPolygon"):
        kind = getattr(geom, "geom_type", type(geom).__name__)
        raise InputError(f"clearance areas: {name} must be a Polygon or MultiPolygon, got {kind}")
    if geom.is_empty:
        raise InputError(f"clearance areas: {name} is empty")
    if not geom.is_valid:
        raise InputError(f"clearance areas: {name} is not a valid polygon: "
                         f"{shapely.is_valid_reason(geom)}")


def _check_offset(offset_m: float) -> None:
    if not (isinstance(offset_m, int | float) and math.isfinite(offset_m) and offset_m >= 0):
        raise InputError(f"clearance offset must be a number >= 0 m, got {offset_m!r}")


def _grown(clearance: Clearance, offset_m: float) -> str:
    """The reason of a clearance measured on an envelope grown beforehand by ``offset_m``."""
    if offset_m <= 0 or clearance.verdict == "cannot-turn":
        return clearance.reason
    return clearance.reason.replace("the envelope", f"the envelope (grown by {offset_m:.2f} m)", 1)


@dataclass(frozen=True)
class Areas:
    """The nested areas a curve's verdict is measured against (shapely, metres).

    Attributes
    ----------
    own_lanes
        The curve's own lanes.
    paved
        All lanes plus the junction polygons.
    roadway
        The roadway of the same direction (e.g. the roundabout's ring), or ``None``; its
        margin is reported, it does not change the verdict.
    levels
        The curve's level segments, each with the areas of its storey
        (:class:`analysis.levels.Level`); empty (the default) judges in plan against the
        three areas above. :func:`evaluate` then judges each segment's part of the sweep
        against its own storey's areas.

    Examples
    --------
    >>> a = Areas(shapely.box(0, 0, 10, 3), shapely.box(0, -3, 10, 6))
    >>> a.roadway is None
    True
    >>> Areas(shapely.box(0, 0, 10, 3), shapely.LineString([(0, 0), (1, 1)]))
    Traceback (most recent call last):
    ...
    vehicles.errors.InputError: clearance areas: paved must be a Polygon or MultiPolygon, ...
    """

    own_lanes: BaseGeometry
    paved: BaseGeometry
    roadway: BaseGeometry | None = None
    levels: tuple[Level, ...] = ()
    _boundaries: dict[str, BaseGeometry] = field(init=False, repr=False, compare=False)
    _segments: dict[str, np.ndarray] = field(init=False, repr=False, compare=False,
                                             default_factory=dict)

    def __post_init__(self) -> None:
        _check_area("own_lanes", self.own_lanes, True)
        _check_area("paved", self.paved, True)
        _check_area("roadway", self.roadway, False)
        bounds = {}
        for name in ("own_lanes", "paved", "roadway"):
            geom = getattr(self, name)
            if geom is not None:
                shapely.prepare(geom)
                bounds[name] = shapely.boundary(geom)
        object.__setattr__(self, "_boundaries", bounds)

    def boundary(self, name: str) -> BaseGeometry:
        """Boundary (all rings) of the named area."""
        return self._boundaries[name]

    def segments(self, name: str) -> np.ndarray:
        """Boundary segments of the named area, ``(k, 2, 2)`` (found once, when first asked).

        Examples
        --------
        >>> Areas(shapely.box(0, 0, 10, 3), shapely.box(0, -3, 10, 6)).segments("paved")[0]
        array([[10., -3.],
               [10.,  6.]])
        """
        if name not in self._segments:
            self._segments[name] = np.stack(ring_segments(getattr(self, name)), axis=1)
        return self._segments[name]


def signed_margin_m(
    envelope: BaseGeometry,
    area: BaseGeometry,
    area_boundary: BaseGeometry | None = None,
    densify_m: float = DEFAULT_DENSIFY_M,
    ignore: BaseGeometry | None = None,
    area_segments: np.ndarray | None = None,
) -> float:
    """Signed margin of an envelope in an area (see the module docstring).

    ``ignore`` (optional) is a region where the area's boundary does not count for the gap
    inside: the lanes' ends where the envelope was trimmed (:func:`end_boxes`).
    ``area_segments`` (optional) are the area's boundary segments (:meth:`Areas.segments`),
    found here when not given.

    Examples
    --------
    A 2 m wide envelope centred in a 3.5 m lane has 0.75 m to spare on each side:

    >>> lane = shapely.box(0.0, 0.0, 50.0, 3.5)
    >>> signed_margin_m(shapely.box(10.0, 0.75, 20.0, 2.75), lane)
    0.75

    Shifted 1 m to the left it reaches 0.25 m beyond the lane:

    >>> signed_margin_m(shapely.box(10.0, 1.75, 20.0, 3.75), lane)
    -0.25

    Exactly on the boundary the margin is zero:

    >>> signed_margin_m(shapely.box(10.0, 1.5, 20.0, 3.5), lane)
    0.0
    """
    if envelope.is_empty:
        raise InputError("signed_margin_m: the envelope is empty")
    beyond = None  # the envelope beyond the area, computed only when it is not covered
    if not shapely.covers(area, envelope):  # a quick test against the prepared area first
        beyond = shapely.difference(envelope, area)
    outside = beyond
    if beyond is not None and ignore is not None and shapely.area(beyond) >= 1e-6:
        outside = shapely.difference(beyond, ignore)
    if outside is None or shapely.area(outside) < 1e-6:
        # covered, but for slivers under a square millimetre (floating-point noise along a
        # shared edge) and what pokes out in the ignored region (past the trimmed ends)
        boundary = area_boundary if area_boundary is not None else shapely.boundary(area)
        # Only the boundary near the envelope can be nearest: look within a window first
        # (a junction's boundary is long, an envelope local), the whole boundary if need be.
        x0, y0, x1, y1 = envelope.bounds
        for reach in (NEAR_M, math.inf):
            near = boundary
            if math.isfinite(reach):
                near = shapely.clip_by_rect(boundary, x0 - reach, y0 - reach, x1 + reach,
                                            y1 + reach)
            if ignore is not None:
                near = shapely.difference(near, ignore)
            if near.is_empty:
                continue
            gap = float(shapely.distance(envelope, near))
            if gap <= reach:
                return gap
        return math.inf
    # the deepest point lies on the envelope's boundary beyond the area, or, where a piece
    # beyond the area holds none of it (an island the envelope covers whole), at the
    # piece's pole of inaccessibility
    lines = shapely.difference(shapely.boundary(envelope), area)
    pieces = shapely.get_parts(beyond)
    pieces = pieces[~shapely.is_empty(pieces) & (shapely.area(pieces) > 0)]
    lone = pieces[~shapely.intersects(pieces, lines)] if not lines.is_empty else pieces
    extra = np.empty((0, 2))
    if len(lone):
        circles = shapely.maximum_inscribed_circle(lone, densify_m)
        extra = shapely.get_coordinates(shapely.get_point(circles, 0))
    coords, part = shapely.get_coordinates(shapely.get_parts(lines), return_index=True)
    probe = np.concatenate([coords, extra])
    if not len(probe):
        return 0.0
    # Distances to the area's boundary segments that reach into a window about the probes
    # first (every probe lies outside the area, so its distance to the area is that to the
    # boundary): one no larger than the window's margin is exact (the nearest boundary point
    # then lies in the window, on one of those segments); a larger one is measured on the area.
    segs = area_segments if area_segments is not None else np.stack(ring_segments(area), axis=1)
    lo, hi = probe.min(axis=0) - NEAR_M, probe.max(axis=0) + NEAR_M
    into = (np.all(np.maximum(segs[:, 0], segs[:, 1]) >= lo, axis=1)
            & np.all(np.minimum(segs[:, 0], segs[:, 1]) <= hi, axis=1))
    segs = np.ascontiguousarray(segs[into])

    def distance(xy: np.ndarray) -> np.ndarray:
        d = segments_distance(xy, segs)
        far = ~(d <= NEAR_M)
        if far.any():
            d[far] = shapely.distance(shapely.points(xy[far]), area)
        return d

    # compiled; the same search with the area's own distance when a probe is beyond the window
    deepest = farthest_from_segments(coords, part[1:] == part[:-1], segs, densify_m / 2, NEAR_M)
    if math.isnan(deepest):
        deepest = farthest_on_lines(lines, distance, densify_m / 2)
    if len(extra):
        deepest = max(deepest, float(np.max(distance(extra))))
    return -deepest


def farthest_on_lines(
    lines: BaseGeometry,
    distance: Callable[[np.ndarray], np.ndarray],
    tolerance_m: float,
) -> float:
    """Largest value of a distance function over lines, found to within ``tolerance_m``.

    ``distance`` maps ``(k, 2)`` points to ``(k,)`` distances and must be 1-Lipschitz (a
    distance to a fixed set is). Branch and bound: on a segment of length ``L`` whose ends
    are at ``d_a`` and ``d_b`` no point is farther than ``(d_a + d_b + L) / 2``, so only
    segments that could beat the best point found so far by more than the tolerance are
    halved and probed at their midpoints, until none is left. The result is short of the
    true maximum by at most ``tolerance_m``, with far fewer probes than an even densification
    where most of the lines are not the farthest.

    Examples
    --------
    The distance from a circle of radius 1 about the origin, along a 10 m segment through it:

    >>> line = shapely.LineString([(-5.0, 0.2), (5.0, 0.2)])
    >>> to_circle = lambda p: np.abs(np.hypot(p[:, 0], p[:, 1]) - 1.0)
    >>> round(farthest_on_lines(line, to_circle, 0.01), 2)
    4.0

    The farthest point inside a segment, not at its ends (the distance to the x axis along a
    roof line); and no lines at all:

    >>> roof = shapely.LineString([(0.0, 0.0), (4.0, 3.0), (8.0, 0.0)])
    >>> farthest_on_lines(roof, lambda p: np.abs(p[:, 1]), 0.01)
    3.0
    >>> farthest_on_lines(shapely.LineString(), lambda p: np.abs(p[:, 1]), 0.01)
    0.0
    """
    coords, part = shapely.get_coordinates(shapely.get_parts(lines), return_index=True)
    if not len(coords):
        return 0.0
    d = distance(coords)
    best = float(np.max(d))
    joined = part[1:] == part[:-1]
    a, b = coords[:-1][joined], coords[1:][joined]
    da, db = d[:-1][joined], d[1:][joined]
    while len(a):
        bound = 0.5 * (da + db + np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]))
        open_ = bound > best + tolerance_m
        if not open_.any():
            break
        a, b, da, db = a[open_], b[open_], da[open_], db[open_]
        mid = 0.5 * (a + b)
        dm = distance(mid)
        best = max(best, float(np.max(dm)))
        a, b = np.concatenate([a, mid]), np.concatenate([mid, b])
        da, db = np.concatenate([da, dm]), np.concatenate([dm, db])
    return best


@dataclass(frozen=True)
class Clearance:
    """Verdict and margins of one envelope.

    Attributes
    ----------
    verdict
        One of :data:`VERDICTS`.
    margin_m
        Signed margin to the own lanes (decides clear / encroaches).
    paved_margin_m
        Signed margin to the paved area (decides fails).
    roadway_margin_m
        Signed margin to the same-direction roadway, or ``None`` when not given.
    offset_m
        Clearance offset the envelope was grown by first.
    reason
        Why the verdict is what it is, in words.
    """

    verdict: str
    margin_m: float
    paved_margin_m: float
    roadway_margin_m: float | None
    offset_m: float
    reason: str


#: The reason of a run whose envelope holds nothing to judge (never ``clear``).
NOTHING_SWEPT = ("nothing was swept between the feature's ends: the curve is shorter than one "
                 "step of the model, or has no lane to be judged against")


def classify(
    envelope: BaseGeometry,
    areas: Areas,
    offset_m: float = 0.0,
    cannot_turn_reason: str = "",
    densify_m: float = DEFAULT_DENSIFY_M,
    ignore: BaseGeometry | None = None,
) -> Clearance:
    """Margins and verdict of an envelope against the areas.

    Parameters
    ----------
    envelope
        Swept envelope (Polygon or MultiPolygon, metres).
    areas
        Own lanes, paved area and optionally the roadway.
    offset_m
        Clearance offset (m, >= 0): the envelope is buffered by it first.
    cannot_turn_reason
        Non-empty when the run could not follow the curve: the verdict is then
        ``cannot-turn`` whatever the margins.
    densify_m
        An overreach is found to within half this (m).
    ignore
        Region where the areas' boundaries do not count for the gaps (see
        :func:`signed_margin_m`).

    Examples
    --------
    >>> areas = Areas(shapely.box(0, 0, 50, 3.5), shapely.box(0, -0.5, 50, 7.0))
    >>> classify(shapely.box(10, 0.75, 20, 2.75), areas).verdict
    'clear'
    >>> c = classify(shapely.box(10, 0.75, 20, 2.75), areas, offset_m=0.3)
    >>> c.verdict, round(c.margin_m, 9)
    ('clear', 0.45)
    >>> classify(shapely.box(10, 2.0, 20, 4.0), areas).verdict
    'encroaches'
    >>> classify(shapely.box(10, -1.0, 20, 1.0), areas).verdict
    'fails'
    >>> classify(shapely.box(10, 0.75, 20, 2.75), areas, cannot_turn_reason="lock").verdict
    'cannot-turn'
    >>> classify(shapely.Polygon(), areas).verdict  # nothing swept: nothing is clear
    'cannot-turn'
    """
    _check_offset(offset_m)
    grown = shapely.buffer(envelope, offset_m, quad_segs=8) if offset_m > 0 else envelope
    if grown.is_empty:
        # the run stopped before its body swept anything between the curve's ends, or the
        # curve is shorter than one step of the model (a network drawn 10,000 times too
        # small): nothing was judged, so nothing is clear
        return Clearance("cannot-turn", math.nan, math.nan, None, float(offset_m),
                         cannot_turn_reason or NOTHING_SWEPT)
    margins = {}
    for name in ("own_lanes", "paved", "roadway"):
        area = getattr(areas, name)
        if area is not None:
            margins[name] = _within_precision(signed_margin_m(
                grown, area, areas.boundary(name), densify_m, ignore, areas.segments(name)))
    own, paved, road = margins["own_lanes"], margins["paved"], margins.get("roadway")
    if not (math.isfinite(own) and math.isfinite(paved)):  # no area to judge against
        return Clearance("cannot-turn", math.nan, math.nan, None, float(offset_m),
                         cannot_turn_reason or NOTHING_SWEPT)
    grown_by = f" (grown by {offset_m:.2f} m)" if offset_m > 0 else ""
    if cannot_turn_reason:
        verdict, reason = "cannot-turn", cannot_turn_reason
    elif paved < 0:
        verdict = "fails"
        reason = f"the envelope{grown_by} leaves the paved area by {-paved:.2f} m"
    elif own < 0:
        verdict = "encroaches"
        reason = f"the envelope{grown_by} leaves its own lanes by {-own:.2f} m, stays paved"
    else:
        verdict = "clear"
        reason = f"the envelope{grown_by} stays {own:.2f} m inside its own lanes"
    return Clearance(verdict, own, paved, road, float(offset_m), reason)


def end_boxes(path: Path, reach_m: float) -> BaseGeometry:
    """Two boxes beyond the path's ends: what lies in them is trimmed from the envelope.

    One box lies behind the start line (the normal through the first point), ``reach_m``
    long and ``2 reach_m`` wide, aligned with the path's initial heading; the other past the
    end line likewise.

    Examples
    --------
    A straight 10 m path: the body behind the start and ahead of the end goes.

    >>> from analysis.polyline import prepare_path
    >>> p = prepare_path([(0.0, 0.0), (10.0, 0.0)])
    >>> boxes = end_boxes(p, 8.0)
    >>> shapely.difference(shapely.box(-5.0, -1.0, 12.0, 1.0), boxes).bounds
    (0.0, -1.0, 10.0, 1.0)

    Nothing is cut from an envelope that stays between the ends:

    >>> shapely.difference(shapely.box(1.0, -1.0, 9.0, 1.0), boxes).area
    16.0
    """
    point = path.xy[[0, -1]]  # both ends at once: behind the start, past the end
    heading = path.heading_rad[[0, -1]]
    u = np.array([[-1.0], [1.0]]) * np.stack([np.cos(heading), np.sin(heading)], axis=1)
    n = np.stack([-u[:, 1], u[:, 0]], axis=1)
    corners = np.stack([point + reach_m * n, point - reach_m * n,
                        point - reach_m * n + reach_m * u, point + reach_m * n + reach_m * u],
                       axis=1)
    return shapely.union_all(shapely.polygons(corners))


@dataclass(frozen=True)
class RunResult:
    """A run, its swept path and its clearance.

    Attributes
    ----------
    run
        The tracking run.
    swept
        Envelope, wheel tracks, offtracking and swept width.
    clearance
        Verdict and margins.
    measured
        The envelope as measured: grown by the offset, trimmed at the path's ends.
    """

    run: TrackingRun
    swept: SweptPath
    clearance: Clearance
    measured: BaseGeometry

    @property
    def verdict(self) -> str:
        """The verdict, one of :data:`VERDICTS`."""
        return self.clearance.verdict

    @property
    def margin_m(self) -> float:
        """Signed margin to the own lanes."""
        return self.clearance.margin_m


def evaluate(
    run: TrackingRun,
    areas: Areas,
    offset_m: float = 0.0,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    width_step_m: float = DEFAULT_WIDTH_STEP_M,
    trim_ends: bool = True,
    feature_m: tuple[float, float] | None = None,
) -> RunResult:
    """Swept path, margins and verdict of one run.

    With ``feature_m`` (where the feature begins and ends along the centre line, e.g. a
    curve's ``core_start_m`` and ``core_end_m``), only the samples while some part of the
    vehicle is in the feature decide (:func:`analysis.feature.feature_mask`): the envelope
    is swept over them, and a tracking error beyond the tolerance counts only there
    (:func:`analysis.feature.feature_reason`). What happens on the lead-in and run-out
    belongs to the neighbouring curves. Without it the whole run decides.

    The envelope is grown by ``offset_m``, trimmed at the path's ends when ``trim_ends``
    (see the module docstring), then measured against the areas.

    Examples
    --------
    >>> from analysis.tracking import simulate
    >>> from vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 1.75), (30.0, 1.75)])
    >>> areas = Areas(shapely.box(-10, 0, 40, 3.5), shapely.box(-10, -3.5, 40, 7.0))
    >>> r = evaluate(run, areas, offset_m=0.3)
    >>> r.verdict, round(r.margin_m, 9)
    ('clear', 0.55)
    """
    _check_offset(offset_m)
    reason = run.reason
    judged = run
    mask = None
    if feature_m is not None:
        mask = feature_mask(run, feature_m)
        reason = feature_reason(run, mask)
        keep = np.flatnonzero(mask)
        if len(keep) >= 1:
            # one sample either side: the sweep into and out of the window
            lo, hi = max(int(keep[0]) - 1, 0), min(int(keep[-1]) + 1, len(mask) - 1)
            judged = slice_run(run, np.arange(lo, hi + 1))
    swept = swept_path(judged, tolerance_m=tolerance_m, width_step_m=width_step_m,
                       stations_m=feature_m)
    measured = swept.envelope
    if offset_m > 0:
        measured = shapely.buffer(measured, offset_m, quad_segs=8)
    ignore = boxes = None
    if trim_ends:
        v = run.vehicle
        reach = v.overall_length_m + max(v.width_m, v.trailer.width_m if v.trailer else 0.0)
        boxes = end_boxes(run.path, reach + offset_m + 1.0)
        measured = shapely.difference(measured, boxes)
        # the lanes' end lines, which the trimmed envelope meets at the (smoothed) path's
        # end normal; a lane's flat end follows its last chord, a few degrees off that
        ignore = shapely.buffer(boxes, END_SLACK_M, quad_segs=1)
    parts = []
    if areas.levels:  # each level's part of the sweep against its own storey's areas
        parts = level_sweeps(run, areas.levels, mask, offset_m, boxes,
                             (tolerance_m, width_step_m), feature_m)
    if not parts:
        clearance = classify(measured, areas, 0.0, reason, ignore=ignore)
    else:
        clearance = worst_level([(lv, where, classify(env, lv.areas, 0.0, reason,
                                                        ignore=ignore))
                                  for lv, where, env, _ in parts])
        rows = [w for _, _, _, w in parts if w is not None]
        if rows:
            widths = np.concatenate(rows)
            widths = widths[np.argsort(widths[:, 0], kind="stable")]
            i_w = int(np.argmax(widths[:, 1]))
            swept = dataclasses.replace(swept, swept_width_m=widths,
                                        max_swept_width_m=float(widths[i_w, 1]),
                                        max_swept_width_station_m=float(widths[i_w, 0]))
    return RunResult(run, swept, dataclasses.replace(clearance, offset_m=float(offset_m),
                                                     reason=_grown(clearance, offset_m)),
                     measured)


def worst_level(found: list[tuple[Level, tuple[float, float], Clearance]]) -> Clearance:
    """The worst level stretch's verdict and reason (naming it), the least margins
    (:mod:`analysis.levels`; ``found`` holds each stretch's level, its stations and its
    clearance).

    Examples
    --------
    >>> from analysis.levels import Level
    >>> lv = Level(0.0, 1.0, None)
    >>> a = Clearance("clear", 0.2, 0.5, None, 0.0, "stays")
    >>> b = Clearance("encroaches", -0.1, 0.3, None, 0.0, "leaves")
    >>> c = worst_level([(lv, (0.0, 10.0), a), (lv, (10.0, 20.0), b)])
    >>> c.verdict, c.margin_m, c.paved_margin_m, c.reason
    ('encroaches', -0.1, 0.3, 'leaves (on the level at 0.5 m, stations 10.0-20.0 m)')
    """
    lv, (a, b), worst = min(found, key=lambda f: (worst_first(VERDICTS, f[2].verdict),
                                                  f[2].margin_m))
    roads = [c.roadway_margin_m for _, _, c in found if c.roadway_margin_m is not None]
    where = "" if worst.verdict == "cannot-turn" else (
        f" (on the level at {lv.z_m:.1f} m, stations {a:.1f}-{b:.1f} m)")
    return Clearance(worst.verdict, finite_min([c.margin_m for _, _, c in found]),
                     finite_min([c.paved_margin_m for _, _, c in found]),
                     finite_min(roads) if roads else None, worst.offset_m, worst.reason + where)


def evaluate_batch(
    runs: Sequence[TrackingRun],
    areas: Areas | Sequence[Areas],
    offset_m: float = 0.0,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    width_step_m: float = DEFAULT_WIDTH_STEP_M,
) -> list[RunResult]:
    """:func:`evaluate` for many runs: one :class:`Areas` for all, or one per run.

    Examples
    --------
    >>> evaluate_batch([], Areas(shapely.box(0, 0, 1, 1), shapely.box(0, 0, 2, 2)))
    []
    """
    if isinstance(areas, Areas):
        per_run = [areas] * len(runs)
    else:
        per_run = list(areas)
        if len(per_run) != len(runs):
            raise InputError(f"evaluate_batch: {len(runs)} runs but {len(per_run)} area sets")
    return [evaluate(r, a, offset_m, tolerance_m, width_step_m)
            for r, a in zip(runs, per_run, strict=True)]
