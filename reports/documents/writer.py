"""Writing a report's folder: the tables, the documents and every drawing and export.

:func:`write_report` writes ``clearance.csv`` and ``summary.json``, the curve figures, each
network's sheets and exports, and ``report.md`` and ``report.html``. With the study's
executor still open, the figures, sheets and exports are drawn in its workers
(:class:`~clearance.reports.documents.drawings.Drawings`), which send the files back as
bytes, while this process draws the network plans and writes the tables; the files are the
same whichever process draws them (``tests/reports/test_report.py``). What a report writes
into its folder is :data:`LAYOUT` (a folder holding anything else is never replaced).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from clearance.reports.documents.drawings import Drawings, network_tasks
from clearance.reports.documents.markdown import markdown
from clearance.reports.documents.plotting import PNG, PNG_SVG
from clearance.reports.documents.report import Section, anchor, build_sections, html_document
from clearance.reports.documents.route_maps import route_maps, routes_html
from clearance.reports.documents.sheet_settings import DEFAULT_SHEETS, SheetSettings
from clearance.reports.exports.patches import write_patches
from clearance.reports.exports.study import export_names, georeferenced, write_exports
from clearance.reports.output.atomic import write_text_atomic
from clearance.reports.output.output_dir import Layout
from clearance.reports.results.routes import route_summary, routes_csv
from clearance.reports.results.tables import clearance_csv, summary_json
from clearance.reports.results.waivers import Waived
from clearance.reports.study.executor import (
    Executor,
)
from clearance.reports.study.routes import RouteStudy
from clearance.reports.study.run import (
    COLUMNS,
    Study,
)

__all__ = ["LAYOUT", "write_report"]


#: What a report writes into its folder (the folder it may replace holds nothing else).
LAYOUT = Layout(
    "report",
    # swept.*: the single export files of earlier versions, replaced by exports/
    files=frozenset({"clearance.csv", "summary.json", "routes.csv", "report.md", "report.html",
                     "swept.geojson", "swept.add.xml", "swept.dxf"}),
    folders={"figures": (".png", ".svg", ".jpg"), "fcd": (".xml",),
             "exports": (".add.xml", ".dxf", ".geojson"), "sheets": (".pdf",),
             "patches": (".xml",)},
    signature=("clearance.csv", ",".join(COLUMNS[:4])),
)


def write_report(study: Study, folder: Path, tables: list[Path], units: str = "m",
                 waived: Waived | None = None, origin: tuple[float, float] | None = None,
                 executor: Executor | None = None,
                 routes: RouteStudy | None = None,
                 sheets: SheetSettings = DEFAULT_SHEETS, svg: bool = False) -> None:
    """Write every output of ``study`` into ``folder`` (which must be new or empty);
    ``waived`` runs are shown as such (:mod:`clearance.reports.results.waivers`); ``origin`` (lat,
    lon) places the networks without a projection in the GeoJSON exports; ``sheets`` says
    which runs get a sheet (a route study's baseline is their ghost unless another is
    named). With ``executor`` the curve figures, sheets and exports are drawn in its workers
    (:class:`Drawings`). Figures are PNG; ``svg``: an SVG beside each."""
    from clearance.reports.documents.sheets import write_sheets

    if routes is not None and routes.baseline and not sheets.ghost:
        sheets = replace(sheets, ghost=routes.baseline)

    write_text_atomic(folder / "clearance.csv", clearance_csv(study, waived, units))
    write_text_atomic(folder / "summary.json", summary_json(
        study, tables, waived, route_summary(routes.rows) if routes is not None else None))
    if routes is not None:
        write_text_atomic(folder / "routes.csv", routes_csv(routes.rows))
    for nc in study.networks:
        write_patches(folder / "patches", nc.name, nc.network, nc.curves,
                      [r for r in study.records if r.network == nc.name], study.table)
    formats = PNG_SVG if svg else PNG
    if executor is None:
        exports = write_exports(study, folder, origin)
        sections = build_sections(study, folder, units, waived, formats=formats)
        write_sheets(study, folder / "sheets", tables, units, sheets)
    else:
        drawings = Drawings(executor, folder)
        into = folder if executor.shares_disk else None
        for drawing, path in network_tasks(study, tables, units, origin, sheets, into):
            drawings.submit(drawing, path)
        exports = {nc.name: export_names(nc.name, georeferenced(nc, origin))
                   for nc in study.networks}
        sections = build_sections(study, folder, units, waived,
                                  draw=drawings.curve_figure(study, units, formats),
                                  formats=formats)
        drawings.finish()
        drawings.write_sheets(study, tables, sheets)
        drawings.mark_lost(sections, exports)
    first = (_routes_section(routes, sections, folder, units, formats) if routes is not None
             else [])
    write_text_atomic(folder / "report.md", markdown(study, sections, folder, units))
    write_text_atomic(folder / "report.html", html_document(study, sections, units, exports,
                                                            first))


def _routes_section(routes: RouteStudy, sections: list[Section], folder: Path,
                    units: str, formats: tuple[str, ...]) -> list[str]:
    """The routes' maps, drawn here, and their section of report.html (each passage linked
    to its curve's section where the report has one)."""
    links = {c.curve_id: anchor(s.name, c.curve_id) for s in sections for c in s.curves}
    return routes_html(routes, route_maps(routes, folder, units, formats), links)
