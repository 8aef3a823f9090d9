"""The report documents: ``report.html`` (one self-contained file) and ``report.md``.

``report.html`` opens with every curve that is not clear, worst first over the networks
(:mod:`clearance.reports.documents.not_clear`). Then per network: the verdict counts, a
plan with the worst curves marked, a vehicle × curve matrix of verdicts and margins
(folded), and for each failing or tight curve a section with its runs in words and a figure
of the swept paths over the lanes, the junction and the curbs. The worst curves' sections
are open with their figures; the figures embedded stay within a budget of bytes
(:mod:`clearance.reports.documents.embedding`), and the other failing curves' sections and
the tight ones' are folded in ``<details>`` (no script: a click or a link opens them,
and they print open). The HTML embeds its figures (PNG as data URIs) and references
nothing outside itself; the Markdown links the PNG files written beside it (SVG versions
are there too).
"""

from __future__ import annotations

import hashlib
import html
import re
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from clearance.networks.curves import Curve
from clearance.reports.documents.embedding import FIGURE_BYTES, embed_within, figure_img
from clearance.reports.documents.figures import COLOURS, plot_curve, plot_network, worst_by_curve
from clearance.reports.documents.not_clear import (
    NOT_CLEAR_ID,
    NotClear,
    not_clear_first,
    not_clear_html,
    run_rank,
)
from clearance.reports.documents.plotting import PNG
from clearance.reports.documents.profile_figure import VerticalEntry, vertical_entries
from clearance.reports.documents.wording import (
    SYMBOL,
    VERDICT_CLASS,
    cell_margin,
    margin_words,
    run_words,
    short_id,
)
from clearance.reports.output.file_names import file_name
from clearance.reports.results.feedback import (
    serves_counts,
    serves_html,
    serves_sentence,
    size_order,
)
from clearance.reports.results.provenance import provenance_summary
from clearance.reports.results.records import VERDICT_ORDER, RunRecord
from clearance.reports.results.text_table import counted
from clearance.reports.results.units import length_scale, text_in_units
from clearance.reports.results.vertical import vertical_words
from clearance.reports.results.waivers import Waived
from clearance.reports.study.run import NetworkCurves, Study

__all__ = ["CSS", "CurveEntry", "MATRIX_VEHICLES", "MAX_CURVE_FIGURES", "MAX_ENVELOPES",
           "SYMBOL", "Section", "TIGHT_M", "anchor", "build_sections", "cell_margin",
           "figure_order", "fold", "html_document", "is_not_clear", "margin_words",
           "pick_envelopes", "run_words"]

#: A curve is *tight* when its smallest margin is below this (m) though clear.
TIGHT_M = 0.25
#: At most this many curve figures per network (the worst first): every failing or tight
#: curve of the samples; a large network lists the rest in its matrix and clearance.csv.
MAX_CURVE_FIGURES = 60
#: At most this many envelopes in one curve figure (the worst vehicles).
MAX_ENVELOPES = 4

@dataclass
class CurveEntry:
    """One failing or tight curve of a section: its runs and its figure."""

    curve_id: str
    figure: Path | None
    runs: list  # RunRecord, worst first
    drawn: list[str]  # the vehicles the figure shows
    #: What the curve serves, in words (:func:`clearance.reports.results.feedback.serves_sentence`).
    serves: str = ""
    #: Why the curve has no figure though it was to have one (its drawing was lost).
    missing: str = ""


@dataclass
class Section:
    """One network's part of the report."""

    name: str
    counts: dict[str, int]
    plan: Path
    worst: pd.DataFrame
    matrix: pd.DataFrame  # rows curve_id, columns vehicles: "verdict|margin"
    all_clear: int
    omitted: int = 0
    #: Every failing or tight curve in matrix order: curve id, its figure (None beyond
    #: :data:`MAX_CURVE_FIGURES` or when lost), every run worst first, the vehicles drawn.
    curves: list[CurveEntry] = field(default_factory=list)
    #: Vehicles, curves and runs of the network.
    n_vehicles: int = 0
    n_curves: int = 0
    #: Waived runs: curve id, vehicle, verdict, margin (m), reason, waiver's file:line.
    waived: list[tuple[str, str, str, float, str, str]] = field(default_factory=list)
    #: The vertical checks: curves where a run scrapes or is too steep, and ramps.
    vertical: list[VerticalEntry] = field(default_factory=list)
    #: Curves by the largest vehicle they serve: vehicle (``""``: none), curves it is
    #: the largest that clears, curves it is the largest that stays paved on
    #: (:func:`clearance.reports.results.feedback.serves_counts`), smallest vehicle first.
    serves: list[tuple[str, int, int]] = field(default_factory=list)
    #: Swung runs on the curves without a section of their own (they clear with room to
    #: spare, but only by swinging wide): said in words under the matrix.
    swung: list = field(default_factory=list)
    #: Outputs of the network that were not drawn (their drawing was lost), in words.
    lost: list[str] = field(default_factory=list)
    #: What is not a verdict, in words: the curves a vehicle's SUMO class may not use (not
    #: run), the elements SUMO loads that were left out or repaired.
    notes: list[str] = field(default_factory=list)


