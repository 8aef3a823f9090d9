"""The second pass of a drive: a swung path for every run that does not clear on its lane.

:func:`clearance.networks.driving.drive.drive` first drives every run on its lane's centre line.
For each run that is not ``clear`` there, :func:`swing_pass` drives the search's candidates
(:func:`clearance.networks.driving.candidates.candidates`: the centre line offset toward the
outside of the turn by a fixed family of profiles, held or fitted to the room at each end of the
turn, and corner cuts toward the inside), all runs' candidates together in batches of
:attr:`~clearance.networks.driving.runs.DriveOptions.batch_size`
(:func:`clearance.analysis.tracking.simulate_batch`),
judges each one the follower could drive against the curve's areas over the whole
manoeuvre (:func:`clearance.analysis.clearance.judge` with the candidate's window: its
clearance alone), and keeps the
best (:func:`clearance.networks.driving.judging.rank`; the lane's result wins ties), measured
in full once chosen (:func:`clearance.analysis.clearance.evaluate`). A candidate
the follower cannot drive within the lock and steering rate in that window is not judged (it
ranks as ``cannot-turn``). The candidates go in rounds of growing size: round ``k``
drives the ``k``-th amplitude of every shape (the held one with the middle apex cut) of
every run still searching; a run stops searching after the first round in which a
candidate is ``clear``, or keeps its body on the pavement in a better tier than its lane
path's (a driver swings only as far as the turn needs: a wider swing of the same shape
reaches further into the lanes beside). A run still searching after the last round gets
the other cuts of its best held amplitude and of its two neighbours. A run that cannot
turn and has no candidate within its room that the follower can drive gets the held
family again with the room unbounded (up to
:attr:`~clearance.networks.driving.candidates.SwingSearch.max_amplitude_m`):
then it ``fails`` by how far the best of those leaves the pavement, and is ``cannot-turn``
only when none of them can be driven either.

The lane-following result stays beside the chosen one (:attr:`DrivenRun.lane_result`), and
:attr:`DrivenRun.path` says which was taken (``lane`` or ``swung``). SUMO places the lane
path during the lane pass, or, with FCD output, the chosen path after this pass
(:mod:`clearance.networks.driving.drive`).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable

import numpy as np

from clearance.analysis.clearance import Areas, Clearance, RunResult, evaluate, judge
from clearance.analysis.failures import GEOMETRY_FAILURES
from clearance.analysis.feature import feature_mask, feature_reason
from clearance.analysis.polyline import Path
from clearance.analysis.screen import AREAS, reach_floors
from clearance.analysis.tracking import TrackingRun, TrackingSettings, simulate_batch
from clearance.networks.driving.candidates import (
    LOOPED_EXCESS_DEG,
    Candidate,
    SwingSearch,
    candidates,
    excess_turning_deg,
)
from clearance.networks.driving.judging import (
    BETTER_BY_M,
    TIERS,
    decisive_margin,
    key_ceiling,
    rank,
    swing_reason,
    tier,
)
from clearance.networks.driving.refine import (
    Knots,
    RefineSearch,
    compass_moves,
    lattice_knots,
    refined_candidate,
    seed_knots,
)
from clearance.networks.driving.room import outside_rooms_m, outside_sign, search_turn_deg
from clearance.networks.driving.runs import DrivenRun, DriveOptions, DriveStats, SwungLine

__all__ = ["needs_swing", "swing_pass"]

log = logging.getLogger(__name__)


def needs_swing(d: DrivenRun) -> bool:
    """Whether a run gets the search: judged, not clear, no error."""
    return not d.error and d.result is not None and d.result.verdict != "clear"


@dataclasses.dataclass(frozen=True)
class _Run:
    """What the search of one run needs, measured once: its path and feature, its rooms."""

    path: Path
    feature_m: tuple[float, float]
    turn_angle_deg: float
    room_m: float
    rooms_m: tuple[float, float, float] | None
    inside_m: float
    reach_m: float
    looped: bool = False


def _measure(d: DrivenRun, paths: dict[str, Path], areas: dict[str, Areas]) -> _Run | None:
    """The room the pavement gives the run, outward and (at the middle) inward."""
    c = d.curve
    feature = (c.core_start_m, c.core_end_m)
    try:
        path = paths[c.curve_id]
        turn = search_turn_deg(c.turn_angle_deg, path, feature)
        side = outside_sign(turn)
        rooms: tuple[float, float, float] | None = None
        inside = 0.0
        if side:
            paved, half = areas[c.curve_id].paved, 0.5 * d.vehicle.width_m
            rooms = outside_rooms_m(path, feature, side, paved, half)
            inside = outside_rooms_m(path, feature, -side, paved, half)[1]
    except GEOMETRY_FAILURES as exc:
        log.info("%s: no swung paths: %s", c.curve_id, exc)
        return None
    room = max(0.0, min(rooms)) if rooms else 0.0
    # a junction's internal lane drawn with a loop or kink (not a roundabout's ring, whose
    # turns back and forth are the road's)
    looped = c.kind == "turn" and (excess_turning_deg(path, feature, c.turn_angle_deg)
                                   > LOOPED_EXCESS_DEG)
    # all a judged sample's body covers
    return _Run(path, feature, turn, room, rooms, inside,
                d.vehicle.overall_length_m + 2.0, looped)


def _family(d: DrivenRun, m: _Run, search: SwingSearch, step: int | None,
            room_m: float | None = None) -> list[tuple[DrivenRun, Candidate]]:
    """The run's candidates of size ``step`` (all sizes: ``None``); with ``room_m``, the
    held ones for that room instead of the pavement's."""
    try:
        if room_m is not None:
            return [(d, cand) for cand in candidates(m.path, m.feature_m, m.turn_angle_deg,
                                                     search, room_m, m.reach_m, step=step)]
        return [(d, cand) for cand in candidates(
            m.path, m.feature_m, m.turn_angle_deg, search, m.room_m, m.reach_m, m.rooms_m,
            m.inside_m, step, m.looped)]
    except GEOMETRY_FAILURES as exc:  # no candidates
        log.info("%s: no swung paths: %s", d.curve.curve_id, exc)
        return []


