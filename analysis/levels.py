"""Levels: judging a vehicle only against the lanes and junctions of its own storey.

A parking helix or a garage lies over itself in plan; judged in plan, a vehicle on the upper
floor would be measured against the lanes of the floor below (docs/design.md §6, "Levels").

Definitions
-----------
Band
    A vehicle whose path is at height ``z`` meets only the parts of lanes and junctions whose
    height lies within ``z +- LEVEL_BAND_M`` (1.5 m). A storey's clear height is about
    2.1-2.5 m, so a floor-to-floor height of at least 2.4 m always puts the next floor
    outside the band, and a ramp's own lane a metre above or below stays inside it.
Level slot
    A curve's heights are cut into slots of ``LEVEL_STEP_M`` (1.0 m) from its lowest point
    up (:func:`level_slots`); each slot's areas hold the parts of lanes and junctions
    within the band of the slot's middle height ``z_m``. A run's path is cut into stretches
    by the slot its height lies in (:func:`path_segments`, with a hysteresis of
    :data:`SLOT_HYSTERESIS_M`), so a part within 0.75 m of a station's height is always
    met there, and one more than 2.25 m away never is. The slots are of heights, not of
    stations, so that a swung path (which has its own stations) meets the same storeys.
Corridor
    A stretch judges the envelope swept while some part of the vehicle is on it, cut to
    the stretch's corridor: the points within a vehicle's reach of its part of the path,
    between the normals at its ends (:func:`corridor`). The corridors of consecutive
    stretches overlap by :data:`CORRIDOR_OVERLAP_M`, so that no wedge on the outside of a
    bend is left out. The verdict is the worst stretch's, the margins the least.

A network whose heights all lie within ``LEVEL_STEP_M`` of each other is flat: it has no
levels and is judged in plan, exactly as before.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from clearance.analysis.envelope import swept_path
from clearance.analysis.feature import feature_mask, slice_run
from clearance.analysis.tracking import TrackingRun

__all__ = ["CORRIDOR_OVERLAP_M", "LEVEL_BAND_M", "LEVEL_STEP_M", "Level", "SLOT_HYSTERESIS_M",
           "band_pieces", "corridor", "finite_min", "is_flat", "level_slots", "level_sweeps",
           "path_segments", "worst_first"]

LEVEL_BAND_M = 1.5
"""A vehicle meets the parts of lanes and junctions within this height of its own (m)."""

LEVEL_STEP_M = 1.0
"""The heights of one level segment's stations lie within this of each other (m)."""

CORRIDOR_OVERLAP_M = 0.5
"""Consecutive segments' corridors overlap by this along the path (m)."""


@dataclass(frozen=True)
class Level:
    """One storey of a curve: a slot of heights and the areas of the parts near it.

    Attributes
    ----------
    z_lo_m, z_hi_m
        The slot (m): the stations of a path whose height lies in it are judged against
        :attr:`areas` (:func:`path_segments`).
    areas
        Own lanes, paved area and roadway of that storey
        (:class:`clearance.analysis.clearance.Areas`):
        the parts within :data:`LEVEL_BAND_M` of :attr:`z_m`.
    """

    z_lo_m: float
    z_hi_m: float
    areas: Any  # clearance.analysis.clearance.Areas (which holds levels: not imported here)

    @property
    def z_m(self) -> float:
        """The slot's middle height (m)."""
        return 0.5 * (self.z_lo_m + self.z_hi_m)


def level_slots(z_m: np.ndarray, step_m: float = LEVEL_STEP_M) -> list[tuple[float, float]]:
    """Slots of ``step_m`` of height from the lowest of ``z_m`` up past the highest.

    Examples
    --------
    >>> level_slots(np.array([0.0, 2.5]))
    [(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)]
    >>> level_slots(np.array([4.0, 4.0]))
    [(4.0, 5.0)]
    """
    lo, hi = float(np.min(z_m)), float(np.max(z_m))
    n = max(int(math.floor((hi - lo) / step_m)) + 1, 1)
    return [(lo + k * step_m, lo + (k + 1) * step_m) for k in range(n)]


#: A path stays in its slot while its height is within this of the slot (m), so that a
#: floor at a slot's edge does not flicker between two.
SLOT_HYSTERESIS_M = 0.25


