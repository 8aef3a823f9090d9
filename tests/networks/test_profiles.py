"""Radius profiles of many lines: stations kept as four numbers, and the compiled loops
against the vectorised numpy version they replaced (kept here as the reference)."""

from __future__ import annotations

import doctest
from unittest import mock

import numpy as np
import pytest

import clearance.networks.profile_kernel
import clearance.networks.profiles
from clearance.networks.curves import extract_curves
from clearance.networks.profiles import Profiles, Stations, profiles
from clearance.networks.reader import read_network
from clearance.networks.samples import build as samples

RNG = np.random.default_rng(20240611)


# --- the reference: networks/profiles.py as it was before the compiled loops ---------------

_GAP_M = 10.0


def reference_profiles(lines, core_from_m, core_to_m, chunk_lines=20000, **kw) -> Profiles:
    """:func:`profiles` with its compiled chunks replaced by the numpy version below
    (the loop over chunks, which only concatenates their results, is the library's)."""
    with mock.patch.object(clearance.networks.profiles, "_chunk", _reference_chunk), \
            mock.patch.object(clearance.networks.profiles, "CHUNK_LINES", chunk_lines):
        return profiles(lines, core_from_m, core_to_m, **kw)


def _reference_chunk(lines, a, b, step, window, margin, adaptive, min_chord, max_window):
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
    h = _reference_unwrap(np.arctan2(vec[:, 1], vec[:, 0]), line_of[ii])
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
    raw_u = _reference_unwrap(raw, line_of[:-1], seg_ok)
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


def _reference_unwrap(angles, line_of, ok=None):
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


# --- comparing ------------------------------------------------------------------------------


def _bits(x: np.ndarray) -> np.ndarray:
    """The float64 values as integers: equal only if equal to the bit (``-0.0 != 0.0``)."""
    return np.ascontiguousarray(x, dtype=np.float64).view(np.int64)


def assert_same(got: Profiles, want: Profiles) -> None:
    """Every field of ``got`` equal to ``want``'s to the bit."""
    assert len(got.s_m) == len(want.s_m) == len(got.stations) == len(want.stations)
    assert got.stations == want.stations
    for name in ("s_m", "curvature_per_m", "radius_m"):
        g, w = getattr(got, name), getattr(want, name)
        assert len(g) == len(w), name
        for n, (x, y) in enumerate(zip(g, w, strict=True)):
            assert x.shape == y.shape, (name, n)
            bad = np.flatnonzero(_bits(x) != _bits(y))
            assert bad.size == 0, (name, n, bad[:5], x[bad[:5]], y[bad[:5]])
    for name in ("min_radius_m", "turn_deg"):
        x, y = getattr(got, name), getattr(want, name)
        assert x.shape == y.shape, name
        bad = np.flatnonzero(_bits(x) != _bits(y))
        assert bad.size == 0, (name, bad[:5], x[bad[:5]], y[bad[:5]])