def build_sections(study: Study, folder: Path, units: str = "m",
                   waived: Waived | None = None,
                   draw: Callable[[NetworkCurves, Curve, list[RunRecord], Path], Path] | None
                   = None, formats: tuple[str, ...] = PNG) -> list[Section]:
    """Draw every figure under ``folder/figures`` (the files of ``formats``, PNG first) and
    collect what the documents show.

    ``draw(nc, curve, records, stem)``, when given, draws a curve's figure instead of
    :func:`clearance.reports.documents.figures.plot_curve` (in a worker: ``clearance report``) and
    returns
    the path its PNG will have.

    Figures are named by :func:`clearance.reports.output.file_names.file_name`: ``<network>__plan``
    and
    ``<network>__curve__<curve id>`` (with a short hash where the id needed changing).

    Margins shown in the matrix and captions are in ``units``. With ``waived``, each
    section counts and lists its waived runs, and their matrix cells are marked.
    """
    scale = length_scale(units)
    figs = folder / "figures"
    frame = study.frame()
    order = size_order(study.table)

    def serves_text(recs: list) -> str:
        return serves_sentence({r.vehicle: r.verdict for r in recs if r.verdict != "error"},
                               order)
    sections = []
    for nc in study.networks:
        f = frame[frame.network == nc.name]
        # stems: plotting.save appends .png (and .svg)
        plan = plot_network(nc, f, figs / file_name([nc.name, "plan"], room=4), units=units,
                            formats=formats)[0]
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
            png = (plot_curve(nc, by_id[cid], shown, stem, table=study.table, units=units,
                              formats=formats)[0]
                   if draw is None else draw(nc, by_id[cid], shown, stem))
            section.curves.append(CurveEntry(cid, png, recs, [r.vehicle for r in shown],
                                             serves_text(recs)))
        for cid in [c for c in worst.curve_id if c in bad][len(picked):]:
            recs = [r for r in study.records if r.network == nc.name and r.curve_id == cid]
            recs.sort(key=lambda r: (VERDICT_ORDER[r.verdict], r.margin_m))
            section.curves.append(CurveEntry(cid, None, recs, [], serves_text(recs)))
        section.vertical = vertical_entries(
            nc.curves, [r for r in study.records if r.network == nc.name],
            {v.name: v for v in study.table.vehicles()}, figs, nc.name, units, formats)
        section.serves = serves_counts(f, order)
        listed = {c.curve_id for c in section.curves}
        section.swung = [r for r in study.records if r.network == nc.name
                         and r.path == "swung" and r.curve_id not in listed]
        section.n_vehicles = f.vehicle.nunique()
        section.n_curves = len(nc.curves)
        section.notes = network_notes(study, nc)
        sections.append(section)
    return sections


#: The repairs of a network named one by one in the report; beyond these, a count.
MAX_REPAIRS_SHOWN = 5


def network_notes(study: Study, nc: NetworkCurves) -> list[str]:
    """What a network's part of the report says beside its verdicts: per vehicle, how many
    curves its SUMO class may not use (not run, not a verdict); what of the network SUMO
    loads but was left out or repaired (:attr:`clearance.networks.model.Network.repairs`)."""
    out = []
    refused = Counter(v for net, v, _ in study.not_permitted if net == nc.name)
    if refused:
        classes = {v.name: v.vclass for v in study.table.vehicles()}
        out.append("Not run, the curve's lanes not admitting the vehicle's SUMO class: "
                   + ", ".join(f"{v} ({classes.get(v, '?')}) {counted(n, 'curve')}"
                               for v, n in refused.items()) + ".")
    rests = rests_on_words([r for r in study.records if r.network == nc.name])
    if rests:
        out.append(rests)
    repairs = nc.network.repairs
    if repairs:
        shown = "; ".join(repairs[:MAX_REPAIRS_SHOWN])
        more = len(repairs) - MAX_REPAIRS_SHOWN
        out.append(f"SUMO loads this network; {counted(len(repairs), 'element')} no vehicle "
                   f"can be judged on {'was' if len(repairs) == 1 else 'were'} repaired or "
                   f"left out: {shown}" + (f"; and {more} more." if more > 0 else "."))
    return out


