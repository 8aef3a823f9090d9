"""Command-line options shared by the sub-commands."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from clearance.networks.curves import KINDS
from clearance.networks.routes import RouteSelection
from clearance.networks.selection import Selection, parse_bbox
from clearance.reports.documents.sheet_settings import (
    MAX_SHEETS,
    PROJECT_FILE,
    SHEET_CHOICES,
    Project,
    SheetSettings,
    read_project,
)
from clearance.reports.study.routes import RouteStudy, run_route_study
from clearance.vehicles.errors import OptionError
from clearance.vehicles.table import VehicleTable

__all__ = ["add_clearance_option", "add_executor_options", "add_grade_option",
           "add_lane_only_option", "add_net_option", "add_output_option",
           "add_route_options", "add_selection_options", "add_sheet_options",
           "add_table_option",
           "add_units_option", "add_vehicle_option", "add_waivers_option", "announcer",
           "route_selection_of", "route_study", "selection_of",
           "sheet_settings_of"]


def announcer(command: str) -> Callable[[str], None]:
    """What a command says on stderr before its runs (how many, about how long)."""
    def say(text: str) -> None:
        print(f"clearance {command}: {text}", file=sys.stderr, flush=True)

    return say


def add_table_option(p: argparse.ArgumentParser) -> None:
    """``-t/--table TABLE.csv`` (repeatable; default: every bundled table)."""
    p.add_argument("-t", "--table", action="append", metavar="TABLE.csv",
                   help="vehicle table (repeatable); default: every bundled table")


def add_vehicle_option(p: argparse.ArgumentParser, required: bool = False,
                       help: str = "only this vehicle (repeatable)") -> None:
    """``--vehicle NAME`` (repeatable)."""
    p.add_argument("--vehicle", action="append", metavar="NAME", required=required, help=help)


def add_units_option(p: argparse.ArgumentParser, help: str = "output length units") -> None:
    """``--units m|ft`` (default metres)."""
    p.add_argument("--units", choices=("m", "ft"), default="m", help=help)


def add_clearance_option(p: argparse.ArgumentParser) -> None:
    """``--clearance M``: the offset the swept envelope is grown by (default 0 m)."""
    p.add_argument("--clearance", type=float, default=0.0, metavar="M",
                   help="clearance offset the swept envelope is grown by (m, default 0)")


def add_grade_option(p: argparse.ArgumentParser) -> None:
    """``--max-grade-pct PCT``: a grade limit for every vehicle (runs above it are
    ``too-steep``; a vehicle's own ``grade_limit_pct`` applies too, the lower counting)."""
    p.add_argument("--max-grade-pct", type=float, default=None, metavar="PCT",
                   help="grade limit for every vehicle (percent): a run on a steeper curve "
                        "is too-steep; a vehicle's table column grade_limit_pct applies too")


def add_lane_only_option(p: argparse.ArgumentParser) -> None:
    """``--lane-only``: judge every run on its lane's centre line, search no swung paths."""
    p.add_argument("--lane-only", action="store_true",
                   help="judge every run on its lane's centre line only: no swung paths "
                        "for the runs that do not clear there (simulate method)")


def add_executor_options(p: argparse.ArgumentParser) -> None:
    """``--workers N`` and ``--scheduler ADDRESS``: where a study's runs are driven."""
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes on this machine (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="run on a Dask cluster: the scheduler's address (tcp://HOST:8786); "
                        "needs pip install 'sumo-clearance[cluster]'")


def add_selection_options(p: argparse.ArgumentParser,
                          kinds_default: str = "the kinds a study extracts") -> None:
    """``--kind KIND``, ``--junction ID`` (both repeatable) and ``--bbox XMIN,YMIN,XMAX,YMAX``:
    only the curves of one scheme (see :mod:`clearance.networks.selection`)."""
    p.add_argument("--kind", action="append", choices=KINDS, metavar="KIND",
                   help=f"only curves of this kind (repeatable; one of {', '.join(KINDS)}; "
                        f"default: {kinds_default})")
    p.add_argument("--junction", action="append", metavar="ID",
                   help="only curves whose junction is ID (repeatable)")
    p.add_argument("--bbox", metavar="XMIN,YMIN,XMAX,YMAX",
                   help="only curves whose feature meets this box (network coordinates, m; "
                        "write --bbox=XMIN,... when XMIN is negative)")


def selection_of(args: argparse.Namespace) -> Selection:
    """The :class:`~clearance.networks.selection.Selection` of :func:`add_selection_options`'
    options
    (bad values raise :class:`~clearance.vehicles.errors.InputError`)."""
    return Selection(kinds=tuple(dict.fromkeys(args.kind or ())),
                     junctions=tuple(dict.fromkeys(args.junction or ())),
                     bbox=parse_bbox(args.bbox) if args.bbox is not None else None)


def add_waivers_option(p: argparse.ArgumentParser) -> None:
    """``--waivers FILE``: accepted verdicts (see :mod:`clearance.reports.results.waivers`)."""
    p.add_argument("--waivers", metavar="WAIVERS.csv",
                   help="CSV of accepted verdicts: curve_id (or glob), vehicle (or *), "
                        "verdict, reason; waived runs are shown as such and pass check")


def add_net_option(p: argparse.ArgumentParser, repeatable: bool = False,
                   required: bool = False, help: str = ".net.xml or .net.xml.gz",
                   **kwargs) -> None:
    """``-n/--net/--net-file NET`` (SUMO's name beside ours); repeatable for a study."""
    p.add_argument("-n", "--net", "--net-file", dest="net", metavar="NET", required=required,
                   action="append" if repeatable else "store", help=help, **kwargs)


def add_output_option(p: argparse.ArgumentParser, folder: bool, metavar: str, help: str,
                      **kwargs) -> None:
    """``-o/--output/--output-file`` (SUMO's name beside ours), and ``--output-dir`` when
    the output is a folder."""
    names = ["-o", "--output", "--output-file"] + (["--output-dir"] if folder else [])
    p.add_argument(*names, dest="output", metavar=metavar, help=help, **kwargs)


def add_route_options(p: argparse.ArgumentParser, baseline: bool = True) -> None:
    """A route study (:mod:`clearance.reports.study.routes`): ``--routes FILE``,
    ``--additional FILE``, the selection (``--route-vclass``, ``--line``, ``--route-id``)
    and the baseline (``--baseline NAME``, ``--baseline-tolerance M``)."""
    g = p.add_argument_group("routes", "study only the passages along SUMO routes")
    g.add_argument("--routes", "--route-files", dest="routes", action="append",
                   metavar="FILE", help="SUMO route file .rou.xml[.gz] (repeatable): route, "
                                        "vehicle, flow, trip (routed by duarouter)")
    g.add_argument("--additional", "--additional-files", dest="additional", action="append",
                   metavar="FILE", help="SUMO additional file with vehicle types or routes "
                                        "(repeatable)")
    g.add_argument("--route-vclass", action="append", metavar="CLASS",
                   help="only routes of vehicles whose type has this SUMO class (repeatable)")
    g.add_argument("--line", action="append", metavar="NAME",
                   help="only routes of this line (the line attribute; repeatable)")
    g.add_argument("--route-id", action="append", metavar="ID",
                   help="only this route, or the route of this vehicle or flow (repeatable)")
    if not baseline:
        return
    g.add_argument("--baseline", metavar="NAME", default=None,
                   help="compare every other vehicle with this one on each passage "
                        "(vs_baseline in routes.csv: worse, same, better)")
    g.add_argument("--baseline-tolerance", type=float, default=0.10, metavar="M",
                   help="room a vehicle may lack against the baseline before it is worse "
                        "(m, default 0.10)")


def route_selection_of(args: argparse.Namespace) -> RouteSelection:
    """The :class:`~clearance.networks.routes.RouteSelection` of :func:`add_route_options`."""
    return RouteSelection(vclasses=tuple(args.route_vclass or ()),
                          lines=tuple(args.line or ()), route_ids=tuple(args.route_id or ()))


def route_study(args: argparse.Namespace, nets: Sequence[str | Path], table: VehicleTable,
                options: dict[str, Any]) -> RouteStudy | None:
    """The route study ``--routes`` asks for (one network), or None without it."""
    if not args.routes:
        if args.baseline or args.additional or args.line or args.route_id or args.route_vclass:
            raise OptionError("--baseline, --additional, --line, --route-id and "
                              "--route-vclass go with --routes FILE")
        return None
    if len(nets) != 1:
        raise OptionError(f"--routes needs exactly one network (-n NET), not {len(nets)}")
    return run_route_study(nets[0], args.routes, table, args.additional or (),
                           route_selection_of(args), args.baseline,
                           args.baseline_tolerance, **options)


def add_sheet_options(p: argparse.ArgumentParser) -> None:
    """The sheets of a report (:mod:`clearance.reports.documents.sheets`): which runs get
    one, at most how many, the ghost, and the title block's fields (a project file and
    options, :mod:`clearance.reports.documents.sheet_settings`)."""
    g = p.add_argument_group("sheets", "A3 swept-path sheets (sheets/NET.pdf) and their "
                                       "title block")
    g.add_argument("--sheets", choices=SHEET_CHOICES, default="not-clear",
                   help="which runs get a sheet: every run that is not clear (default), "
                        "every run, or none")
    g.add_argument("--max-sheets", type=int, default=MAX_SHEETS, metavar="N",
                   help=f"sheets per network at most, worst first (default {MAX_SHEETS}; "
                        f"0: no limit)")
    g.add_argument("--ghost", metavar="NAME", default=None,
                   help="draw this vehicle faintly on the other vehicles' sheets, for "
                        "comparison (default: the route study's --baseline)")
    g.add_argument("--project", metavar="FILE", default=None,
                   help=f"project file (TOML, a [project] table: name, drawing_number, "
                        f"drawn, checked, revision, date) for the sheets' title block; "
                        f"default: {PROJECT_FILE} in the current folder, when there is one")
    for flag, key, what in (("--project-name", "name", "the project"),
                            ("--drawing-number", "drawing_number",
                             "the drawing number's prefix (sheets PREFIX-001, ...)"),
                            ("--drawn-by", "drawn", "who drew the sheets"),
                            ("--checked-by", "checked", "who checked them"),
                            ("--revision", "revision", "the revision (P01, A, ...)"),
                            ("--drawing-date", "date", "the date of the revision")):
        g.add_argument(flag, dest=f"project_{key}", metavar="TEXT", default=None,
                       help=f"title block: {what} (over the project file's)")


def sheet_settings_of(args: argparse.Namespace, names: Sequence[str]) -> SheetSettings:
    """The :class:`~clearance.reports.documents.sheet_settings.SheetSettings` of
    :func:`add_sheet_options`' options; ``names`` the vehicles of the study (a ghost must
    be one of them). A bad value raises :class:`~clearance.vehicles.errors.InputError`."""
    if args.max_sheets < 0:
        raise OptionError(f"--max-sheets must be 0 (no limit) or more, got {args.max_sheets}")
    if args.ghost is not None and args.ghost not in names:
        raise OptionError(f"--ghost {args.ghost!r}: no such vehicle in the study "
                          f"(vehicles: {', '.join(names)})")
    path = Path(args.project) if args.project else Path(PROJECT_FILE)
    project = read_project(path) if args.project or path.is_file() else Project()
    fields = ("name", "drawing_number", "drawn", "checked", "revision", "date")
    project = project.merged(**{k: getattr(args, f"project_{k}") for k in fields})
    return SheetSettings(args.sheets, args.max_sheets or None, args.ghost or "", project)