def random_line(rng: np.random.Generator) -> np.ndarray:
    """A polyline: a wandering path, a straight line, a zigzag or an arc, some with SUMO's
    0.01 m rounding, some with a z column, a few with a repeated point."""
    kind = rng.integers(6)
    n = int(rng.choice([2, 2, 3, 4, rng.integers(5, 15), rng.integers(15, 80)]))
    start = rng.uniform(-500, 500, 2)
    if kind == 0:  # wandering, chords from 1 cm to 10 m
        step = np.exp(rng.uniform(np.log(0.01), np.log(10.0), n - 1))
        heading = rng.uniform(-np.pi, np.pi) + np.cumsum(rng.normal(0, 0.6, n - 1))
    elif kind == 1:  # straight (collinear), uneven spacing
        step = rng.uniform(0.05, 8.0, n - 1)
        heading = np.full(n - 1, rng.choice([0.0, np.pi / 2, np.pi, rng.uniform(-np.pi, np.pi)]))
    elif kind == 2:  # sharp zigzag, back and forth along one axis at times (turns of pi)
        step = rng.uniform(0.2, 3.0, n - 1)
        base = rng.choice([0.0, rng.uniform(-np.pi, np.pi)])
        heading = base + np.where(np.arange(n - 1) % 2 == 1,
                                  rng.choice([np.pi, 2.8, -2.9]), 0.0)
    elif kind == 3:  # an arc of SUMO-like chords
        radius = rng.uniform(3.0, 60.0)
        step = np.full(n - 1, rng.uniform(0.3, 3.0))
        heading = rng.uniform(-np.pi, np.pi) + np.cumsum(np.full(n - 1, step[0] / radius)
                                                          * rng.choice([-1, 1]))
    elif kind == 4:  # spinning on the spot: many full turns
        step = rng.uniform(0.5, 2.0, n - 1)
        heading = np.cumsum(rng.uniform(1.0, 3.0, n - 1))
    else:  # tiny chords only (every chord extended to the end)
        step = rng.uniform(0.01, 0.2, n - 1)
        heading = rng.uniform(-np.pi, np.pi) + np.cumsum(rng.normal(0, 0.3, n - 1))
    xy = np.vstack([start, start + np.cumsum(np.c_[np.cos(heading), np.sin(heading)]
                                             * step[:, None], axis=0)])
    if rng.random() < 0.4:
        xy = np.round(xy, 2)
        keep = np.r_[True, np.any(np.diff(xy, axis=0) != 0, axis=1)]
        xy = xy[keep]
        if len(xy) < 2:
            xy = np.vstack([xy[:1], xy[:1] + [0.01, 0.0]])
    if rng.random() < 0.1:  # a repeated point (outside the contract, the same all the same)
        i = rng.integers(len(xy))
        xy = np.insert(xy, i, xy[i], axis=0)
    if rng.random() < 0.3:
        xy = np.c_[xy, rng.uniform(0, 5, len(xy))]
    return xy


def random_cores(rng: np.random.Generator, lines: list[np.ndarray]):
    """Cores inside, at 0, at the full length, empty, and beyond either end."""
    a, b = [], []
    for line in lines:
        length = float(np.hypot(*np.diff(line[:, :2], axis=0).T).sum())
        kind = rng.integers(6)
        if kind == 0:
            x, y = 0.0, length
        elif kind == 1:
            x, y = 0.0, rng.uniform(0, length)
        elif kind == 2:
            x, y = rng.uniform(0, length), length
        elif kind == 3:
            x = y = rng.choice([0.0, length, rng.uniform(0, length)])
        elif kind == 4:
            x, y = -rng.uniform(0, 5), length + rng.uniform(0, 5)
        else:
            x, y = np.sort(rng.uniform(0, length, 2))
        a.append(x)
        b.append(y)
    return a, b


# --- tests ----------------------------------------------------------------------------------


def test_stations_give_back_the_profile_stations_exactly():
    rng = np.random.default_rng(7)
    lines = [np.c_[np.cumsum(rng.uniform(0.5, 4, n)), rng.uniform(-1, 1, n)] for n in (3, 9, 30)]
    p = profiles(lines, [1.3, 2.0, 10.1], [4.7, 12.9, 40.05], step_m=0.25, window_m=3.0)
    assert len(p.stations) == len(lines)
    for s, st in zip(p.s_m, p.stations, strict=True):
        assert isinstance(st, Stations) and st.count == len(s)
        assert np.array_equal(st.array(), s)
        assert s[0] == st.start_m and s[-1] <= st.stop_m


@pytest.mark.parametrize("adaptive", [True, False])
@pytest.mark.parametrize("chunk", [20000, 7])
def test_compiled_loops_equal_the_numpy_version_on_random_lines(adaptive, chunk, monkeypatch):
    monkeypatch.setattr(clearance.networks.profiles, "CHUNK_LINES", chunk)
    rng = np.random.default_rng(1000 + chunk + adaptive)
    for step, window, margin, max_window in [(0.25, 3.0, None, 15.0), (0.5, 2.0, 0.0, 15.0),
                                             (0.1, 6.0, 1.3, 4.0), (1.0, 3.0, 10.0, 30.0)]:
        lines = [random_line(rng) for _ in range(150)]
        a, b = random_cores(rng, lines)
        kw = dict(step_m=step, window_m=window, margin_m=margin, adaptive=adaptive,
                  max_window_m=max_window)
        got = profiles(lines, a, b, **kw)
        want = reference_profiles(lines, a, b, chunk_lines=chunk, **kw)
        assert_same(got, want)


