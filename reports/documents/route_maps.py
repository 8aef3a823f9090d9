"""A route study in the report: a map of each line with its passages coloured by verdict
and against the baseline, and the section a transit planner reads first.

The map shows the route over the network's plan (its edges as a wide pale band) and each
passage's feature in the colour of the studied vehicle's verdict (left panel) and of its
comparison with the baseline (right panel: worse magenta, same grey, better blue); the
passages that are not clear or worse are numbered by their order along the route, as in
the section's table.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D

from clearance.networks.plot import plot_plan
from clearance.reports.documents.figures import COLOURS, core_points
from clearance.reports.documents.html_images import img_tag
from clearance.reports.documents.plotting import (
    PNG,
    add_north_arrow,
    add_scale_bar,
    new_figure,
    plan_axes,
    save,
)
from clearance.reports.output.file_names import file_name
from clearance.reports.results.routes import NOT_PERMITTED, PassageRow
from clearance.reports.study.routes import RouteStudy
from clearance.reports.study.run import NetworkCurves

__all__ = ["BAND", "VS_COLOURS", "noted", "plot_route", "route_headline", "route_maps",
           "routes_html"]

#: Colours of the comparison with the baseline.
VS_COLOURS = {"worse": "#d81b60", "same": "#7f8c8d", "better": "#1f77b4", "": "#bbbbbb"}

#: The route's band under its passages.
BAND = "#5dade2"


def noted(rows: Sequence[PassageRow]) -> list[PassageRow]:
    """The rows a planner must look at: not clear, or worse than the baseline."""
    return [r for r in rows if r.vs_baseline == "worse"
            or (r.record is not None and r.record.verdict != "clear")
            or r.record is None]


def rests_cell(row: PassageRow) -> str:
    """What a passage's verdict rests on, as HTML: the network's data or netconvert's
    defaults, and in italics the evidence of the network's own traffic driving it.

    >>> from types import SimpleNamespace as S
    >>> rests_cell(S(record=S(geometry="lane width default 3.2 m"), own_traffic="own buses"))
    'lane width default 3.2 m<br><i>own buses</i>'
    """
    rec = row.record
    text = html.escape(rec.geometry if rec is not None else "")
    if row.own_traffic:
        text += f"<br><i>{html.escape(row.own_traffic)}</i>"
    return text


def route_headline(routes: RouteStudy, route_id: str, vehicle: str) -> str:
    """One sentence per route and vehicle, e.g. ``A-BUS on bus_162: 0 of 16 passages worse
    than CITY-BUS; 2 where both are not clear``."""
    rows = [r for r in routes.rows if r.route.route_id == route_id and r.vehicle == vehicle]
    n = len(rows)
    bad = sum(r.record is None or r.record.verdict != "clear" for r in rows)
    if routes.baseline is None or vehicle == routes.baseline:
        return f"{vehicle} on {route_id}: {bad} of {n} passages not clear"
    worse = sum(r.vs_baseline == "worse" for r in rows)
    both = sum(r.record is not None and r.record.verdict != "clear" and r.baseline is not None
               and r.baseline.verdict != "clear" and r.vs_baseline != "worse" for r in rows)
    return (f"{vehicle} on {route_id}: {worse} of {n} passages worse than {routes.baseline}; "
            f"{both} where both are not clear and it is no worse")


def plot_route(nc: NetworkCurves, routes: RouteStudy, route_id: str, vehicle: str,
               stem: Path, units: str = "m", formats: tuple[str, ...] = PNG) -> list[Path]:
    """The map of one route for one vehicle (see the module docstring); its files (those
    of ``formats``, PNG first)."""
    route = next(r for r in routes.routes if r.route_id == route_id)
    rows = [r for r in routes.rows if r.route.route_id == route_id and r.vehicle == vehicle]
    net = nc.network
    band = [net.lanes[net.edges[e].lanes[0]].shape[:, :2] for e in route.edges
            if net.edges.get(e) is not None and net.edges[e].lanes]
    pts = np.vstack(band) if band else np.zeros((1, 2))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    half = max(float(np.ptp(pts[:, 0])), float(np.ptp(pts[:, 1]))) / 2 + 30.0
    cx, cy = (lo + hi) / 2
    bounds = (cx - half, cx + half, cy - half, cy + half)
    panels = [("verdict", f"{vehicle}: verdict")]
    if routes.baseline is not None and vehicle != routes.baseline:
        panels.append(("vs", f"{vehicle} against {routes.baseline}"))
    fig, _ = new_figure(6.2 * len(panels), 6.6)
    fig.clf()
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    curves = {c.curve_id: c for c in nc.curves}
    for ax, (what, title) in zip(axes, panels, strict=True):
        plot_plan(net, ax, f"{route_id}: {title}", bounds, decorate=False)
        for xy in band:
            ax.plot(xy[:, 0], xy[:, 1], color=BAND, lw=6, alpha=0.35, zorder=5,
                    solid_capstyle="round")
        for r in rows:
            c = curves.get(r.record.curve_id) if r.record is not None else None
            if c is None:
                continue
            colour = (COLOURS[r.record.verdict] if what == "verdict"  # type: ignore[union-attr]
                      else VS_COLOURS[r.vs_baseline])
            core = core_points(c)
            ax.plot(core[:, 0], core[:, 1], color=colour, lw=3.0, zorder=7)
            if r in noted([r]):
                x, y = core[len(core) // 2]
                ax.annotate(str(r.order), (x, y), fontsize=6.5, fontweight="bold",
                            ha="center", va="center", zorder=8,
                            bbox=dict(boxstyle="circle,pad=0.2", fc="white", ec=colour,
                                      lw=1.0))
        plan_axes(ax, units)
        add_scale_bar(ax, units)
        add_north_arrow(ax)
    handles = [Line2D([], [], color=COLOURS[v], lw=3, label=v) for v in
               ("cannot-turn", "fails", "encroaches", "clear")]
    if len(panels) > 1:
        handles += [Line2D([], [], color=VS_COLOURS[v], lw=3, label=f"{v} than the baseline"
                           if v != "same" else "same as the baseline")
                    for v in ("worse", "same", "better")]
    fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 7), fontsize=7.5,
               frameon=False, bbox_to_anchor=(0.5, -0.01),
               title="the route (blue band); each passage coloured; numbers: order along "
                     "the route of the passages to look at", title_fontsize=7.5)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return save(fig, stem, formats)


def route_maps(routes: RouteStudy, folder: Path, units: str = "m",
               formats: tuple[str, ...] = PNG) -> dict[tuple[str, str], Path]:
    """Every route's map for every vehicle but the baseline (all vehicles without one),
    under ``folder/figures/routes/`` (the files of ``formats``); the PNG of each (route,
    vehicle)."""
    nc = routes.study.networks[0]
    vehicles = [v for v in routes.study.table.names if v != routes.baseline] or \
        list(routes.study.table.names)
    out = {}
    for route in routes.routes:
        for v in vehicles:
            stem = folder / "figures" / "routes" / file_name([route.route_id, v], "")
            out[(route.route_id, v)] = plot_route(nc, routes, route.route_id, v, stem,
                                                  units, formats)[0]
    return out


def _m(x: float) -> str:
    return "" if math.isnan(x) else f"{x:+.2f}"


def routes_html(routes: RouteStudy, maps: dict[tuple[str, str], Path],
                curve_link: dict[str, str]) -> list[str]:
    """The report's first section: per route and vehicle, the headline, the map and the
    passages not clear or worse than the baseline (each linked to its curve's section)."""
    e = html.escape
    out = ['<h2 id="routes">Routes</h2>',
           f"<p>{len(routes.routes)} route(s); each passage studied once "
           + (f"and compared with {e(routes.baseline)} (worse: a worse verdict or "
              f"{routes.tolerance_m:.2f} m less room)." if routes.baseline else ".")
           + "</p>"]
    for route in routes.routes:
        out.append(f"<h3>{e(route.route_id)}" + (f" (line {e(route.line)})" if route.line
                                                  and route.line != route.route_id else "")
                   + "</h3>")
        for (rid, v), png in maps.items():
            if rid != route.route_id:
                continue
            out.append(f"<p><b>{e(route_headline(routes, rid, v))}</b></p>")
            kept = (*COLOURS.values(), *VS_COLOURS.values(), BAND)
            out.append(f"<figure>{img_tag(png, f'map of {rid} for {v}', kept=kept)}</figure>")
            rows = noted([r for r in routes.rows
                          if r.route.route_id == rid and r.vehicle == v])
            if not rows:
                continue
            out.append("<table><tr><th>#</th><th>junction</th><th>from → to</th>"
                       "<th>verdict</th><th>margin [m]</th>"
                       + ("<th>baseline</th><th>vs baseline</th><th>more room [m]</th>"
                          if routes.baseline else "")
                       + "<th>worst conflict</th><th>rests on</th></tr>")
            for r in rows:
                verdict = r.record.verdict if r.record is not None else NOT_PERMITTED
                link = curve_link.get(r.record.curve_id, "") if r.record is not None else ""
                cell = f'<a href="#{link}">{e(verdict)}</a>' if link else e(verdict)
                out.append(
                    f"<tr><td>{r.order}</td><td>{e(r.passage.junction)}</td>"
                    f"<td>{e(r.passage.from_edge)} → {e(r.passage.to_edge)}</td>"
                    f"<td>{cell}</td><td>{_m(r.record.margin_m if r.record else math.nan)}"
                    "</td>"
                    + (f"<td>{e(r.baseline.verdict if r.baseline else '')}</td>"
                       f"<td>{e(r.vs_baseline)}</td><td>{_m(r.more_room_m)}</td>"
                       if routes.baseline else "")
                    + f'<td style="text-align:left">'
                      f'{e(r.record.conflict_at if r.record else "")}</td>'
                    + f'<td style="text-align:left">{rests_cell(r)}</td></tr>')
            out.append("</table>")
    return out
