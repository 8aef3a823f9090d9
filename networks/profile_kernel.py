"""Compiled inner loops of :mod:`clearance.networks.profiles` (numba).

:func:`profiles` of :mod:`clearance.networks.profiles` hands a chunk of lines to these loops as one
array of points and a count of points per line. :func:`chord_frame` measures arc length and
the extended chords, numpy takes their headings (its ``arctan2``, whose last bits can differ
from the C library's that numba would call), and :func:`station_profiles` fits the curvature
at every station and finds each line's smallest radius and turn angle.

The loops do the same floating-point operations in the same order as the vectorised numpy
version they replace, so the results are the same to the bit: arc length and the unwrapped
headings are running sums over the whole chunk, as ``np.cumsum`` over the concatenated lines
made them, and the interpolation of headings is ``np.interp``'s: ``fp[j]`` at a knot and at
the ends, else ``slope * (x - xp[j]) + fp[j]`` with ``slope = (fp[j + 1] - fp[j]) /
(xp[j + 1] - xp[j])``, ``j`` the last knot at or before ``x``. Only the search differs: the
stations of a line increase along it, so each interpolation walks a pointer on from the
previous station's knot instead of bisecting. (The interpolation is written out in the
station loop: a compiled helper taking the arrays cost more per call than it computes.)

All lengths are in metres and angles in radians; arrays are float64 unless said otherwise.
Inputs are finite (the ``nan`` cases of numpy's functions are not reproduced). Division
follows numpy's error model (a zero divisor gives ``inf`` or ``nan``, as numpy's slopes
between repeated knots, which are never used).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["GAP_M", "chord_frame", "station_profiles"]

#: Key distance between consecutive lines of a chunk (metres; see :func:`chord_frame`).
GAP_M = 10.0

_TWO_PI = 2 * np.pi


@njit(cache=True, nogil=True, error_model="numpy")
def _clip(x: float, lo: float, hi: float) -> float:  # pragma: no cover - compiled
    """``np.clip(x, lo, hi)`` of one number: ``min(max(x, lo), hi)``.

    With ``lo = -inf`` it is ``np.minimum(x, hi)``, with ``hi = inf`` ``np.maximum(x, lo)``
    (for numbers, not ``nan``).

    Examples
    --------
    >>> _clip(5.0, 0.0, 2.0), _clip(-1.0, 0.0, 2.0), _clip(1.5, 0.0, 2.0)
    (2.0, 0.0, 1.5)

    A lower bound above the upper one gives the upper one, as numpy does; a number already
    within the bounds stays as it is:

    >>> _clip(1.0, 3.0, 2.0), _clip(0.0, 0.0, 0.0)
    (2.0, 0.0)
    """
    x = x if x > lo else lo
    return x if x < hi else hi


@njit(cache=True, nogil=True, error_model="numpy")
def _unwrap(angles: np.ndarray, lo: int, hi: int, acc: float,
            out: np.ndarray) -> float:  # pragma: no cover - compiled
    """Unwrap ``angles[lo:hi]`` into ``out[lo:hi]``, keeping the running sum ``acc``.

    Each step is wrapped to within ±π and added to ``acc`` (the running sum over the chunk
    so far, which is returned); ``out[m]`` is ``acc - acc_at_lo + angles[lo]`` with the sum
    as it stood at ``m``, the same floats as a cumulative sum over the whole chunk re-anchored
    at ``lo``.

    Examples
    --------
    >>> out = np.zeros(3)
    >>> acc = _unwrap(np.array([3.0, -3.0, 3.0]), 0, 3, 0.0, out)
    >>> np.round(out, 4).tolist(), round(acc, 4)
    ([3.0, 3.2832, 3.0], 0.0)

    A straight line: every chord has the same heading, nothing is added.

    >>> _unwrap(np.full(3, 0.5), 0, 3, 7.0, out), out.tolist()
    (7.0, [0.5, 0.5, 0.5])
    """
    start = acc
    a0 = angles[lo]
    out[lo] = (acc - start) + a0
    for m in range(lo, hi - 1):
        d = angles[m + 1] - angles[m]
        d -= _TWO_PI * np.rint(d / _TWO_PI)
        acc += d
        out[m + 1] = (acc - start) + a0
    return acc


@njit(cache=True, nogil=True, error_model="numpy")
def chord_frame(pts: np.ndarray, counts: np.ndarray,
                min_chord: float) -> tuple[np.ndarray, ...]:  # pragma: no cover - compiled
    """Arc length, keys, knots and chord vectors of a chunk of lines.

    Parameters
    ----------
    pts
        ``(P, ≥2)`` the points of every line, one line after the other (x, y; further
        columns are not read).
    counts
        int64, the number of points of each line (at least 2).
    min_chord
        Chords shorter than this are extended to the first point at least this far on (or
        the line's last point).

    Returns
    -------
    s, key
        ``(P,)`` arc length summed over the chunk (no length between one line's end and the
        next line's start), and ``s + GAP_M * c`` for line ``c``: the line's stations are
        found at ``key[start] + s`` (so that the keys of the chunk increase).
    knot, kx, ky
        ``(P - n,)`` for every point but each line's last: the key of the middle of its
        extended chord and the chord's vector, in the order of the points.
    cx, cy
        ``(P - 1,)`` the vector from each point to the next (between lines too, unused).

    Examples
    --------
    Two lines of 3 and 2 points, chords extended to 1.5 m: the first line's first chord
    (1 m) is extended to its third point.

    >>> pts = np.array([[0, 0], [1, 0], [3, 0], [0, 0], [0, 2.0]])
    >>> s, key, knot, kx, ky, cx, cy = chord_frame(pts, np.array([3, 2]), 1.5)
    >>> s.tolist(), key.tolist()
    ([0.0, 1.0, 3.0, 3.0, 5.0], [0.0, 1.0, 3.0, 13.0, 15.0])
    >>> knot.tolist(), kx.tolist(), ky.tolist()
    ([1.5, 2.0, 14.0], [3.0, 2.0, 0.0], [0.0, 0.0, 2.0])
    """
    p_all = pts.shape[0]
    n = counts.shape[0]
    s = np.empty(p_all)
    key = np.empty(p_all)
    knot = np.empty(p_all - n)
    kx = np.empty(p_all - n)
    ky = np.empty(p_all - n)
    cx = np.empty(max(p_all - 1, 0))
    cy = np.empty(max(p_all - 1, 0))
    for i in range(p_all - 1):
        cx[i] = pts[i + 1, 0] - pts[i, 0]
        cy[i] = pts[i + 1, 1] - pts[i, 1]
    acc = 0.0
    first = 0
    g = 0
    for c in range(n):
        last = first + counts[c] - 1
        gap = c * GAP_M
        s[first] = acc
        key[first] = acc + gap
        for i in range(first + 1, last + 1):
            acc += math.hypot(cx[i - 1], cy[i - 1])
            s[i] = acc
            key[i] = acc + gap
        j = first + 1
        for i in range(first, last):
            if j < i + 1:
                j = i + 1
            reach = key[i] + min_chord
            while j < last and key[j] < reach:
                j += 1
            knot[g] = 0.5 * (key[i] + key[j])
            kx[g] = pts[j, 0] - pts[i, 0]
            ky[g] = pts[j, 1] - pts[i, 1]
            g += 1
        first = last + 1
    return s, key, knot, kx, ky, cx, cy


@njit(cache=True, nogil=True, error_model="numpy")
def station_profiles(s: np.ndarray, key: np.ndarray, counts: np.ndarray, knot: np.ndarray,
                     heading: np.ndarray, chord_heading: np.ndarray, core_from: np.ndarray,
                     core_to: np.ndarray, step: float, window: float, margin: float,
                     adaptive: bool,
                     max_window: float) -> tuple[np.ndarray, ...]:  # pragma: no cover
    """Curvature at every station of a chunk of lines, smallest radius and turn of each.

    A numba kernel that must be one piece: the adaptive window of one station reads and
    widens the same running sums the next station starts from, in one pass per line.

    Parameters
    ----------
    s, key, knot
        From :func:`chord_frame`.
    heading, chord_heading
        The headings (``arctan2``) of :func:`chord_frame`'s extended chords and chords.
    core_from, core_to
        The core of each line (arc length from its start).
    step, window, margin, adaptive, max_window
        As :func:`clearance.networks.profiles.profiles`'s ``step_m``, ``window_m``, ``margin_m``,
        ``adaptive``, ``max_window_m``.

    Returns
    -------
    lo, hi, count
        Each line's stations: ``count`` (int64) from ``lo`` every ``step``, up to ``hi``.
    at, curvature, radius
        Every station of every line, one line after the other.
    min_radius, turn
        Each line's smallest radius over its core (``inf``: straight) and the heading change
        from the chord entering the core to the chord leaving it (radians).

    Examples
    --------
    A straight line 4 m long, core 1-3 m, stations every metre 1 m either side: straight
    throughout, no turn.

    >>> pts, counts = np.array([[0.0, 0.0], [4.0, 0.0]]), np.array([2])
    >>> s, key, knot, kx, ky, cx, cy = chord_frame(pts, counts, 1.5)
    >>> out = station_profiles(s, key, counts, knot, np.arctan2(ky, kx), np.arctan2(cy, cx),
    ...                        np.array([1.0]), np.array([3.0]), 1.0, 3.0, 1.0, True, 15.0)
    >>> lo, hi, count, at, curvature, radius, min_radius, turn = out
    >>> lo.tolist(), hi.tolist(), count.tolist(), at.tolist()
    ([0.0], [4.0], [5], [0.0, 1.0, 2.0, 3.0, 4.0])
    >>> curvature.tolist(), radius.tolist(), min_radius.tolist(), turn.tolist()
    ([0.0, 0.0, 0.0, 0.0, 0.0], [inf, inf, inf, inf, inf], [inf], [0.0])

    A right-angle corner at 5 m, core 4-6 m, one pass of a 3 m window: the quarter turn is
    spread over the half-chords either side (a radius of 10 / π m).

    >>> pts, counts = np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 5.0]]), np.array([3])
    >>> s, key, knot, kx, ky, cx, cy = chord_frame(pts, counts, 1.5)
    >>> out = station_profiles(s, key, counts, knot, np.arctan2(ky, kx), np.arctan2(cy, cx),
    ...                        np.array([4.0]), np.array([6.0]), 1.0, 3.0, 1.0, False, 15.0)
    >>> np.round(out[4], 3).tolist(), np.round(out[6], 3).tolist(), np.round(out[7], 4).tolist()
    ([0.209, 0.314, 0.314, 0.314, 0.209], [3.183], [1.5708])
    """
    n = counts.shape[0]
    lo = np.empty(n)
    hi = np.empty(n)
    count = np.empty(n, dtype=np.int64)
    first = 0
    n_all = 0
    for c in range(n):
        last = first + counts[c] - 1
        total = s[last] - s[first]
        lo[c] = _clip(core_from[c] - margin, 0.0, total)
        hi[c] = _clip(core_to[c] + margin, lo[c], total)
        count[c] = np.int64(math.floor((hi[c] - lo[c]) / step + 1e-9)) + 1
        n_all += count[c]
        first = last + 1

    at = np.empty(n_all)
    curvature = np.empty(n_all)
    radius = np.empty(n_all)
    min_radius = np.empty(n)
    turn = np.empty(n)
    h = np.empty(knot.shape[0])
    slopes = np.empty(knot.shape[0])
    raw = np.empty(chord_heading.shape[0])
    acc_h = 0.0
    acc_raw = 0.0
    half0 = 0.5 * window
    first = 0
    o = 0
    for c in range(n):
        last = first + counts[c] - 1
        f, l_ = first - c, last - c - 1  # the line's knots
        acc_h = _unwrap(heading, f, l_ + 1, acc_h, h)
        acc_raw = _unwrap(chord_heading, first, last, acc_raw, raw)
        base = key[first]
        total = s[last] - s[first]
        a_in = core_from[c] - 1e-9
        b_in = core_to[c] + 1e-9
        k_first, k_last = knot[f], knot[l_]
        for g in range(f, l_):  # as np.interp computes them when it has fewer knots than x
            slopes[g] = (h[g + 1] - h[g]) / (knot[g + 1] - knot[g])
        m = count[c]
        for i in range(m):
            at[o + i] = _clip(lo[c] + step * i, -np.inf, hi[c])
        for p in range(2 if adaptive else 1):
            j_far = j_near = f  # the last knot at or before each end of the window
            for i in range(m):
                x = at[o + i]
                if p == 0:
                    half = half0
                else:  # half the radius found, within window .. max_window
                    half = 0.5 * _clip(0.5 / _clip(abs(curvature[o + i]), 1e-9, np.inf),
                                       window, max_window)
                    if half == half0:  # the same window: the same fit as the first pass
                        continue
                w_lo = _clip(x - half, 0.0, np.inf)
                w_hi = _clip(x + half, -np.inf, total)
                span = w_hi - w_lo
                k = 0.0
                if span > 1e-9:
                    dh = 0.0
                    for e in range(2):  # np.interp at the window's far end, then near end
                        if e == 0:
                            xe = _clip(base + w_hi, k_first, k_last)
                            j = j_far
                        else:
                            xe = _clip(base + w_lo, k_first, k_last)
                            j = j_near
                        while j > f and knot[j] > xe:
                            j -= 1
                        while j < l_ and knot[j + 1] <= xe:
                            j += 1
                        if j == l_ or knot[j] == xe:
                            v = h[j]
                        else:
                            v = slopes[j] * (xe - knot[j]) + h[j]
                        if e == 0:
                            dh = v
                            j_far = j
                        else:
                            dh -= v
                            j_near = j
                    k = dh / span
                curvature[o + i] = k
        k_max = 0.0  # over the core
        for i in range(m):
            ak = abs(curvature[o + i])
            radius[o + i] = 1.0 / ak if ak > 1e-12 else np.inf
            x = at[o + i]
            if x >= a_in and x <= b_in and ak > k_max:
                k_max = ak
        o += m
        min_radius[c] = 1.0 / k_max if k_max > 1e-12 else np.inf

        # the chords entering and leaving the core
        t_in = base + core_from[c] - 1e-6
        t_out = base + core_to[c] + 1e-6
        q = first
        while q <= last and key[q] < t_in:
            q += 1
        i_ch = min(max(q - 1, first), last - 1)
        q = first
        while q <= last and key[q] <= t_out:
            q += 1
        j_ch = min(max(q - 1, first), last - 1)
        turn[c] = raw[j_ch] - raw[i_ch]
        first = last + 1
    return lo, hi, count, at, curvature, radius, min_radius, turn