def _settled(lane: RunResult, tried: list[tuple[Candidate, Clearance | None]]) -> bool:
    """Whether a run's search may stop: a candidate is clear, or keeps the body on the
    pavement in a better tier than the lane path's (a wider swing would reach further)."""
    best = max((tier(c) for _, c in tried if c is not None), default=0)
    return best == len(TIERS) - 1 or best > max(1, tier(lane.clearance))


def swing_pass(
    out: list[DrivenRun],
    paths: dict[str, Path],
    areas: dict[str, Areas],
    settings: TrackingSettings,
    options: DriveOptions,
    stats: DriveStats | None = None,
    search: SwingSearch | None = None,
    refine: RefineSearch | None = None,
) -> int:
    """Search swung paths for the runs of ``out`` that are not clear; returns how many
    runs took one. Each run's ``lane_result`` is set (its lane result), and ``result``,
    ``path`` and ``swing_m`` where a swung path is better.
    """
    search = search or SwingSearch()
    refine = refine or RefineSearch()
    gain_m = refine.min_gain_m  # the compass's (see drive_all)
    t0, c0 = time.perf_counter(), time.process_time()
    for d in out:
        d.lane_result = d.result
    runs = [d for d in out if needs_swing(d)]
    measured = {id(d): m for d in runs if (m := _measure(d, paths, areas)) is not None}
    # every candidate the follower could drive, with its clearance (None: it could not be
    # judged); the driven runs only of those that may still be kept (:func:`_prune`: a run's
    # search drives hundreds), to be measured in full once one is chosen (:func:`_choose`)
    tried: dict[int, list[tuple[Candidate, Clearance | None]]] = {id(d): [] for d in runs}
    results: dict[int, dict[int, tuple[Clearance, TrackingRun]]] = {id(d): {} for d in runs}
    judged = 0
    screened = 0
    count = 0

    def drive_all(todo: list[tuple[DrivenRun, Candidate]],
                  floors: list[tuple[float, ...]] | None = None) -> list[tuple[float, ...]]:
        """Drive the candidates and judge those the follower could drive; the order key of
        each (:func:`_key`). With ``floors`` (a key for each candidate: the compass state
        it moves from), a candidate that provably cannot beat its floor by the compass's
        gain, nor become its run's best (:func:`_cannot_win`), is left unjudged."""
        nonlocal count, judged, screened
        count += len(todo)
        keys: list[tuple[float, ...]] = []
        for lo in range(0, len(todo), options.batch_size):
            chunk = todo[lo:lo + options.batch_size]
            driven = simulate_batch([d.vehicle for d, _ in chunk], [c.path for _, c in chunk],
                                    settings)
            for j, ((d, cand), run) in enumerate(zip(chunk, driven, strict=True)):
                res = None
                drivable = not feature_reason(run, feature_mask(run, cand.window_m))
                if drivable and floors is not None and _cannot_win(
                        run, cand, areas[d.curve.curve_id], options.offset_m, floors[lo + j],
                        lane_of(d).clearance, tried[id(d)], gain_m):
                    screened += 1
                    tried[id(d)].append((cand, None))
                elif drivable:
                    res = _judged(d, cand, run, areas[d.curve.curve_id], options.offset_m)
                    tried[id(d)].append((cand, res))
                    if res is not None:
                        judged += 1
                        results[id(d)][len(tried[id(d)]) - 1] = (res, run)
                        _prune(results[id(d)])
                keys.append(_key(res, run.max_error_m))
        return keys

    def lane_of(d: DrivenRun) -> RunResult:
        assert d.result is not None  # needs_swing: only runs with a result
        return d.result

    _family_stages(runs, measured, tried, lane_of, drive_all, search)
    # a run still off the pavement by a little, or that no candidate could drive: refined
    before, t1, c1 = count, time.perf_counter(), time.process_time()
    refined = _refine([d for d in runs if id(d) in measured], measured, tried, lane_of,
                      drive_all, refine)
    taken = sum(_choose(d, lane_of(d), tried[id(d)], results[id(d)], search, refine,
                        areas[d.curve.curve_id], options.offset_m)
                for d in runs)
    if stats is not None:
        stats.refine_runs += refined
        stats.refine_candidates += count - before
        stats.refine_s += time.perf_counter() - t1
        stats.refine_cpu_s += time.process_time() - c1
        stats.swing_judged += judged
        stats.swing_screened += screened
        stats.swing_s += time.perf_counter() - t0
        stats.swing_cpu_s += time.process_time() - c0
        stats.swing_candidates += count
    return taken


