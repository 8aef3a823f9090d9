"""clearance: swept-path checks of SUMO networks for tables of vehicles.

The public API a script needs; each name is imported on first use, so ``import clearance``
(and the command line, which imports its subpackages) stays quick::

    import clearance

    table = clearance.load_tables(clearance.bundled_table_paths())
    network = clearance.load_network("city.net.xml")      # what SUMO loads, repaired as SUMO does
    study = clearance.run_study(["city.net.xml"], table)  # every vehicle x every curve
    frame = study.frame()                                 # the rows of clearance.csv

Subpackages, in the order data flows (each imports only from those before it):
:mod:`clearance.vehicles` (the vehicle table), :mod:`clearance.analysis` (geometry and
kinematics without SUMO), :mod:`clearance.networks` (SUMO networks, curves, areas, driving a
run), :mod:`clearance.reports` (running a study, results, documents, exports, the command line).
Errors: :mod:`clearance.vehicles.errors`.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from clearance.networks.curves import Curve, extract_curves
    from clearance.networks.loading import load_network, load_networks
    from clearance.networks.model import Network
    from clearance.reports.results.records import COLUMNS, VERDICT_ORDER, RunRecord
    from clearance.reports.study.run import Study, run_study
    from clearance.vehicles.errors import (
        ClearanceError,
        GeometryError,
        InputError,
        LimitError,
        NetworkError,
        OptionError,
        RouteError,
        TableError,
    )
    from clearance.vehicles.table import VehicleTable, bundled_table_paths, load_tables
    from clearance.vehicles.vehicle import Vehicle

__all__ = ["COLUMNS", "ClearanceError", "Curve", "GeometryError", "InputError", "LimitError",
           "Network", "NetworkError", "OptionError", "RouteError", "RunRecord", "Study",
           "TableError", "VERDICT_ORDER", "Vehicle", "VehicleTable", "bundled_table_paths",
           "extract_curves", "load_network", "load_networks", "load_tables", "run_study"]

#: Where each public name is defined.
_HOMES = {
    "COLUMNS": "clearance.reports.results.records",
    "VERDICT_ORDER": "clearance.reports.results.records",
    "RunRecord": "clearance.reports.results.records",
    "Study": "clearance.reports.study.run",
    "run_study": "clearance.reports.study.run",
    "Curve": "clearance.networks.curves",
    "extract_curves": "clearance.networks.curves",
    "Network": "clearance.networks.model",
    "load_network": "clearance.networks.loading",
    "load_networks": "clearance.networks.loading",
    "Vehicle": "clearance.vehicles.vehicle",
    "VehicleTable": "clearance.vehicles.table",
    "bundled_table_paths": "clearance.vehicles.table",
    "load_tables": "clearance.vehicles.table",
    **{name: "clearance.vehicles.errors" for name in (
        "ClearanceError", "GeometryError", "InputError", "LimitError", "NetworkError",
        "OptionError", "RouteError", "TableError")},
}


def __getattr__(name: str) -> Any:
    """The public names, imported from their modules on first use (PEP 562)."""
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module 'clearance' has no attribute {name!r}")
    value = getattr(import_module(home), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
