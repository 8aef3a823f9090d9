"""Swung paths: the lateral offset profiles a driver takes through a turn too tight for the lane.

A driver whose vehicle cannot make a turn on its lane's centre line swings wide: out toward
the outside of the turn before it, round on a wider radius, and back after it, using the
rest of its own roadway, then the opposing lanes, then whatever else is paved. This module
makes those paths, a fixed family per run, as offsets of the lane's (smoothed) centre line.

Candidates
----------
Every candidate is the centre line shifted sideways by an offset profile ``d(s)`` (m, left
positive, toward the outside of the turn, :func:`offset_profile`):

- ``d = 0`` up to the ramp's start, ``L = max(min_ramp_m, ramp_per_m * A)`` before the
  feature (clipped to the centre line's start), rising as a half cosine to the amplitude
  ``A`` at the feature's start;
- ``A`` held over the feature; the whole profile is then multiplied by ``1 - c sin^2``
  (``c`` the *apex cut*) from the middle of the ramp in to the middle of the ramp out, so
  that it peaks at the feature's middle: the path cuts back toward the inside at the apex,
  on a wider radius, as a driver does who swings out and then turns in;
- back to ``0`` as a half cosine over ``L`` after the feature (clipped to its end).

Where the lead-in (or run-out) is shorter than half a ramp, the ramp ends (or starts) inside
the feature instead, at most half way through it. The amplitudes are fitted to the run's
room: ``room * k / steps`` for ``k = 1 .. steps`` (:meth:`SwingSearch.amplitudes_m`), the
room being how far the centre line can move outward at the feature's start, middle and end
before the body's side reaches the paved area's edge
(:func:`clearance.networks.driving.room.outside_room_m`, at most 6 m); the family is every amplitude
with every cut of :attr:`SwingSearch.apex_cuts`: a bounded number of candidates per run
(12 by default), in a fixed order (smallest swing first), so the search is deterministic.
A candidate whose offset would fold the line over itself (``1 - kappa d <= 0.2``
anywhere, ``kappa`` the centre line's curvature) is left out.

Two more shapes fit the room where it differs along the turn (:attr:`SwingSearch.shaped`):

- *fitted*: the ends follow the room at the feature's start and at its end separately,
  ``d = f room_start`` up to the feature, a half cosine across it to ``d = f room_end``
  (``f = k / steps``, the middle apex cut), then down: a driver swings wide on a wide
  approach and turns in to a narrow exit lane (or the reverse); only where the two rooms
  differ by more than :data:`FITTED_MIN_M`;
- *inside*: the path cuts the corner toward the *inside* of the turn: the centre line up to
  ``t`` before the feature, then one smooth curve (a cubic Hermite, tangent to the centre
  line at both ends, as round as a circular arc where the two tangents are alike) to ``t``
  after it, then the centre line again: a wider radius tangent to the same approach and
  exit lanes, the path a car takes across the middle of a junction whose drawn lane turns
  tighter than it can (:func:`corner_cut`; ``t = inside_step_m 2^(k - 1)``: 2, 4, 8,
  16 m). Kept where its deepest cut, inside the feature, is within the room toward the
  inside at the feature's middle. A feature that is not one corner (it turns the other way
  somewhere, tighter than :data:`REVERSE_RADIUS_M`, as a roundabout's entry and exit do, or
  turns back by more than 150°) is cut instead by ``d = -B sin^2(pi (s - a) / (e - a))``
  over the whole manoeuvre (:func:`apex_bump`, ``B = f room_inside``, ramps as for ``B``).

The offset path is the smoothed centre line's points moved along its normals,
``p + d n``; the profile and the centre line are smooth, so the offset is too (its
curvature is ``kappa / (1 - kappa d)`` plus the profile's own, :func:`max_curvature_1_m`).
The same follower drives it (:func:`clearance.analysis.tracking.simulate_batch`), within the
vehicle's lock and steering rate: a candidate the vehicle cannot follow is ``cannot-turn``.

Which candidate
---------------
Each followed candidate is judged, and the best kept, by
:mod:`clearance.networks.driving.judging`.
The candidates are tried in rounds of growing size, and the search of a run stops once a
round finds a paved path better than its lane's (:mod:`clearance.networks.driving.swing`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from clearance.analysis.polyline import Path
from clearance.networks.driving.room import outside_sign
from clearance.networks.driving.shapes import (
    apex_bump,
    corner_cut,
    kept_part,
    offset_profile,
    offset_run,
    ramp_bounds,
    shaped_profile,
)

__all__ = ["Candidate", "FITTED_MIN_M", "JOG_MAX_DEG", "LOOPED_EXCESS_DEG", "MIN_FOLD",
           "REVERSE_RADIUS_M", "SwingSearch", "candidates", "excess_turning_deg"]

FloatArray = NDArray[np.float64]


FITTED_MIN_M = 0.25
"""The fitted shape is tried only where the rooms at the feature's ends differ by more (m)."""

