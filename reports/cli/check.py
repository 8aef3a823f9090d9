"""``clearance check``: a CI gate on the clearance of design vehicles.

Without ``--expect``: exit 0 when every run is ``clear``, waived (``--waivers``, see
:mod:`clearance.reports.results.waivers`) or has a verdict given with ``--allow``; 1 when any is
not (each listed with curve, vehicle, verdict and margin; an ``error`` run is never clear), 2 on bad
input.

With ``--expect GOLDEN.csv`` (:mod:`clearance.reports.results.golden`): the verdicts are compared
with a golden file of the verdicts the networks are meant to produce. Exit 1 when any verdict is
worse than its golden one (and not waived), an expected run is missing on a curve that is
still there, the study has curves or runs the golden file does not know (*new*; allowed
with ``--allow-new``) or the golden file has curves the study no longer finds (*gone*;
allowed with ``--allow-gone``): in each case the gate no longer covers the network as the
golden file says. Better verdicts are reported (the golden file may be out of date) but
pass. ``--write-golden`` writes the current verdicts as a golden file instead and exits 0
once it is written, whatever the verdicts.

Vertical findings (:mod:`clearance.reports.results.vertical`: ``scrapes``, ``too-steep``) fail the
gate in both modes unless given with ``--allow``; each is listed with the part of the body, the
depth and the station. They are not verdicts of the golden file (a run has its plan
verdict and its vertical finding side by side).

``--kind``, ``--junction`` and ``--bbox`` check only the curves of one scheme
(:mod:`clearance.networks.selection`); with ``--expect``, only the golden rows of that selection are
judged.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd

from clearance.networks.selection import Selection
from clearance.reports.cli.options import (
    add_clearance_option,
    add_executor_options,
    add_grade_option,
    add_lane_only_option,
    add_net_option,
    add_route_options,
    add_selection_options,
    add_table_option,
    add_waivers_option,
    announcer,
    route_study,
    selection_of,
)
from clearance.reports.output.atomic import write_text_atomic
from clearance.reports.results.gate import not_allowed, vertical_not_allowed
from clearance.reports.results.golden import compare, golden_text, read_golden, relevant
from clearance.reports.results.text_table import counted
from clearance.reports.results.vertical import FINDINGS, vertical_words
from clearance.reports.results.waivers import Waived, read_waivers, study_waivers
from clearance.reports.study.routes import RouteStudy
from clearance.reports.study.run import METHODS, Study, run_study
from clearance.vehicles.errors import OptionError
from clearance.vehicles.table import load_tables

__all__ = ["ALLOWABLE", "add_parser", "run"]

ALLOWABLE = ("encroaches", "fails", "cannot-turn", *FINDINGS)


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "check",
        help="CI gate: exit 1 when a design vehicle does not clear a curve",
        description="Exit 0 when every curve of the networks is clear for every design "
                    "vehicle (or waived, or has only allowed verdicts), 1 when any is not, 2 "
                    "on bad input. With --expect, compare with a golden file of verdicts "
                    "instead: worse verdicts, new and gone curves exit 1.",
    )
    add_net_option(p, repeatable=True, required=True, help="SUMO network (repeatable)")
    p.add_argument("--design-vehicle", action="append", metavar="NAME", required=True,
                   help="design vehicle (repeatable)")
    add_table_option(p)
    p.add_argument("--allow", action="append", choices=ALLOWABLE, default=[],
                   help="a verdict or vertical finding that does not fail the gate "
                        "(repeatable)")
    p.add_argument("--method", choices=METHODS, default="simulate")
    add_clearance_option(p)
    add_grade_option(p)
    add_lane_only_option(p)
    add_executor_options(p)
    add_selection_options(p)
    add_waivers_option(p)
    add_route_options(p)
    golden = p.add_mutually_exclusive_group()
    golden.add_argument("--expect", metavar="GOLDEN.csv",
                        help="compare with this golden file of verdicts")
    golden.add_argument("--write-golden", metavar="GOLDEN.csv",
                        help="write the verdicts found as a golden file (exit 0 once written)")
    p.add_argument("--allow-new", action="store_true",
                   help="with --expect: curves and runs the golden file does not know pass")
    p.add_argument("--allow-gone", action="store_true",
                   help="with --expect: golden curves the study no longer finds pass")
    p.set_defaults(run=run)


def _warn_unused(waived: Waived) -> None:
    for w in waived.unused:
        print(f"clearance check: warning: {w.where}: waiver matches no run "
              f"(curve {w.curve_id!r}, vehicle {w.vehicle!r}, network {w.network!r})",
              file=sys.stderr)


def _print_waived(frame: pd.DataFrame, waived: Waived) -> None:
    for r in frame.itertuples():
        key = (r.network, r.vehicle, r.curve_id)
        if key in waived.by:
            print(f"waived: {r.network}: {r.curve_id}: {r.vehicle}: {r.verdict} "
                  f"({r.margin_m:+.2f} m): {waived.reasons[key]} ({waived.by[key].where})")


def _expect(args: argparse.Namespace, golden: pd.DataFrame, study: Study,
            frame: pd.DataFrame, waived: Waived, selection: Selection) -> int:
    found_curves = set(zip(frame.network, frame.curve_id, strict=True))
    judged, outside, not_judged = relevant(golden, study.table.names,
                                           [n.name for n in study.networks], found_curves,
                                           selection)
    cmp = compare(frame, judged, waived.reasons)
    for line in cmp.better:
        print(f"better than expected: {line}")
    for line in cmp.worse_waived:
        print(f"worse than expected, waived: {line}")
    for line in cmp.worse:
        print(f"WORSE than expected: {line}")
    new_tag = "new (allowed)" if args.allow_new else "NEW"
    for line in cmp.new_curves:
        print(f"{new_tag} curve, not in the golden file: {line}")
    for line in cmp.new_runs:
        print(f"{new_tag} run, not in the golden file: {line}")
    gone_tag = "gone (allowed)" if args.allow_gone else "GONE"
    for line in cmp.gone_curves:
        print(f"{gone_tag} curve, in the golden file but not found: {line}")
    print(f"{cmp.expected} expected verdicts: {len(cmp.worse)} worse, "
          f"{len(cmp.worse_waived)} worse but waived, {len(cmp.better)} better, "
          f"{cmp.as_expected} as expected; {len(cmp.new_curves)} new curves, "
          f"{len(cmp.new_runs)} new runs, {len(cmp.gone_curves)} gone curves")
    if outside:
        print(f"{outside} golden verdicts outside the selection ({selection.describe()})")
    if not_judged:
        print(f"{not_judged} golden verdicts not judged: their curves are not found and "
              f"may lie outside the selection ({selection.describe()})")
    failed = bool(cmp.worse)
    failed |= bool(cmp.new_curves or cmp.new_runs) and not args.allow_new
    failed |= bool(cmp.gone_curves) and not args.allow_gone
    return 1 if failed else 0


def _vertical_failures(frame: pd.DataFrame, allowed: set[str]) -> int:
    """Print the runs whose vertical finding (scrapes, too-steep) is not allowed; their
    number."""
    bad = vertical_not_allowed(frame, allowed)
    for r in bad:
        print(f"{r.network}: {r.curve_id}: {r.vehicle}: {vertical_words(r)}")
    return len(bad)


def _baseline_gate(routes: RouteStudy) -> int:
    """Exit 1 when a design vehicle is worse than the baseline on a passage of the routes
    (each listed with route, junction and how much more room it needs)."""
    worse = [r for r in routes.rows if r.vs_baseline == "worse"]
    for r in worse:
        more = (f", {r.more_room_m:.2f} m more room" if r.more_room_m == r.more_room_m
                else "")
        print(f"{r.route.route_id}: passage {r.order} at {r.passage.junction or '-'} "
              f"({r.passage.from_edge} -> {r.passage.to_edge}): {r.vehicle} "
              f"{r.record.verdict if r.record else 'not permitted'} worse than "
              f"{routes.baseline} ({r.baseline.verdict if r.baseline else 'not run'}){more}")
    vehicles = sorted({r.vehicle for r in routes.rows} - {routes.baseline or ""})
    passages = len({(r.route.route_id, r.order) for r in routes.rows})
    print(f"{len(routes.routes)} route(s), {passages} passage(s): "
          + "; ".join(f"{v}: {sum(r.vehicle == v for r in worse)} worse than "
                      f"{routes.baseline}" for v in vehicles))
    return 1 if worse else 0


def run(args: argparse.Namespace) -> int:
    if (args.allow_new or args.allow_gone) and not args.expect:
        raise OptionError("--allow-new and --allow-gone go with --expect GOLDEN.csv")
    table = load_tables(args.table, args.design_vehicle)
    selection = selection_of(args)
    golden = read_golden(Path(args.expect)) if args.expect else None
    waivers = (read_waivers(Path(args.waivers), load_tables(args.table, warn=False).names)
               if args.waivers else [])
    options = dict(method=args.method, clearance_m=args.clearance, selection=selection,
                   announce=announcer("check"), workers=args.workers,
                   scheduler=args.scheduler, swing=not args.lane_only,
                   max_grade_pct=args.max_grade_pct)
    routes = route_study(args, args.net, table, options)
    study = routes.study if routes is not None else run_study(args.net, table, **options)
    if routes is not None and routes.baseline is not None:
        return _baseline_gate(routes)
    frame = study.frame()
    if not selection.is_empty:
        print(f"selection: {selection.describe()}: "
              f"{counted(sum(len(n.curves) for n in study.networks), 'curve')}")
    if args.write_golden:
        write_text_atomic(args.write_golden, golden_text(frame))
        print(f"wrote {args.write_golden} ({len(frame)} verdicts)")
        return 0
    waived = study_waivers(frame, waivers)
    _warn_unused(waived)
    _print_waived(frame, waived)
    if golden is not None:
        code = _expect(args, golden, study, frame, waived, selection)
        vertical = _vertical_failures(frame, set(args.allow))
        if vertical:
            print(f"{counted(vertical, 'run')} with a vertical finding not allowed "
                  f"(scrapes, too-steep)")
        return 1 if code or vertical else 0
    allowed = {"clear", *args.allow}
    failing = not_allowed(frame, allowed, waived)
    for r in failing.itertuples():
        key = (r.network, r.vehicle, r.curve_id)
        note = ""
        if key in waived.too_bad:
            w = waived.too_bad[key]
            note = f" (worse than {w.where} accepts: {w.verdict})"
        where = f", worst {r.conflict_at}" if r.conflict_at else ""
        rests = f"; rests on {r.geometry}" if r.geometry and r.geometry != "data" else ""
        print(f"{r.network}: {r.curve_id}: {r.vehicle}: {r.verdict} ({r.margin_m:+.2f} m"
              f"{where}){note}{rests}")
    vertical = _vertical_failures(frame, allowed)
    print(f"{len(frame)} runs, {len(waived)} waived, {len(failing)} not allowed "
          f"(allowed: {', '.join(sorted(allowed))}); {vertical} with a vertical finding "
          f"not allowed (scrapes, too-steep)")
    return 1 if len(failing) or vertical else 0
