"""A route study: the table's vehicles through the passages of a network's routes.

:func:`run_route_study` reads the route files (:mod:`clearance.networks.routes`), checks
them against the network, keeps the selected routes, finds each route's passages
(:mod:`clearance.networks.passages`) and runs the study on their curves only, once each
whatever the number of routes through them: the same search, judge and margins as a
whole-network study of those junctions. The result is the study and, per route x passage
x vehicle, the rows of ``routes.csv`` (:mod:`clearance.reports.results.routes`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from clearance.networks.curves import KINDS, CurveOptions, extract_curves
from clearance.networks.loading import load_network
from clearance.networks.model import Network
from clearance.networks.passages import Passage, passages_of, route_passages
from clearance.networks.routes import (
    Route,
    RouteSelection,
    check_routes,
    read_routes,
    select_routes,
)
from clearance.networks.selection import Selection
from clearance.reports.results.routes import DEFAULT_TOLERANCE_M, PassageRow, route_rows
from clearance.reports.study.run import APPROACH_M, Study, run_study
from clearance.vehicles.errors import OptionError
from clearance.vehicles.table import VehicleTable

__all__ = ["RouteStudy", "route_curve_ids", "route_passages_of", "run_route_study",
           "selected_routes"]


@dataclass
class RouteStudy:
    """A route study's result: the routes, their passages, the study of their curves and
    the rows of ``routes.csv``."""

    routes: list[Route]
    passages: dict[str, list[tuple[int, Passage]]]
    study: Study
    rows: list[PassageRow]
    baseline: str | None
    tolerance_m: float
    #: Consecutive edge pairs of the routes no curve covers (no internal lane, a kind
    #: not studied), by route.
    uncovered: dict[str, int]


def route_passages_of(net: Network, routes: Sequence[Route]
                      ) -> tuple[dict[str, list[tuple[int, Passage]]], dict[str, int]]:
    """Each route's passages on the network (every curve kind, U-turns included: a route
    may make one), and how many of each route's edge-to-edge steps no curve covers."""
    curves = extract_curves(net, KINDS, CurveOptions(approach_length_m=APPROACH_M),
                            areas=False)
    by_edges = passages_of(net, curves)
    out, uncovered = {}, {}
    for r in routes:
        found = route_passages(r.edges, by_edges)
        out[r.route_id] = found
        covered = {i + k for i, p in found for k in range(len(p.edges) - 1)}
        uncovered[r.route_id] = sum(1 for i in range(len(r.edges) - 1) if i not in covered)
    return out, uncovered


def selected_routes(net: Network, route_files: Sequence[str | Path],
                    additional: Sequence[str | Path] = (),
                    route_selection: RouteSelection | None = None) -> list[Route]:
    """The routes of the files, checked against ``net`` as SUMO checks them, selected."""
    routes = read_routes(route_files, additional, net.path)
    check_routes(routes, net)
    return select_routes(routes, route_selection or RouteSelection())


def route_curve_ids(net: Network, routes: Sequence[Route]) -> frozenset[str]:
    """The ids of the curves of the routes' passages (``clearance simulate --routes``)."""
    passages, _ = route_passages_of(net, routes)
    return frozenset(c for found in passages.values() for _, p in found for c in p.curve_ids)


def run_route_study(net_path: str | os.PathLike[str], route_files: Sequence[str | Path],
                    table: VehicleTable, additional: Sequence[str | Path] = (),
                    route_selection: RouteSelection | None = None,
                    baseline: str | None = None,
                    tolerance_m: float = DEFAULT_TOLERANCE_M,
                    study: Callable[..., Study] = run_study, **study_options: Any
                    ) -> RouteStudy:
    """The table's vehicles through the passages of the selected routes of ``route_files``
    on the network ``net_path`` (``study_options`` go to
    :func:`~clearance.reports.study.run.run_study`).

    Raises
    ------
    RouteError
        A route file that is malformed, names what the network does not have, or whose
        selection matches no route.
    OptionError
        A baseline that is not one of the table's vehicles, or a negative tolerance.
    """
    if baseline is not None and baseline not in table.names:
        raise OptionError(f"--baseline {baseline!r} is not one of the study's vehicles "
                          f"({', '.join(table.names)})")
    if not tolerance_m >= 0:
        raise OptionError(f"--baseline-tolerance must be a length >= 0 m, not {tolerance_m}")
    net = load_network(net_path)
    routes = selected_routes(net, route_files, additional, route_selection)
    passages, uncovered = route_passages_of(net, routes)
    ids = frozenset(c for found in passages.values() for _, p in found for c in p.curve_ids)
    base = study_options.pop("selection", None) or Selection()
    result = study([net_path], table, selection=replace(base, kinds=KINDS, curve_ids=ids),
                   **study_options)
    rows = route_rows(routes, passages, result.records, table.names, baseline, tolerance_m,
                      {n: table.vehicle(n).vclass for n in table.names})
    return RouteStudy(routes, passages, result, rows, baseline, tolerance_m, uncovered)
