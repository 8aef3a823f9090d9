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

``margin_m`` is the margin to the own lanes (:mod:`clearance.analysis.margins`), the one
that decides between ``clear`` and ``encroaches``.

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
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from clearance.analysis.envelope import (
    DEFAULT_TOLERANCE_M,
    DEFAULT_WIDTH_STEP_M,
    SweptPath,
    ring_segments,
    swept_envelope,
    swept_path,
)
from clearance.analysis.feature import feature_mask, feature_reason, slice_run
from clearance.analysis.levels import Level, finite_min, level_sweeps, worst_first
from clearance.analysis.margins import DEFAULT_DENSIFY_M, signed_margin_m, within_precision
from clearance.analysis.polyline import Path
from clearance.analysis.tracking import TrackingRun
from clearance.vehicles.errors import GeometryError

__all__ = ["Areas", "Clearance", "END_SLACK_M", "NOTHING_SWEPT", "RunResult", "VERDICTS",
           "classify", "end_boxes", "evaluate", "evaluate_batch", "judge", "judged_part",
           "worst_level"]

VERDICTS = ("cannot-turn", "fails", "encroaches", "clear")
"""Verdicts, worst first."""


END_SLACK_M = 0.1
"""Boundaries this close to the trimmed ends of a run do not count (m): they are cuts."""


def _check_area(name: str, geom: BaseGeometry | None, required: bool) -> None:
    if geom is None:
        if required:
            raise GeometryError(f"clearance areas: {name} is missing")
        return
    if not isinstance(geom, BaseGeometry) or geom.geom_type not in ("Polygon", "MultiPolygon"):
        kind = getattr(geom, "geom_type", type(geom).__name__)
        raise GeometryError(f"clearance areas: {name} must be a Polygon or MultiPolygon, "
                            f"got {kind}")
    if geom.is_empty:
        raise GeometryError(f"clearance areas: {name} is empty")
    if not geom.is_valid:
        raise GeometryError(f"clearance areas: {name} is not a valid polygon: "
                         f"{shapely.is_valid_reason(geom)}")