def _family_stages(runs: list[DrivenRun], measured: dict[int, _Run],
                   tried: dict[int, list[tuple[Candidate, Clearance | None]]],
                   lane_of: Callable[[DrivenRun], RunResult], drive_all: _Driver,
                   search: SwingSearch) -> None:
    """The family of shapes (:mod:`clearance.networks.driving.candidates`) for every run:
    rounds of growing size until a candidate keeps the body paved, the other apex cuts
    about the best held size, and the widest swings for a run that cannot turn."""
    # rounds of growing size: the k-th amplitude of every shape (held ones with the middle
    # cut), until a candidate keeps the body paved
    first = dataclasses.replace(search, apex_cuts=(search.middle_cut,))
    active = [d for d in runs if id(d) in measured]
    for k in range(1, search.steps + 1):
        todo = [x for d in active for x in _family(d, measured[id(d)], first, k)]
        drive_all(todo, None)
        active = [d for d in active if not _settled(lane_of(d), tried[id(d)])]
    # then the other cuts of the best held amplitude so far and of its neighbours
    others = tuple(c for c in search.apex_cuts if c != search.middle_cut)
    if others:
        rest = dataclasses.replace(search, apex_cuts=others, shaped=False)
        drive_all([x for d in active for k in _near_steps(tried[id(d)], search.steps)
                   for x in _family(d, measured[id(d)], rest, k)], None)
    # a run that cannot turn within the pavement's room: the widest swings, beyond it
    wider = [x for d in runs if id(d) in measured and not tried[id(d)]
             and lane_of(d).verdict == "cannot-turn"
             for x in _family(d, measured[id(d)], search, None, math.inf)]
    drive_all(wider, None)