def path_segments(
    s_m: np.ndarray, z_m: np.ndarray, levels: Sequence[Level]
) -> list[tuple[float, float, int]]:
    """A path cut into stretches by the level slot its height lies in.

    Returns ``(start_m, end_m, level index)`` rows covering ``s_m[0] .. s_m[-1]``: a
    stretch ends where the height leaves its slot by more than
    :data:`SLOT_HYSTERESIS_M` (at the midpoint between the two stations); a height beyond
    every slot takes the nearest.

    Examples
    --------
    >>> lv = [Level(0.0, 1.0, None), Level(1.0, 2.0, None)]
    >>> path_segments(np.array([0.0, 10.0, 20.0]), np.array([0.0, 1.1, 1.6]), lv)
    [(0.0, 15.0, 0), (15.0, 20.0, 1)]
    >>> path_segments(np.array([0.0, 10.0]), np.array([5.0, 5.0]), lv)
    [(0.0, 10.0, 1)]
    """
    mids = np.array([lv.z_m for lv in levels])

    def nearest(z: float) -> int:
        return int(np.argmin(np.abs(mids - z)))

    out: list[tuple[float, float, int]] = []
    current, start = nearest(float(z_m[0])), float(s_m[0])
    for i in range(1, len(s_m)):
        lv, z = levels[current], float(z_m[i])
        if lv.z_lo_m - SLOT_HYSTERESIS_M <= z <= lv.z_hi_m + SLOT_HYSTERESIS_M:
            continue
        k = nearest(z)
        if k == current:  # beyond the last slot: it stays
            continue
        cut = 0.5 * (float(s_m[i - 1]) + float(s_m[i]))
        out.append((start, cut, current))
        current, start = k, cut
    out.append((start, float(s_m[-1]), current))
    return out


def is_flat(z_m: np.ndarray, step_m: float = LEVEL_STEP_M) -> bool:
    """True when every height lies within ``step_m`` of every other (one level, in plan).

    Examples
    --------
    >>> is_flat(np.array([0.0, 0.4, 0.9])), is_flat(np.array([0.0, 1.2])), is_flat(np.empty(0))
    (True, False, True)
    """
    return not len(z_m) or float(np.max(z_m) - np.min(z_m)) <= step_m


def band_pieces(shape: np.ndarray, z_lo: float, z_hi: float) -> list[np.ndarray]:
    """The pieces of a polyline ``(N, 3)`` whose height lies within ``z_lo .. z_hi``, as
    ``(M, 2)`` plane polylines (height linear along each segment; crossings interpolated).

    Examples
    --------
    A line rising from 0 to 4 m over 40 m: its part within 1 .. 2 m lies at 10 .. 20 m.

    >>> line = np.array([[0.0, 0.0, 0.0], [40.0, 0.0, 4.0]])
    >>> [p.tolist() for p in band_pieces(line, 1.0, 2.0)]
    [[[10.0, 0.0], [20.0, 0.0]]]
    >>> band_pieces(line, 5.0, 6.0)  # above it
    []
    >>> [len(p) for p in band_pieces(np.array([[0, 0, 0.0], [5, 0, 0.0], [9, 0, 0.0]]), -1, 1)]
    [3]
    """
    pts = np.asarray(shape, dtype=float)
    if len(pts) == 1:
        return [pts[:, :2].copy()] if z_lo <= pts[0, 2] <= z_hi else []
    pieces: list[np.ndarray] = []
    current: list[np.ndarray] = []
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        za, zb = a[2], b[2]
        if za == zb:
            t0, t1 = (0.0, 1.0) if z_lo <= za <= z_hi else (1.0, 0.0)
        else:
            ta, tb = (z_lo - za) / (zb - za), (z_hi - za) / (zb - za)
            t0, t1 = max(min(ta, tb), 0.0), min(max(ta, tb), 1.0)
        if t0 > t1:  # this segment lies outside the band
            if len(current) > 1:
                pieces.append(np.array(current))
            current = []
            continue
        p0, p1 = a[:2] + t0 * (b[:2] - a[:2]), a[:2] + t1 * (b[:2] - a[:2])
        if current and (t0 > 0.0 or not np.allclose(current[-1], p0)):
            if len(current) > 1:
                pieces.append(np.array(current))
            current = []
        if not current:
            current = [p0]
        current.append(p1)
        if t1 < 1.0:  # leaves the band inside this segment
            if len(current) > 1:
                pieces.append(np.array(current))
            current = []
    if len(current) > 1:
        pieces.append(np.array(current))
    return pieces


def corridor(path_xy: np.ndarray, s_m: np.ndarray, start_m: float, end_m: float,
             reach_m: float) -> BaseGeometry:
    """The points within ``reach_m`` of a stretch ``start_m .. end_m`` of a plane path
    (flat ends: between the normals at the stretch's ends).

    ``path_xy`` ``(N, 2)`` with stations ``s_m``; a stretch beyond the path's ends is cut
    to them (the envelope is trimmed at the path's ends anyway).

    Examples
    --------
    >>> xy = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> corridor(xy, np.array([0.0, 10.0]), 2.0, 5.0, 1.0).bounds
    (2.0, -1.0, 5.0, 1.0)
    >>> round(corridor(xy, np.array([0.0, 10.0]), 4.0, 4.0, 1.0).area, 6)  # one station
    0.0
    """
    a, b = max(start_m, float(s_m[0])), min(end_m, float(s_m[-1]))
    inner = (s_m > a) & (s_m < b)
    xs = np.interp([a, b], s_m, path_xy[:, 0])
    ys = np.interp([a, b], s_m, path_xy[:, 1])
    pts = np.vstack([[xs[0], ys[0]], path_xy[inner], [xs[1], ys[1]]])
    keep = np.concatenate(([True], np.hypot(*np.diff(pts, axis=0).T) > 1e-9))
    pts = pts[keep]
    if len(pts) < 2:
        return shapely.Polygon()
    return shapely.buffer(shapely.LineString(pts), reach_m, cap_style="flat", quad_segs=8)


