"""The candidate lines a search of swung paths has driven, judged and kept, per run.

:class:`Trials` drives candidates in batches (:func:`clearance.analysis.tracking.simulate_batch`),
judges each one the follower could drive within its window
(:func:`clearance.analysis.clearance.judge`) and keeps, per run, every judged candidate's
clearance in order (``tried``: the order :func:`clearance.networks.driving.judging.rank`
reads) and the driven run of those that may still be chosen (``results``, pruned as it
goes: :func:`prune`).

Screened rounds
---------------
A compass search (:mod:`clearance.networks.driving.refine`) drives a dozen moves per start
and round and keeps only the best; most of the others leave the pavement further, and
judging them exactly is most of the search's cost. In a screened round
(:meth:`Trials.drive` with ``groups``, one group per start) each drivable move first gets
a bound read off its body's corners (:func:`clearance.analysis.screening.paved_reach_bound_m`):
where it leaves the pavement by at least a centimetre, its order key
(:func:`order_key`) is at most ``(1, -bound)``. Each group's moves are judged best bound
first until the best judged key is above every bound left; those left are not judged. A
move left out is one the compass would not have taken, and one
:func:`~clearance.networks.driving.judging.rank` would not have kept: the search keeps
rank's running choice as the moves are added (:meth:`Trials.may_lead`), and judges a move
after all where its bound could beat it. The path chosen, its verdict and its margins are
the ones judging every move gives.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

from clearance.analysis.clearance import Areas, Clearance, judge
from clearance.analysis.failures import GEOMETRY_FAILURES
from clearance.analysis.feature import feature_mask, feature_reason
from clearance.analysis.margins import PRECISION_M
from clearance.analysis.screening import paved_reach_bound_m
from clearance.analysis.tracking import TrackingRun, TrackingSettings, simulate_batch
from clearance.networks.driving.candidates import Candidate
from clearance.networks.driving.judging import BETTER_BY_M, decisive_margin, tier
from clearance.networks.driving.runs import DrivenRun, DriveOptions

__all__ = ["Key", "Trials", "order_key", "prune"]

log = logging.getLogger(__name__)

#: A candidate's place in the search's order (:func:`order_key`): larger is better.
Key = tuple[float, ...]


def order_key(clearance: Clearance | None, error_m: float) -> Key:
    """The order of candidates in the refinement: that of
    :func:`~clearance.networks.driving.judging.rank` (the tier, then the decisive margin);
    among those the follower could not drive, the least lateral error.

    Examples
    --------
    >>> order_key(Clearance("fails", -2.0, -0.3, -1.0, 0.0, ""), 0.1)
    (1.0, -0.3, 0.0)
    >>> order_key(None, 0.8)  # not driven within its tolerance
    (0.0, -inf, -0.8)
    """
    if clearance is None:
        return (0.0, -math.inf, -error_m)
    return (float(tier(clearance)), decisive_margin(clearance), 0.0)


def prune(results: dict[int, tuple[Clearance, TrackingRun]]) -> None:
    """Drop the results of a run's candidates that can no longer be kept: of a worse tier
    than the best so far, or short of its decisive margin by more than
    :data:`~clearance.networks.driving.judging.BETTER_BY_M`
    (:func:`clearance.networks.driving.judging.rank` keeps a
    path within that of the best of its tier, never one further short).

    Examples
    --------
    >>> c = lambda m: Clearance("fails", -2.0, m, -1.0, 0.0, "")
    >>> results = {0: (c(-0.5), None), 1: (c(-0.3), None), 2: (c(-0.33), None)}
    >>> prune(results)
    >>> sorted(results)
    [1, 2]
    """
    keys = {i: (tier(c), decisive_margin(c)) for i, (c, _) in results.items()}
    top = max(keys.values())
    for i, (t, m) in keys.items():
        if t < top[0] or m < top[1] - BETTER_BY_M - 1e-9:
            del results[i]


class Trials:
    """The candidates driven for the runs of one search (see the module docstring)."""

    def __init__(self, runs: Sequence[DrivenRun], areas: dict[str, Areas],
                 settings: TrackingSettings, options: DriveOptions) -> None:
        self.areas, self.settings, self.options = areas, settings, options
        #: per run: every candidate judged, with its clearance (``None``: not judgeable)
        self.tried: dict[int, list[tuple[Candidate, Clearance | None]]] = {
            id(d): [] for d in runs}
        #: per run: the clearance and driven run of those that may still be kept, by place
        self.results: dict[int, dict[int, tuple[Clearance, TrackingRun]]] = {
            id(d): {} for d in runs}
        self.count = self.judged = self.screened = 0
        self._lane = {id(d): d.result.clearance if d.result else None for d in runs}
        self._leader: dict[int, tuple[int, tuple[int, float]]] = {}

    def drive(self, todo: list[tuple[DrivenRun, Candidate]],
              groups: Sequence[int] | None = None) -> list[Key]:
        """Drive ``todo`` and judge the candidates the follower could drive; the order key
        of each (:func:`order_key`; a move screened out: its bound, below its group's best).
        With ``groups`` (a group per candidate), a screened round."""
        self.count += len(todo)
        keys: list[Key] = []
        drivable: list[tuple[int, DrivenRun, Candidate, TrackingRun]] = []
        for lo in range(0, len(todo), self.options.batch_size):
            chunk = todo[lo:lo + self.options.batch_size]
            runs = simulate_batch([d.vehicle for d, _ in chunk], [c.path for _, c in chunk],
                                  self.settings)
            for j, ((d, cand), run) in enumerate(zip(chunk, runs, strict=True), start=lo):
                keys.append(order_key(None, run.max_error_m))
                if not feature_reason(run, feature_mask(run, cand.window_m)):
                    drivable.append((j, d, cand, run))
        bounds: dict[int, Key | None] = {}
        judged = (self._screen(drivable, groups, bounds) if groups is not None
                  else {j: self._judge(d, cand, run) for j, d, cand, run in drivable})
        for j, d, cand, run in drivable:
            if j not in judged:
                bound = bounds[j]
                if bound is not None and not self.may_lead(d, bound):
                    keys[j] = bound
                    self.screened += 1
                    continue
                judged[j] = self._judge(d, cand, run)
            res = judged[j]
            self.tried[id(d)].append((cand, res))
            if res is not None:
                self.results[id(d)][len(self.tried[id(d)]) - 1] = (res, run)
                prune(self.results[id(d)])
            keys[j] = order_key(res, run.max_error_m)
        return keys

    def _judge(self, d: DrivenRun, cand: Candidate, run: TrackingRun) -> Clearance | None:
        """A driven candidate's clearance over its window (``None`` where it cannot be
        judged): :func:`clearance.analysis.clearance.judge`."""
        try:
            res = judge(run, self.areas[d.curve.curve_id], self.options.offset_m,
                        feature_m=cand.window_m)
        except GEOMETRY_FAILURES as exc:
            log.info("%s x %s: a swung path could not be judged: %s", d.vehicle.name,
                     d.curve.curve_id, exc)
            return None
        self.judged += 1
        return res

    def _bound(self, d: DrivenRun, cand: Candidate, run: TrackingRun) -> Key | None:
        """The most a drivable candidate's order key can be, where its corners show it
        leaving the pavement (``None``: no bound)."""
        try:
            reach = paved_reach_bound_m(run, self.areas[d.curve.curve_id],
                                        self.options.offset_m, cand.window_m)
        except GEOMETRY_FAILURES:
            return None
        return (1.0, -reach, 0.0) if reach >= PRECISION_M else None

    def _screen(self, drivable: list[tuple[int, DrivenRun, Candidate, TrackingRun]],
                groups: Sequence[int], bounds: dict[int, Key | None]
                ) -> dict[int, Clearance | None]:
        """Judge each group's candidates best bound first, until the best judged key is
        above every bound left; the clearances judged, by place in the round (``bounds``:
        each candidate's, filled)."""
        judged: dict[int, Clearance | None] = {}
        by_group: dict[int, list[tuple[Key, int, DrivenRun, Candidate, TrackingRun]]] = {}
        for j, d, cand, run in drivable:
            bound = bounds[j] = self._bound(d, cand, run)
            top = (math.inf,) if bound is None else bound
            by_group.setdefault(groups[j], []).append((top, j, d, cand, run))
        for members in by_group.values():
            members.sort(key=lambda m: m[0], reverse=True)
            best: Key = (-math.inf,)
            for top, j, d, cand, run in members:
                if top < best:
                    break
                judged[j] = self._judge(d, cand, run)
                best = max(best, order_key(judged[j], run.max_error_m))
        return judged

    def may_lead(self, d: DrivenRun, bound: Key) -> bool:
        """Whether a candidate whose order key is at most ``bound`` could become
        :func:`~clearance.networks.driving.judging.rank`'s choice if added to the run's
        tried candidates now: rank's running choice is kept as they are added."""
        tried = self.tried[id(d)]
        lane = self._lane[id(d)]
        pos, key = self._leader.get(id(d), (0, (tier(lane), decisive_margin(lane))))
        for _, c in tried[pos:]:  # rank, from where it was left
            k = (tier(c), decisive_margin(c))
            if k[0] > key[0] or (k[0] == key[0] and k[1] > key[1] + BETTER_BY_M):
                key = k
        self._leader[id(d)] = (len(tried), key)
        t = int(bound[0])
        return t > key[0] or (t == key[0] and bound[1] > key[1] + BETTER_BY_M)
