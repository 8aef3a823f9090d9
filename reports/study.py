"""Running a study: every vehicle through every curve of every network.

:func:`run_study` reads each network, extracts its curves with lead-ins and run-outs of
a fixed :data:`APPROACH_M`, whatever the table (a vehicle's verdicts never depend on which
other vehicles are in it; the verdict is judged in the feature only), keeps for each
vehicle the curves whose lanes admit its SUMO class (:func:`permitted_groups`; the others
are counted as not permitted), and measures every vehicle on those curves by one of two
methods:

``simulate``
    Each vehicle is driven along each curve with its kinematic model within its steering
    lock and rate, placed every step in a libsumo simulation (:mod:`networks.driver`); the
    swept envelope of the run is measured against the curve's areas.
``analytic``
    Each vehicle in the steady turn of the local radius at every station
    (:mod:`reports.analytic`): fast and on the safe side for short turns.

The result is a :class:`Study`: one :class:`RunRecord` per network × vehicle × curve, in a
stable order (network, curve, vehicle table order), and the networks with their curves.
"""

from __future__ import annotations

import logging
import os
import sys
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
from shapely.geometry.base import BaseGeometry

from networks.curves import Curve, CurveOptions, extract_curves, permits
from networks.reader import Network, read_network
from reports.analytic import run_analytic
from vehicles.errors import InputError
from vehicles.table import VehicleTable
from vehicles.vehicle import Vehicle

log = logging.getLogger(__name__)

METHODS = ("simulate", "analytic")

#: Columns of ``clearance.csv`` in order.
COLUMNS = ["network", "vehicle", "curve_id", "kind", "junction", "verdict", "margin_m",
           "paved_margin_m", "curve_radius_m", "vehicle_min_radius_m", "swept_width_m",
           "available_width_m", "max_offtracking_m", "max_tracking_error_m", "turn_angle_deg",
           "max_grade_pct", "method", "clearance_m", "reason"]

#: Verdicts worst first; ``error`` is a run SUMO failed (its reason says why).
VERDICT_ORDER = {"error": -1, "cannot-turn": 0, "fails": 1, "encroaches": 2, "clear": 3}


@dataclass
class RunRecord:
    """One vehicle on one curve of one network."""

    network: str
    vehicle: str
    curve_id: str
    kind: str
    junction: str
    verdict: str
    margin_m: float
    paved_margin_m: float
    curve_radius_m: float
    vehicle_min_radius_m: float
    swept_width_m: float
    available_width_m: float
    max_offtracking_m: float
    max_tracking_error_m: float
    turn_angle_deg: float
    max_grade_pct: float
    method: str
    clearance_m: float
    reason: str
    envelope: BaseGeometry | None = field(repr=False)

    def row(self) -> dict[str, object]:
        return {c: getattr(self, c) for c in COLUMNS}


@dataclass
class NetworkCurves:
    """A network of the study with its curves."""

    name: str
    path: Path
    network: Network
    curves: list[Curve]


@dataclass
class Study:
    """The result of :func:`run_study`."""

    records: list[RunRecord]
    networks: list[NetworkCurves]
    table: VehicleTable
    method: str
    clearance_m: float
    #: (network, vehicle, curve id) of every curve whose lanes do not admit the
    #: vehicle's SUMO class: not run, not a verdict
    not_permitted: list[tuple[str, str, str]] = field(default_factory=list)

    def frame(self) -> pd.DataFrame:
        """One row per network × vehicle × curve (the columns of ``clearance.csv``)."""
        return pd.DataFrame([r.row() for r in self.records], columns=COLUMNS)


def network_name(path: Path, taken: Iterable[str] = ()) -> str:
    """A short unique name of a network file: its stem without ``.net``.

    Examples
    --------
    >>> network_name(Path("a/roundabout.net.xml.gz"))
    'roundabout'
    >>> network_name(Path("b/roundabout.net.xml"), ["roundabout"])
    'roundabout-2'
    """
    name = path.name
    for suffix in (".gz", ".xml", ".net"):
        name = name.removesuffix(suffix)
    base, n = name, 2
    taken = set(taken)
    while name in taken:
        name, n = f"{base}-{n}", n + 1
    return name


#: Lead-in and run-out of every curve of a study (m): the same whatever the vehicle table.
APPROACH_M = 30.0