def _prune(results: dict[int, tuple[Clearance, TrackingRun]]) -> None:
    """Drop the results of a run's candidates that can no longer be kept: of a worse tier
    than the best so far, or short of its decisive margin by more than
    :data:`~clearance.networks.driving.judging.BETTER_BY_M`
    (:func:`clearance.networks.driving.judging.rank` keeps a
    path within that of the best of its tier, never one further short)."""
    keys = {i: (tier(c), decisive_margin(c)) for i, (c, _) in results.items()}
    top = max(keys.values())
    for i, (t, m) in keys.items():
        if t < top[0] or m < top[1] - BETTER_BY_M - 1e-9:
            del results[i]


def _cannot_win(run: TrackingRun, cand: Candidate, areas: Areas, offset_m: float,
                floor: tuple[float, ...], lane: Clearance,
                tried: list[tuple[Candidate, Clearance | None]], gain_m: float) -> bool:
    """Whether a compass move the follower can drive need not be judged: the best key its
    floors allow (:func:`clearance.analysis.screen.reach_floors`,
    :func:`~clearance.networks.driving.judging.key_ceiling`) neither beats the state it
    moves from by ``gain_m`` (:func:`_better`: the search would not take it) nor would
    replace the best of its run's paths so far (``lane``, then those ``tried``:
    :func:`~clearance.networks.driving.judging.rank` would not keep it). Its judging could
    then change nothing the search does or keeps: its verdict, margins and choice are
    the same as judging every move."""
    if floor[0] < 1:
        return False  # any path it can drive beats a state it could not drive
    # only the areas whose floor can put it below the state's tier or margin
    names = AREAS[:min(int(floor[0]), len(AREAS))]
    ceiling = key_ceiling(reach_floors(run, areas, offset_m, cand.window_m, names=names))
    if ceiling is None:
        return False
    so_far = [lane, *(c for _, c in tried)]
    best = so_far[rank(so_far)]
    top = (tier(best), decisive_margin(best))
    wins = ceiling[0] > top[0] or (ceiling[0] == top[0] and ceiling[1] > top[1] + BETTER_BY_M)
    return not wins and not _better((float(ceiling[0]), ceiling[1], 0.0), floor, gain_m)


def _key(clearance: Clearance | None, error_m: float) -> tuple[float, ...]:
    """The order of candidates in the refinement: that of :func:`rank` (the tier, then the
    decisive margin); among those the follower could not drive, the least lateral error."""
    if clearance is None:
        return (0.0, -math.inf, -error_m)
    return (float(tier(clearance)), decisive_margin(clearance), 0.0)


def _better(key: tuple[float, ...], than: tuple[float, ...], by_m: float) -> bool:
    """Whether a refinement's move is worth taking: a better tier, or a margin (or, among
    paths that cannot be driven, a lateral error) better by more than ``by_m``."""
    if key[0] != than[0]:
        return key[0] > than[0]
    if key[1] != than[1]:
        return key[1] > than[1] + by_m
    return key[2] > than[2] + by_m


def _hopeless(key: tuple[float, ...], done: int, refine: RefineSearch) -> bool:
    """Whether a compass search that has run ``done`` rounds stops without a path on the
    pavement: none it can drive after :attr:`~RefineSearch.drivable_by` rounds, or still
    off the pavement by more than :attr:`~RefineSearch.max_loss_m` after
    :attr:`~RefineSearch.near_by` rounds (searches that end paved get there sooner)."""
    if key[0] == 0:
        return done >= refine.drivable_by
    return key[0] == 1 and done >= refine.near_by and key[1] < -refine.max_loss_m


