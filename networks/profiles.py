"""Curvature profiles and turn angles of many polylines at once (vectorised numpy).

The method (see :mod:`networks.geometry`): the heading of a line is known at the midpoint of
each chord and interpolated linearly in between, so the turn at a vertex is spread over the
half-chords either side; curvature is the change of that heading over a window of arc
length. Chords shorter than ``min_chord_m`` are extended to the first point at least that
far on (SUMO writes coordinates to 0.01 m, a heading noise of 1° on 0.5 m chords). A second
pass widens the window to half the radius found (up to ``max_window_m``) so that rounding
does not make wide curves look tight.

All lines are concatenated and processed in chunks, so that the per-call cost of numpy is
paid per chunk, not per line.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

#: Chords shorter than this (m) are extended before headings are taken.
MIN_CHORD_M = 1.5

#: The widest window of arc length the adaptive curvature fit uses (metres).
MAX_WINDOW_M = 15.0

#: Lines per chunk (bounds the memory of the station arrays).
CHUNK_LINES = 20000

_GAP_M = 10.0  # key distance between consecutive lines


@dataclass(frozen=True, slots=True)
class Stations:
    """Stations every ``step_m`` from ``start_m``, the last one no further than ``stop_m``:
    ``s_i = min(start_m + step_m * i, stop_m)`` for ``i < count`` (four numbers instead of
    an array; :meth:`array` gives the same floats the profile was computed at).

    Examples
    --------
    >>> Stations(1.0, 2.1, 6, 0.25).array().tolist()
    [1.0, 1.25, 1.5, 1.75, 2.0, 2.1]
    """

    start_m: float
    stop_m: float
    count: int
    step_m: float

    def array(self) -> np.ndarray:
        """The stations (metres)."""
        return np.minimum(self.start_m + self.step_m * np.arange(self.count), self.stop_m)


@dataclass(frozen=True)
class Profiles:
    """Results for a batch of lines, in input order."""

    s_m: list[np.ndarray]
    stations: list[Stations]
    curvature_per_m: list[np.ndarray]
    radius_m: list[np.ndarray]
    min_radius_m: np.ndarray
    turn_deg: np.ndarray


def profiles(
    lines: Sequence[np.ndarray],
    core_from_m: Sequence[float],
    core_to_m: Sequence[float],
    step_m: float = 0.25,
    window_m: float = 3.0,
    margin_m: float | None = None,
    adaptive: bool = True,
    min_chord_m: float = MIN_CHORD_M,
    max_window_m: float = MAX_WINDOW_M,
) -> Profiles:
    """Curvature at stations every ``step_m`` over each line's core ± ``margin_m``.

    Parameters
    ----------
    lines
        Polylines (N, ≥2) without repeated points.
    core_from_m, core_to_m
        The core of each line (plane arc length); ``min_radius_m`` is taken over it, and
        ``turn_deg`` is the heading change from the chord entering it to the chord leaving
        it (degrees, left positive, unwrapped).
    margin_m
        Stations extend this far either side of the core (default: ``window_m``).

    Examples
    --------
    >>> a = np.linspace(0, np.pi / 2, 10)
    >>> arc = np.c_[20 * np.sin(a), 20 - 20 * np.cos(a)]
    >>> line = np.vstack(([-10.0, 0.0], arc, [20.0, 30.0]))
    >>> p = profiles([line, np.array([[0, 0], [5, 0.0]])], [10.0, 0.0], [41.4, 5.0])
    >>> round(float(p.min_radius_m[0]), 1), round(float(p.turn_deg[0]), 1)
    (20.0, 90.0)
    >>> p.min_radius_m[1], p.turn_deg[1]
    (np.float64(inf), np.float64(0.0))
    """
    margin = window_m if margin_m is None else margin_m
    out_s: list[np.ndarray] = []
    out_k: list[np.ndarray] = []
    out_r: list[np.ndarray] = []
    mins: list[np.ndarray] = []
    turns: list[np.ndarray] = []
    stations: list[Stations] = []
    a_all = np.asarray(core_from_m, dtype=float)
    b_all = np.asarray(core_to_m, dtype=float)
    for lo in range(0, len(lines), CHUNK_LINES):
        hi = min(lo + CHUNK_LINES, len(lines))
        s, k, r, m, t, st = _chunk(
            lines[lo:hi],
            a_all[lo:hi],
            b_all[lo:hi],
            step_m,
            window_m,
            margin,
            adaptive,
            min_chord_m,
            max_window_m,
        )
        out_s += s
        out_k += k
        out_r += r
        mins.append(m)
        turns.append(t)
        stations += st
    empty = np.zeros(0)
    return Profiles(
        out_s,
        stations,
        out_k,
        out_r,
        np.concatenate(mins) if mins else empty,
        np.concatenate(turns) if turns else empty,
    )


def _chunk(lines, a, b, step, window, margin, adaptive, min_chord, max_window):
    n = len(lines)
    counts = np.fromiter((len(x) for x in lines), dtype=np.int64, count=n)
    if np.any(counts < 2):
        raise ValueError("every line needs at least two points")
    pts = np.concatenate([x[:, :2] for x in lines])
    start = np.concatenate(([0], np.cumsum(counts)[:-1]))
    last = start + counts - 1
    line_of = np.repeat(np.arange(n), counts)
    d = pts[1:] - pts[:-1]
    seg = np.hypot(d[:, 0], d[:, 1])
    seg[start[1:] - 1] = 0.0  # no chord between one line's end and the next line's start
    s_glob = np.concatenate(([0.0], np.cumsum(seg)))
    total = s_glob[last] - s_glob[start]
    key = s_glob + line_of * _GAP_M
    base = key[start]

    # extended chords -> headings at knots (one per point but the last of each line)
    not_last = np.ones(len(pts), dtype=bool)
    not_last[last] = False
    ii = np.flatnonzero(not_last)
    jj = np.searchsorted(key, key[ii] + min_chord, side="left")
    jj = np.maximum(np.minimum(jj, last[line_of[ii]]), ii + 1)
    vec = pts[jj] - pts[ii]
    knot = 0.5 * (key[ii] + key[jj])
    h = _unwrap_per_line(np.arctan2(vec[:, 1], vec[:, 0]), line_of[ii])
    first_knot = knot[start - np.arange(n)]  # index of line c's first knot: start_c - c
    last_knot = knot[last - np.arange(n) - 1]

    # stations
    lo = np.clip(a - margin, 0.0, total)
    hi = np.clip(b + margin, lo, total)
    n_st = np.floor((hi - lo) / step + 1e-9).astype(np.int64) + 1
    st_line = np.repeat(np.arange(n), n_st)
    st_start = np.concatenate(([0], np.cumsum(n_st)[:-1]))
    within = np.arange(int(n_st.sum())) - np.repeat(st_start, n_st)
    s_st = np.minimum(lo[st_line] + step * within, hi[st_line])
    k_base = base[st_line]
    k_tot = total[st_line]
    k_first = first_knot[st_line]
    k_last = last_knot[st_line]

    def fit(half):
        w_lo = np.maximum(s_st - half, 0.0)
        w_hi = np.minimum(s_st + half, k_tot)
        span = w_hi - w_lo
        x_lo = np.clip(k_base + w_lo, k_first, k_last)
        x_hi = np.clip(k_base + w_hi, k_first, k_last)
        dh = np.interp(x_hi, knot, h) - np.interp(x_lo, knot, h)
        return np.where(span > 1e-9, dh / np.maximum(span, 1e-9), 0.0)

    k = fit(0.5 * window)
    if adaptive:
        wide = np.clip(0.5 / np.maximum(np.abs(k), 1e-9), window, max_window)
        k = fit(0.5 * wide)

    # smallest radius over each core
    abs_k = np.abs(k)
    inside = (s_st >= a[st_line] - 1e-9) & (s_st <= b[st_line] + 1e-9)
    max_k = np.maximum.reduceat(np.where(inside, abs_k, 0.0), st_start)
    with np.errstate(divide="ignore"):
        min_r = np.where(max_k > 1e-12, 1.0 / np.maximum(max_k, 1e-300), np.inf)

    # turn angle from raw chords
    seg_ok = np.ones(len(pts) - 1, dtype=bool) if len(pts) > 1 else np.zeros(0, dtype=bool)
    seg_ok[start[1:] - 1] = False
    raw = np.arctan2(d[:, 1], d[:, 0])
    raw_u = _unwrap_per_line(raw, line_of[:-1], seg_ok)
    i_ch = np.searchsorted(key, base + a - 1e-6, side="left") - 1
    j_ch = np.searchsorted(key, base + b + 1e-6, side="right") - 1
    i_ch = np.clip(i_ch, start, last - 1)
    j_ch = np.clip(j_ch, start, last - 1)
    turn = np.degrees(raw_u[j_ch] - raw_u[i_ch])

    with np.errstate(divide="ignore"):
        radius = np.where(abs_k > 1e-12, 1.0 / np.maximum(abs_k, 1e-300), np.inf)
    bounds = np.cumsum(n_st)[:-1].tolist()
    starts = [0, *bounds]
    ends = [*bounds, len(s_st)]
    split = [(s_st[i:j], k[i:j], radius[i:j]) for i, j in zip(starts, ends, strict=True)]
    stations = [
        Stations(a_, b_, c_, step)
        for a_, b_, c_ in zip(lo.tolist(), hi.tolist(), n_st.tolist(), strict=True)
    ]
    out = [x[0] for x in split], [x[1] for x in split], [x[2] for x in split], min_r, turn
    return (*out, stations)


def _unwrap_per_line(angles: np.ndarray, line_of: np.ndarray, ok: np.ndarray | None = None):
    """Unwrap angles within each line (jumps between lines and at ``~ok`` are not counted)."""
    if len(angles) == 0:
        return angles
    dh = np.diff(angles)
    dh -= 2 * np.pi * np.round(dh / (2 * np.pi))
    same = line_of[1:] == line_of[:-1]
    if ok is not None:
        same &= ok[1:] & ok[:-1]
    dh = np.where(same, dh, 0.0)
    out = np.concatenate(([0.0], np.cumsum(dh)))
    # re-anchor each run at its own first angle so values stay near the raw ones
    run_start = np.concatenate(([True], ~same))
    anchor = np.maximum.accumulate(np.where(run_start, np.arange(len(angles)), 0))
    return out - out[anchor] + angles[anchor]
