"""The shapes of swung paths: offset profiles of a centre line, and corner cuts.

The curves :mod:`clearance.networks.driving.candidates` makes its candidates from (docs/design.md
§6,
*Paths*): the offset profile ``d(s)`` of a *held* swing (:func:`offset_profile`, its ramps
:func:`ramp_bounds`) and of a *fitted* one (:func:`shaped_profile`), the inward
:func:`apex_bump` of a feature that is not one corner, the :func:`corner_cut` of one that
is, and the centre line moved by a profile (:func:`offset_path`). Lengths in metres,
offsets left positive unless a function says "toward the outside".
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from clearance.analysis.polyline import Path, prepare_path

__all__ = ["apex_bump", "corner_cut", "kept_part", "max_curvature_1_m", "moved", "nearest_on",
           "offset_path", "offset_profile", "offset_run", "ramp_bounds", "shaped_profile"]

FloatArray = NDArray[np.float64]


def _half_cosine(t: FloatArray) -> FloatArray:
    """0 at ``t <= 0``, 1 at ``t >= 1``, a half cosine between."""
    return 0.5 - 0.5 * np.cos(math.pi * np.clip(t, 0.0, 1.0))


def ramp_bounds(length_m: float, feature_m: tuple[float, float], ramp_m: float
                ) -> tuple[float, float, float, float]:
    """Where the ramps in and out begin and end along a centre line of ``length_m``.

    Returns ``(a, b, c, e)``: up from ``a`` to ``b``, down from ``c`` to ``e``.

    Examples
    --------
    Room for whole ramps; a lead-in too short for one (the ramp ends inside the feature):

    >>> ramp_bounds(60.0, (25.0, 35.0), 8.0)
    (17.0, 25.0, 35.0, 43.0)
    >>> ramp_bounds(60.0, (2.0, 12.0), 8.0)
    (0.0, 4.0, 12.0, 20.0)

    A feature that fills the line: the ramps meet in its middle.

    >>> ramp_bounds(10.0, (0.0, 10.0), 8.0)
    (0.0, 4.0, 6.0, 10.0)
    """
    cs, ce = max(0.0, feature_m[0]), min(length_m, feature_m[1])
    mid = 0.5 * (cs + ce)
    a = max(0.0, cs - ramp_m)
    b = cs if cs - a >= 0.5 * ramp_m else min(a + 0.5 * ramp_m, mid)
    e = min(length_m, ce + ramp_m)
    c = ce if e - ce >= 0.5 * ramp_m else max(e - 0.5 * ramp_m, mid)
    return a, b, c, e


def offset_profile(station_m: FloatArray, feature_m: tuple[float, float], amplitude_m: float,
                   ramp_m: float, apex_cut: float = 0.0) -> FloatArray:
    """The offset ``d(s) >= 0`` of a swung path (toward the outside; the caller signs it).

    Examples
    --------
    Zero before the ramp and after it, the amplitude over the feature:

    >>> s = np.arange(0.0, 61.0, 1.0)
    >>> d = offset_profile(s, (25.0, 35.0), 2.0, 8.0)
    >>> [round(float(d[k]), 9) for k in (10, 21, 30, 50)]
    [0.0, 1.0, 2.0, 0.0]

    A cut of one half brings the middle of the feature back to half the amplitude:

    >>> float(offset_profile(s, (25.0, 35.0), 2.0, 8.0, apex_cut=0.5)[30])
    1.0

    A zero amplitude is the centre line itself:

    >>> bool(np.all(offset_profile(s, (25.0, 35.0), 0.0, 8.0) == 0.0))
    True
    """
    s = np.asarray(station_m, dtype=float)
    a, b, c, e = ramp_bounds(float(s[-1]), feature_m, ramp_m)
    up = _half_cosine((s - a) / (b - a)) if b > a else (s >= a).astype(float)
    down = 1.0 - (_half_cosine((s - c) / (e - c)) if e > c else (s > c).astype(float))
    d = amplitude_m * np.minimum(up, down)
    lo, hi = 0.5 * (a + b), 0.5 * (c + e)  # the cut spans the feature and half the ramps
    if apex_cut > 0 and hi > lo:
        inside = (s > lo) & (s < hi)
        d[inside] *= 1.0 - apex_cut * np.sin(math.pi * (s[inside] - lo) / (hi - lo)) ** 2
    return np.asarray(d, dtype=np.float64)


def shaped_profile(station_m: FloatArray, feature_m: tuple[float, float], start_m: float,
                   end_m: float, ramp_in_m: float, ramp_out_m: float, apex_cut: float = 0.0
                   ) -> FloatArray:
    """The offset of a *fitted* swung path (toward the outside; see the module docstring).

    Up to ``start_m`` over the ramp in, a half cosine across the feature to ``end_m``,
    down over the ramp out; times ``1 - apex_cut sin^2`` between the ramps' middles.

    Examples
    --------
    Equal ends are :func:`offset_profile`:

    >>> s = np.arange(0.0, 61.0, 1.0)
    >>> bool(np.allclose(shaped_profile(s, (25.0, 35.0), 2.0, 2.0, 8.0, 8.0, 0.3),
    ...                  offset_profile(s, (25.0, 35.0), 2.0, 8.0, 0.3)))
    True

    Wide before the turn, narrow after it:

    >>> d = shaped_profile(s, (25.0, 35.0), 3.0, 0.5, 12.0, 6.0)
    >>> [round(float(d[k]), 6) for k in (10, 25, 30, 35, 41)]
    [0.0, 3.0, 1.75, 0.5, 0.0]
    """
    s = np.asarray(station_m, dtype=float)
    length = float(s[-1])
    a, b, _, _ = ramp_bounds(length, feature_m, ramp_in_m)
    _, _, c, e = ramp_bounds(length, feature_m, ramp_out_m)
    up = _half_cosine((s - a) / (b - a)) if b > a else (s >= a).astype(float)
    down = 1.0 - (_half_cosine((s - c) / (e - c)) if e > c else (s > c).astype(float))
    across = start_m + (end_m - start_m) * (_half_cosine((s - b) / (c - b)) if c > b
                                            else (s > b).astype(float))
    d = np.where(s < b, start_m * up, np.where(s > c, end_m * down, across))
    lo, hi = 0.5 * (a + b), 0.5 * (c + e)
    if apex_cut > 0 and hi > lo:
        inside = (s > lo) & (s < hi)
        d[inside] *= 1.0 - apex_cut * np.sin(math.pi * (s[inside] - lo) / (hi - lo)) ** 2
    return np.asarray(d, dtype=np.float64)


def apex_bump(station_m: FloatArray, feature_m: tuple[float, float], depth_m: float,
              ramp_m: float) -> FloatArray:
    """``depth_m sin^2(pi (s - a) / (e - a))`` over the manoeuvre ``[a, e]`` of
    :func:`ramp_bounds` (toward the inside; the caller signs it), zero outside it.

    Examples
    --------
    >>> s = np.arange(0.0, 61.0, 1.0)
    >>> d = apex_bump(s, (25.0, 35.0), 1.5, 6.0)
    >>> [round(float(d[k]), 6) for k in (19, 30, 41)]
    [0.0, 1.5, 0.0]
    """
    s = np.asarray(station_m, dtype=float)
    a, _, _, e = ramp_bounds(float(s[-1]), feature_m, ramp_m)
    if not e > a:
        return np.zeros(len(s))
    t = np.clip((s - a) / (e - a), 0.0, 1.0)
    return np.asarray(depth_m * np.sin(math.pi * t) ** 2, dtype=np.float64)


def corner_cut(path: Path, feature_m: tuple[float, float], lead_m: float,
               name: str | None = None) -> tuple[Path, FloatArray, FloatArray, tuple[float, float]]:
    """The path that cuts a turn's corner: the centre line up to ``lead_m`` before the
    feature, a cubic Hermite curve tangent to it there and ``lead_m`` after the feature,
    the centre line again from there.

    The Hermite's end tangents are ``c 2 tan(theta / 4) / sin(theta / 2)`` long (``c`` the
    chord, ``theta`` the turn between the two ends): the length that makes it a circular
    arc, to within 0.03 % of the radius, when the two ends are alike.

    Returns the path, the signed lateral offset of each centre-line point to it (left
    positive) and its station there, and ``(start, end)``: where it leaves and rejoins the
    centre line, along the new path.

    Examples
    --------
    A right angle drawn with a 4 m radius; cut from 6 m before it to 6 m after it, the
    corner becomes an arc of radius 10 m: its apex 6 (sqrt 2 - 1) = 2.49 m inside:

    >>> a = np.radians(np.linspace(90, 0, 46))
    >>> arc = np.c_[4 * np.cos(a), 25 + 4 * np.sin(a)]
    >>> p = prepare_path(np.vstack([[(-25.0, 29.0)], arc, [(4.0, 0.0)]]), 0.1)
    >>> q, d, st, (s0, s1) = corner_cut(p, (25.0, 25.0 + 2 * math.pi), 6.0)
    >>> round(float(-np.min(d)), 2), round(1 / max_curvature_1_m(q)), round(s0, 1)
    (2.49, 10, 19.0)

    No lead (or a feature of no length at the line's ends) leaves the line as it is:

    >>> corner_cut(p, (25.0, 25.0 + 2 * math.pi), 0.0)[0] is p
    True
    """
    s = path.station_m
    s0 = max(0.0, feature_m[0] - lead_m)
    s1 = min(path.length_m, feature_m[1] + lead_m)
    i0 = int(np.searchsorted(s, s0, side="right")) - 1
    i1 = int(np.searchsorted(s, s1, side="left"))
    if lead_m <= 0 or i1 - i0 < 2 or i1 >= len(s):
        return path, np.zeros(len(s)), s.copy(), (float(s0), float(s1))
    p0, p1 = path.xy[i0], path.xy[i1]
    h0, h1 = float(path.heading_rad[i0]), float(path.heading_rad[i1])
    theta = abs(math.remainder(h1 - h0, 2 * math.pi))
    chord = float(np.hypot(*(p1 - p0)))
    scale = chord * (2 * math.tan(theta / 4) / math.sin(theta / 2) if theta > 1e-6 else 1.0)
    t0 = scale * np.array([math.cos(h0), math.sin(h0)])
    t1 = scale * np.array([math.cos(h1), math.sin(h1)])
    u = np.linspace(0.0, 1.0, max(8, int(math.ceil(2.0 * chord / path.spacing_m))))[:, None]
    curve = ((2 * u**3 - 3 * u**2 + 1) * p0 + (u**3 - 2 * u**2 + u) * t0
             + (-2 * u**3 + 3 * u**2) * p1 + (u**3 - u**2) * t1)
    xy = np.vstack([path.xy[:i0], curve, path.xy[i1 + 1:]])
    pts: NDArray[np.float64] = xy
    if path.z is not None:
        z_mid = np.interp(np.linspace(s[i0], s[i1], len(curve)), s, path.z)
        pts = np.column_stack([xy, np.concatenate([path.z[:i0], z_mid, path.z[i1 + 1:]])])
    new = prepare_path(pts, path.spacing_m, name=name or path.name)
    # the points up to i0 and from i1 on are the new path's own: only those between move
    cut_m = new.length_m - (path.length_m - s[i1]) - s[i0]  # the Hermite's length
    guess = s[i0] + (s[i0:i1 + 1] - s[i0]) * (cut_m / (s[i1] - s[i0]))
    mid_station, near = nearest_on(new.xy, path.xy[i0:i1 + 1], guess)
    station = np.concatenate([s[:i0], mid_station, s[i1 + 1:] - s[i1] + mid_station[-1]])
    h = path.heading_rad[i0:i1 + 1]
    d = np.zeros(len(s))
    d[i0:i1 + 1] = ((near[:, 0] - path.xy[i0:i1 + 1, 0]) * -np.sin(h)
                    + (near[:, 1] - path.xy[i0:i1 + 1, 1]) * np.cos(h))
    d[i0] = d[i1] = 0.0
    return new, d, station, (float(station[i0]), float(station[i1]))


def nearest_on(line_xy: FloatArray, points_xy: FloatArray,
               guess_m: FloatArray | None = None, band_m: float = 3.0
               ) -> tuple[FloatArray, FloatArray]:
    """Each point's nearest point on a polyline, and its station there (m).

    What ``shapely.line_locate_point`` and ``line_interpolate_point`` give (the first of
    equally near segments wins), for all the points in one numpy step. With ``guess_m``
    (a station near each point's answer) only the segments within ``band_m`` of it are
    searched: shapely's calls walked the whole line once per point, a quarter of a study's
    time on real networks.

    Examples
    --------
    >>> line = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]])
    >>> st, near = nearest_on(line, np.array([[1.0, -0.5], [3.0, 1.5], [-1.0, 0.0]]))
    >>> st.tolist(), near.tolist()
    ([1.0, 3.5, 0.0], [[1.0, 0.0], [2.0, 1.5], [0.0, 0.0]])

    Searched near a guess of 0 m only, the second point finds the first segment's end:

    >>> nearest_on(line, np.array([[3.0, 1.5]]), np.zeros(1), 0.5)[0].tolist()
    [2.0]

    A line of one segment of no length is its one point:

    >>> nearest_on(np.array([[1.0, 1.0], [1.0, 1.0]]), np.array([[0.0, 0.0]]))[1].tolist()
    [[1.0, 1.0]]
    """
    a, ab = line_xy[:-1], np.diff(line_xy, axis=0)
    length = np.hypot(ab[:, 0], ab[:, 1])
    start = np.concatenate([[0.0], np.cumsum(length)])[:-1]
    if guess_m is None:
        k = np.broadcast_to(np.arange(len(a)), (len(points_xy), len(a)))
    else:
        lo = np.maximum(np.searchsorted(start, np.asarray(guess_m) - band_m, "right") - 1, 0)
        hi = np.searchsorted(start, np.asarray(guess_m) + band_m, side="right")
        width = max(1, int(np.max(hi - lo))) if len(lo) else 1
        k = np.clip(lo[:, None] + np.arange(width), 0, len(a) - 1)
    p = points_xy[:, None, :]
    sa, sab = a[k], ab[k]
    t = np.clip(np.sum((p - sa) * sab, axis=2) / np.maximum(length[k] ** 2, 1e-300), 0.0, 1.0)
    foot = sa + t[..., None] * sab
    j = np.argmin(np.sum((p - foot) ** 2, axis=2), axis=1)
    rows = np.arange(len(points_xy))
    kk = k[rows, j]
    station = start[kk] + t[rows, j] * length[kk]
    return np.asarray(station, dtype=np.float64), np.asarray(foot[rows, j], dtype=np.float64)


def offset_path(path: Path, offset_m: FloatArray, name: str | None = None) -> Path:
    """The path moved sideways by ``offset_m`` at each of its points (left positive).

    Examples
    --------
    A straight line moved by 1.5 m is the parallel line 1.5 m to its left:

    >>> p = prepare_path([(0.0, 0.0), (10.0, 0.0)], spacing_m=0.5)
    >>> q = offset_path(p, np.full(len(p.xy), 1.5))
    >>> bool(np.allclose(q.xy[:, 1], 1.5)), q.length_m
    (True, 10.0)

    A zero offset is the path itself:

    >>> bool(np.allclose(offset_path(p, np.zeros(len(p.xy))).xy, p.xy))
    True
    """
    d = np.asarray(offset_m, dtype=float)
    if d.shape != (len(path.xy),):
        raise ValueError(f"{path.name}: one offset per point is needed, got {d.shape}")
    if not d.any():
        return path if name is None else dataclasses.replace(path, name=name)
    xy = moved(path, d)
    pts = xy if path.z is None else np.column_stack([xy, path.z])
    return prepare_path(pts, path.spacing_m, name=name or path.name)


def moved(path: Path, d: FloatArray) -> FloatArray:
    """The path's points moved by ``d`` along their left normals.

    Examples
    --------
    >>> p = prepare_path([(0.0, 0.0), (2.0, 0.0)], spacing_m=1.0)
    >>> moved(p, np.array([1.0, 0.0, -1.0])).tolist()
    [[0.0, 1.0], [1.0, 0.0], [2.0, -1.0]]
    """
    h = path.heading_rad
    return np.asarray(path.xy + d[:, None] * np.stack([-np.sin(h), np.cos(h)], axis=1),
                      dtype=np.float64)


def max_curvature_1_m(path: Path) -> float:
    """Largest absolute curvature of a path (1/m), as the follower sees it.

    Examples
    --------
    >>> a = np.radians(np.arange(0, 91, 2))
    >>> round(max_curvature_1_m(prepare_path(np.c_[8 * np.cos(a), 8 * np.sin(a)])), 3)
    0.125
    """
    return float(np.max(np.abs(path.curvature_1_m))) if len(path.xy) else 0.0


def offset_run(path: Path, lane: Path, keep: slice, d: FloatArray,
               span_m: tuple[float, float], feature_m: tuple[float, float], name: str
               ) -> tuple[Path, tuple[float, float], FloatArray]:
    """A swung path ready to drive: ``lane`` (the points ``keep`` of ``path``) moved by
    ``d``; the judged window on it (the manoeuvre ``span_m`` and the feature, both in
    ``path``'s stations, on the offset line's stations); and the offset line's station at
    each of the lane's points (the station map).

    Examples
    --------
    A straight line moved 1 m left: the window keeps its stations.

    >>> p = prepare_path([(0.0, 0.0), (20.0, 0.0)], spacing_m=1.0)
    >>> q, window, smap = offset_run(p, p, slice(None), np.ones(21), (4.0, 16.0),
    ...                              (8.0, 12.0), "moved")
    >>> float(q.xy[0, 1]), window, float(smap[-1])
    (1.0, (4.0, 16.0), 20.0)

    A zero offset is the lane itself:

    >>> offset_run(p, p, slice(None), np.zeros(21), (4.0, 16.0), (8.0, 12.0), "x")[1]
    (4.0, 16.0)
    """
    p = offset_path(lane, d, name=name)
    smap = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(moved(lane, d), axis=0).T))])
    ls, s0 = lane.station_m, path.station_m[keep][0]
    window = (float(np.interp(min(span_m[0], feature_m[0]) - s0, ls, smap)),
              float(np.interp(max(span_m[1], feature_m[1]) - s0, ls, smap)))
    return p, window, smap


def kept_part(path: Path, a: float, e: float, reach_m: float | None) -> tuple[Path, slice]:
    """The part of ``path`` from ``reach_m`` before station ``a`` to ``reach_m`` after
    ``e`` (all of it without ``reach_m``), its stations from 0, and the slice of its points.

    Examples
    --------
    >>> p = prepare_path([(0.0, 0.0), (60.0, 0.0)], spacing_m=1.0)
    >>> part, keep = kept_part(p, 20.0, 30.0, 5.0)
    >>> keep, float(part.xy[0, 0]), part.length_m
    (slice(15, 36, None), 15.0, 20.0)
    >>> kept_part(p, 20.0, 30.0, None)[1]
    slice(None, None, None)
    """
    if reach_m is None:
        return path, slice(None)
    s = path.station_m
    i0 = int(np.searchsorted(s, a - reach_m, side="right")) - 1
    i1 = int(np.searchsorted(s, e + reach_m, side="left")) + 1
    keep = slice(max(i0, 0), min(i1, len(s)))
    st = path.station_m[keep] - path.station_m[keep][0]
    part = Path(path.name, path.xy[keep], None if path.z is None else path.z[keep], st,
                path.heading_rad[keep], path.curvature_1_m[keep], path.spacing_m,
                float(st[-1]))
    return part, keep