def _refine(runs: list[DrivenRun], measured: dict[int, _Run],
            tried: dict[int, list[tuple[Candidate, Clearance | None]]],
            lane_of: Callable[[DrivenRun], RunResult], drive_all: _Driver,
            refine: RefineSearch) -> int:
    """The search of :mod:`clearance.networks.driving.refine` for every run whose best path so far
    leaves the pavement by at most
    :attr:`~clearance.networks.driving.refine.RefineSearch.max_loss_m`,
    or cannot turn: compass searches from the family's best held or fitted paths as knots,
    or from the best of those and the coarse lattice. All runs' candidates of a stage are
    driven together. Returns how many runs were refined."""
    firsts: list[tuple[DrivenRun, Candidate]] = []
    knots: list[Knots] = []
    for d in runs:
        so_far = [lane_of(d).clearance] + [c for _, c in tried[id(d)]]
        c = so_far[rank(so_far)]
        if tier(c) > 1 or (c is not None and tier(c) == 1
                           and c.paved_margin_m < -refine.max_loss_m):
            continue
        m = measured[id(d)]
        # the family's best held or fitted paths as knots, best first; the lattice where
        # there are fewer than the starts wanted (none drivable, or the best a corner cut)
        order = sorted(range(len(tried[id(d)])),
                       key=lambda i: _key(tried[id(d)][i][1], 0.0), reverse=True)
        seeds = list(dict.fromkeys(
            seed_knots(tried[id(d)][i][0], m.feature_m) for i in order
            if tried[id(d)][i][1] is not None
            and tried[id(d)][i][0].shape in ("held", "fitted")))[:refine.starts]
        if len(seeds) < refine.starts:
            seeds += lattice_knots(m.rooms_m, refine)
        for k in dict.fromkeys(seeds):
            cand = refined_candidate(m.path, m.feature_m, m.turn_angle_deg, k, m.reach_m)
            if cand is not None:
                firsts.append((d, cand))
                knots.append(k)
    found: dict[int, list[tuple[tuple[float, ...], Knots]]] = {}
    for (d, _), k, key in zip(firsts, knots, drive_all(firsts, None), strict=True):
        found.setdefault(id(d), []).append((key, k))
    starts = [(d, s) for d in runs for s in sorted(found.get(id(d), []), key=lambda x: x[0],
                                                   reverse=True)[:refine.starts]]
    _compass(starts, measured, drive_all, refine)
    return len(found)


_Driver = Callable[[list[tuple[DrivenRun, Candidate]], list[tuple[float, ...]] | None],
                   list[tuple[float, ...]]]


def _compass(starts: list[tuple[DrivenRun, tuple[tuple[float, ...], Knots]]],
             measured: dict[int, _Run], drive_all: _Driver, refine: RefineSearch) -> None:
    """A compass search from each of ``starts`` (a run, and knots with their order key); a
    run's searches stop once one of them finds a path on the pavement."""
    def candidate(d: DrivenRun, k: Knots) -> Candidate | None:
        m = measured[id(d)]
        return refined_candidate(m.path, m.feature_m, m.turn_angle_deg, k, m.reach_m)

    state = [(d, k, np.array(refine.step.values()), key) for d, (key, k) in starts]
    for r in range(refine.rounds):
        paved = {id(d) for d, _, _, key in state if key[0] >= 2}
        active = [i for i, (d, _, _, key) in enumerate(state)
                  if id(d) not in paved and not _hopeless(key, r, refine)]
        moves: list[tuple[DrivenRun, Candidate]] = []
        which: list[tuple[int, Knots]] = []
        for i in active:
            d, knots, step, _ = state[i]
            for k in compass_moves(knots, step, refine):
                if (cand := candidate(d, k)) is not None:
                    moves.append((d, cand))
                    which.append((i, k))
        if not moves:
            break
        best_move: dict[int, tuple[tuple[float, ...], Knots]] = {}
        floors = [state[i][3] for i, _ in which]
        for (i, k), key in zip(which, drive_all(moves, floors), strict=True):
            if i not in best_move or key > best_move[i][0]:
                best_move[i] = (key, k)
        for i in active:
            d, knots, step, key = state[i]
            if i in best_move and _better(best_move[i][0], key, refine.min_gain_m):
                state[i] = (d, best_move[i][1], step, best_move[i][0])
            else:
                state[i] = (d, knots, step / 2.0, key)


