"""``clearance compare``: side-by-side turning geometry of vehicle models, with figures."""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from clearance.reports.cli.options import (
    add_output_option,
    add_table_option,
    add_units_option,
    add_vehicle_option,
)
from clearance.reports.documents import compare, templates
from clearance.reports.output.atomic import write_text_atomic
from clearance.reports.results.text_table import counted
from clearance.vehicles.table import load_tables

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "compare",
        help="compare vehicle models: turning circles, rho(theta), swept width, templates",
        description="A side-by-side table of the models' turning circles and swept widths, "
                    "and figures: turning circles, rho against the Ackermann angle (the "
                    "paper's Figure 5), swept width against it (Figure 6), 90° and 180° "
                    "turning templates of each model at one scale, and templates.pdf: one "
                    "A3 sheet per model with its 90° and 180° templates dimensioned (CTR, "
                    "inside radius, swept width; trailer inside radius and articulation).",
    )
    add_table_option(p)
    add_vehicle_option(p)
    add_units_option(p)
    add_output_option(p, folder=True, metavar="DIR", default="compare",
                      help="output folder (default: ./compare)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    table = load_tables(args.table, args.vehicle)
    out = Path(args.output)
    frame = compare.comparison_table(table, args.units)
    written = [write_text_atomic(out / "compare.csv",
                                 frame.to_csv(index=False, float_format="%.6g",
                                              lineterminator="\n"))]
    written += compare.plot_turning_circles(table, out / "turning_circles", args.units)
    written += compare.plot_rho_theta(table, out / "rho_theta", args.units)
    written += compare.plot_swept_width_theta(table, out / "swept_width_theta", args.units)
    built = {a: templates.build_templates(table, a) for a in (90.0, 180.0)}
    written += templates.plot_templates(table, out, args.units, built=built)
    written.append(templates.write_template_sheets(table, out / "templates.pdf", args.units,
                                                   built))
    shown = frame.drop(columns=["category", "units"]).round(2)
    with pd.option_context("display.width", 250, "display.max_columns", 40,
                           "display.max_rows", 500):
        print(f"{counted(len(frame), 'model')}, sorted by wall-to-wall diameter "
              f"(lengths in {args.units})")
        print(shown.to_string(index=False))
    print(f"wrote {len(written)} files under {out}/")
    return 0
