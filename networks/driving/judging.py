"""Judging candidate paths: which of a run's paths a driver would take.

Each followed candidate's envelope is judged against the curve's areas over its window, and
the best is kept (:func:`rank`): the worst area the envelope leaves first (none, then its
own lanes but not its roadway, then the roadway but not the paved area, then the paved
area, then ``cannot-turn``: :data:`TIERS`), then within a tier the path a designer would
draw (:func:`decisive_margin`): the most room for a clear one, the least reach beyond what it
encroaches on for the others. The lane's own result wins ties: a swung path is taken only
when it is better by a whole tier, or by more than :data:`BETTER_BY_M` in the same tier.
:func:`swing_reason` says the chosen path in words."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from clearance.analysis.clearance import Clearance

__all__ = ["BETTER_BY_M", "ENCROACHED", "TIERS", "decisive_margin", "encroaches_on",
           "key_ceiling", "rank", "swing_reason", "tier"]


BETTER_BY_M = 0.05
"""A swung path in the lane's own tier must beat its margin by more than this (m)."""


TIERS = ("cannot-turn", "leaves paved", "leaves roadway", "leaves own lanes", "clear")
"""What a path's envelope leaves, worst first (:func:`tier`)."""


ENCROACHED = ("", "same-direction lanes", "opposing lanes", "shoulder")
"""What an envelope encroaches on (:func:`encroaches_on`): nothing, then worst last."""


def tier(clearance: Clearance | None) -> int:
    """Index in :data:`TIERS` of what a clearance's envelope leaves (higher is better).

    Examples
    --------
    >>> c = Clearance("encroaches", -0.4, 0.6, -0.1, 0.0, "")
    >>> TIERS[tier(c)]
    'leaves roadway'
    >>> TIERS[tier(Clearance("encroaches", -0.4, 0.6, 0.2, 0.0, ""))]
    'leaves own lanes'
    >>> TIERS[tier(None)]
    'cannot-turn'
    """
    if clearance is None or clearance.verdict == "cannot-turn":
        return 0
    if clearance.verdict == "fails":
        return 1
    if clearance.verdict == "clear":
        return 4
    road = clearance.roadway_margin_m
    return 3 if road is not None and road >= 0 else 2


def decisive_margin(clearance: Clearance | None) -> float:
    """The margin that orders paths of one tier: the room to spare where the path stays in
    its lanes, else the least it encroaches on what it reaches into.

    A clear path: its margin to its own lanes (the most room best). One that leaves its own
    lanes but stays in its roadway: its margin to its own lanes (the least reach into the
    same-direction lanes best). One that leaves its roadway but stays paved: its margin to
    the roadway (the least reach into the opposing lanes best), whatever room it leaves to
    the curb. One that leaves the pavement: its margin to the paved area.

    Examples
    --------
    >>> decisive_margin(Clearance("encroaches", -0.4, 0.6, -0.1, 0.0, ""))
    -0.1
    >>> decisive_margin(Clearance("encroaches", -0.4, 0.6, 0.2, 0.0, ""))
    -0.4
    >>> decisive_margin(Clearance("fails", -2.0, -0.3, -1.0, 0.0, ""))
    -0.3
    >>> decisive_margin(None)
    -inf
    """
    t = tier(clearance)
    if t == 0 or clearance is None:
        return -math.inf
    if t in (3, 4):
        return clearance.margin_m
    if t == 2:
        return float(clearance.roadway_margin_m)  # type: ignore[arg-type]  # tier 2 has one
    return clearance.paved_margin_m


def key_ceiling(floors: Mapping[str, float]) -> tuple[int, float] | None:
    """The best (tier, decisive margin) a path can have whose reach beyond its areas is at
    least ``floors`` (by area name, each at least the network's precision:
    :func:`clearance.analysis.screen.reach_floors`); None when they bound nothing.

    Examples
    --------
    Off the pavement by 0.3 m at least: it fails, with a paved margin of -0.3 m at best;
    beyond its own lanes only: it leaves them, by 0.2 m at least:

    >>> key_ceiling({"own_lanes": 0.9, "paved": 0.3})
    (1, -0.3)
    >>> key_ceiling({"own_lanes": 0.2})
    (3, -0.2)
    >>> key_ceiling({}) is None
    True
    """
    if "paved" in floors:
        return 1, -floors["paved"]
    if "roadway" in floors:
        return 2, -floors["roadway"]
    if "own_lanes" in floors:
        return 3, -floors["own_lanes"]
    return None


