"""The report documents: ``report.html`` (one self-contained file) and ``report.md``.

Per network: the verdict counts, a plan with the worst curves marked, a vehicle × curve
matrix of verdicts and margins, and for each failing or tight curve a figure of the swept
paths over the lanes, the junction and the curbs. The HTML embeds its figures (PNG as data
URIs) and references nothing outside itself; the Markdown links the PNG files written
beside it (SVG versions are there too).
"""

from __future__ import annotations

import base64
import html
import math
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from reports.figures import COLOURS, plot_curve, plot_network, worst_by_curve
from reports.file_names import file_name
from reports.study import VERDICT_ORDER, Study
from reports.units import length_scale
from reports.waivers import Waived

__all__ = ["CSS", "MAX_CURVE_FIGURES", "MAX_ENVELOPES", "SYMBOL", "Section", "TIGHT_M",
           "build_sections", "html_document", "markdown", "pick_envelopes"]

#: A curve is *tight* when its smallest margin is below this (m) though clear.
TIGHT_M = 0.25
#: At most this many curve figures per network (the worst first): every failing or tight
#: curve of the samples; a large network lists the rest in its matrix and clearance.csv.
MAX_CURVE_FIGURES = 60
#: At most this many envelopes in one curve figure (the worst vehicles).
MAX_ENVELOPES = 4

SYMBOL = {"clear": "✓", "encroaches": "~", "fails": "✗", "cannot-turn": "⊘", "error": "!"}


@dataclass
class Section:
    """One network's part of the report."""

    name: str
    counts: dict[str, int]
    plan: Path
    worst: pd.DataFrame
    matrix: pd.DataFrame  # rows curve_id, columns vehicles: "verdict|margin"
    all_clear: int
    curve_figures: list[tuple[str, Path, str]] = field(default_factory=list)
    omitted: int = 0
    #: Waived runs: curve id, vehicle, verdict, margin (m), reason, waiver's file:line.
    waived: list[tuple[str, str, str, float, str, str]] = field(default_factory=list)


def build_sections(study: Study, folder: Path, units: str = "m",
                   waived: Waived | None = None) -> list[Section]:
    """Draw every figure under ``folder/figures`` and collect what the documents show.

    Figures are named by :func:`reports.file_names.file_name`: ``<network>__plan`` and
    ``<network>__curve__<curve id>`` (with a short hash where the id needed changing).

    Margins shown in the matrix and captions are in ``units``. With ``waived``, each
    section counts and lists its waived runs, and their matrix cells are marked.
    """
    scale = length_scale(units)
    figs = folder / "figures"
    frame = study.frame()
    sections = []
    for nc in study.networks:
        f = frame[frame.network == nc.name]
        # stems: plotting.save appends .png and .svg
        plan = plot_network(nc, f, figs / file_name([nc.name, "plan"], room=4))[0]
        worst = worst_by_curve(f)
        counts = {v: int((f.verdict == v).sum()) for v in sorted(VERDICT_ORDER,
                                                                   key=VERDICT_ORDER.__getitem__)
                  if v != "error" or (f.verdict == "error").any()}
        cells = f.assign(cell=f.verdict + "|" + (f.margin_m / scale).round(2).astype(str))
        if waived is not None:
            keys = list(zip(f.network, f.vehicle, f.curve_id, strict=True))
            marks = ["|w" if k in waived.by else "" for k in keys]
            cells = cells.assign(cell=cells.cell + pd.Series(marks, index=f.index, dtype=str))
            counts["waived"] = sum(1 for k in keys if k in waived.by)
        matrix = cells.pivot(index="curve_id", columns="vehicle", values="cell")
        matrix = matrix[list(dict.fromkeys(f.vehicle))]
        bad = set(worst.curve_id[(worst.verdict != "clear") | (worst.margin_m < TIGHT_M)])
        curve_order = [c.curve_id for c in nc.curves if c.curve_id in bad]
        matrix = matrix.loc[[c for c in worst.curve_id if c in bad]]
        section = Section(nc.name, counts, plan, worst, matrix,
                          len(worst) - len(bad))
        if waived is not None:
            section.waived = [
                (r.curve_id, r.vehicle, r.verdict, float(r.margin_m),
                 waived.reasons[k], waived.by[k].where)
                for r in f.itertuples()
                if (k := (r.network, r.vehicle, r.curve_id)) in waived.by]
        picked = [c for c in worst.curve_id if c in bad][:MAX_CURVE_FIGURES]
        section.omitted = len(curve_order) - len(picked)
        by_id = {c.curve_id: c for c in nc.curves}
        for cid in picked:
            recs = [r for r in study.records if r.network == nc.name and r.curve_id == cid]
            recs.sort(key=lambda r: (VERDICT_ORDER[r.verdict], r.margin_m))
            shown = pick_envelopes(recs)
            stem = figs / file_name([nc.name, "curve", cid], room=4)
            png = plot_curve(nc, by_id[cid], shown, stem)[0]
            caption = ", ".join(f"{r.vehicle} {r.verdict} ({r.margin_m / scale:+.2f} {units})"
                                for r in shown)
            section.curve_figures.append((cid, png, caption))
        sections.append(section)
    return sections


