"""Centre lines for tracking: validation, uniform resampling, headings, projection, circle fit.

A centre line arrives as an ``(N, 2)`` or ``(N, 3)`` polyline in metres (SUMO plane
coordinates). :func:`prepare_path` resamples it at a uniform spacing and gives every sample
a continuous heading: each segment keeps its own heading at its middle, and the turn at a
vertex is spread linearly over the arc length ``+-r`` around it, ``r`` half the shorter of
the two segments there. For a polyline sampled evenly from a circle this is the circle's
exact tangent everywhere (the chord's heading is the tangent at its middle), so a vehicle
tracking it sees the true curve, not the chords; a long straight stays straight up to
``r`` before the next vertex, instead of starting to turn at its far end.

:func:`project_window` projects one point per path onto its path, searching only a few
segments around the previous match (a vehicle moves a bounded distance per step), which
keeps a batch of runs ``O(N)`` per step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from clearance.analysis.kernels import project_near
from clearance.vehicles.errors import GeometryError

__all__ = ["DEFAULT_SPACING_M", "Path", "SMOOTH_SIGMA_M", "catmull_rom", "fit_circle",
           "prepare_path", "project_window", "smooth_polyline"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

DEFAULT_SPACING_M = 0.1
"""Default resampling step of a centre line (m)."""


@dataclass(frozen=True)
class Path:
    """A centre line resampled at a uniform spacing.

    Attributes
    ----------
    name
        What the path is (used in messages), e.g. a curve id.
    xy
        ``(M, 2)`` resampled points (m).
    z
        ``(M,)`` elevation (m), or ``None`` for a 2-D input.
    station_m
        ``(M,)`` arc length of each point from the start, ``station_m[-1] == length_m``.
    heading_rad
        ``(M,)`` smooth tangent heading (unwrapped, counter-clockwise from +x).
    curvature_1_m
        ``(M,)`` ``d heading / d s`` (left positive).
    spacing_m
        Uniform distance between consecutive points.
    length_m
        Length of the input polyline.
    """

    name: str
    xy: FloatArray
    z: FloatArray | None
    station_m: FloatArray
    heading_rad: FloatArray
    curvature_1_m: FloatArray
    spacing_m: float
    length_m: float

    def heading_at(self, station_m: ArrayLike) -> FloatArray:
        """Smooth heading at the given stations (clamped to the ends).

        Examples
        --------
        >>> p = prepare_path([(0, 0), (10, 0)])
        >>> float(p.heading_at(5.0))
        0.0
        """
        return np.interp(np.asarray(station_m, dtype=np.float64), self.station_m, self.heading_rad)

    def point_at(self, station_m: ArrayLike) -> FloatArray:
        """Points ``(..., 2)`` at the given stations (clamped to the ends).

        Examples
        --------
        >>> p = prepare_path([(0, 0), (10, 0)])
        >>> p.point_at(2.5).tolist()
        [2.5, 0.0]
        """
        s = np.asarray(station_m, dtype=np.float64)
        xs = np.interp(s, self.station_m, self.xy[:, 0])
        return np.stack([xs, np.interp(s, self.station_m, self.xy[:, 1])], axis=-1)


def _turn(d1: np.ndarray, d2: np.ndarray) -> float:
    """Signed turn (rad, left positive) from direction ``d1`` to direction ``d2``."""
    return math.atan2(d1[0] * d2[1] - d1[1] * d2[0], d1[0] * d2[0] + d1[1] * d2[1])


def _arc_weight(p: np.ndarray) -> float:
    """How much the end of a polyline, its first points ``p``, is taken for a piece of arc.

    An arc sampled evenly (as SUMO draws a helix or a ring, or cut short where a curve
    starts inside it) has an end chord ``a`` no longer than the next, ``b``, and turns alike
    at its next two vertices: the same curvature, turn over mean chord, to within 20 %.
    A straight lead into a corner has the longer end chord, or a turn at the first vertex
    unlike the next one's. 1 for an arc, 0 for a lead, blended between (``1.25 < a / b < 2``,
    curvatures within 20-50 % of each other); 0 with fewer than four points (nothing to
    compare).

    Examples
    --------
    >>> a = np.radians([0.0, 5.0, 10.0, 15.0])
    >>> _arc_weight(np.c_[np.sin(a), 1 - np.cos(a)])
    1.0
    >>> _arc_weight(np.array([[0.0, 0.0], [10.0, 0.0], [17.0, 2.0], [20.0, 2.5]]))
    0.0
    """
    if len(p) < 4:
        return 0.0
    d = np.diff(p[:4, :2], axis=0)
    c = np.hypot(d[:, 0], d[:, 1])
    length = min(max((2.0 - c[0] / max(c[1], 1e-12)) / 0.75, 0.0), 1.0)
    k1 = _turn(d[0], d[1]) / (0.5 * (c[0] + c[1]))
    k2 = _turn(d[1], d[2]) / (0.5 * (c[1] + c[2]))
    big = max(abs(k1), abs(k2))
    alike = min(abs(k1), abs(k2)) / big if big > 0 and k1 * k2 > 0 else 0.0
    return float(length * min(max((alike - 0.5) / 0.3, 0.0), 1.0))


def _phantom(p: np.ndarray) -> np.ndarray:
    """A point one chord before ``p[0]``, continuing the polyline ``p`` (Catmull-Rom's end).

    Where the end is a piece of arc (:func:`_arc_weight`) the phantom chord turns like the
    curve, by ``2 a / (a + b)`` of the turn at ``p[1]`` (chords ``a``, ``b``), so the
    spline's end lies on the arc with the arc's tangent; where it is a straight lead it
    continues the first chord straight.
    """
    d1, d2 = p[1, :2] - p[0, :2], p[2, :2] - p[1, :2]
    a, b = math.hypot(*d1), math.hypot(*d2)
    back = _arc_weight(p) * _turn(d1, d2) * 2 * a / (a + b)  # the phantom chord turns back
    c, s = math.cos(back), math.sin(back)
    out: np.ndarray = 2 * p[0] - p[1]  # z (a third column) goes on linearly
    out[:2] = p[0, :2] - np.array([c * d1[0] + s * d1[1], -s * d1[0] + c * d1[1]])
    return out


def catmull_rom(points: ArrayLike, spacing_m: float) -> np.ndarray:
    """A centripetal Catmull-Rom curve through every vertex, sampled about every ``spacing_m``.

    SUMO draws a junction's internal lane with five points, chords of several metres that
    turn by 20 to 30 degrees at each vertex. The vertices lie on the designed arc, the chords
    do not: a vehicle following the chords would be judged against a sagitta of tens of
    centimetres. The centripetal spline passes through the vertices, has no cusps or
    self-intersections, and on points of a circle stays within a small fraction of the
    sagitta of the circle. Straight runs stay straight. ``z`` (a third column) is carried
    along by the same spline.

    Examples
    --------
    Five points on a quarter circle of radius 10 m, as SUMO writes an internal lane: the
    spline between the middle points lies on the circle to within 2 cm (the chords miss it
    by 19 cm).

    >>> a = np.radians(np.linspace(0, 90, 5))
    >>> c = catmull_rom(np.c_[10 * np.cos(a), 10 * np.sin(a)], 0.1)
    >>> bool(np.abs(np.hypot(c[40:120, 0], c[40:120, 1]) - 10).max() < 0.02)
    True

    A straight line (the degenerate case) stays straight:

    >>> s = catmull_rom([(0.0, 0.0), (5.0, 0.0), (10.0, 0.0)], 1.0)
    >>> float(np.abs(s[:, 1]).max()), s[-1].tolist()
    (0.0, [10.0, 0.0])
    """
    pts = np.asarray(points, dtype=np.float64)
    if len(pts) < 3:
        return pts
    # phantom end points continue the end chords, turning like the curve there
    ext = np.vstack([_phantom(pts[:4]), pts, _phantom(pts[:-5:-1])])
    d = np.hypot(*np.diff(ext[:, :2], axis=0).T)
    dt = np.sqrt(np.maximum(d, 1e-12))  # centripetal: alpha = 1/2
    t = np.concatenate([[0.0], np.cumsum(dt)])
    # every piece at once: piece i (between vertices i and i + 1 of ext) gets n_i samples
    piece = np.arange(1, len(ext) - 2)
    count = np.maximum(1, np.ceil(d[piece] / spacing_m).astype(np.intp))
    i = np.repeat(piece, count)
    step = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count) + 1
    t0, t1, t2, t3 = (t[i + k][:, None] for k in (-1, 0, 1, 2))
    p0, p1, p2, p3 = (ext[i + k] for k in (-1, 0, 1, 2))
    u = t1 + (t2 - t1) * (step / np.repeat(count, count))[:, None]
    a1 = (t1 - u) / (t1 - t0) * p0 + (u - t0) / (t1 - t0) * p1
    a2 = (t2 - u) / (t2 - t1) * p1 + (u - t1) / (t2 - t1) * p2
    a3 = (t3 - u) / (t3 - t2) * p2 + (u - t2) / (t3 - t2) * p3
    b1 = (t2 - u) / (t2 - t0) * a1 + (u - t0) / (t2 - t0) * a2
    b2 = (t3 - u) / (t3 - t1) * a2 + (u - t1) / (t3 - t1) * a3
    return np.vstack([pts[:1], (t2 - u) / (t2 - t1) * b1 + (u - t1) / (t2 - t1) * b2])


#: Smoothing scale of network centre lines (m): the Gaussian's standard deviation along the
#: line. SUMO's junction shapes kink where two internal lanes meet; a curve's radius is
#: fitted over 3 m of arc length, and its centre line is followed at the same scale.
SMOOTH_SIGMA_M = 2.0


def _end_tangent(d: np.ndarray) -> np.ndarray:
    """Unit tangent at an end of a line, from its next points ``d`` relative to the end point.

    A least-squares circle through the end point, ``v = c1 u + c2 (u^2 + v^2)`` in the frame
    of the chord to the farthest point (a line where ``c2 = 0``; its slope at the end point
    is ``c1``): the tangent of the curve over the fitted stretch, exact on a circle or a
    line, which SUMO's 0.01 m rounding of a short end chord does not tilt as it tilts a
    difference.

    Examples
    --------
    Points of the circle of radius 5 m through the origin, tangent along +x there:

    >>> a = np.linspace(0.02, 0.4, 20)
    >>> t = _end_tangent(np.c_[5 * np.sin(a), 5 * (1 - np.cos(a))])
    >>> [round(float(v), 6) + 0.0 for v in t]
    [1.0, 0.0]
    """
    far = d[-1] / np.hypot(*d[-1])
    u = d @ far
    v = d @ np.array([-far[1], far[0]])
    c1 = np.linalg.lstsq(np.c_[u, u * u + v * v], v, rcond=None)[0][0]
    t: np.ndarray = far + c1 * np.array([-far[1], far[0]])
    return t / float(np.hypot(*t))


def smooth_polyline(points: ArrayLike, spacing_m: float, sigma_m: float = SMOOTH_SIGMA_M
                    ) -> np.ndarray:
    """A centre line through SUMO's vertices, smoothed over ``sigma_m`` of arc length.

    A centripetal Catmull-Rom spline through the vertices (:func:`catmull_rom`, whose ends
    continue an arc round), resampled every ``spacing_m``, then a Gaussian filter ``G``
    along the line whose ends are held (beyond each end the line is mirrored across its
    normal there, so a straight line goes on straight and a circle round its centre; the
    normal is that of a circle fitted over ``sigma_m`` at an end that is a piece of arc,
    so that SUMO's rounding of a short end chord does not tilt it), applied as
    ``2 G - G G``: kinks shorter than ``sigma_m`` are smoothed out, while a circle keeps its
    radius (a plain Gaussian would shrink it by ``sigma^2 / 2R``). A line that starts
    inside a curve starts on it, with its tangent and curvature.

    Examples
    --------
    A circle of radius 10 m keeps its radius to within a centimetre, ends included, and its
    tangent at the ends: the first 0.1 m chord turns from the tangent by half its arc,
    0.29 degrees, to within 0.01 degrees (the input's first chord turns by 0.5 degrees):

    >>> a = np.radians(np.linspace(0, 270, 271))
    >>> c = smooth_polyline(np.c_[10 * np.cos(a), 10 * np.sin(a)], 0.1)
    >>> r = np.hypot(c[:, 0], c[:, 1])
    >>> bool(np.abs(r - 10).max() < 0.01), bool(np.hypot(*(c[0] - [10.0, 0.0])) < 0.005)
    (True, True)
    >>> d = c[1] - c[0]
    >>> half_arc = math.degrees(math.hypot(*d) / 20.0)
    >>> bool(abs(math.degrees(math.atan2(d[1], d[0])) - 90.0 - half_arc) < 0.01)
    True
    >>> smooth_polyline([(0.0, 0.0), (10.0, 0.0)], 1.0)[:, 1].tolist() == [0.0] * 11
    True

    A line shorter than the filter's reach (3 ``sigma_m``) is smoothed over all its points
    and stays straight:

    >>> short = smooth_polyline([(0.0, 0.0), (2.9, 1.36)], 0.1)
    >>> d = short - short[0]
    >>> len(short), bool(np.abs(d[:, 0] * 1.36 - d[:, 1] * 2.9).max() < 1e-9)
    (34, True)
    """
    vertices = np.asarray(points, dtype=np.float64)
    # at an end that is a piece of arc the mirror's normal is a fitted circle's (SUMO's 1 cm
    # rounding tilts a short end chord); elsewhere the line's own, from the last 0.2 m
    arc_end = (_arc_weight(vertices), _arc_weight(vertices[::-1]))
    pts = catmull_rom(vertices, spacing_m)
    seg = np.hypot(*np.diff(pts[:, :2], axis=0).T)
    pts = pts[np.concatenate([[True], seg > 1e-9])]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts[:, :2], axis=0).T))])
    n = max(2, math.ceil(s[-1] / spacing_m) + 1)
    t = np.linspace(0.0, s[-1], n)
    res = np.column_stack([np.interp(t, s, pts[:, j]) for j in range(pts.shape[1])])
    h = t[1] - t[0] if n > 1 else spacing_m
    half = int(math.ceil(3 * sigma_m / h)) if h > 0 else 0
    if half < 1 or n < 3:
        return res
    half = min(half, n - 1)
    fit = max(3, min(half, int(math.ceil(sigma_m / h))))  # the end tangent's fit: sigma_m
    kernel = np.exp(-0.5 * (np.arange(-half, half + 1) * h / sigma_m) ** 2)
    kernel /= kernel.sum()

    def mirrored(a: np.ndarray, end: int, step: int) -> np.ndarray:
        # the points next to an end, mirrored across the line's normal there: a straight
        # line goes on straight and a circle goes on round its own centre
        p0 = a[end]
        near = a[end + step::step][:half]  # the half points next to the end, inwards
        # second-order one-sided difference: the tangent of a curve, not of a chord
        tan = 4 * a[end + step, :2] - a[end + 2 * step, :2] - 3 * p0[:2]
        w = arc_end[0 if step > 0 else 1]
        if w > 0.0:
            tan = (1.0 - w) * tan / np.hypot(*tan) + w * _end_tangent(near[:fit, :2] - p0[:2])
        tan = tan / np.hypot(*tan)
        d = near[:, :2] - p0[:2]
        refl = near.copy()
        refl[:, :2] = p0[:2] + d - 2 * (d @ tan)[:, None] * tan
        if a.shape[1] > 2:
            refl[:, 2:] = 2 * p0[2:] - near[:, 2:]
        return refl[::-1]

    def blur(a: np.ndarray) -> np.ndarray:
        head = mirrored(a, 0, 1)
        tail = mirrored(a, n - 1, -1)[::-1]
        padded = np.vstack([head, a, tail])
        return np.column_stack([np.convolve(padded[:, j], kernel, mode="valid")
                                for j in range(a.shape[1])])

    once = blur(res)
    # twice once less twice: no shrink of curves to first order
    smooth: np.ndarray = 2 * once - blur(once)
    return smooth


def prepare_path(
    points: ArrayLike, spacing_m: float = DEFAULT_SPACING_M, name: str = "path",
    smooth: bool = False,
) -> Path:
    """Validate a centre line and resample it for tracking.

    Parameters
    ----------
    points
        ``(N, 2)`` or ``(N, 3)`` polyline in metres, ``N >= 2``. Repeated consecutive points
        are dropped.
    spacing_m
        Resampling step (m), > 0. The last step is shortened to end on the last point.
    name
        What the path is, for error messages.
    smooth
        Follow the vertices smoothed at the scale of the radius fit (:func:`smooth_polyline`)
        instead of the chords: for SUMO centre lines, whose vertices lie on the designed
        curve and whose chords and lane joints kink.

    Raises
    ------
    clearance.vehicles.errors.GeometryError
        Non-finite coordinates, fewer than two distinct points, or a reversal (a vertex
        where the polyline turns back by more than 179 degrees).
    ValueError
        Not an (N, 2) or (N, 3) array of numbers, or a spacing that is not positive.

    Examples
    --------
    A straight line keeps its heading and has zero curvature:

    >>> p = prepare_path([(0.0, 0.0), (3.0, 4.0)], spacing_m=1.0)
    >>> p.length_m, len(p.xy), round(float(p.heading_rad[0]), 6), float(p.curvature_1_m.max())
    (5.0, 6, 0.927295, 0.0)

    A circle of radius 10 m sampled every 5 degrees has curvature 0.1 1/m:

    >>> a = np.radians(np.arange(0, 91, 5))
    >>> c = prepare_path(np.c_[10 * np.cos(a), 10 * np.sin(a)])
    >>> round(float(np.median(c.curvature_1_m)), 4)
    0.1
    """
    try:
        pts = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: centre line is not an array of numbers ({exc})") from None
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"{name}: centre line must be an (N, 2) or (N, 3) array, got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(pts), axis=1))[0])
        raise GeometryError(f"{name}: centre line point {bad} is not finite: {pts[bad].tolist()}")
    if not (spacing_m > 0 and math.isfinite(spacing_m)):
        raise ValueError(f"{name}: spacing_m must be a positive number, got {spacing_m!r}")
    seg = np.diff(pts[:, :2], axis=0)
    seg_len = np.hypot(seg[:, 0], seg[:, 1])
    keep = np.concatenate([[True], seg_len > 1e-9])
    pts = pts[keep]
    if len(pts) < 2:
        raise GeometryError(f"{name}: centre line needs at least two distinct points")
    if smooth:
        pts = smooth_polyline(pts, spacing_m)
        seg_len = np.hypot(*np.diff(pts[:, :2], axis=0).T)
        pts = pts[np.concatenate([[True], seg_len > 1e-9])]
    seg = np.diff(pts[:, :2], axis=0)
    seg_len = np.hypot(seg[:, 0], seg[:, 1])
    seg_heading = np.unwrap(np.arctan2(seg[:, 1], seg[:, 0]))
    turn = np.abs(np.diff(seg_heading))
    if np.any(turn > math.radians(179.0)):
        bad = int(np.flatnonzero(turn > math.radians(179.0))[0]) + 1
        raise GeometryError(f"{name}: centre line turns back on itself at point {bad}")
    vert_station = np.concatenate([[0.0], np.cumsum(seg_len)])
    length = float(vert_station[-1])
    # heading breakpoints: the turn at interior vertex v ramps over S_v -+ r_v
    r = 0.5 * np.minimum(seg_len[:-1], seg_len[1:])
    ramp_s = np.stack([vert_station[1:-1] - r, vert_station[1:-1] + r], axis=1).ravel()
    ramp_h = np.stack([seg_heading[:-1], seg_heading[1:]], axis=1).ravel()
    # the end headings: each end chord's own where it leads straight into the next vertex,
    # the arc's tangent (the chord's, turned back by the arc over half a chord) where the
    # chords are alike, as on a finely sampled curve
    h_start, h_end = seg_heading[0], seg_heading[-1]
    if len(seg_len) > 1:
        a0, b0, a1, b1 = seg_len[0], seg_len[1], seg_len[-1], seg_len[-2]
        h_start -= _arc_weight(pts) * (seg_heading[1] - seg_heading[0]) * a0 / (a0 + b0)
        h_end += _arc_weight(pts[::-1]) * (seg_heading[-1] - seg_heading[-2]) * a1 / (a1 + b1)
    brk_s = np.concatenate([[0.0], ramp_s, [length]])
    brk_h = np.concatenate([[h_start], ramp_h, [h_end]])
    n = max(2, math.ceil(length / spacing_m - 1e-9) + 1)
    station = np.minimum(np.arange(n) * spacing_m, length)
    station[-1] = length
    xy = np.stack([np.interp(station, vert_station, pts[:, 0]),
                   np.interp(station, vert_station, pts[:, 1])], axis=1)
    z = np.interp(station, vert_station, pts[:, 2]) if pts.shape[1] == 3 else None
    heading = np.interp(station, brk_s, brk_h)
    curvature = np.gradient(heading, station) if n > 2 else np.zeros(n)
    return Path(name, xy, z, station, heading, curvature, float(spacing_m), length)


def project_window(
    px: FloatArray,
    py: FloatArray,
    path_xy: FloatArray,
    n_points: IntArray,
    segment: IntArray,
    window: int,
) -> tuple[IntArray, FloatArray, FloatArray]:
    """Project one point per path onto its path, near the previous match.

    Parameters
    ----------
    px, py
        ``(N,)`` points to project.
    path_xy
        ``(N, M, 2)`` paths, padded past ``n_points[i]`` (padding is never read).
    n_points
        ``(N,)`` number of points of each path (>= 2).
    segment
        ``(N,)`` segment index of the previous match.
    window
        Number of segments to search ahead of ``segment`` (one behind is searched too).

    Returns
    -------
    segment, along_m, lateral_m
        The matched segment, the distance along it from its first point (negative before
        the path's start, beyond the segment's length past the path's end) and the signed
        lateral offset (left of the path positive).

    Examples
    --------
    >>> xy = np.array([[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]])
    >>> seg, along, lat = project_window(np.array([1.5]), np.array([-0.2]), xy,
    ...                                  np.array([3]), np.array([0]), 2)
    >>> int(seg[0]), float(along[0]), float(lat[0])
    (1, 0.5, -0.2)
    """
    seg, along, lateral = project_near(np.asarray(px, dtype=np.float64),
                                       np.asarray(py, dtype=np.float64),
                                       np.ascontiguousarray(path_xy, dtype=np.float64),
                                       np.asarray(n_points, dtype=np.int64),
                                       np.asarray(segment, dtype=np.int64), int(window))
    return seg.astype(np.intp), along, lateral


def fit_circle(x: ArrayLike, y: ArrayLike) -> tuple[float, float, float]:
    """Least-squares circle through points (algebraic fit of Kasa).

    Solves ``x^2 + y^2 + D x + E y + F = 0`` in the least-squares sense; exact for points
    on a circle, and unbiased enough for the small noise of an integrated path.

    Returns
    -------
    xc_m, yc_m, radius_m

    Raises
    ------
    clearance.vehicles.errors.GeometryError
        Collinear points (a straight line has no finite circle).
    ValueError
        Fewer than three points, or unequal counts of x and y.

    Examples
    --------
    >>> a = np.linspace(0.0, 1.0, 5)
    >>> [round(v, 9) for v in fit_circle(1 + 2 * np.cos(a), -1 + 2 * np.sin(a))]
    [1.0, -1.0, 2.0]

    Points on a straight line have no circle:

    >>> fit_circle([0.0, 1.0, 2.0], [1.0, 3.0, 5.0])
    Traceback (most recent call last):
    ...
    clearance.vehicles.errors.GeometryError: fit_circle: the points are (nearly) collinear; ...
    """
    xs = np.asarray(x, dtype=np.float64).ravel()
    ys = np.asarray(y, dtype=np.float64).ravel()
    if xs.size < 3 or xs.size != ys.size:
        raise ValueError("fit_circle: needs at least three (x, y) points of equal count")
    mx, my = xs.mean(), ys.mean()
    u, w = xs - mx, ys - my
    spread = np.linalg.svd(np.stack([u, w], axis=1), compute_uv=False)
    if spread[0] == 0 or spread[1] <= 1e-9 * spread[0]:
        raise GeometryError("fit_circle: the points are (nearly) collinear; no finite circle")
    a = np.stack([u, w, np.ones_like(u)], axis=1)
    b = -(u * u + w * w)
    (d, e, f), *_ = np.linalg.lstsq(a, b, rcond=None)
    r2 = (d * d + e * e) / 4.0 - f
    scale = max(float(np.ptp(u)), float(np.ptp(w)), 1e-300)
    if not np.isfinite(r2) or r2 <= 0 or math.sqrt(r2) > 1e6 * scale:
        raise GeometryError("fit_circle: the points are (nearly) collinear; no finite circle")
    return float(mx - d / 2.0), float(my - e / 2.0), float(math.sqrt(r2))