def test_exact_reversals_and_min_chord_zero_equal_the_numpy_version():
    # chords turning by exactly pi (a half-way wrap: numpy rounds it to even), no extension
    # of short chords, every chord extended to the end, integer coordinates
    lines = [np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [3.0, 0.0], [0.5, 0.0]]),
             np.array([[0.0, 0.0], [0.0, 1.0], [0.0, -1.0], [0.0, 2.0]]),
             np.array([[0.0, 0.0], [1.0, 0.0]]),
             np.array([[5.0, 5.0], [5.0, 6.0], [6.0, 6.0]]),
             np.array([[0, 0], [3, 0], [3, 4], [10, 4]])]  # integers
    a, b = [0.0, 0.5, 0.0, 0.0, 1.0], [7.0, 5.0, 1.0, 2.0, 12.0]
    for min_chord in (0.0, 1.5, 100.0):
        for adaptive in (True, False):
            kw = dict(min_chord_m=min_chord, adaptive=adaptive)
            assert_same(profiles(lines, a, b, **kw), reference_profiles(lines, a, b, **kw))


@pytest.mark.parametrize("name", samples.SAMPLES)
def test_compiled_loops_equal_the_numpy_version_on_the_sample_curves(name):
    net = read_network(samples.SAMPLES_DIR / name / f"{name}.net.xml")
    curves = extract_curves(net, areas=False)
    assert curves
    lines = [c.centerline for c in curves]
    a = [c.core_start_m for c in curves]
    b = [c.core_end_m for c in curves]
    for kw in (dict(step_m=0.25, window_m=3.0), dict(adaptive=False),
               dict(step_m=0.1, window_m=5.0, margin_m=8.0)):
        got = profiles(lines, a, b, **kw)
        assert_same(got, reference_profiles(lines, a, b, **kw))


def test_the_comparison_sees_a_difference():
    lines = [random_line(RNG) for _ in range(20)]
    a, b = random_cores(RNG, lines)
    want = reference_profiles(lines, a, b)
    got = profiles(lines, a, b)
    bumped = Profiles(got.s_m, got.stations, got.curvature_per_m, got.radius_m,
                      got.min_radius_m, np.nextafter(got.turn_deg, np.inf))
    with pytest.raises(AssertionError):
        assert_same(bumped, want)
    k = [x.copy() for x in got.curvature_per_m]
    k[3][-1] = -k[3][-1] if k[3][-1] != 0 else -0.0
    with pytest.raises(AssertionError):
        assert_same(Profiles(got.s_m, got.stations, k, got.radius_m, got.min_radius_m,
                             got.turn_deg), want)


def test_empty_input_and_short_lines():
    p = profiles([], [], [])
    assert (p.s_m, p.stations, p.curvature_per_m, p.radius_m) == ([], [], [], [])
    assert p.min_radius_m.shape == p.turn_deg.shape == (0,)
    with pytest.raises(ValueError, match="at least two points"):
        profiles([np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([[1.0, 1.0]])], [0, 0], [1, 1])
    with pytest.raises(ValueError, match="at least two points"):
        profiles([np.zeros((0, 2))], [0.0], [0.0])
    with pytest.raises(ValueError, match="x and y"):
        profiles([np.zeros((3, 1))], [0.0], [0.0])
    # lines of two and three columns together are read as x, y
    two = np.array([[0.0, 0.0], [3.0, 1.0], [5.0, 4.0]])
    p = profiles([two, np.c_[two, [1.0, 2.0, 3.0]]], [0.5, 0.5], [4.0, 4.0])
    assert_same(p, reference_profiles([two, np.c_[two, [1.0, 2.0, 3.0]]], [0.5, 0.5],
                                      [4.0, 4.0]))


def test_a_straight_line_has_no_curvature_and_no_turn():
    line = np.array([[0.0, 0.0], [3.0, 4.0], [6.0, 8.0], [7.5, 10.0]])
    p = profiles([line], [2.0], [10.0], step_m=0.5, window_m=2.0)
    assert np.all(p.curvature_per_m[0] == 0.0) and np.all(np.isinf(p.radius_m[0]))
    assert p.min_radius_m.tolist() == [np.inf] and p.turn_deg.tolist() == [0.0]


def test_docstring_examples():
    for mod in (clearance.networks.profiles, clearance.networks.profile_kernel):
        result = doctest.testmod(mod)
        assert result.failed == 0 and result.attempted > 0, mod.__name__