def pick_envelopes(records: list, limit: int = MAX_ENVELOPES) -> list:
    """The runs a curve's figure shows: the worst of each verdict, then the next worst.

    ``records`` are sorted worst first. Showing one run of each verdict (the one with the
    smallest margin) tells a reader which vehicles fail and how close the ones that clear
    come; the remaining places go to the next worst runs.

    Examples
    --------
    >>> from types import SimpleNamespace as R
    >>> rs = [R(verdict=v, margin_m=m) for v, m in
    ...       [("cannot-turn", -3), ("cannot-turn", -2), ("fails", -0.2), ("clear", 0.1)]]
    >>> [(r.verdict, r.margin_m) for r in pick_envelopes(rs, 3)]
    [('cannot-turn', -3), ('fails', -0.2), ('clear', 0.1)]
    """
    firsts = [r for i, r in enumerate(records)
              if i == 0 or r.verdict != records[i - 1].verdict]
    rest = [r for r in records if all(r is not f for f in firsts)]
    chosen = (firsts + rest)[:limit]
    return sorted(chosen, key=lambda r: records.index(r))


def _cell_margin(text: str) -> str:
    """A matrix cell's margin: signed, two decimals; "n/a" when the run has none."""
    value = float(text)
    return f"{value:+.2f}" if math.isfinite(value) else "n/a"


def _md_cell(text: str) -> str:
    r"""Text for a Markdown table cell (``|`` escaped, runs of white space as one space).

    Examples
    --------
    >>> print(_md_cell("a|b \n c"))
    a\|b c
    >>> _md_cell("")
    ''
    """
    return " ".join(text.split()).replace("|", "\\|")


def _rel(path: Path, folder: Path) -> str:
    return path.relative_to(folder).as_posix()


def _fmt_margin(m: float, units: str) -> str:
    return f"{m / length_scale(units):+.2f} {units}" if math.isfinite(m) else "n/a"