REVERSE_RADIUS_M = 50.0
"""A feature that turns against its turn tighter than this somewhere is not one corner."""

JOG_MAX_DEG = 30.0
"""A feature turning no more than this overall is a *jog*, a sideways step (degrees)."""

LOOPED_EXCESS_DEG = 60.0
"""A junction turn whose centre line turns this much more, back and forth, than its net
turn (:func:`excess_turning_deg`) is *looped*: SUMO drew its internal lane with a kink or a
loop that no driver follows, and the search also tries the direct corner cuts."""

MIN_FOLD = 0.2
"""A candidate is left out where ``1 - kappa d`` (the offset's stretch) falls to this."""


@dataclass(frozen=True)
class SwingSearch:
    """The bounds of the search (lengths in metres).

    Attributes
    ----------
    steps
        Amplitudes per run: ``room * k / steps`` for ``k = 1 .. steps``, ``room`` the
        outward room of the run (:func:`clearance.networks.driving.room.outside_room_m`, at most
        ``max_amplitude_m``).
    max_amplitude_m, min_amplitude_m
        The widest swing searched; the narrowest (where the room is smaller, only this).
    apex_cuts
        Fractions of the amplitude taken back at the feature's middle (0: held).
    ramp_per_m, min_ramp_m
        The ramps in and out are ``max(min_ramp_m, ramp_per_m * A)`` long.
    shaped
        Also the *fitted* and *inside* shapes (``steps`` of each, where they apply).
    inside_step_m
        The inside shapes leave the centre line ``inside_step_m 2^(k - 1)`` before the
        feature and rejoin it as far after (``k = 1 .. steps``).

    Examples
    --------
    >>> SwingSearch().count, SwingSearch().amplitudes_m(3.0)
    (24, (0.75, 1.5, 2.25, 3.0))
    >>> SwingSearch().amplitudes_m(0.05), SwingSearch().amplitudes_m(float("inf"))[-1]
    ((0.15,), 6.0)
    >>> SwingSearch(steps=0)
    Traceback (most recent call last):
    ...
    ValueError: swing search: steps must be >= 1, got 0
    """

    steps: int = 4
    max_amplitude_m: float = 6.0
    min_amplitude_m: float = 0.15
    apex_cuts: tuple[float, ...] = (0.0, 0.3, 0.6)
    ramp_per_m: float = 4.0
    min_ramp_m: float = 6.0
    shaped: bool = True
    inside_step_m: float = 2.0

    def __post_init__(self) -> None:
        if not (isinstance(self.steps, int) and self.steps >= 1):
            raise ValueError(f"swing search: steps must be >= 1, got {self.steps!r}")
        if not (0 < self.min_amplitude_m <= self.max_amplitude_m
                and math.isfinite(self.max_amplitude_m)):
            raise ValueError("swing search: amplitudes must be 0 < min <= max, finite")
        if not self.apex_cuts or not all(0 <= c < 1 for c in self.apex_cuts):
            raise ValueError(f"swing search: apex cuts must be in [0, 1), got {self.apex_cuts}")
        if not (self.ramp_per_m > 0 and self.min_ramp_m > 0 and self.inside_step_m > 0):
            raise ValueError("swing search: ramp and inside step lengths must be > 0 m")

    @property
    def middle_cut(self) -> float:
        """The apex cut of the first rounds and of the fitted shapes (the middle one)."""
        return self.apex_cuts[len(self.apex_cuts) // 2]

    @property
    def count(self) -> int:
        """Candidates per run (at most; folding ones left out; a jog's apex bumps too)."""
        return self.steps * (len(self.apex_cuts) + (3 if self.shaped else 0))

    def amplitudes_m(self, room_m: float) -> tuple[float, ...]:
        """The amplitudes searched for an outward room of ``room_m``, smallest first."""
        top = min(room_m, self.max_amplitude_m)
        if not top > self.min_amplitude_m:
            return (self.min_amplitude_m,)
        return tuple(round(max(self.min_amplitude_m, top * k / self.steps), 3)
                     for k in range(1, self.steps + 1))

    def ramp_m(self, amplitude_m: float) -> float:
        """Length of the ramps in and out for an amplitude (m)."""
        return max(self.min_ramp_m, self.ramp_per_m * amplitude_m)


@dataclass(frozen=True)
class Candidate:
    """One swung path.

    Attributes
    ----------
    amplitude_m, apex_cut
        The profile's amplitude (outward, m) and apex cut fraction.
    offset_m
        Signed offset ``d`` at each point of the centre line the path keeps (left
        positive; all of it unless cropped, :func:`candidates`).
    path
        The offset path, ready for the follower.
    window_m
        ``(start, end)``: the ramps and the feature along ``path`` (m), the part judged.
    station_map
        The offset path's station at each of those points.
    shape
        ``held`` (the amplitude over the whole feature), ``fitted`` (``amplitude_m`` at the
        feature's start, ``exit_m`` at its end), ``inside`` (cutting the corner, at most
        ``inside_m`` inside the centre line within the feature; ``amplitude_m`` 0) or
        ``refined`` (:mod:`clearance.networks.driving.refine`: ``amplitude_m`` at the feature's
        start, ``apex_m`` at its apex, ``exit_m`` at its end; negative toward the inside).
    step
        Its size in its shape's family: ``k`` of ``k = 1 .. steps`` (the round it is
        tried in, :func:`clearance.networks.driving.swing.swing_pass`).
    """

    amplitude_m: float
    apex_cut: float
    offset_m: FloatArray
    path: Path
    window_m: tuple[float, float]
    station_map: FloatArray
    shape: str = "held"
    exit_m: float = 0.0
    inside_m: float = 0.0
    step: int = 1
    apex_m: float = 0.0

    @property
    def how(self) -> str:
        """The path in words (the start of :func:`swing_reason`).

        Examples
        --------
        >>> from clearance.analysis.polyline import prepare_path
        >>> z = np.zeros(1)
        >>> p = prepare_path([(0.0, 0.0), (1.0, 0.0)])
        >>> Candidate(2.0, 0.0, z, p, (0.0, 1.0), z).how
        'swings 2.00 m out from the lane centre line'
        >>> Candidate(3.5, 0.3, z, p, (0.0, 1.0), z, "fitted", 0.5).how
        'swings 3.50 m out before the turn and 0.50 m after it'
        >>> Candidate(0.0, 0.0, z, p, (0.0, 1.0), z, "inside", inside_m=1.25).how
        'cuts the corner 1.25 m inside the lane centre line, on a wider radius'
        >>> print(Candidate(1.0, 0.0, z, p, (0.0, 1.0), z, "refined", -0.3, apex_m=0.6).how)
        ... # doctest: +NORMALIZE_WHITESPACE
        takes its own line: 1.00 m out at the turn's start, 0.60 m out at its apex,
        0.30 m in at its end
        >>> print(Candidate(0.0, 0.0, z, p, (0.0, 1.0), z, "refined", 0.0, apex_m=-0.7).how)
        ... # doctest: +NORMALIZE_WHITESPACE
        takes its own line: on the centre line at the turn's start, 0.70 m in at its apex,
        on the centre line at its end
        """
        if self.shape == "refined":
            def side(x: float) -> str:
                if abs(x) < 0.005:
                    return "on the centre line"
                return f"{abs(x):.2f} m {'in' if x < 0 else 'out'}"
            return (f"takes its own line: {side(self.amplitude_m)} at the turn's start, "
                    f"{side(self.apex_m)} at its apex, {side(self.exit_m)} at its end")
        if self.shape == "inside":
            return (f"cuts the corner {self.inside_m:.2f} m inside the lane centre line, "
                    "on a wider radius")
        if self.shape == "fitted":
            return (f"swings {self.amplitude_m:.2f} m out before the turn and "
                    f"{self.exit_m:.2f} m after it")
        how = f"swings {self.amplitude_m:.2f} m out"
        return how + (f" ({self.apex_cut:.0%} of it taken back at the apex)"
                      if self.apex_cut > 0 else " from the lane centre line")


def excess_turning_deg(path: Path, feature_m: tuple[float, float],
                       turn_angle_deg: float) -> float:
    """How much more the path turns within the feature, counting every turn whichever its
    hand, than the feature's turn ``turn_angle_deg`` (from the heading in to the heading
    out; degrees): about 0 for a turn of one hand, twice the turn back for a line that turns
    back on itself, 360 for a loop.

    Examples
    --------
    A quarter circle turns 90 degrees and nothing more; a 4 m-radius loop drawn into a
    straight line turns 360 degrees, all of it in excess of the straight line's 0:

    >>> from clearance.analysis.polyline import prepare_path
    >>> a = np.radians(np.linspace(90, 0, 31))
    >>> arc = np.c_[4 * np.cos(a), 20 + 4 * np.sin(a)]
    >>> p = prepare_path(np.vstack([[(-20.0, 24.0)], arc, [(4.0, 0.0)]]), 0.1)
    >>> round(excess_turning_deg(p, (19.0, 27.3), -90.0))
    0
    >>> t = np.radians(np.linspace(-90, 270, 73))
    >>> loop = np.c_[4 * np.cos(t), 4 + 4 * np.sin(t)]
    >>> q = prepare_path(np.vstack([[(-20.0, 0.0)], loop, [(20.0, 0.0)]]), 0.1)
    >>> round(excess_turning_deg(q, (15.0, 50.0), 0.0) / 10) * 10
    360

    A feature with fewer than two points has none:

    >>> excess_turning_deg(p, (5.0, 5.0), -90.0)
    0.0
    """
    s = path.station_m
    inside = (s >= feature_m[0]) & (s <= feature_m[1])
    if int(inside.sum()) < 2:
        return 0.0
    turns = np.diff(np.unwrap(path.heading_rad[inside]))
    return float(np.degrees(np.sum(np.abs(turns))) - abs(turn_angle_deg))


def candidates(path: Path, feature_m: tuple[float, float], turn_angle_deg: float,
               search: SwingSearch | None = None, room_m: float = math.inf,
               reach_m: float | None = None,
               rooms_m: tuple[float, float, float] | None = None,
               inside_room_m: float = 0.0, step: int | None = None,
               looped: bool = False) -> list[Candidate]:
    """The swung paths of one run, in the search's order (see the module docstring).

    With ``step`` only those of that size ``k`` (:attr:`Candidate.step`).

    With ``reach_m`` each candidate keeps only the centre line from ``reach_m`` before its
    ramp in to ``reach_m`` after its ramp out (a vehicle's length and a little more: all a
    judged sample's body can cover), so that it is driven no further than it is judged.
    With ``rooms_m`` (the outward room at the feature's start, middle and end,
    :func:`clearance.networks.driving.room.outside_rooms_m`) and :attr:`SwingSearch.shaped`, the
    *fitted* shapes follow; with ``inside_room_m`` (the room toward the inside at the
    middle) the *inside* ones. A ``looped`` turn (:data:`LOOPED_EXCESS_DEG`) gets the corner
    cuts whatever its inside room: each leaves the centre line before the loop and rejoins it
    after, on a curve that follows the turn's net course.

    Examples
    --------
    A right-hand quarter circle of radius 4 m between two 20 m straights: 12 candidates,
    all offset to the left (the outside), each with the lane's ends:

    >>> from clearance.analysis.polyline import prepare_path
    >>> a = np.radians(np.linspace(90, 0, 31))
    >>> arc = np.c_[4 * np.cos(a), 20 + 4 * np.sin(a)]
    >>> p = prepare_path(np.vstack([[(-20.0, 24.0)], arc, [(4.0, 0.0)]]), smooth=True)
    >>> cs = candidates(p, (20.0, 26.3), -90.0)
    >>> len(cs), bool(all(c.offset_m.max() > 0 for c in cs))
    (12, True)
    >>> bool(np.allclose(cs[0].path.xy[[0, -1]], p.xy[[0, -1]], atol=1e-6))
    True

    A wide approach and a narrow exit add the fitted shapes; room inside, the inside ones
    (offsets to the right, the inside of this turn):

    >>> cs = candidates(p, (20.0, 26.3), -90.0, room_m=0.5, rooms_m=(3.0, 5.0, 0.5),
    ...                 inside_room_m=2.0)
    >>> [(c.amplitude_m, c.exit_m) for c in cs if c.shape == "fitted"][:2]
    [(0.75, 0.125), (1.5, 0.25)]
    >>> [(c.shape, c.inside_m) for c in cs[-2:]]
    [('inside', 0.679), ('inside', 1.521)]
    >>> bool(cs[-1].offset_m.min() < -1.5 and cs[-1].offset_m.max() <= 0)
    True

    A feature that does not turn has no outside and no candidates:

    >>> candidates(p, (20.0, 26.3), 0.0)
    []

    Cropped 8 m beyond the ramps, the smallest swing (a 6 m ramp) starts 14 m before the
    feature:

    >>> c = candidates(p, (20.0, 26.3), -90.0, reach_m=8.0)[0]
    >>> round(float(c.window_m[0]), 6), bool(np.allclose(c.path.xy[0], p.point_at(6.0)))
    (8.0, True)
    """
    search = search or SwingSearch()
    side = outside_sign(turn_angle_deg)
    if side == 0.0:
        return []
    # (shape, start amplitude, exit amplitude, cut, ramp in, ramp out)
    plans: list[tuple[str, float, float, float, float, float, int]] = []
    for k, amp in enumerate(search.amplitudes_m(room_m), start=1):
        ramp = search.ramp_m(amp)
        plans += [("held", amp, amp, cut, ramp, ramp, k) for cut in search.apex_cuts]
    if search.shaped and rooms_m is not None:
        top = search.max_amplitude_m
        r0, r1 = min(max(rooms_m[0], 0.0), top), min(max(rooms_m[2], 0.0), top)
        if abs(r0 - r1) > FITTED_MIN_M:
            cut = search.middle_cut
            for k in range(1, search.steps + 1):
                a0 = round(max(search.min_amplitude_m, r0 * k / search.steps), 3)
                a1 = round(r1 * k / search.steps, 3)
                plans.append(("fitted", a0, a1, cut, search.ramp_m(a0), search.ramp_m(a1), k))
    s = path.station_m
    out = []
    for shape, a0, a1, cut, ramp_in, ramp_out, k in plans:
        if step is not None and k != step:
            continue
        a, _, _, _ = ramp_bounds(path.length_m, feature_m, ramp_in)
        _, _, _, e = ramp_bounds(path.length_m, feature_m, ramp_out)
        lane, keep = kept_part(path, a, e, reach_m)
        if shape == "held":
            d = side * offset_profile(s, feature_m, a0, ramp_in, cut)[keep]
        else:
            d = side * shaped_profile(s, feature_m, a0, a1, ramp_in, ramp_out, cut)[keep]
        if np.min(1.0 - lane.curvature_1_m * d) <= MIN_FOLD:
            continue
        label = f"swung {a0:g} m, cut {cut:g}" if shape == "held" else f"swung {a0:g} to {a1:g} m"
        p, window, smap = offset_run(path, lane, keep, d, (a, e), feature_m,
                                      f"{path.name} ({label})")
        out.append(Candidate(float(a0), float(cut), d, p, window, smap, shape, float(a1),
                             step=k))
    corner = False
    if search.shaped and inside_room_m > search.min_amplitude_m:
        k_in = path.curvature_1_m[(s >= feature_m[0]) & (s <= feature_m[1])]
        jog = abs(turn_angle_deg) <= JOG_MAX_DEG
        corner = jog or (abs(turn_angle_deg) <= 150.0 and not len(k_in) == 0
                         and float(np.max(side * k_in)) < 1.0 / REVERSE_RADIUS_M)
        if corner:
            out += _corner_cuts(path, feature_m, side, search, inside_room_m, reach_m, jog,
                                step)
        if not corner or jog:  # a jog may also be driven as its step, eased inward
            out += _apex_bumps(path, feature_m, side, search, inside_room_m, reach_m, step)
    if search.shaped and looped and not corner:  # the cuts across the loop, on any side
        out += _corner_cuts(path, feature_m, side, search, math.inf, reach_m, step=step,
                            either_side=True)
    return out


def _corner_cuts(path: Path, feature_m: tuple[float, float], side: float, search: SwingSearch,
                 inside_room_m: float, reach_m: float | None, jog: bool = False,
                 step: int | None = None, either_side: bool = False) -> list[Candidate]:
    """The *inside* candidates of one corner: :func:`corner_cut` 2, 4, 8, 16 m out; a jog's
    (docs/design.md §6) two shortest one-sided (2 m before to 16 m after, and the reverse);
    with ``step``, the ``step``-th only. ``either_side``: the cut's depth is its largest
    distance from the centre line on either side (a looped turn's)."""
    out = []
    s = path.station_m
    leads = [search.inside_step_m * 2.0 ** (k - 1) for k in range(1, search.steps + 1)]
    pairs = [(t, t) for t in leads]
    if jog and search.steps > 2:
        pairs = [(leads[-1], leads[0]), (leads[0], leads[-1]), *pairs[2:]]
    for k, (before, after) in enumerate(pairs, start=1):
        if step is not None and k != step:
            continue
        lane, keep = kept_part(path, feature_m[0] - before, feature_m[1] + after, reach_m)
        base = float(s[keep][0])
        lead = 0.5 * (before + after)  # window_in: ``before`` ahead, ``after`` past it
        feat = (feature_m[0] - base, feature_m[1] - base)
        window_in = (feat[0] - before + lead, feat[1] + after - lead)
        label = f"{lead:g} m" if before == after else f"{before:g} to {after:g} m"
        p, d, smap, window = corner_cut(lane, window_in, lead,
                                        name=f"{path.name} (corner cut {label})")
        ls = lane.station_m
        inner = (ls >= feat[0]) & (ls <= feat[1])
        cut = np.abs(d[inner]) if jog or either_side else -side * d[inner]
        depth = float(np.max(cut)) if inner.any() else 0.0
        if p is lane or depth <= search.min_amplitude_m or (depth > inside_room_m and not jog):
            continue
        out.append(Candidate(0.0, 0.0, d, p, window, smap, "inside", 0.0, round(depth, 3),
                             step=k))
    return out


def _apex_bumps(path: Path, feature_m: tuple[float, float], side: float, search: SwingSearch,
                inside_room_m: float, reach_m: float | None, step: int | None = None
                ) -> list[Candidate]:
    """The *inside* candidates of a feature that is not one corner: :func:`apex_bump`."""
    out = []
    s = path.station_m
    top = min(inside_room_m, search.max_amplitude_m)
    for k in range(1, search.steps + 1):
        if step is not None and k != step:
            continue
        depth = round(top * k / search.steps, 3)
        ramp = search.ramp_m(depth)
        a, _, _, e = ramp_bounds(path.length_m, feature_m, ramp)
        lane, keep = kept_part(path, a, e, reach_m)
        d = -side * apex_bump(s, feature_m, depth, ramp)[keep]
        if np.min(1.0 - lane.curvature_1_m * d) <= MIN_FOLD:
            continue
        p, window, smap = offset_run(path, lane, keep, d, (a, e), feature_m,
                                      f"{path.name} (cut {depth:g} m inside)")
        out.append(Candidate(0.0, 0.0, d, p, window, smap, "inside", 0.0, depth, step=k))
    return out

