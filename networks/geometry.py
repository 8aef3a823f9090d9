"""Plane geometry of polylines: arc length, headings, curvature over arc length, grades.

Headings are mathematical (radians, counter-clockwise from +x); left turns are positive.
Curvature is fitted over arc length, not from vertex angles: the heading of a polyline is
taken as the heading of each chord at the chord's midpoint and interpolated linearly in
between, so the turn at a vertex is spread over the half-chords on either side. For points
on a circle of radius R with chords subtending α, this gives ``α / (2 R sin(α/2)) ≈ 1/R``
(0.6 % high for SUMO's five-point 90° internal lanes, α = 22.5°), independently of how
unevenly the points are spaced. A window of arc length then averages that curvature.
"""

from __future__ import annotations

import math

import numpy as np

from clearance.networks.profiles import profiles

__all__ = ["MIN_CHORD_M", "arc_length", "chord_headings", "clean_polyline", "curvature_profile",
           "cut_polyline", "grades_pct", "heading_at", "heading_rad_to_navigational",
           "navigational_to_heading_rad", "radius_from_curvature", "signed_turn_deg", "turns_back",
           "unwrap"]

#: Chords shorter than this (metres) are dropped before computing headings.
MIN_CHORD_M = 1e-6


def navigational_to_heading_rad(angle_deg: float | np.ndarray) -> float | np.ndarray:
    """Convert a SUMO angle (degrees clockwise from north) to a heading (rad, CCW from +x).

    Examples
    --------
    >>> round(navigational_to_heading_rad(90.0), 6)  # east
    0.0
    >>> round(navigational_to_heading_rad(0.0), 6)  # north
    1.570796
    """
    return (
        np.radians(90.0 - np.asarray(angle_deg))
        if np.ndim(angle_deg)
        else math.radians(90.0 - float(angle_deg))
    )


def heading_rad_to_navigational(heading_rad: float | np.ndarray) -> float | np.ndarray:
    """Convert a heading (rad, CCW from +x) to a SUMO angle in [0, 360) degrees.

    Examples
    --------
    >>> heading_rad_to_navigational(0.0)  # east
    90.0
    >>> heading_rad_to_navigational(math.pi / 2)  # north
    0.0
    """
    out = np.mod(90.0 - np.degrees(heading_rad), 360.0)
    return out if np.ndim(out) else float(out)


def clean_polyline(points: np.ndarray) -> np.ndarray:
    """Drop consecutive points closer than :data:`MIN_CHORD_M` in the plane.

    Examples
    --------
    >>> clean_polyline(np.array([[0, 0, 0], [0, 0, 1], [1, 0, 0.0]])).tolist()
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    pts = np.asarray(points, dtype=float)
    if len(pts) < 2:
        return pts
    d = pts[1:, :2] - pts[:-1, :2]
    step = np.hypot(d[:, 0], d[:, 1])
    if step.min() > MIN_CHORD_M:
        return pts
    keep = np.concatenate(([True], step > MIN_CHORD_M))
    return pts[keep]


def arc_length(points: np.ndarray) -> np.ndarray:
    """Cumulative plane arc length at each point (metres, starting at 0).

    Examples
    --------
    >>> arc_length(np.array([[0, 0], [3, 4], [3, 4]])).tolist()
    [0.0, 5.0, 5.0]
    """
    pts = np.asarray(points, dtype=float)
    out = np.zeros(len(pts))
    if len(pts) > 1:
        d = pts[1:, :2] - pts[:-1, :2]
        np.cumsum(np.hypot(d[:, 0], d[:, 1]), out=out[1:])
    return out


def chord_headings(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unwrapped chord headings (rad) and the arc length of each chord's midpoint.

    The points must be cleaned (:func:`clean_polyline`).

    Examples
    --------
    >>> h, s = chord_headings(np.array([[0, 0], [1, 0], [1, 1.0]]))
    >>> np.degrees(h).round(1).tolist(), s.tolist()
    ([0.0, 90.0], [0.5, 1.5])
    """
    pts = np.asarray(points, dtype=float)
    d = pts[1:, :2] - pts[:-1, :2]
    h = unwrap(np.arctan2(d[:, 1], d[:, 0]))
    s = arc_length(pts)
    return h, 0.5 * (s[:-1] + s[1:])


def unwrap(angles_rad: np.ndarray) -> np.ndarray:
    """Remove 2π jumps between consecutive angles (a lean ``numpy.unwrap``).

    Examples
    --------
    >>> np.degrees(unwrap(np.radians([170.0, -170.0]))).round(6).tolist()
    [170.0, 190.0]
    >>> unwrap(np.zeros(0)).size
    0
    """
    a = np.asarray(angles_rad, dtype=float)
    if len(a) < 2:
        return a.copy()
    d = a[1:] - a[:-1]
    d -= (2 * np.pi) * np.round(d / (2 * np.pi))
    out = np.empty_like(a)
    out[0] = a[0]
    np.cumsum(d, out=out[1:])
    out[1:] += a[0]
    return out