def markdown(study: Study, sections: list[Section], folder: Path, units: str = "m") -> str:
    """``report.md``: the same content as the HTML, figures linked as PNG (SVG beside)."""
    lines = [f"# Clearance report ({study.method})", "",
             f"{len(study.records)} runs: {len(study.table)} vehicles × the curves of "
             f"{len(sections)} network(s); clearance offset {study.clearance_m:g} m. "
             "Verdicts, worst first: cannot-turn (the steered axle cannot follow the centre "
             "line within the lock and steering rate), fails (the swept path leaves the "
             "pavement), encroaches (it leaves its own lanes), clear. Margins in "
             f"{'metres' if units == 'm' else 'feet'}: the gap to the own lanes (negative: "
             "how far beyond).", "",
             "Symbols in the matrices: ✓ clear, ~ encroaches, ✗ fails, ⊘ cannot-turn"
             + ("; (waived): accepted by a waiver, listed with its reason under each "
                "network." if any(x.waived for x in sections) else "."), ""]
    for s in sections:
        lines += [f"## {s.name}", "",
                  "| " + " | ".join(s.counts) + " |", "|" + "---|" * len(s.counts),
                  "| " + " | ".join(str(v) for v in s.counts.values()) + " |", "",
                  f"![plan of {s.name}]({_rel(s.plan, folder)})", "",
                  "Worst curves (numbered on the plan):", ""]
        for i, r in enumerate(s.worst.head(8).itertuples(), start=1):
            if r.verdict == "clear" and r.margin_m > TIGHT_M:
                break
            lines.append(f"{i}. `{r.curve_id}`: {r.vehicle} {r.verdict} "
                         f"({_fmt_margin(r.margin_m, units)})")
        lines += ["", f"### Vehicle × curve matrix ({len(s.matrix)} failing or tight curves; "
                  f"{s.all_clear} curves clear for every vehicle with at least "
                  f"{TIGHT_M} m to spare are left out)", ""]
        if len(s.matrix):
            heads = ["curve", *s.matrix.columns]
            lines += ["| " + " | ".join(heads) + " |", "|" + "---|" * len(heads)]
            for cid, row in s.matrix.iterrows():
                cells = []
                for c in row:
                    if not isinstance(c, str):  # no run of this vehicle on this curve
                        cells.append("–")
                        continue
                    verdict, margin, *w = c.split("|")
                    cells.append(f"{SYMBOL[verdict]} {_cell_margin(margin)}"
                                 + (" (waived)" if w else ""))
                lines.append(f"| `{cid}` | " + " | ".join(cells) + " |")
        lines.append("")
        if s.waived:
            lines += [f"### Waived runs ({len(s.waived)})", "",
                      "| curve | vehicle | verdict | margin | reason | waiver |",
                      "|---|---|---|---|---|---|"]
            lines += [f"| `{cid}` | {v} | {verdict} | {_fmt_margin(m, units)} | "
                      f"{_md_cell(reason)} | {_md_cell(where)} |"
                      for cid, v, verdict, m, reason, where in s.waived]
            lines.append("")
        for cid, png, caption in s.curve_figures:
            lines += [f"### `{cid}`", "", f"![{cid}]({_rel(png, folder)})", "",
                      caption, ""]
        if s.omitted:
            lines += [f"({s.omitted} more failing or tight curves are in the matrix and "
                      "in clearance.csv, without a figure.)", ""]
    lines += ["## Files", "",
              "- `clearance.csv`: one row per network × vehicle × curve",
              "- `summary.json`: counts by verdict per network and vehicle, inputs with "
              "SHA-256, versions",
              "- `swept.geojson`: envelopes for GIS; `swept.add.xml`: SUMO polygons "
              "(`sumo-gui -n NET -a swept.add.xml`); `swept.dxf`: one layer per vehicle",
              "- `figures/`: every figure as PNG and SVG", ""]
    return "\n".join(lines)


CSS = """
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;
color:#222}
table{border-collapse:collapse;font-size:12px;margin:0.5em 0}
th,td{border:1px solid #ccc;padding:2px 5px;text-align:right}
th{background:#f2f2f2;position:sticky;top:0}
td.id{text-align:left;font-family:monospace}
.matrix{overflow-x:auto;max-height:600px}
img{max-width:100%;height:auto}
figure{margin:1em 0}
figcaption{font-size:12px;color:#555}
"""


def _img(png: Path, alt: str) -> str:
    data = base64.b64encode(png.read_bytes()).decode("ascii")
    return f'<img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'