def _check_offset(offset_m: float) -> None:
    if not (isinstance(offset_m, int | float) and math.isfinite(offset_m) and offset_m >= 0):
        raise ValueError(f"clearance offset must be a number >= 0 m, got {offset_m!r}")


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
        (:class:`clearance.analysis.levels.Level`); empty (the default) judges in plan against the
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
    clearance.vehicles.errors.GeometryError: clearance areas: paved must be a Polygon or ...
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
        :func:`~clearance.analysis.margins.signed_margin_m`).

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
            margins[name] = within_precision(signed_margin_m(
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

    >>> from clearance.analysis.polyline import prepare_path
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
    vehicle is in the feature decide (:func:`clearance.analysis.feature.feature_mask`): the envelope
    is swept over them, and a tracking error beyond the tolerance counts only there
    (:func:`clearance.analysis.feature.feature_reason`). What happens on the lead-in and run-out
    belongs to the neighbouring curves. Without it the whole run decides.

    The envelope is grown by ``offset_m``, trimmed at the path's ends when ``trim_ends``
    (see the module docstring), then measured against the areas.

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 1.75), (30.0, 1.75)])
    >>> areas = Areas(shapely.box(-10, 0, 40, 3.5), shapely.box(-10, -3.5, 40, 7.0))
    >>> r = evaluate(run, areas, offset_m=0.3)
    >>> r.verdict, round(r.margin_m, 9)
    ('clear', 0.55)
    """
    _check_offset(offset_m)
    reason, judged, mask = judged_part(run, feature_m)
    swept = swept_path(judged, tolerance_m=tolerance_m, width_step_m=width_step_m,
                       stations_m=feature_m)
    measured, boxes, ignore = _measured(swept.envelope, run, offset_m, trim_ends)
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


def judge(
    run: TrackingRun,
    areas: Areas,
    offset_m: float = 0.0,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    feature_m: tuple[float, float] | None = None,
) -> Clearance:
    """The clearance :func:`evaluate` gives a run, without the rest of its result.

    A search judging many candidate paths reads only their clearances; the envelope is
    swept and measured as :func:`evaluate` does (the same verdict and margins), but the
    wheel tracks, offtracking and swept widths are not computed. On a network with levels
    it is :func:`evaluate`'s clearance.

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 1.75), (30.0, 1.75)])
    >>> areas = Areas(shapely.box(-10, 0, 40, 3.5), shapely.box(-10, -3.5, 40, 7.0))
    >>> judge(run, areas, offset_m=0.3) == evaluate(run, areas, offset_m=0.3).clearance
    True
    >>> judge(run, areas, feature_m=(5.0, 10.0)) == evaluate(run, areas,
    ...                                                    feature_m=(5.0, 10.0)).clearance
    True

    A window the run never reaches (the degenerate case) judges the whole run, as
    :func:`evaluate` does:

    >>> judge(run, areas, feature_m=(100.0, 110.0)) == judge(run, areas)
    True
    """
    if areas.levels:
        return evaluate(run, areas, offset_m, tolerance_m, feature_m=feature_m).clearance
    _check_offset(offset_m)
    reason, judged, _ = judged_part(run, feature_m)
    measured, _, ignore = _measured(swept_envelope(judged, tolerance_m)[0], run, offset_m, True)
    clearance = classify(measured, areas, 0.0, reason, ignore=ignore)
    return dataclasses.replace(clearance, offset_m=float(offset_m),
                               reason=_grown(clearance, offset_m))


def judged_part(run: TrackingRun, feature_m: tuple[float, float] | None
                ) -> tuple[str, TrackingRun, np.ndarray | None]:
    """What decides a run over a window (see :func:`evaluate`): the reason it cannot be
    driven there (``""``: it can), its samples there with one either side, and the mask.

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 0.0), (30.0, 0.0)])
    >>> reason, part, mask = judged_part(run, None)  # no window: the whole run
    >>> reason, part is run, mask
    ('', True, None)
    >>> len(judged_part(run, (10.0, 12.0))[1].trajectory.s_m) < len(run.trajectory.s_m)
    True
    """
    if feature_m is None:
        return run.reason, run, None
    mask = feature_mask(run, feature_m)
    keep = np.flatnonzero(mask)
    judged = run
    if len(keep) >= 1:
        # one sample either side: the sweep into and out of the window
        lo, hi = max(int(keep[0]) - 1, 0), min(int(keep[-1]) + 1, len(mask) - 1)
        judged = slice_run(run, np.arange(lo, hi + 1))
    return feature_reason(run, mask), judged, mask


def _measured(envelope: BaseGeometry, run: TrackingRun, offset_m: float, trim_ends: bool
              ) -> tuple[BaseGeometry, BaseGeometry | None, BaseGeometry | None]:
    """The envelope grown by the offset and trimmed at the path's ends; the end boxes and
    the region where the areas' boundaries do not count (both ``None`` untrimmed)."""
    measured = envelope
    if offset_m > 0:
        measured = shapely.buffer(measured, offset_m, quad_segs=8)
    if not trim_ends:
        return measured, None, None
    v = run.vehicle
    reach = v.overall_length_m + max(v.width_m, v.trailer.width_m if v.trailer else 0.0)
    boxes = end_boxes(run.path, reach + offset_m + 1.0)
    # the lanes' end lines, which the trimmed envelope meets at the (smoothed) path's end
    # normal; a lane's flat end follows its last chord, a few degrees off that
    return (shapely.difference(measured, boxes), boxes,
            shapely.buffer(boxes, END_SLACK_M, quad_segs=1))


def worst_level(found: list[tuple[Level, tuple[float, float], Clearance]]) -> Clearance:
    """The worst level stretch's verdict and reason (naming it), the least margins
    (:mod:`clearance.analysis.levels`; ``found`` holds each stretch's level, its stations and its
    clearance).

    Examples
    --------
    >>> from clearance.analysis.levels import Level
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
            raise ValueError(f"evaluate_batch: {len(runs)} runs but {len(per_run)} area sets")
    return [evaluate(r, a, offset_m, tolerance_m, width_step_m)
            for r, a in zip(runs, per_run, strict=True)]