def heading_at(points: np.ndarray, s_m: np.ndarray) -> np.ndarray:
    """Smoothed, unwrapped heading (rad) at arc lengths ``s_m`` (linear between chord midpoints).

    Examples
    --------
    >>> pts = np.array([[0, 0], [2, 0], [2, 2.0]])
    >>> np.degrees(heading_at(pts, np.array([0.0, 2.0, 4.0]))).round(1).tolist()
    [0.0, 45.0, 90.0]
    """
    h, s_mid = chord_headings(points)
    return np.interp(s_m, s_mid, h)


def signed_turn_deg(points: np.ndarray) -> float:
    """Heading change from the first chord to the last (degrees, left positive, unwrapped).

    A U-turn to the left gives +180, a full loop to the right -360; a straight line 0.

    Examples
    --------
    >>> signed_turn_deg(np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]]))
    180.0
    >>> signed_turn_deg(np.array([[0, 0], [1, 0.0]]))
    0.0
    """
    pts = clean_polyline(points)
    if len(pts) < 3:
        return 0.0
    h, _ = chord_headings(pts)
    return float(np.degrees(h[-1] - h[0]))


def curvature_profile(
    points: np.ndarray,
    step_m: float = 0.25,
    window_m: float = 3.0,
    s_from_m: float = 0.0,
    s_to_m: float | None = None,
    adaptive: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Signed curvature (1/m, left positive) at stations along a polyline.

    Headings at chord midpoints (chords extended to at least
    :data:`~clearance.networks.profiles.MIN_CHORD_M`), interpolated, differenced over a window of
    ``window_m`` of arc length centred on each station (shrunk at the ends of the line);
    with ``adaptive``, a second pass uses a window of half the radius found (between
    ``window_m`` and :data:`MAX_WINDOW_M`). Stations are every ``step_m`` from
    ``s_from_m`` to ``s_to_m`` (default: the end). See :func:`clearance.networks.profiles.profiles`
    for many lines at once.

    Returns
    -------
    s_m, curvature_per_m
        Arrays of the same length (empty for a line of fewer than two distinct points).

    Examples
    --------
    A quarter circle of radius 10 m drawn with only five points:

    >>> a = np.linspace(0, np.pi / 2, 5)
    >>> s, k = curvature_profile(np.c_[10 * np.sin(a), 10 - 10 * np.cos(a)])
    >>> round(float(1 / k[len(k) // 2]), 1)
    9.9

    A straight line has zero curvature; a single point has no profile:

    >>> curvature_profile(np.array([[0, 0], [5, 0.0]]), step_m=2.5)[1].tolist()
    [0.0, 0.0, 0.0]
    >>> curvature_profile(np.array([[1.0, 1.0]]))[0].size
    0
    """
    pts = clean_polyline(points)
    if len(pts) < 2:
        return np.zeros(0), np.zeros(0)
    end = float(arc_length(pts)[-1]) if s_to_m is None else s_to_m
    p = profiles([pts], [s_from_m], [end], step_m, window_m, margin_m=0.0, adaptive=adaptive)
    return p.s_m[0], p.curvature_per_m[0]


def radius_from_curvature(curvature_per_m: np.ndarray) -> np.ndarray:
    """Radius (m) of each curvature value, ``inf`` where the line is straight.

    Examples
    --------
    >>> radius_from_curvature(np.array([0.1, -0.05, 0.0])).tolist()
    [10.0, 20.0, inf]
    """
    k = np.abs(np.asarray(curvature_per_m, dtype=float))
    with np.errstate(divide="ignore"):
        return np.where(k > 1e-12, 1.0 / np.maximum(k, 1e-300), np.inf)


def grades_pct(
    points: np.ndarray, s_from_m: float, s_to_m: float, window_m: float = 3.0, step_m: float = 0.5
) -> tuple[float, float]:
    """Largest grade and largest change of grade (percent) between two arc lengths.

    The grade at a station is the rise over the ``window_m`` (plane arc length) centred on
    it; the change of grade is the difference between the grade of the ``window_m`` after a
    station and that of the ``window_m`` before it (algebraic difference, as at a crest or
    sag). Both are maxima of absolute values.

    Examples
    --------
    A 5 % ramp that starts from level ground after 10 m:

    >>> x = np.array([0.0, 10.0, 30.0])
    >>> g, dg = grades_pct(np.c_[x, 0 * x, [0.0, 0.0, 1.0]], 0.0, 30.0)
    >>> round(g, 2), round(dg, 2)
    (5.0, 5.0)

    A flat line:

    >>> grades_pct(np.array([[0, 0, 0], [10, 0, 0.0]]), 0.0, 10.0)
    (0.0, 0.0)
    """
    pts = clean_polyline(points)
    if len(pts) < 2:
        return 0.0, 0.0
    s_all = arc_length(pts)
    total = float(s_all[-1])
    a, b = max(0.0, s_from_m), min(total, s_to_m)
    if b <= a:
        return 0.0, 0.0
    z = pts[:, 2]
    if z.min() == z.max():
        return 0.0, 0.0
    n = max(int(math.ceil((b - a) / step_m)), 1) + 1
    s = np.linspace(a, b, n)
    half = 0.5 * window_m

    def rise_over(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        lo = np.minimum(np.maximum(lo, 0.0), total)
        hi = np.minimum(np.maximum(hi, 0.0), total)
        span = hi - lo
        dz = np.interp(hi, s_all, z) - np.interp(lo, s_all, z)
        return np.where(span > 1e-6, dz / np.maximum(span, 1e-6), 0.0)

    grade = rise_over(s - half, s + half)
    change = rise_over(s, s + window_m) - rise_over(s - window_m, s)
    return float(100.0 * np.abs(grade).max()), float(100.0 * np.abs(change).max())


def cut_polyline(
    points: np.ndarray, s_from_m: float, s_to_m: float, s: np.ndarray | None = None
) -> np.ndarray:
    """The part of a polyline between two arc lengths (interpolating the end points, z too).

    ``s`` may give the arc length of each point (:func:`arc_length`) when known.

    Examples
    --------
    >>> cut_polyline(np.array([[0, 0, 0], [10, 0, 1.0]]), 2.0, 5.0).tolist()
    [[2.0, 0.0, 0.2], [5.0, 0.0, 0.5]]
    >>> cut_polyline(np.array([[0, 0, 0], [10, 0, 1.0]]), 4.0, 4.0).shape
    (1, 3)
    """
    pts = np.asarray(points, dtype=float)
    if s is None:
        s = arc_length(pts)
    total = float(s[-1])
    a = min(max(s_from_m, 0.0), total)
    b = min(max(s_to_m, a), total)
    ends = _points_at(pts, s, np.array([a, b]))
    if b - a <= 0:
        return ends[:1]
    i, j = np.searchsorted(s, [a, b], side="right")
    inner = pts[i:j]
    if len(inner) and s[j - 1] >= b:
        inner = inner[:-1]
    return np.vstack((ends[:1], inner, ends[1:]))


def turns_back(approach: np.ndarray, exit_: np.ndarray, min_turn_deg: float = 135.0,
               reach_m: float = 30.0, within_m: float = 15.0) -> bool:
    """Whether a movement from a lane drawn ``approach`` into one drawn ``exit_`` is a U-turn:
    it turns by at least ``min_turn_deg`` between the approach's last chord and the exit's
    first, and the exit runs back alongside the approach: the points ``reach_m`` back along
    each (their far ends, if shorter) are within ``within_m``.

    SUMO gives ``dir="t"`` to its automatic turnarounds onto the reverse edge only; a turn
    onto the other carriageway of a divided road, round a median's nose or a turning loop,
    is a ``dir="l"`` or even ``"s"`` connection, and no less a U-turn.

    Examples
    --------
    Back along a carriageway 7 m away, a U-turn; a sharp 140° left into a road that leaves
    at 40°, not one; nor a right angle:

    >>> west = np.array([[100.0, 0.0], [0.0, 0.0]])
    >>> turns_back(west, np.array([[0.0, 7.0], [100.0, 7.0]]))
    True
    >>> a = np.radians(-40.0)
    >>> turns_back(west, np.array([[0.0, 0.0], [100 * np.cos(a), 100 * np.sin(a)]]))
    False
    >>> turns_back(west, np.array([[0.0, 0.0], [0.0, 100.0]]))
    False

    A lane of a single point has no heading: not a U-turn.

    >>> turns_back(np.array([[0.0, 0.0]]), np.array([[0.0, 7.0], [100.0, 7.0]]))
    False
    """
    a = clean_polyline(np.asarray(approach, dtype=float)[:, :2])
    b = clean_polyline(np.asarray(exit_, dtype=float)[:, :2])
    if len(a) < 2 or len(b) < 2:
        return False
    da, db = a[-1] - a[-2], b[1] - b[0]
    turn = math.degrees(math.atan2(da[0] * db[1] - da[1] * db[0], float(da @ db)))
    if abs(turn) < min_turn_deg:
        return False
    sa, sb = arc_length(a), arc_length(b)
    p = _points_at(a, sa, np.array([max(0.0, float(sa[-1]) - reach_m)]))[0]
    q = _points_at(b, sb, np.array([min(float(sb[-1]), reach_m)]))[0]
    return bool(np.hypot(*(p - q)) <= within_m)


def _points_at(pts: np.ndarray, s: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Points (all columns) at arc lengths ``at`` by linear interpolation."""
    k = np.clip(np.searchsorted(s, at, side="right") - 1, 0, len(s) - 2)
    seg = s[k + 1] - s[k]
    t = np.where(seg > 0, (at - s[k]) / np.where(seg > 0, seg, 1.0), 0.0)
    return pts[k] + t[:, None] * (pts[k + 1] - pts[k])
