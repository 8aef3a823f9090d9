"""The second pass of a drive: a swung path for every run that does not clear on its lane.

:func:`networks.driver.drive` first drives every run on its lane's centre line. For each
run that is not ``clear`` there, :func:`swing_pass` drives the search's candidates
(:func:`analysis.path_search.candidates`: the centre line offset toward the outside of the
turn by a fixed family of profiles), all runs' candidates together in batches of
:attr:`~networks.runs.DriveOptions.batch_size` (:func:`analysis.tracking.simulate_batch`),
judges each one the follower could drive against the curve's areas over the whole
manoeuvre (:func:`analysis.clearance.evaluate` with the candidate's window), and keeps the
best (:func:`analysis.path_search.rank`; the lane's result wins ties). A candidate the
follower cannot drive within the lock and steering rate in that window is not judged (it
ranks as ``cannot-turn``). The candidates of a run are judged smallest swing first, and the
first ``clear`` one ends that run's search (no later one can be in a better tier).

The lane-following result stays beside the chosen one (:attr:`DrivenRun.lane_result`), and
:attr:`DrivenRun.path` says which was taken (``lane`` or ``swung``). SUMO replays the lane
path only (it runs before this pass): swung paths are the model's.
"""

from __future__ import annotations

import dataclasses
import logging
import time

import shapely

from analysis.clearance import Areas, RunResult, evaluate, feature_mask, feature_reason
from analysis.path_search import Candidate, SwingSearch, candidates, rank, swing_reason
from analysis.polyline import Path
from analysis.tracking import TrackingSettings, simulate_batch
from networks.runs import DrivenRun, DriveOptions, DriveStats
from vehicles.errors import InputError

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
    todo: list[tuple[DrivenRun, Candidate]] = []
    for d in out:
        if not needs_swing(d):
            continue
        c = d.curve
        try:
            for cand in candidates(paths[c.curve_id], (c.core_start_m, c.core_end_m),
                                   c.turn_angle_deg, search):
                todo.append((d, cand))
        except InputError as exc:  # an offset line the follower refuses: no candidates
            log.info("%s: no swung paths: %s", c.curve_id, exc)
    judged: dict[int, list[tuple[Candidate, RunResult | None]]] = {}
    done: set[int] = set()
    size = options.batch_size
    for lo in range(0, len(todo), size):
        chunk = todo[lo:lo + size]
        runs = simulate_batch([d.vehicle for d, _ in chunk], [c.path for _, c in chunk],
                              settings)
        for (d, cand), run in zip(chunk, runs, strict=True):
            key = id(d)
            if key in done:
                continue
            res = None
            if not feature_reason(run, feature_mask(run, cand.window_m)):
                try:
                    res = evaluate(run, areas[d.curve.curve_id], options.offset_m,
                                   feature_m=cand.window_m)
                except (InputError, ValueError, shapely.errors.ShapelyError) as exc:
                    log.info("%s x %s: a swung path could not be judged: %s",
                             d.vehicle.name, d.curve.curve_id, exc)
            judged.setdefault(key, []).append((cand, res))
            if res is not None and res.verdict == "clear":
                done.add(key)
    taken = 0
    for d in out:
        if not needs_swing(d):
            continue
        tried = judged.get(id(d), [])
        lane = d.result
        best = rank([lane.clearance] + [r.clearance if r is not None else None
                                        for _, r in tried])
        if best == 0:
            if lane.verdict == "cannot-turn":
                widest = max(search.amplitudes_m)
                d.result = dataclasses.replace(lane, clearance=dataclasses.replace(
                    lane.clearance, reason=f"{lane.clearance.reason}; nor can it swing wide: "
                    f"none of the {len(tried)} swung paths (outward offsets up to "
                    f"{widest:g} m) is within its lock and steering rate"))
            continue
        cand, res = tried[best - 1]
        why = swing_reason(cand.amplitude_m, cand.apex_cut, res.clearance)
        why += f" (on the lane centre line: {lane.verdict}"
        if lane.verdict != "cannot-turn":
            why += f", margin {lane.margin_m:.2f} m"
        why += ")"
        d.result = dataclasses.replace(res, clearance=dataclasses.replace(res.clearance,
                                                                          reason=why))
        d.path = "swung"
        d.swing_m = cand.amplitude_m
        taken += 1
    if stats is not None:
        stats.swing_s += time.perf_counter() - t0
        stats.swing_cpu_s += time.process_time() - c0
        stats.swing_candidates += len(todo)
    return taken