def level_sweeps(
    run: TrackingRun,
    levels: Sequence[Level],
    mask: np.ndarray | None,
    offset_m: float,
    boxes: BaseGeometry | None,
    steps: tuple[float, float],
    feature_m: tuple[float, float] | None,
) -> list[tuple[Level, tuple[float, float], BaseGeometry, np.ndarray | None]]:
    """Each level stretch's part of a run's sweep, as judged, and its swept widths.

    The run's path is cut by height into stretches (:func:`path_segments`). A stretch
    judges the sweep while some part of the vehicle is on it (and, with ``mask``, among the
    feature's samples), grown by ``offset_m``, cut to its :func:`corridor` and trimmed by
    ``boxes`` (the path's end boxes), against its level's areas; its swept widths are those
    of its stations in the feature (``feature_m``) on that sweep alone (one passage),
    ``(K, 2)`` rows of (station, width), or None when it holds none of the feature.
    ``steps`` are the sweep's tolerance and the width step (m). Returns
    ``(level, (start_m, end_m), judged part, widths)`` for the stretches whose judged part
    is not empty; none for a path without heights.

    Examples
    --------
    A car up a 30 m ramp rising 3 m, in slots of 1 m: three stretches, each a part of the
    sweep; a path without heights has none.

    >>> from clearance.analysis.polyline import prepare_path
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> levels = [Level(float(k), k + 1.0, None) for k in range(3)]
    >>> run = simulate(car, prepare_path([(0.0, 0.0, 0.0), (30.0, 0.0, 3.0)]))
    >>> parts = level_sweeps(run, levels, None, 0.0, None, (0.02, 0.5), None)
    >>> [round(lv.z_m, 1) for lv, *_ in parts], [round(float(w[:, 1].max()), 2) for *_, w in parts]
    ([0.5, 1.5, 2.5], [1.8, 1.8, 1.8])
    >>> level_sweeps(simulate(car, prepare_path([(0.0, 0.0), (30.0, 0.0)])), levels, None, 0.0,
    ...              None, (0.02, 0.5), None)
    []
    """
    path = run.path
    if path.z is None or not levels:
        return []
    v = run.vehicle
    reach = v.overall_length_m + v.width_m + offset_m + 1.0
    if v.trailer is not None:
        reach += v.trailer.wheelbase_m + v.trailer.front_overhang_m + v.trailer.width_m
    lo_f, hi_f = feature_m if feature_m is not None else (-math.inf, math.inf)
    out: list[tuple[Level, tuple[float, float], BaseGeometry, np.ndarray | None]] = []
    for start, end, k in path_segments(path.station_m, path.z, levels):
        a, b = start - CORRIDOR_OVERLAP_M, end + CORRIDOR_OVERLAP_M
        m = feature_mask(run, (a, b))
        if mask is not None:
            m &= mask
        keep = np.flatnonzero(m)
        if not len(keep):
            continue
        part = slice_run(run, np.arange(max(int(keep[0]) - 1, 0),
                                        min(int(keep[-1]) + 1, len(m) - 1) + 1))
        stations = (max(start, lo_f), min(end, hi_f))
        some = stations[0] <= stations[1]
        sp = swept_path(part, steps[0], steps[1], stations_m=stations if some else None)
        env = sp.envelope
        if offset_m > 0:
            env = shapely.buffer(env, offset_m, quad_segs=8)
        env = shapely.intersection(env, corridor(path.xy, path.station_m, a, b, reach))
        if boxes is not None:
            env = shapely.difference(env, boxes)
        if shapely.area(env) >= 1e-6:
            out.append((levels[k], (start, end), env, sp.swept_width_m if some else None))
    return out


def worst_first(verdicts: tuple[str, ...], verdict: str) -> int:
    """Rank of a verdict in ``verdicts`` (worst first); unknown verdicts rank last.

    Examples
    --------
    >>> worst_first(("fails", "clear"), "clear"), worst_first(("fails", "clear"), "odd")
    (1, 2)
    """
    return verdicts.index(verdict) if verdict in verdicts else len(verdicts)


def finite_min(values: list[float]) -> float:
    """The least of the values that are not ``nan`` (``nan`` when none is).

    Examples
    --------
    >>> finite_min([0.3, math.nan, -0.1]), math.isnan(finite_min([math.nan]))
    (-0.1, True)
    """
    kept = [v for v in values if not math.isnan(v)]
    return min(kept) if kept else math.nan
