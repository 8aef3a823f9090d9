"""The second pass of a drive: a swung path for every run that does not clear on its lane.

:func:`networks.sumo.driver.drive` first drives every run on its lane's centre line. For each
run that is not ``clear`` there, :func:`swing_pass` drives the search's candidates
(:func:`analysis.path_search.candidates`: the centre line offset toward the outside of the
turn by a fixed family of profiles, held or fitted to the room at each end of the turn, and
corner cuts toward the inside), all runs' candidates together in batches of
:attr:`~networks.sumo.runs.DriveOptions.batch_size` (:func:`analysis.tracking.simulate_batch`),
judges each one the follower could drive against the curve's areas over the whole
manoeuvre (:func:`analysis.clearance.evaluate` with the candidate's window), and keeps the
best (:func:`analysis.path_search.rank`; the lane's result wins ties). A candidate the
follower cannot drive within the lock and steering rate in that window is not judged (it
ranks as ``cannot-turn``). The driven candidates are judged in two stages: every held
amplitude with the middle apex cut and every fitted and inside shape, then the other cuts
of the best held amplitude so far and of its two neighbours; the first ``clear`` one ends
that run's search (no later one can be in a better tier). A run that cannot turn and has
no candidate within its room that the follower can drive gets the held family again with
the room unbounded (up to :attr:`~analysis.path_search.SwingSearch.max_amplitude_m`):
then it ``fails`` by how far the best of those leaves the pavement, and is ``cannot-turn``
only when none of them can be driven either.

The lane-following result stays beside the chosen one (:attr:`DrivenRun.lane_result`), and
:attr:`DrivenRun.path` says which was taken (``lane`` or ``swung``). SUMO replays the lane
path only (it runs before this pass): swung paths are the model's.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time

import shapely

from analysis.clearance import Areas, RunResult, evaluate
from analysis.feature import feature_mask, feature_reason
from analysis.path_search import (
    Candidate,
    SwingSearch,
    candidates,
    outside_rooms_m,
    outside_sign,
    rank,
    swing_reason,
)
from analysis.polyline import Path
from analysis.tracking import TrackingRun, TrackingSettings, simulate_batch
from networks.sumo.runs import DrivenRun, DriveOptions, DriveStats
from vehicles.errors import InputError

__all__ = ["needs_swing", "swing_pass"]

log = logging.getLogger(__name__)


def needs_swing(d: DrivenRun) -> bool:
    """Whether a run gets the search: judged, not clear, no error."""
    return not d.error and d.result is not None and d.result.verdict != "clear"


def swing_pass(
    out: list[DrivenRun],
    paths: dict[str, Path],
    areas: dict[str, Areas],
    settings: TrackingSettings,
    options: DriveOptions,
    stats: DriveStats | None = None,
    search: SwingSearch | None = None,
) -> int:
    """Search swung paths for the runs of ``out`` that are not clear; returns how many
    runs took one. Each run's ``lane_result`` is set (its lane result), and ``result``,
    ``path`` and ``swing_m`` where a swung path is better.
    """
    search = search or SwingSearch()
    t0, c0 = time.perf_counter(), time.process_time()
    for d in out:
        d.lane_result = d.result
    def family(d: DrivenRun, room_m: float | None) -> list[tuple[DrivenRun, Candidate]]:
        c = d.curve
        feature = (c.core_start_m, c.core_end_m)
        try:
            path = paths[c.curve_id]
            side = outside_sign(c.turn_angle_deg)
            rooms: tuple[float, float, float] | None = None
            inside = 0.0
            if room_m is None:  # the room the pavement gives, outward and (middle) inward
                if side:
                    paved, half = areas[c.curve_id].paved, 0.5 * d.vehicle.width_m
                    rooms = outside_rooms_m(path, feature, side, paved, half)
                    inside = outside_rooms_m(path, feature, -side, paved, half)[1]
                room_m = max(0.0, min(rooms)) if rooms else 0.0
            reach = d.vehicle.overall_length_m + 2.0  # all a judged sample's body covers
            return [(d, cand) for cand in candidates(path, feature, c.turn_angle_deg,
                                                     search, room_m, reach, rooms, inside)]
        except (InputError, shapely.errors.ShapelyError) as exc:  # no candidates
            log.info("%s: no swung paths: %s", c.curve_id, exc)
            return []

    driven: dict[int, list[tuple[Candidate, TrackingRun]]] = {}

    def drive_all(todo: list[tuple[DrivenRun, Candidate]]) -> None:
        for lo in range(0, len(todo), options.batch_size):
            chunk = todo[lo:lo + options.batch_size]
            runs = simulate_batch([d.vehicle for d, _ in chunk], [c.path for _, c in chunk],
                                  settings)
            for (d, cand), run in zip(chunk, runs, strict=True):
                if not feature_reason(run, feature_mask(run, cand.window_m)):
                    driven.setdefault(id(d), []).append((cand, run))

    todo = [x for d in out if needs_swing(d) for x in family(d, None)]
    drive_all(todo)
    # a run that cannot turn within the pavement's room: the widest swings, beyond it
    wider = [x for d in out if needs_swing(d) and id(d) not in driven
             and d.result is not None and d.result.verdict == "cannot-turn"
             for x in family(d, math.inf)]
    drive_all(wider)
    todo += wider
    judged: dict[int, list[tuple[Candidate, RunResult | None]]] = {}
    for d in out:
        if needs_swing(d):
            judged[id(d)] = _judge(d, driven.get(id(d), []), areas[d.curve.curve_id],
                                   options.offset_m, search)
    taken = 0
    for d in out:
        if not needs_swing(d):
            continue
        tried = judged[id(d)]
        lane = d.result
        assert lane is not None  # needs_swing: only runs with a result
        best = rank([lane.clearance] + [r.clearance if r is not None else None
                                        for _, r in tried])
        if best == 0:
            if lane.verdict == "cannot-turn":
                d.result = dataclasses.replace(lane, clearance=dataclasses.replace(
                    lane.clearance, reason=f"{lane.clearance.reason}; nor can it swing wide: "
                    f"none of its swung paths (outward offsets up to "
                    f"{search.max_amplitude_m:g} m, as far as the pavement allows) is "
                    "within its lock and steering rate"))
            continue
        cand, res = tried[best - 1]
        assert res is not None  # rank never picks a candidate that was not judged
        why = swing_reason(cand.amplitude_m, cand.apex_cut, res.clearance, cand.how)
        why += f" (on the lane centre line: {lane.verdict}"
        if lane.verdict != "cannot-turn":
            why += f", margin {lane.margin_m:.2f} m"
        why += ")"
        d.result = dataclasses.replace(res, clearance=dataclasses.replace(res.clearance,
                                                                          reason=why))
        d.path = "swung"
        d.swing_m = max(cand.amplitude_m, cand.exit_m) if cand.shape != "inside" else \
            -cand.inside_m
        taken += 1
    if stats is not None:
        stats.swing_judged += sum(1 for j in judged.values() for _, r in j if r is not None)
        stats.swing_s += time.perf_counter() - t0
        stats.swing_cpu_s += time.process_time() - c0
        stats.swing_candidates += len(todo)
    return taken


def _judge(d: DrivenRun, driven: list[tuple[Candidate, TrackingRun]], areas: Areas,
           offset_m: float, search: SwingSearch) -> list[tuple[Candidate, RunResult | None]]:
    """The verdicts of a run's driven candidates, in two stages.

    First every amplitude with the middle apex cut and every fitted and inside shape; then
    the other cuts of the best held amplitude and its neighbours. A ``clear`` candidate
    ends the search.
    """
    cuts = search.apex_cuts
    first_cut = cuts[len(cuts) // 2]
    amps = sorted({c.amplitude_m for c, _ in driven if c.shape == "held"})
    out: list[tuple[Candidate, RunResult | None]] = []

    def judge(items: list[tuple[Candidate, TrackingRun]]) -> bool:
        for cand, run in items:
            try:
                res = evaluate(run, areas, offset_m, feature_m=cand.window_m)
            except (InputError, ValueError, shapely.errors.ShapelyError) as exc:
                log.info("%s x %s: a swung path could not be judged: %s", d.vehicle.name,
                         d.curve.curve_id, exc)
                res = None
            out.append((cand, res))
            if res is not None and res.verdict == "clear":
                return True
        return False

    stage1 = [x for x in driven if x[0].apex_cut == first_cut or x[0].shape != "held"]
    if judge(stage1):
        return out
    held = [(c, r) for c, r in out if c.shape == "held"]
    best = rank([None] + [r.clearance if r else None for _, r in held])
    near = set(amps)
    if best:
        k = amps.index(held[best - 1][0].amplitude_m)
        near = set(amps[max(0, k - 1):k + 2])
    judge([x for x in driven if x[0].shape == "held" and x[0].apex_cut != first_cut
           and x[0].amplitude_m in near])
    return out
