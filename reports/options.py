"""Command-line options shared by the sub-commands."""

from __future__ import annotations

import argparse


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


def add_executor_options(p: argparse.ArgumentParser) -> None:
    """``--workers N`` and ``--scheduler ADDRESS``: where a study's runs are driven."""
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes on this machine (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="run on a Dask cluster: the scheduler's address (tcp://HOST:8786); "
                        "needs pip install 'sumo-clearance[cluster]'")
