"""Refined swung paths: a local search of one offset profile where the family falls short.

The fixed family of :mod:`clearance.networks.driving.candidates` tries a few shapes of a few sizes.
Where the best of them still leaves the paved area by a little, or none of them can be driven, the
path a driver would take often lies between them: out early on a wide approach, a late
apex, the exit taken on the inside of a narrow exit lane. A driver finds it by adjusting
the line; this module does the same with a *compass search* (a pattern search without
derivatives) over the six numbers of one profile (:class:`Knots`):

- the offset toward the outside of the turn at the feature's start (``start_m``), at its
  apex (``apex_m``, at the fraction ``apex_at`` of the feature) and at its end
  (``end_m``); negative is toward the inside;
- the lengths of the ramps in and out (``ramp_in_m``, ``ramp_out_m``), over which the
  offset leaves the lane centre line before the feature and rejoins it after.

Between these five knots the offset follows half cosines (:func:`knot_profile`): smooth,
with no sideways jump.

The search (:class:`RefineSearch`) starts from the family's two best held or fitted paths
as knots (:func:`seed_knots`), or, where there are fewer (none could be driven, or the best
was a corner cut), from the best of those and a coarse lattice (:func:`lattice_knots`).
From each start a *compass search* tries, each round, the twelve moves of one step up and
down in each number (:func:`compass_moves`), within fixed bounds; the best move that
improves the margin by more than :attr:`RefineSearch.min_gain_m` is taken, and when none
does the steps are halved. The order of paths is that of the family
(:func:`clearance.networks.driving.judging.rank`: the worst area left, then the margin), and a
path the vehicle cannot drive within its lock and steering rate ranks by how far it left the line,
so that the search moves toward paths it can drive. A run's searches stop once one finds a
path on the pavement; a search stops early when it has found nothing drivable after
:attr:`RefineSearch.drivable_by` rounds or is still off the pavement by more than
:attr:`RefineSearch.max_loss_m` after :attr:`RefineSearch.near_by`; else after
:attr:`RefineSearch.rounds` rounds: at most :attr:`RefineSearch.count` candidates per run,
in a fixed order, so the search is deterministic and bounded. Which runs get it, and how
the candidates of all runs are driven together, is :mod:`clearance.networks.driving.swing`'s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from clearance.analysis.polyline import Path
from clearance.networks.driving.candidates import MIN_FOLD, Candidate
from clearance.networks.driving.room import outside_sign
from clearance.networks.driving.shapes import kept_part, offset_run

__all__ = ["Knots", "MIN_FEATURE_M", "RefineSearch", "compass_moves", "knot_profile",
           "lattice_knots", "refined_candidate", "seed_knots"]

FloatArray = NDArray[np.float64]

MIN_FEATURE_M = 2.0
"""A feature shorter than this is widened about its middle to this length for the knots (m)."""


@dataclass(frozen=True)
class Knots:
    """The six numbers of a refined profile (offsets toward the outside of the turn, m).

    Examples
    --------
    >>> k = Knots(6.0, 1.0, 0.5, 0.0, 6.0, 0.5)
    >>> k.values()
    (6.0, 1.0, 0.5, 0.0, 6.0, 0.5)
    >>> Knots.of((6.0, 1.0, 0.5, 0.0, 6.0, 0.5)) == k
    True
    """

    ramp_in_m: float
    start_m: float
    apex_m: float
    end_m: float
    ramp_out_m: float
    apex_at: float

    def values(self) -> tuple[float, ...]:
        """The numbers in order."""
        return dataclasses.astuple(self)

    @classmethod
    def of(cls, values: tuple[float, ...] | FloatArray) -> Knots:
        """Knots from six numbers (rounded to the millimetre, so that equal moves are equal)."""
        return cls(*(round(float(v), 3) for v in values))


@dataclass(frozen=True)
class RefineSearch:
    """The bounds of the refinement (lengths in metres).

    Attributes
    ----------
    rounds
        Rounds of compass moves per run (each at most 12 candidates).
    max_loss_m
        Only runs whose best path leaves the paved area by at most this are refined (and
        runs no path of the family can drive): a path further off is no near miss.
    lower, upper
        The bounds of each number: offsets from 3 m inside to 6 m outside the centre
        line, ramps of 2 to 24 m, the apex within the middle 70 % of the feature.
    step
        The first step of each number.
    min_gain_m
        A move is taken only where it improves the margin by more than this; else the
        steps are halved.
    min_room_m
        An outward room under this gives the lattice no swing there (:func:`lattice_knots`).
    starts
        Compass searches per run: from the family's best held or fitted paths as knots
        (:func:`seed_knots`), and where there are fewer, from the best of those and the
        lattice (:func:`lattice_knots`).
    lattice_levels
        The offsets of the lattice at each knot: this many, evenly from none to all of the
        room there.
    drivable_by, near_by
        A compass search stops early when, after ``drivable_by`` rounds, it has found no
        line the vehicle can drive, or, after ``near_by`` rounds, its line still leaves the
        pavement by more than ``max_loss_m``.

    Examples
    --------
    >>> RefineSearch().count
    221
    >>> RefineSearch(rounds=0)
    Traceback (most recent call last):
    ...
    ValueError: refine search: rounds must be >= 1, got 0
    """

    rounds: int = 8
    max_loss_m: float = 0.5
    lower: Knots = Knots(2.0, -3.0, -3.0, -3.0, 2.0, 0.15)
    upper: Knots = Knots(24.0, 6.0, 6.0, 6.0, 24.0, 0.85)
    step: Knots = Knots(4.0, 0.8, 0.8, 0.8, 4.0, 0.15)
    min_gain_m: float = 0.01
    min_room_m: float = 0.15
    starts: int = 2
    lattice_levels: int = 3
    drivable_by: int = 2
    near_by: int = 3

    def __post_init__(self) -> None:
        if not (isinstance(self.rounds, int) and self.rounds >= 1):
            raise ValueError(f"refine search: rounds must be >= 1, got {self.rounds!r}")
        if not (isinstance(self.starts, int) and self.starts >= 1):
            raise ValueError(f"refine search: starts must be >= 1, got {self.starts!r}")
        if not (isinstance(self.lattice_levels, int) and self.lattice_levels >= 2):
            raise ValueError("refine search: lattice_levels must be >= 2, got "
                             f"{self.lattice_levels!r}")
        lo, hi, st = self.lower.values(), self.upper.values(), self.step.values()
        if not (all(a <= b for a, b in zip(lo, hi, strict=True)) and all(x > 0 for x in st)
                and lo[0] > 0 and lo[4] > 0 and 0 <= lo[5] <= hi[5] <= 1):
            raise ValueError("refine search: bounds must be lower <= upper, ramps > 0 m, "
                             "the apex inside the feature, steps > 0")

    @property
    def count(self) -> int:
        """Candidates per run, at most: the family's seeds, the lattice, and 12 moves a
        round from each start."""
        return self.starts + self.lattice_levels ** 3 + 12 * self.rounds * self.starts

    def clip(self, values: FloatArray) -> Knots:
        """Knots within the bounds."""
        return Knots.of(np.clip(values, self.lower.values(), self.upper.values()))


def knot_profile(station_m: FloatArray, feature_m: tuple[float, float], knots: Knots
                 ) -> FloatArray:
    """The offset toward the outside at each station: zero up to ``ramp_in_m`` before the
    feature, half cosines through ``start_m`` at its start, ``apex_m`` at ``apex_at`` of
    it and ``end_m`` at its end, back to zero ``ramp_out_m`` after it.

    The ramps end at the centre line's ends where the lead-in or run-out is shorter; a
    feature shorter than :data:`MIN_FEATURE_M` is widened about its middle to that length.

    Examples
    --------
    >>> s = np.arange(0.0, 61.0, 1.0)
    >>> k = Knots(8.0, 2.0, 1.0, -0.5, 6.0, 0.5)
    >>> d = knot_profile(s, (25.0, 35.0), k)
    >>> [round(float(d[i]), 6) for i in (10, 17, 21, 25, 30, 35, 38, 41, 50)]
    [0.0, 0.0, 1.0, 2.0, 1.0, -0.5, -0.25, 0.0, 0.0]

    A feature of no length is widened to 2 m:

    >>> d = knot_profile(s, (30.0, 30.0), k)
    >>> [round(float(d[i]), 6) for i in (29, 30, 31)]
    [2.0, 1.0, -0.5]
    """
    s = np.asarray(station_m, dtype=float)
    f0, f1 = feature_m
    if f1 - f0 < MIN_FEATURE_M:
        mid = 0.5 * (f0 + f1)
        f0, f1 = mid - 0.5 * MIN_FEATURE_M, mid + 0.5 * MIN_FEATURE_M
    xs = [max(float(s[0]), f0 - knots.ramp_in_m), f0, f0 + knots.apex_at * (f1 - f0), f1,
          min(float(s[-1]), f1 + knots.ramp_out_m)]
    ys = [0.0, knots.start_m, knots.apex_m, knots.end_m, 0.0]
    d = np.zeros(len(s))
    d[s >= xs[0]] = ys[0] if xs[1] > xs[0] else ys[1]
    for i in range(4):
        a, b = xs[i], xs[i + 1]
        inside = (s >= a) & (s <= b)
        if b > a:
            t = (s[inside] - a) / (b - a)
            d[inside] = ys[i] + (ys[i + 1] - ys[i]) * (0.5 - 0.5 * np.cos(math.pi * t))
    d[s > xs[4]] = 0.0 if xs[4] > xs[3] else ys[3]
    return d


def compass_moves(knots: Knots, step: FloatArray, search: RefineSearch) -> list[Knots]:
    """The moves of one round: each number one ``step`` down and up, within the bounds;
    a move the bounds cancel is left out.

    Examples
    --------
    >>> r = RefineSearch()
    >>> moves = compass_moves(Knots(6.0, 0.0, 0.0, 0.0, 6.0, 0.5),
    ...                       np.array(r.step.values()), r)
    >>> len(moves), moves[0], moves[3].start_m
    (12, Knots(ramp_in_m=2.0, start_m=0.0, apex_m=0.0, end_m=0.0, ramp_out_m=6.0, apex_at=0.5), 0.8)

    At a bound the move beyond it is left out:

    >>> len(compass_moves(Knots(2.0, 6.0, 0.0, 0.0, 6.0, 0.5), np.array(r.step.values()), r))
    10
    """
    base = np.array(knots.values())
    out = []
    for j in range(len(base)):
        for sign in (-1.0, 1.0):
            moved = base.copy()
            moved[j] += sign * step[j]
            k = search.clip(moved)
            if k != knots:
                out.append(k)
    return out


def lattice_knots(rooms_m: tuple[float, float, float] | None, search: RefineSearch
                  ) -> list[Knots]:
    """The coarse lattice the search starts from: each of the offsets at the feature's
    start, apex (its middle) and end at none, half and all of the outward room there
    (:func:`clearance.networks.driving.room.outside_rooms_m`, within the bounds; a room under
    :attr:`RefineSearch.min_room_m` gives none only), ramps as the family's
    (``max(6, 4 A)``, ``A`` the largest offset).

    Examples
    --------
    >>> ks = lattice_knots((2.0, 4.0, 0.5), RefineSearch())
    >>> len(ks), ks[0].values(), ks[-1].values()
    (27, (6.0, 0.0, 0.0, 0.0, 6.0, 0.5), (16.0, 2.0, 4.0, 0.5, 16.0, 0.5))

    No room outward anywhere: the lane centre line alone.

    >>> [k.values() for k in lattice_knots((0.0, -0.2, 0.1), RefineSearch())]
    [(6.0, 0.0, 0.0, 0.0, 6.0, 0.5)]
    >>> len(lattice_knots(None, RefineSearch()))
    1
    """
    def levels(room: float, top: float) -> list[float]:
        r = min(room, top)
        if not r >= search.min_room_m:
            return [0.0]
        n = search.lattice_levels
        return [round(r * k / (n - 1), 3) for k in range(n)]

    rooms = rooms_m or (0.0, 0.0, 0.0)
    up = search.upper
    out = []
    for a in levels(rooms[0], up.start_m):
        for b in levels(rooms[1], up.apex_m):
            for c in levels(rooms[2], up.end_m):
                ramp = min(up.ramp_in_m, max(6.0, 4.0 * max(a, b, c)))
                out.append(Knots.of((ramp, a, b, c, ramp, 0.5)))
    return out


def seed_knots(candidate: Candidate | None, feature_m: tuple[float, float]) -> Knots:
    """Where the refinement starts: a held or fitted candidate's offsets as knots (its apex
    cut at the feature's middle), or the lane centre line (``None`` or a corner cut).

    Examples
    --------
    >>> from clearance.analysis.polyline import prepare_path
    >>> z = np.zeros(1)
    >>> p = prepare_path([(0.0, 0.0), (1.0, 0.0)])
    >>> seed_knots(Candidate(2.0, 0.5, z, p, (0.0, 1.0), z), (10.0, 20.0))
    Knots(ramp_in_m=8.0, start_m=2.0, apex_m=1.0, end_m=2.0, ramp_out_m=8.0, apex_at=0.5)
    >>> seed_knots(None, (10.0, 20.0)).values()
    (6.0, 0.0, 0.0, 0.0, 6.0, 0.5)
    """
    if candidate is None or candidate.shape not in ("held", "fitted"):
        return Knots(6.0, 0.0, 0.0, 0.0, 6.0, 0.5)
    a0 = candidate.amplitude_m
    a1 = a0 if candidate.shape == "held" else candidate.exit_m
    ramp = max(6.0, 4.0 * max(abs(a0), abs(a1)))
    apex = 0.5 * (a0 + a1) * (1.0 - candidate.apex_cut)
    return Knots.of((ramp, a0, apex, a1, ramp, 0.5))


def refined_candidate(path: Path, feature_m: tuple[float, float], turn_angle_deg: float,
                      knots: Knots, reach_m: float | None = None) -> Candidate | None:
    """The swung path of ``knots`` (shape ``refined``), cropped ``reach_m`` beyond its
    ramps as :func:`clearance.networks.driving.candidates.candidates` does; ``None`` where the
    offset would fold the line over itself or the feature does not turn.

    Examples
    --------
    A right-hand quarter circle of radius 4 m between two 20 m straights, swung 1 m out
    before the turn and 0.3 m in after it:

    >>> from clearance.analysis.polyline import prepare_path
    >>> a = np.radians(np.linspace(90, 0, 31))
    >>> arc = np.c_[4 * np.cos(a), 20 + 4 * np.sin(a)]
    >>> p = prepare_path(np.vstack([[(-20.0, 24.0)], arc, [(4.0, 0.0)]]), smooth=True)
    >>> c = refined_candidate(p, (20.0, 26.3), -90.0, Knots(8.0, 1.0, 0.6, -0.3, 6.0, 0.5))
    >>> c.shape, round(float(c.offset_m.max()), 3), round(float(c.offset_m.min()), 3)
    ('refined', 1.0, -0.3)
    >>> c.how  # doctest: +NORMALIZE_WHITESPACE
    "takes its own line: 1.00 m out at the turn's start, 0.60 m out at its apex,
    0.30 m in at its end"

    A straight feature has no outside:

    >>> refined_candidate(p, (20.0, 26.3), 0.0, Knots(8.0, 1.0, 0.6, -0.3, 6.0, 0.5)) is None
    True
    """
    side = outside_sign(turn_angle_deg)
    if side == 0.0:
        return None
    a = max(0.0, feature_m[0] - knots.ramp_in_m)
    e = min(path.length_m, feature_m[1] + knots.ramp_out_m)
    lane, keep = kept_part(path, a, e, reach_m)
    d = side * knot_profile(path.station_m, feature_m, knots)[keep]
    if np.min(1.0 - lane.curvature_1_m * d) <= MIN_FOLD:
        return None
    label = f"refined {knots.start_m:g}/{knots.apex_m:g}/{knots.end_m:g} m"
    p, window, smap = offset_run(path, lane, keep, d, (a, e), feature_m,
                                 f"{path.name} ({label})")
    return Candidate(knots.start_m, 0.0, d, p, window, smap, "refined", knots.end_m,
                     apex_m=knots.apex_m)
