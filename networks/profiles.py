"""Curvature profiles and turn angles of many polylines at once (compiled loops).

The method (see :mod:`clearance.networks.geometry`): the heading of a line is known at the midpoint
of each chord and interpolated linearly in between, so the turn at a vertex is spread over the
half-chords either side; curvature is the change of that heading over a window of arc
length. Chords shorter than ``min_chord_m`` are extended to the first point at least that
far on (SUMO writes coordinates to 0.01 m, a heading noise of 1° on 0.5 m chords). A second
pass widens the window to half the radius found (up to ``max_window_m``) so that rounding
does not make wide curves look tight.

All lines are concatenated and processed in chunks, so that the per-call cost of numpy and
of the compiled loops (:mod:`clearance.networks.profile_kernel`) is paid per chunk, not per line.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import repeat
from typing import NamedTuple

import numpy as np

from clearance.networks.collector import gc_paused
from clearance.networks.profile_kernel import chord_frame, station_profiles

__all__ = ["CHUNK_LINES", "MAX_WINDOW_M", "MIN_CHORD_M", "Profiles", "Stations", "profiles"]

#: Chords shorter than this (m) are extended before headings are taken.
MIN_CHORD_M = 1.5

#: The widest window of arc length the adaptive curvature fit uses (metres).
MAX_WINDOW_M = 15.0

#: Lines per chunk (bounds the memory of the station arrays).
CHUNK_LINES = 20000


class Stations(NamedTuple):
    """Stations every ``step_m`` from ``start_m``, the last one no further than ``stop_m``:
    ``s_i = min(start_m + step_m * i, stop_m)`` for ``i < count`` (four numbers instead of
    an array; :meth:`array` gives the same floats the profile was computed at). A named
    tuple: a large network has hundreds of thousands, made in half the time of a frozen
    dataclass.

    Examples
    --------
    >>> Stations(1.0, 2.1, 6, 0.25).array().tolist()
    [1.0, 1.25, 1.5, 1.75, 2.0, 2.1]
    """

    start_m: float
    stop_m: float
    count: int  # type: ignore[assignment]  # the field shadows tuple.count, on purpose
    step_m: float

    def array(self) -> np.ndarray:
        """The stations (metres).

        Examples
        --------
        One station where the stations start and stop at the same place:

        >>> Stations(3.0, 3.0, 1, 0.25).array().tolist()
        [3.0]
        """
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
        Polylines (N, ≥2) without repeated points, finite coordinates (x, y, and any more
        columns, which are not read; taken as float64).
    core_from_m, core_to_m
        The core of each line (plane arc length); ``min_radius_m`` is taken over it, and
        ``turn_deg`` is the heading change from the chord entering it to the chord leaving
        it (degrees, left positive, unwrapped).
    margin_m
        Stations extend this far either side of the core (default: ``window_m``).

    Raises
    ------
    ValueError
        A line of fewer than two points.

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

    The straight line is straight at every station; no lines, no profiles:

    >>> p.curvature_per_m[1].tolist() == [0.0] * 21, p.radius_m[1].max()
    (True, np.float64(inf))
    >>> q = profiles([], [], [])
    >>> q.s_m, q.stations, q.min_radius_m.shape
    ([], [], (0,))
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
    with gc_paused():  # a few objects per line, all kept: nothing for the collector to free
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


def _chunk(
    lines: Sequence[np.ndarray],
    a: np.ndarray,
    b: np.ndarray,
    step: float,
    window: float,
    margin: float,
    adaptive: bool,
    min_chord: float,
    max_window: float,
) -> tuple[
    list[np.ndarray], list[np.ndarray], list[np.ndarray], np.ndarray, np.ndarray, list[Stations]
]:
    """:func:`profiles` of one chunk of lines: stations, curvature and radius per line, and
    the smallest radii, turn angles (degrees) and :class:`Stations` of the lines.

    The loops are compiled (:mod:`clearance.networks.profile_kernel`); numpy takes the headings of
    the chords between them.

    Examples
    --------
    A straight line 2 m long, core 0.5-1.5 m, stations every 0.5 m and 0.5 m either side:

    >>> s, k, r, min_r, turn, st = _chunk(
    ...     [np.array([[0.0, 0.0], [2.0, 0.0]])], np.array([0.5]), np.array([1.5]),
    ...     0.5, 3.0, 0.5, True, MIN_CHORD_M, MAX_WINDOW_M)
    >>> s[0].tolist(), k[0].tolist(), min_r.tolist(), turn.tolist()
    ([0.0, 0.5, 1.0, 1.5, 2.0], [0.0, 0.0, 0.0, 0.0, 0.0], [inf], [0.0])
    >>> st
    [Stations(start_m=0.0, stop_m=2.0, count=5, step_m=0.5)]
    """
    n = len(lines)
    counts = np.fromiter(map(len, lines), dtype=np.int64, count=n)
    if np.any(counts < 2):
        raise ValueError("every line needs at least two points")
    try:  # x, y (and z, not read) of every point; lines of mixed widths need slicing
        pts = np.concatenate(lines)
    except ValueError:
        pts = np.empty((0, 0))
    if pts.ndim != 2 or pts.shape[1] < 2:
        pts = np.concatenate([x[:, :2] for x in lines])
        if pts.shape[1] < 2:
            raise ValueError("every line needs x and y")
    pts = pts.astype(np.float64, copy=False)
    s, key, knot, kx, ky, cx, cy = chord_frame(pts, counts, float(min_chord))
    lo, hi, n_st, s_st, k, radius, min_r, turn = station_profiles(
        s,
        key,
        counts,
        knot,
        np.arctan2(ky, kx),
        np.arctan2(cy, cx),
        np.ascontiguousarray(a, dtype=np.float64),
        np.ascontiguousarray(b, dtype=np.float64),
        float(step),
        float(window),
        float(margin),
        bool(adaptive),
        float(max_window),
    )
    bounds = np.cumsum(n_st).tolist()
    starts = [0, *bounds[:-1]]
    out_s = [s_st[i:j] for i, j in zip(starts, bounds, strict=True)]
    out_k = [k[i:j] for i, j in zip(starts, bounds, strict=True)]
    out_r = [radius[i:j] for i, j in zip(starts, bounds, strict=True)]
    stations = list(map(Stations, lo.tolist(), hi.tolist(), n_st.tolist(), repeat(step, n)))
    return out_s, out_k, out_r, min_r, np.degrees(turn), stations