def rests_on_words(records: list) -> str:
    """What a network's runs that are not clear rest on, in words: data or netconvert's
    defaults, and the defaults that carry most of them (:mod:`clearance.networks.provenance`).

    >>> from types import SimpleNamespace as R
    >>> print(rests_on_words([R(verdict="fails", geometry="lane width default 3.2 m"),
    ...                       R(verdict="encroaches", geometry="data"),
    ...                       R(verdict="clear", geometry="data")]))
    ... # doctest: +NORMALIZE_WHITESPACE
    Of 2 runs not clear, 1 rests on the network's data and 1 on netconvert's defaults
    (lane width default 3.2 m: 1 run): check those against the street before acting on them.
    >>> rests_on_words([R(verdict="clear", geometry="data")])
    ''
    """
    frame = pd.DataFrame({"network": "n", "verdict": [r.verdict for r in records],
                          "geometry": [r.geometry for r in records]})
    if frame.empty:
        return ""
    split = provenance_summary(frame)["n"]
    n = split["not_clear"]
    if not n["runs"]:
        return ""
    text = (f"Of {counted(n['runs'], 'run')} not clear, {n['on_data']} "
            f"{'rests' if n['on_data'] == 1 else 'rest'} on the network's data and "
            f"{n['on_defaults']} on netconvert's defaults")
    if n["on_defaults"]:
        text += (" (" + "; ".join(f"{k}: {counted(v, 'run')}" for k, v
                                  in list(split["defaults_carrying"].items())[:4])
                 + "): check those against the street before acting on them")
    return text + "."


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


#: Each verdict's cells (:data:`~clearance.reports.documents.wording.VERDICT_CLASS`) in the
#: verdict's colour, light.
_VERDICT_CSS = "".join(f"td.{VERDICT_CLASS[v]}{{background:{c}33}}\n" for v, c in COLOURS.items())

CSS = """
body{font-family:system-ui,sans-serif;max-width:1200px;margin:1.5em auto;padding:0 1em;
color:#222;line-height:1.4}
nav.toc{border:1px solid #ddd;padding:0.5em 1em;background:#fafafa}
nav.toc ol{margin:0.2em 0}
nav.toc p{margin:0.2em 0;font-size:12px;color:#444}
table{border-collapse:collapse;font-size:12px;margin:0.5em 0}
th,td{border:1px solid #ccc;padding:2px 5px;text-align:right}
th{background:#f2f2f2}
td.id,th.id{text-align:left;font-family:monospace;white-space:nowrap}
td.tx{text-align:left}
.first{overflow:auto;max-height:60vh;border:1px solid #ddd}
.first table{margin:0}
.first thead th{position:sticky;top:0;z-index:1;text-align:left}
.first td{white-space:nowrap}
.first td.wrap{white-space:normal;text-align:left;min-width:12em}
.matrix{overflow:auto;max-width:100%;max-height:85vh}
.matrix table{margin:0}
.matrix thead th{position:sticky;top:0;z-index:2}
.matrix th.id,.matrix td.id{position:sticky;left:0;background:#fff;z-index:1}
.matrix thead th.id{z-index:3;background:#f2f2f2}
.matrix th.v{min-width:4.5em;max-width:7em;white-space:normal;overflow-wrap:break-word;
font-size:11px;text-align:center;vertical-align:bottom}
.matrix td a{color:inherit;text-decoration:none;display:block}
.matrix td a:hover{text-decoration:underline}
details.fold{margin:0.8em 0;padding:0.2em 0.8em;border:1px solid #ddd;background:#fcfcfc}
details.fold>summary{cursor:pointer;padding:0.2em 0}
details.runs>summary{cursor:pointer;padding-left:0.3em}
summary h3{display:inline;font-size:1.05em}
img{max-width:100%;height:auto}
figure{margin:1em 0}
figure.curve,figure.profile{display:flex;flex-wrap:wrap;gap:0 1.5em;align-items:flex-start}
figure.curve figcaption,figure.profile figcaption{flex:1 1 20em}
figcaption{font-size:12px;color:#444}
figcaption ul{margin:0.3em 0;padding-left:1.2em}
.summary{font-size:14px}
@media print{
body{max-width:none;margin:0;font-size:10pt}
nav.toc{break-after:page}
h2{break-before:page}
.first,.matrix{overflow:visible;max-height:none}
.first{border:0}
.matrix thead{display:table-header-group}
.matrix{break-inside:avoid}
.first thead th,.matrix thead th,.matrix th.id,.matrix td.id{position:static}
.matrix table{font-size:7pt}
.matrix td{white-space:nowrap;padding:1px 3px}
details::details-content{content-visibility:visible;display:block}
details.fold{border:0;padding:0}
tr,figure{break-inside:avoid}
a{color:inherit;text-decoration:none}
}
""" + _VERDICT_CSS