def rank(clearances: Sequence[Clearance | None]) -> int:
    """Index of the best of ``clearances`` (the first is the lane's; it wins ties).

    Examples
    --------
    A swing 0.8 m into the opposing lanes beats one 1.5 m into them, though the wider one
    leaves more room to the curb; both beat a lane path the vehicle cannot follow:

    >>> lane = Clearance("cannot-turn", -1.0, -0.5, None, 0.0, "lock")
    >>> wide = Clearance("encroaches", -1.2, 0.3, -0.8, 0.0, "")
    >>> wider = Clearance("encroaches", -2.0, 0.5, -1.5, 0.0, "")
    >>> rank([lane, wide, wider]), rank([lane, wider, wide]), rank([wider, None])
    (1, 2, 0)
    >>> rank([wide, Clearance("encroaches", -1.2, 0.33, -0.78, 0.0, "")])
    0
    """
    best, key = 0, (tier(clearances[0]), decisive_margin(clearances[0]))
    for i, c in enumerate(clearances[1:], start=1):
        k = (tier(c), decisive_margin(c))
        if k[0] > key[0] or (k[0] == key[0] and k[1] > key[1] + BETTER_BY_M):
            best, key = i, k
    return best


def encroaches_on(clearance: Clearance | None) -> str:
    """What the envelope encroaches on, worst only (:data:`ENCROACHED`; ``""`` when clear).

    The roadway (same direction) tells the lanes of the own direction from the rest of the
    paved area, taken for the opposing lanes; beyond the paved area is the shoulder.

    Examples
    --------
    >>> encroaches_on(Clearance("encroaches", -0.4, 0.6, 0.2, 0.0, ""))
    'same-direction lanes'
    >>> encroaches_on(Clearance("encroaches", -0.4, 0.6, -0.1, 0.0, ""))
    'opposing lanes'
    >>> encroaches_on(Clearance("fails", -0.4, -0.2, -0.1, 0.0, ""))
    'shoulder'
    >>> encroaches_on(Clearance("clear", 0.3, 0.6, 0.5, 0.0, ""))
    ''
    """
    if clearance is None or clearance.verdict in ("clear", "cannot-turn"):
        return ""
    if clearance.verdict == "fails":
        return "shoulder"
    road = clearance.roadway_margin_m
    return "same-direction lanes" if road is not None and road >= 0 else "opposing lanes"


def swing_reason(amplitude_m: float, apex_cut: float, clearance: Clearance,
                 how: str | None = None) -> str:
    """The verdict of a swung path in words (``how``: the path's own, :attr:`Candidate.how`).

    Examples
    --------
    >>> print(swing_reason(2.25, 0.0, Clearance("encroaches", -2.0, 0.5, -1.4, 0.0, "")))
    ... # doctest: +NORMALIZE_WHITESPACE
    swings 2.25 m out from the lane centre line and 1.40 m into the opposing lanes,
    stays paved (0.50 m to spare)
    >>> print(swing_reason(1.5, 0.5, Clearance("encroaches", -1.1, 0.5, 0.4, 0.0, "")))
    ... # doctest: +NORMALIZE_WHITESPACE
    swings 1.50 m out (50% of it taken back at the apex) and 1.10 m into the
    same-direction lanes, stays in its roadway (0.40 m to spare)
    >>> print(swing_reason(5.5, 0.0, Clearance("fails", -3.0, -0.62, -2.0, 0.0, "")))
    swings 5.50 m out from the lane centre line and still leaves the paved area by 0.62 m
    """
    if how is None:
        how = f"swings {amplitude_m:.2f} m out"
        how += (f" ({apex_cut:.0%} of it taken back at the apex)" if apex_cut > 0 else
                " from the lane centre line")
    c = clearance
    if c.verdict == "clear":
        return f"{how} and stays {c.margin_m:.2f} m inside its own lanes"
    if c.verdict == "fails":
        return f"{how} and still leaves the paved area by {-c.paved_margin_m:.2f} m"
    on = encroaches_on(c)
    if on == "same-direction lanes":
        return (f"{how} and {-c.margin_m:.2f} m into the same-direction lanes, stays in its "
                f"roadway ({c.roadway_margin_m:.2f} m to spare)")
    into = -c.roadway_margin_m if c.roadway_margin_m is not None else -c.margin_m
    return (f"{how} and {into:.2f} m into the opposing lanes, stays paved "
            f"({c.paved_margin_m:.2f} m to spare)")
