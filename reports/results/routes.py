"""A route study's results: each route's passages, each vehicle's verdict there, and how it
compares with the baseline vehicle (``routes.csv``).

A passage with several curves (lane-to-lane connections) is judged by the one a driver
would take: the best verdict, then the largest margin, as the whole-network study ranks
runs (:data:`~clearance.reports.results.records.VERDICT_ORDER`). With a baseline vehicle
(``--baseline NAME``, usually the bus that runs the line today) each other vehicle's
passage is ``worse`` when its verdict is worse, or it needs more room: its margin to its
lanes or to the pavement smaller by more than the tolerance (its reach beyond them larger);
``better`` when its verdict is better or it has more room by more than the tolerance with
none less; ``same`` otherwise.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from clearance.networks.passages import Passage
from clearance.networks.routes import Route
from clearance.reports.results.records import VERDICT_ORDER, RunRecord

__all__ = ["CONTRADICTED", "DEFAULT_TOLERANCE_M", "NOT_PERMITTED", "ROUTE_COLUMNS", "PassageRow",
           "own_traffic_words", "best_record",
           "compare_runs", "route_rows", "route_summary", "routes_csv"]

#: Room a vehicle may lack against the baseline before it counts as worse (m).
DEFAULT_TOLERANCE_M = 0.10

#: The verdict of a passage whose lanes the vehicle's class may not use (not run).
NOT_PERMITTED = "not permitted"

ROUTE_COLUMNS = ["route_id", "line", "order", "junction", "kind", "from_edge", "to_edge",
                 "curve_id", "vehicle", "verdict", "margin_m", "paved_margin_m",
                 "baseline", "baseline_verdict", "baseline_margin_m", "vs_baseline",
                 "more_room_m", "geometry", "conflict_at", "own_traffic"]

#: The verdicts the network's own traffic is held against: it drives where the study's vehicle
#: of its class cannot.
CONTRADICTED = ("fails", "cannot-turn")

_PLURAL = {"bus": "buses", "coach": "coaches", "truck": "trucks", "trailer": "trailers",
           "delivery": "delivery vehicles", "passenger": "cars", "taxi": "taxis"}
_PASSAGE_WORD = {"turn": "turn", "uturn": "U-turn", "roundabout": "roundabout passage",
                 "ramp": "ramp", "bend": "bend"}


@dataclass(frozen=True)
class PassageRow:
    """One row of ``routes.csv``: a route's passage and one vehicle's run there."""

    route: Route
    order: int
    passage: Passage
    vehicle: str
    record: RunRecord | None
    baseline: RunRecord | None
    vs_baseline: str
    more_room_m: float
    #: The network's own traffic that drives this passage while the vehicle fails there, in
    #: words (:func:`own_traffic_words`); ``""`` otherwise.
    own_traffic: str = ""

    def row(self) -> dict[str, object]:
        r, b = self.record, self.baseline
        return {"route_id": self.route.route_id, "line": self.route.line,
                "order": self.order, "junction": self.passage.junction,
                "kind": self.passage.kind, "from_edge": self.passage.from_edge,
                "to_edge": self.passage.to_edge,
                "curve_id": r.curve_id if r else "", "vehicle": self.vehicle,
                "verdict": r.verdict if r else NOT_PERMITTED,
                "margin_m": _m(r.margin_m if r else math.nan),
                "paved_margin_m": _m(r.paved_margin_m if r else math.nan),
                "baseline": b.vehicle if b else "",
                "baseline_verdict": b.verdict if b else "",
                "baseline_margin_m": _m(b.margin_m if b else math.nan),
                "vs_baseline": self.vs_baseline, "more_room_m": _m(self.more_room_m),
                "geometry": r.geometry if r else "", "conflict_at": r.conflict_at if r else "",
                "own_traffic": self.own_traffic}


def _m(value: float) -> str:
    return "" if math.isnan(value) else f"{value + 0.0:.3f}"


def _low_nan(x: float) -> float:
    return -math.inf if math.isnan(x) else x


def _key(r: RunRecord) -> tuple[int, float, float]:
    return VERDICT_ORDER[r.verdict], _low_nan(r.margin_m), _low_nan(r.paved_margin_m)


def best_record(records: Sequence[RunRecord]) -> RunRecord | None:
    """The run a driver would take among a passage's curves: best verdict, then margin.

    >>> from types import SimpleNamespace as Run
    >>> a = Run(curve_id="c1", verdict="fails", margin_m=-1.0, paved_margin_m=-0.2)
    >>> b = Run(curve_id="c2", verdict="encroaches", margin_m=-0.5, paved_margin_m=0.4)
    >>> best_record([a, b]).curve_id, best_record([])
    ('c2', None)
    """
    return max(records, key=_key) if records else None


def compare_runs(run: RunRecord | None, baseline: RunRecord | None, tolerance_m: float
                 ) -> tuple[str, float]:
    """``worse``, ``same`` or ``better`` than the baseline's run, and how much more room the
    run needs than the baseline's (m; the larger of the two margins' shortfalls, NaN
    where a margin is missing). ``""`` where either was not run.

    >>> from types import SimpleNamespace as Run
    >>> base = Run(verdict="encroaches", margin_m=-0.4, paved_margin_m=0.8)
    >>> longer = Run(verdict="encroaches", margin_m=-0.9, paved_margin_m=0.5)
    >>> compare_runs(longer, base, 0.1)
    ('worse', 0.5)
    >>> compare_runs(base, base, 0.1)
    ('same', 0.0)
    """
    if run is None or baseline is None:
        return "", math.nan
    more = max(baseline.margin_m - run.margin_m, baseline.paved_margin_m - run.paved_margin_m)
    rank, base_rank = VERDICT_ORDER[run.verdict], VERDICT_ORDER[baseline.verdict]
    if rank < base_rank:
        return "worse", more
    if rank > base_rank:
        return "better", more
    if math.isnan(more):  # cannot-turn or error both: no margins to compare
        return "same", more
    if more > tolerance_m:
        return "worse", more
    less = min(baseline.margin_m - run.margin_m, baseline.paved_margin_m - run.paved_margin_m)
    return ("better" if less < -tolerance_m and more <= 0 else "same"), more


def own_traffic_words(passage: Passage, vclass: str, drivers: Sequence[Route]) -> str:
    """The evidence of the network's own traffic on a passage where a vehicle of class
    ``vclass`` fails: the routes of that class that drive it and their types' sizes.

    >>> from clearance.networks.routes import Route
    >>> p = Passage(("a", "b"), "J", "turn", ("c",))
    >>> r = Route("bus_1", ("a", "b"), "Bus", "bus", "1", "f", ("v",), (12.0, 2.5))
    >>> print(own_traffic_words(p, "bus", [r, r]))  # doctest: +NORMALIZE_WHITESPACE
    this network's own buses take this turn (route bus_1; type Bus 12.0 × 2.5 m): the failure
    likely rests on the drawing
    >>> own_traffic_words(p, "truck", [r])
    ''
    """
    same = [r for r in drivers if r.vclass == vclass]
    if not same:
        return ""
    ids = list(dict.fromkeys(r.route_id for r in same))
    shown = ", ".join(ids[:5]) + (f" and {len(ids) - 5} more" if len(ids) > 5 else "")
    types = ", ".join(f"{t} {size[0]:.1f} × {size[1]:.1f} m" for t, size in
                      dict.fromkeys((r.vtype, r.size_m) for r in same))
    return (f"this network's own {_PLURAL.get(vclass, vclass + ' vehicles')} take this "
            f"{_PASSAGE_WORD.get(passage.kind, passage.kind)} "
            f"(route{'s' if len(ids) > 1 else ''} {shown}; type{'s' if ',' in types else ''} "
            f"{types}): the failure likely rests on the drawing")


def route_rows(routes: Sequence[Route], passages: Mapping[str, list[tuple[int, Passage]]],
               records: Sequence[RunRecord], vehicles: Sequence[str],
               baseline: str | None = None, tolerance_m: float = DEFAULT_TOLERANCE_M,
               vclasses: Mapping[str, str] | None = None) -> list[PassageRow]:
    """Every route x passage x vehicle, in route order then the vehicles' order; with the
    vehicles' SUMO classes (``vclasses``), a run that fails or cannot turn where the routes'
    own vehicles of its class drive carries that evidence (:func:`own_traffic_words`)."""
    by_run = {(r.vehicle, r.curve_id): r for r in records}
    drivers: dict[Passage, list[Route]] = {}
    for route in routes:
        for _, passage in passages[route.route_id]:
            drivers.setdefault(passage, []).append(route)
    out = []
    for route in routes:
        for order, passage in passages[route.route_id]:
            best = {v: best_record([by_run[(v, c)] for c in passage.curve_ids
                                    if (v, c) in by_run]) for v in vehicles}
            base = best.get(baseline) if baseline else None
            for v in vehicles:
                if baseline is None:
                    vs, more = "", math.nan
                elif v == baseline:
                    vs, more = "baseline", math.nan
                else:
                    vs, more = compare_runs(best[v], base, tolerance_m)
                rec = best[v]
                own = (own_traffic_words(passage, vclasses[v], drivers[passage])
                       if vclasses and v in vclasses and rec and rec.verdict in CONTRADICTED
                       else "")
                out.append(PassageRow(route, order, passage, v, rec, base, vs, more, own))
    return out


def routes_csv(rows: Sequence[PassageRow]) -> str:
    """``routes.csv``: :data:`ROUTE_COLUMNS`, one row per route x passage x vehicle."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=ROUTE_COLUMNS, lineterminator="\n")
    w.writeheader()
    w.writerows(r.row() for r in rows)
    return buf.getvalue()


def route_summary(rows: Sequence[PassageRow]) -> dict[str, dict[str, dict[str, int]]]:
    """Per route and vehicle: passages by verdict, and by ``vs_baseline`` (``summary.json``)."""
    out: dict[str, dict[str, dict[str, int]]] = {}
    for r in rows:
        counts = out.setdefault(r.route.route_id, {}).setdefault(r.vehicle, {})
        verdict = r.record.verdict if r.record else NOT_PERMITTED
        counts[verdict] = counts.get(verdict, 0) + 1
        if r.own_traffic:
            counts["driven_by_own_traffic"] = counts.get("driven_by_own_traffic", 0) + 1
        if r.vs_baseline and r.vs_baseline != "baseline":
            key = f"vs_baseline_{r.vs_baseline}"
            counts[key] = counts.get(key, 0) + 1
    return out