#: Matrix columns (vehicles) per table: wider matrices are split into several tables, each
#: with the curve names, so that each fits a screen and a printed page.
MATRIX_VEHICLES = 12


def anchor(network: str, curve_id: str | None = None) -> str:
    """The HTML id of a network's section or of one of its curves: letters, digits, ``-``
    and ``_`` with a short hash of the names (unique where the names are).

    >>> anchor("intersection")
    'net-intersection-4b6914c6'
    >>> anchor("intersection", "turn:X:XN_in_0->XW_out_0")[:31]
    'curve-intersection-turn-X-XN_in'
    """
    key = network if curve_id is None else f"{network}\0{curve_id}"
    digest = hashlib.sha1(key.encode()).hexdigest()[:8]
    text = network if curve_id is None else f"{network}-{curve_id}"
    safe = re.sub(r"[^A-Za-z0-9_]+", "-", text).strip("-")[:60]
    return f"{'net' if curve_id is None else 'curve'}-{safe}-{digest}"


def is_not_clear(c: CurveEntry) -> bool:
    """Whether a vehicle does not clear the curve (else it is tight: clear, with less
    than :data:`TIGHT_M` to spare)."""
    return any(r.verdict != "clear" for r in c.runs)


def fold(summary: str, body: Sequence[str], kind: str = "fold") -> str:
    """``body`` in a ``<details>`` of class ``kind`` that is closed until its ``summary``
    is clicked (or a link leads into it): it takes no room on the page, needs no script,
    and prints open (``CSS``)."""
    return (f'<details class="{kind}"><summary>{summary}</summary>' + "".join(body)
            + "</details>")


def _summary_html(s: Section, units: str) -> str:
    e = html.escape
    not_clear = sum(v for k, v in s.counts.items() if k not in ("clear", "waived"))
    worst = s.worst.iloc[0] if len(s.worst) else None
    text = (f"{counted(s.n_curves, 'curve')} × {counted(s.n_vehicles, 'vehicle')}: "
            f"{counted(not_clear, 'run')} not clear")
    if worst is not None and (worst.verdict != "clear" or worst.margin_m < TIGHT_M):
        text += (f"; the worst: {e(str(worst.vehicle))} on <code>{e(str(worst.curve_id))}"
                 f"</code>, {e(str(worst.verdict))}, {margin_words(worst.margin_m, units)}")
    return f'<p class="summary">{text}.</p>'