def html_document(study: Study, sections: list[Section], units: str = "m") -> str:
    """``report.html``: one self-contained file (figures embedded, no external assets)."""
    e = html.escape
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           f"<title>Clearance report ({e(study.method)})</title>",
           f"<style>{CSS}</style></head><body>",
           f"<h1>Clearance report ({e(study.method)})</h1>",
           f"<p>{len(study.records)} runs: {len(study.table)} vehicles × the curves of "
           f"{len(sections)} network(s); clearance offset {study.clearance_m:g} m. Verdicts, "
           "worst first: <b>cannot-turn</b> (the steered axle cannot follow the centre line "
           "within the lock and steering rate), <b>fails</b> (the swept path leaves the "
           "pavement), <b>encroaches</b> (it leaves its own lanes), <b>clear</b>. Margins in "
           f"{'metres' if units == 'm' else 'feet'}: the gap to the own lanes (negative: how "
           "far beyond).</p>"]
    for s in sections:
        out.append(f"<h2>{e(s.name)}</h2><table><tr>"
                   + "".join(f"<th>{e(k)}</th>" for k in s.counts) + "</tr><tr>"
                   + "".join(f"<td>{v}</td>" for v in s.counts.values()) + "</tr></table>")
        out.append(f"<figure>{_img(s.plan, 'plan of ' + s.name)}<figcaption>Plan of "
                   f"{e(s.name)}: each curve coloured by its worst verdict; the worst curves "
                   "numbered as in the list below.</figcaption></figure><ol>")
        for r in s.worst.head(8).itertuples():
            if r.verdict == "clear" and r.margin_m > TIGHT_M:
                break
            out.append(f"<li><code>{e(r.curve_id)}</code>: {e(r.vehicle)} {e(r.verdict)} "
                       f"({_fmt_margin(r.margin_m, units)})</li>")
        out.append("</ol>")
        out.append(f"<h3>Vehicle × curve matrix</h3><p>{len(s.matrix)} failing or tight "
                   f"curves; {s.all_clear} curves clear for every vehicle with at least "
                   f"{TIGHT_M} m to spare are left out.</p>")
        if len(s.matrix):
            out.append('<div class="matrix"><table><tr><th>curve</th>'
                       + "".join(f"<th>{e(v)}</th>" for v in s.matrix.columns) + "</tr>")
            for cid, row in s.matrix.iterrows():
                cells = []
                for c in row:
                    if not isinstance(c, str):
                        cells.append("<td>–</td>")
                        continue
                    verdict, margin, *w = c.split("|")
                    colour = COLOURS[verdict]
                    tip = f"{verdict}, waived" if w else verdict
                    cells.append(f'<td style="background:{colour}33" title="{e(tip)}">'
                                 f"{SYMBOL[verdict]} {_cell_margin(margin)}"
                                 f"{' (waived)' if w else ''}</td>")
                out.append(f'<tr><td class="id">{e(str(cid))}</td>{"".join(cells)}</tr>')
            out.append("</table></div>")
        if s.waived:
            out.append(f"<h3>Waived runs ({len(s.waived)})</h3><table><tr><th>curve</th>"
                       "<th>vehicle</th><th>verdict</th><th>margin</th><th>reason</th>"
                       "<th>waiver</th></tr>")
            out += [f'<tr><td class="id">{e(cid)}</td><td>{e(v)}</td><td>{e(verdict)}</td>'
                    f"<td>{_fmt_margin(m, units)}</td><td>{e(reason)}</td><td>{e(where)}</td>"
                    "</tr>" for cid, v, verdict, m, reason, where in s.waived]
            out.append("</table>")
        for cid, png, caption in s.curve_figures:
            out.append(f"<h3><code>{e(cid)}</code></h3><figure>{_img(png, cid)}"
                       f"<figcaption>{e(caption)}</figcaption></figure>")
        if s.omitted:
            out.append(f"<p>{s.omitted} more failing or tight curves are in the matrix and in "
                       "clearance.csv, without a figure.</p>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"