def load_networks(paths: Sequence[str | Path]) -> list[NetworkCurves]:
    """Read each network and extract its curves, with :data:`APPROACH_M` lead-ins."""
    out: list[NetworkCurves] = []
    opts = CurveOptions(approach_length_m=APPROACH_M)
    for p in paths:
        path = Path(p)
        net = read_network(path)
        curves = extract_curves(net, options=opts, build_ahead=True)
        name = network_name(path, [n.name for n in out])
        if not curves:
            log.warning("%s: no curves found", path)
        out.append(NetworkCurves(name, path, net, curves))
    return out


def progress_bar(total: int, desc: str) -> Callable[[int], None]:
    """A tqdm bar on an interactive terminal; silent in CI and when output is piped."""
    if os.environ.get("CI") or not sys.stderr.isatty() or total == 0:
        return lambda n: None
    from tqdm import tqdm

    bar = tqdm(total=total, desc=desc, unit="run", leave=False, dynamic_ncols=True)

    def update(n: int) -> None:
        bar.update(n)
        if bar.n >= total:
            bar.close()

    return update


def _analytic_records(nc: NetworkCurves, vehicles: list[Vehicle], clearance_m: float,
                      update: Callable[[int], None]) -> list[RunRecord]:
    records = []
    for curve in nc.curves:
        for v in vehicles:
            r = run_analytic(v, curve, clearance_m)
            c = r.clearance
            records.append(RunRecord(
                nc.name, v.name, curve.curve_id, curve.kind, curve.junction, c.verdict,
                c.margin_m, c.paved_margin_m, curve.min_radius_m, r.vehicle_min_radius_m,
                r.swept_width_m, curve.lane_width_m, r.max_offtracking_m, 0.0,
                curve.turn_angle_deg, curve.max_grade_pct, "analytic", clearance_m,
                c.reason, r.envelope))
        update(len(vehicles))
    return records


def run_study(
    network_paths: Sequence[str | Path],
    table: VehicleTable,
    method: str = "simulate",
    clearance_m: float = 0.0,
    fcd_dir: Path | None = None,
) -> Study:
    """Every vehicle of ``table`` through every curve of every network.

    Raises
    ------
    InputError
        An unknown method, a negative clearance, or bad networks (named).
    """
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}: use {' or '.join(METHODS)}")
    if not clearance_m >= 0:
        raise InputError(f"--clearance must be a distance >= 0 m, not {clearance_m}")
    vehicles = table.vehicles()
    nets = load_networks(network_paths)
    total = sum(len(n.curves) for n in nets) * len(vehicles)
    update = progress_bar(total, f"{method} {len(vehicles)} vehicles")
    records: list[RunRecord] = []
    refused: list[tuple[str, str, str]] = []
    for whole in nets:
        for nc, group, barred in permitted_groups(whole, vehicles):
            refused += barred
            update(len(barred))
            if not nc.curves:
                continue
            if method == "analytic":
                records += _analytic_records(nc, group, clearance_m, update)
            else:
                from reports.simulated import simulated_records

                records += simulated_records(nc, group, clearance_m, update, fcd_dir)
    order = {v.name: i for i, v in enumerate(vehicles)}
    net_order = {n.name: i for i, n in enumerate(nets)}
    curve_order = {(n.name, c.curve_id): i for n in nets for i, c in enumerate(n.curves)}
    records.sort(key=lambda r: (net_order[r.network], curve_order[(r.network, r.curve_id)],
                                order[r.vehicle]))
    return Study(records, nets, table, method, clearance_m, sorted(refused))


def permitted_groups(
    nc: NetworkCurves, vehicles: list[Vehicle]
) -> list[tuple[NetworkCurves, list[Vehicle], list[tuple[str, str, str]]]]:
    """The vehicles by SUMO class, each group with the curves its lanes admit it on
    (:func:`networks.curves.permits`) and the (network, vehicle, curve) it may not use.

    A vehicle is checked only on the curves it may drive; the others are not permitted,
    never a failure, and not run at all."""
    by_class: dict[str, list[Vehicle]] = {}
    for v in vehicles:
        by_class.setdefault(v.vclass, []).append(v)
    out = []
    for vclass, group in by_class.items():
        ok = [c for c in nc.curves if permits(nc.network, c, vclass)]
        kept = {id(c) for c in ok}
        barred = [(nc.name, v.name, c.curve_id) for c in nc.curves if id(c) not in kept
                  for v in group]
        out.append((NetworkCurves(nc.name, nc.path, nc.network, ok), group, barred))
    return out