def _matrix_html(s: Section, links: dict[str, str]) -> list[str]:
    """The vehicle × curve matrix in tables of at most :data:`MATRIX_VEHICLES` vehicles;
    each cell the verdict's sign and class and the margin, linked to the curve's
    section."""
    e = html.escape
    out = []
    vehicles = list(s.matrix.columns)
    tables = -(-len(vehicles) // MATRIX_VEHICLES)
    size = -(-len(vehicles) // max(tables, 1))  # balanced: 37 vehicles in 10, 10, 10, 7
    for lo in range(0, len(vehicles), size):
        chunk = vehicles[lo:lo + size]
        if len(vehicles) > MATRIX_VEHICLES:
            out.append(f"<p>Vehicles {lo + 1}–{lo + len(chunk)} of {len(vehicles)}:</p>")
        out.append('<div class="matrix"><table><thead><tr><th class="id">curve</th>'
                   + "".join(f'<th class="v">{e(v)}</th>' for v in chunk) + "</tr></thead><tbody>")
        for cid, row in s.matrix[chunk].iterrows():
            href = links[str(cid)]
            cells = []
            for c in row:
                if not isinstance(c, str):
                    cells.append("<td>–</td>")
                    continue
                verdict, margin, *w = c.split("|")
                cells.append(f'<td class="{VERDICT_CLASS[verdict]}"><a href="#{href}">'
                             f"{SYMBOL[verdict]} {cell_margin(margin)}"
                             f"{' (waived)' if w else ''}</a></td>")
            out.append(f'<tr><td class="id" title="{e(str(cid))}"><a href="#{href}">'
                       f'{e(short_id(str(cid)))}</a></td>{"".join(cells)}</tr>')
        out.append("</tbody></table></div>")
    return out


def _vertical_html(s: Section, units: str) -> list[str]:
    """The section's vertical checks: each curve's profile figure and its runs' findings."""
    e = html.escape
    out = [f'<h3 id="{anchor(s.name)}-vertical">Vertical checks</h3>']
    if not s.vertical:
        return out + ["<p>No run scrapes or is too steep, and the network has no ramp.</p>"]
    out.append("<p>Beside each run's plan verdict: whether the body clears the ground at "
               "crests (the underside between the axles) and sags (the front and rear "
               "overhangs), and the grade against the limit; the figure draws the worst "
               "vehicle at its worst placement.</p>")
    for v in s.vertical:
        runs = _vertical_runs_html(v.runs, units)
        head = f"<h4><code>{e(v.curve_id)}</code> (vertical)</h4>"
        if v.figure is not None:
            out.append(f'{head}<figure class="profile">'
                       f"{figure_img(v.figure, v.curve_id + ' profile')}"
                       f"<figcaption>{runs}</figcaption></figure>")
        else:
            out.append(f"{head}{runs}")
    return out


def _vertical_runs_html(runs: list, units: str) -> str:
    """A curve's vertical findings, worst first, then the vehicles with nothing to say
    (clear), folded when there are more than :data:`MAX_CLEAR_LISTED` of them."""
    e = html.escape
    said = [(r, vertical_words(r, units)) for r in runs]
    found = "".join(f"<li>{e(r.vehicle)}: {e(w)}</li>" for r, w in said if w)
    clear = [f"<li>{e(r.vehicle)}: clear</li>" for r, w in said if not w]
    if len(clear) <= MAX_CLEAR_LISTED:
        return f"<ul>{found}{''.join(clear)}</ul>"
    return ((f"<ul>{found}</ul>" if found else "")
            + fold(f"{'and ' if found else ''}{counted(len(clear), 'vehicle')} clear",
                   [f"<ul>{''.join(clear)}</ul>"], kind="runs"))


def _head_html(study: Study, sections: list[Section], units: str) -> list[str]:
    """The document's head (title, styles) and its opening paragraph: what was run and how
    to read the verdicts and margins."""
    e = html.escape
    return ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>Clearance report ({e(study.method)})</title>",
            f"<style>{CSS}</style></head><body>",
            f'<h1 id="top">Clearance report ({e(study.method)})</h1>',
            f"<p>{counted(len(study.records), 'run')}: {counted(len(study.table), 'vehicle')}"
            f" × the curves of {counted(len(sections), 'network')}; clearance offset "
            f"{text_in_units(f'{study.clearance_m:g} m', units)}. Verdicts, worst first: "
            "<b>cannot-turn</b> (the steered axle cannot follow the centre line within the "
            "lock and steering rate), "
            "<b>fails</b> (the swept path leaves the pavement), <b>encroaches</b> (it leaves "
            "its own lanes), <b>clear</b>. Margins in "
            f"{'metres' if units == 'm' else 'feet'}: the gap between the swept path and the "
            "edge of its own lanes (negative: how far beyond) and, for the pavement, the gap "
            "to the pavement's edge.</p>"]


def _toc_html(sections: list[Section], not_clear: int) -> list[str]:
    """The contents list: what is not clear, then per network its section, its matrix and
    its curves; the files; and how to open the folded parts."""
    e = html.escape
    toc = ['<nav class="toc" aria-label="Contents"><b>Contents</b><ol>',
           f'<li><a href="#{NOT_CLEAR_ID}">Not clear, worst first</a> '
           f"({counted(not_clear, 'curve')})</li>"]
    for s in sections:
        net = anchor(s.name)
        toc.append(f'<li><a href="#{net}">{e(s.name)}</a> — '
                   f'<a href="#{net}-matrix">matrix</a>'
                   + (f', <a href="#{net}-curves">{counted(len(s.curves), "curve")}</a>'
                      if s.curves else "") + "</li>")
    toc.append('<li><a href="#files">Files</a></li></ol><p>A part marked ▸ (each matrix, '
               "the curves without a figure here, the tight ones) is folded: click it, or a "
               "link into it, to open it; Chrome and Edge print it open.</p></nav>")
    return toc


def _worst_html(s: Section, units: str, links: dict[str, str]) -> str:
    """The section's worst curves as numbered on the plan (linked to their sections), or
    that every curve is clear with room to spare."""
    e = html.escape
    items = []
    for r in s.worst.head(8).itertuples():
        if r.verdict == "clear" and r.margin_m > TIGHT_M:
            break
        target = links.get(str(r.curve_id))
        name = f"<code>{e(str(r.curve_id))}</code>"
        if target:
            name = f'<a href="#{target}">{name}</a>'
        items.append(f"<li>{name}: "
                     f"{e(str(r.vehicle))} {e(str(r.verdict))}, "
                     f"{margin_words(r.margin_m, units)}</li>")
    if items:
        return "<p>Worst curves (numbered on the plan):</p><ol>" + "".join(items) + "</ol>"
    return ("<p>Every curve is clear for every vehicle with at least "
            f"{text_in_units(f'{TIGHT_M} m', units)} to spare.</p>")


def _overview_html(s: Section, units: str, links: dict[str, str]) -> list[str]:
    """The top of a network's section: heading, summary, what its curves serve, the counts
    by verdict, the plan, the notes and lost outputs, and the worst curves."""
    e = html.escape
    out = [f'<h2 id="{anchor(s.name)}">{e(s.name)}</h2>', _summary_html(s, units)]
    if s.serves:
        out.append(serves_html(s.serves))
    out.append("<table><tr>" + "".join(f"<th>{e(k)}</th>" for k in s.counts)
               + "</tr><tr>" + "".join(f"<td>{v}</td>" for v in s.counts.values())
               + "</tr></table>")
    out.append(f"<figure>{figure_img(s.plan, 'plan of ' + s.name, lazy=False)}<figcaption>"
               f"Plan of {e(s.name)}: each curve coloured by its worst verdict; the worst "
               "curves numbered as in the list below.</figcaption></figure>")
    out += [f"<p>{e(t)}</p>" for t in s.notes]
    out += [f'<p class="lost">{e(t)}</p>' for t in s.lost]
    out.append(_worst_html(s, units, links))
    return out


def _matrix_section_html(s: Section, units: str, links: dict[str, str]) -> list[str]:
    """A section's vehicle × curve matrix, folded, with how to read its cells (unfolded
    when it has no row: then only the sentence)."""
    heading = f'<h3 id="{anchor(s.name)}-matrix">Vehicle × curve matrix</h3>'
    spare = text_in_units(f"{TIGHT_M} m", units)
    text = (f"{counted(len(s.matrix), 'failing or tight curve')}; "
            f"{counted(s.all_clear, 'curve')} clear for every vehicle with at least "
            f"{spare} to spare left out.")
    if not len(s.matrix):
        return [heading, f"<p>{text}</p>"]
    how = ("<p>Each cell: the verdict (✓ clear, ~ encroaches, ✗ fails, ⊘ cannot-turn) and "
           "the margin to the own lanes; click it for the curve.</p>")
    return [fold(f"{heading} {counted(len(s.matrix), 'curve')} × "
                 f"{counted(len(s.matrix.columns), 'vehicle')}",
                 [f"<p>{text}</p>", how, *_matrix_html(s, links)])]


def _waived_html(s: Section, units: str) -> list[str]:
    """The section's waived runs as a table (nothing when none is waived)."""
    e = html.escape
    if not s.waived:
        return []
    out = [f"<h3>Waived runs ({len(s.waived)})</h3><table><tr><th>curve</th>"
           "<th>vehicle</th><th>verdict</th><th>margin</th><th>reason</th>"
           "<th>waiver</th></tr>"]
    out += [f'<tr><td class="id">{e(cid)}</td><td>{e(v)}</td><td>{e(verdict)}</td>'
            f"<td>{margin_words(m, units)}</td><td>{e(reason)}</td>"
            f"<td>{e(where)}</td></tr>"
            for cid, v, verdict, m, reason, where in s.waived]
    out.append("</table>")
    return out


#: A curve's section lists at most this many clear runs below those not clear; more are
#: folded under a line naming the closest (a study of 37 vehicles lists 25 clear runs).
MAX_CLEAR_LISTED = 3


def _runs_html(c: CurveEntry, units: str) -> str:
    """Every vehicle's run on a curve in words, worst first: those not clear in a list,
    then the clear ones, folded when there are more than :data:`MAX_CLEAR_LISTED` of them
    beside runs not clear."""
    e = html.escape

    def items(runs: list) -> str:
        return "".join(f"<li>{e(run_words(r, units))}"
                       + (" (drawn)" if r.vehicle in c.drawn else "") + "</li>"
                       for r in runs)
    bad = [r for r in c.runs if r.verdict != "clear"]
    clear = [r for r in c.runs if r.verdict == "clear"]
    if not bad or len(clear) <= MAX_CLEAR_LISTED:
        return f"<ul>{items(c.runs)}</ul>"
    closest = min(clear, key=run_rank)
    return (f"<ul>{items(bad)}</ul>" + fold(
        f"and {counted(len(clear), 'vehicle')} clear, the closest {e(closest.vehicle)} "
        f"({e(margin_words(closest.margin_m, units))})", [f"<ul>{items(clear)}</ul>"],
        kind="runs"))


def _curve_html(c: CurveEntry, units: str, target: str, embedded: dict[Path, str]) -> str:
    """One curve's section: its heading, what it serves, its figure (embedded, or the file
    it is in, or why it has none) and every vehicle's run in words, worst first
    (:func:`_runs_html`)."""
    e = html.escape
    runs = _runs_html(c, units)
    head = f'<h4 id="{target}"><code>{e(c.curve_id)}</code></h4>'
    if c.serves:
        head += f'<p class="serves">{e(c.serves)}</p>'
    if c.figure is not None and c.figure in embedded:
        return (f'{head}<figure class="curve">{embedded[c.figure]}<figcaption>'
                f"<code>{e(c.curve_id)}</code>, every vehicle worst first (the figure draws "
                f"{counted(len(c.drawn), 'envelope')}):{runs}</figcaption></figure>")
    if c.missing:
        return f"{head}<p>{e(c.missing)} Every vehicle worst first:</p>{runs}"
    if c.figure is not None:
        return (f"{head}<p>Figure not on this page (it embeds the worst curves' figures "
                f"only): <code>figures/{e(c.figure.name)}</code>, drawing "
                f"{counted(len(c.drawn), 'envelope')}; every vehicle worst first:</p>{runs}")
    return (f"{head}<p>No figure (beyond the first {MAX_CURVE_FIGURES} of the network); "
            f"every vehicle worst first:</p>{runs}")


def _curves_html(s: Section, units: str, links: dict[str, str],
                 embedded: dict[Path, str]) -> list[str]:
    """The section's failing and tight curves: open, those not clear whose figure the page
    embeds (or says was lost), worst first; folded, the other curves not clear and the
    tight ones."""
    if not s.curves:
        return []
    failing = [c for c in s.curves if is_not_clear(c)]
    shown = [c for c in failing if c.missing or (c.figure is not None and c.figure in embedded)]
    rest = [c for c in failing if all(c is not d for d in shown)]
    tight = [c for c in s.curves if not is_not_clear(c)]
    out = [f'<h3 id="{anchor(s.name)}-curves">Failing and tight curves</h3>']
    out += [_curve_html(c, units, links[c.curve_id], embedded) for c in shown]
    if rest:
        out.append(fold(f"{counted(len(rest), 'more curve')} not clear, without a figure "
                        "here: every vehicle's run in words",
                        [_curve_html(c, units, links[c.curve_id], embedded) for c in rest]))
    if tight:
        spare = text_in_units(f"{TIGHT_M} m", units)
        out.append(fold(f"{counted(len(tight), 'tight curve')}: clear for every vehicle, "
                        f"with less than {spare} to spare",
                        [_curve_html(c, units, links[c.curve_id], embedded) for c in tight]))
    return out


def _swung_html(s: Section, units: str) -> list[str]:
    """The swung runs on the curves without a section of their own, folded (nothing when
    none)."""
    e = html.escape
    if not s.swung:
        return []
    return [fold(f"<h3>Swung paths on the other curves ({len(s.swung)})</h3>",
                 ["<p>Runs that clear with room to spare only by swinging wide:</p><ul>"
                  + "".join(f"<li><code>{e(r.curve_id)}</code>: "
                            f"{e(run_words(r, units))}</li>" for r in s.swung)
                  + "</ul>"])]


def _section_html(s: Section, units: str, embedded: dict[Path, str]) -> list[str]:
    """One network's part of ``report.html``, from its heading to the link back to the
    contents."""
    links = {c.curve_id: anchor(s.name, c.curve_id) for c in s.curves}
    out = _overview_html(s, units, links)
    out += _matrix_section_html(s, units, links)
    out += _waived_html(s, units)
    out += _curves_html(s, units, links, embedded)
    out += _vertical_html(s, units)
    out += _swung_html(s, units)
    out.append('<p><a href="#top">Back to the contents</a></p>')
    return out


def _files_html(exports: dict[str, dict[str, str]] | None) -> list[str]:
    """The closing list of the files beside the report (with each network's exports) and
    the end of the document."""
    e = html.escape
    out = ['<h2 id="files">Files</h2><ul>'
           "<li><code>clearance.csv</code>: one row per network × vehicle × curve</li>"
           "<li><code>summary.json</code>: counts by verdict per network and vehicle, "
           "inputs with SHA-256, versions</li>"
           "<li><code>figures/</code>: every figure as PNG and SVG at full resolution "
           "(this page embeds smaller copies of the plans and of the worst curves' "
           "figures)</li>"]
    for name, files in (exports or {}).items():
        out.append(f"<li>{e(name)}: <code>exports/{e(files['sumo'])}</code> (<code>sumo-gui "
                   f"-n NET -a exports/{e(files['sumo'])}</code>), "
                   f"<code>exports/{e(files['dxf'])}</code> (CAD), "
                   f"<code>exports/{e(files['geojson'])}</code> (GIS)</li>")
    out.append("</ul></body></html>")
    return out


def figure_order(sections: list[Section], ranked: list[NotClear]) -> list[tuple[Path, str]]:
    """The curve figures in the order ``report.html`` embeds them until its budget is spent
    (:func:`clearance.reports.documents.embedding.embed_within`): each network's worst
    curve that has a figure, then every curve not clear worst first (``ranked``), then the
    tight ones worst first; each once, as its PNG and alternative text."""
    by_key = {(s.name, c.curve_id): c for s in sections for c in s.curves}
    failing = [by_key[r.network, r.curve_id] for r in ranked]
    firsts: dict[str, CurveEntry] = {}  # network: its worst curve with a figure
    for r, c in zip(ranked, failing, strict=True):
        if c.figure is not None:
            firsts.setdefault(r.network, c)
    tight = sorted((c for s in sections for c in s.curves if not is_not_clear(c)),
                   key=lambda c: min(map(run_rank, c.runs)))
    chosen = {id(c): c for c in [*firsts.values(), *failing, *tight] if c.figure is not None}
    return [(c.figure, c.curve_id) for c in chosen.values() if c.figure is not None]


def html_document(study: Study, sections: list[Section], units: str = "m",
                  exports: dict[str, dict[str, str]] | None = None,
                  first: Sequence[str] = (), figure_bytes: int = FIGURE_BYTES) -> str:
    """``report.html``: one self-contained file (figures embedded, compact, no external
    assets): a contents list; every curve not clear, worst first, over the networks
    (:mod:`clearance.reports.documents.not_clear`); then per network a summary, the plan,
    the vehicle × curve matrix (folded; every cell linked to its curve's section) and a
    section per failing or tight curve listing every vehicle's verdict and margins in
    words. The worst curves' sections are open with their figures, within
    ``figure_bytes`` of embedded figures (:func:`figure_order`); the other curves' are
    folded, as are the tight ones'."""
    ranked = not_clear_first((s.name, c.curve_id, c.runs) for s in sections for c in s.curves)
    links = {(s.name, c.curve_id): anchor(s.name, c.curve_id)
             for s in sections for c in s.curves}
    embedded = embed_within(figure_order(sections, ranked), figure_bytes)
    tight = sum(not is_not_clear(c) for s in sections for c in s.curves)
    spare = text_in_units(f"{TIGHT_M} m", units)
    tight_words = (f"{counted(tight, 'more curve')} clear with less than {spare} to spare: "
                   "in the sections of their networks (folded)." if tight else "")
    waived = {(s.name, cid, v) for s in sections for cid, v, *_ in s.waived}
    out = (_head_html(study, sections, units) + _toc_html(sections, len(ranked))
           + not_clear_html(ranked, links, units, len(sections), tight_words, waived)
           + list(first))
    for s in sections:
        out += _section_html(s, units, embedded)
    out += _files_html(exports)
    return "\n".join(out) + "\n"