def _near_steps(tried: list[tuple[Candidate, Clearance | None]], steps: int) -> list[int]:
    """The sizes whose other apex cuts are tried: the best held candidate's and its
    neighbours' (every size when no held one could be judged)."""
    held = [(c, r) for c, r in tried if c.shape == "held"]
    best = rank([None] + [c for _, c in held])
    if not best:
        return list(range(1, steps + 1))
    k = held[best - 1][0].step
    return [j for j in (k - 1, k, k + 1) if 1 <= j <= steps]


def _choose(d: DrivenRun, lane: RunResult, tried: list[tuple[Candidate, Clearance | None]],
            results: dict[int, tuple[Clearance, TrackingRun]], search: SwingSearch,
            refine: RefineSearch, areas: Areas, offset_m: float) -> bool:
    """Keep the best of the lane path and the tried candidates (``results``: the clearances
    and driven runs of those that may be kept, by their place in ``tried``), measured in
    full (:func:`clearance.analysis.clearance.evaluate`: its clearance is the one judged);
    whether a swung one won."""
    best = rank([lane.clearance] + [c for _, c in tried])
    while best:
        if best - 1 not in results:  # pruned: only after the best could not be measured
            best = 0
            break
        cand, run = tried[best - 1][0], results[best - 1][1]  # kept: never pruned (_prune)
        try:
            res = evaluate(run, areas, offset_m, feature_m=cand.window_m)
            break
        except GEOMETRY_FAILURES as exc:  # its envelope judged, its widths or tracks not
            log.info("%s x %s: a swung path could not be measured: %s", d.vehicle.name,
                     d.curve.curve_id, exc)
            tried[best - 1] = (cand, None)
            best = rank([lane.clearance] + [c for _, c in tried])
    if best == 0:
        if lane.verdict == "cannot-turn":
            d.result = dataclasses.replace(lane, clearance=dataclasses.replace(
                lane.clearance, reason=f"{lane.clearance.reason}; nor can it swing wide: "
                f"none of its swung paths (outward offsets up to "
                f"{search.max_amplitude_m:g} m, as far as the pavement allows, and refined "
                f"lines from {-refine.lower.start_m:g} m inside to {refine.upper.start_m:g} m "
                "outside the lane centre line) is within its lock and steering rate"))
        return False
    why = swing_reason(cand.amplitude_m, cand.apex_cut, res.clearance, cand.how)
    why += f" (on the lane centre line: {lane.verdict}"
    if lane.verdict != "cannot-turn":
        why += f", margin {lane.margin_m:.2f} m"
    why += ")"
    d.result = dataclasses.replace(res, clearance=dataclasses.replace(res.clearance,
                                                                      reason=why))
    d.path = "swung"
    d.swing_m = _swing_m(cand)
    d.line = SwungLine(cand.path, cand.window_m, d.swing_m)  # to draw it again, no search
    return True


def _swing_m(cand: Candidate) -> float:
    """The largest outward offset of a swung path; where it never goes out, its deepest
    inward one, negative (a corner cut's depth)."""
    if cand.shape == "inside":
        return -cand.inside_m
    offsets = (cand.amplitude_m, cand.apex_m, cand.exit_m)
    return max(offsets) if max(offsets) > 0 else min(offsets)


def _judged(d: DrivenRun, cand: Candidate, run: TrackingRun, areas: Areas,
            offset_m: float) -> Clearance | None:
    """A driven candidate's clearance over its window (``None`` where it cannot be judged):
    :func:`clearance.analysis.clearance.judge`, its envelope without widths or tracks."""
    try:
        return judge(run, areas, offset_m, feature_m=cand.window_m)
    except GEOMETRY_FAILURES as exc:
        log.info("%s x %s: a swung path could not be judged: %s", d.vehicle.name,
                 d.curve.curve_id, exc)
        return None
