"""``report.md``: the report's content as Markdown, figures linked as PNG (SVG beside).

The same sections as ``report.html`` (:func:`clearance.reports.documents.report.build_sections`).
Names and
reasons are escaped as text (:func:`_md_cell`: a vehicle named ``<script>`` is shown, never
run), ids are code spans holding them exactly (:func:`_md_code`).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from clearance.reports.documents.not_clear import not_clear_first, not_clear_for
from clearance.reports.documents.report import (
    SYMBOL,
    TIGHT_M,
    Section,
    cell_margin,
    margin_words,
    run_words,
)
from clearance.reports.documents.wording import margins_words, rests_words
from clearance.reports.results.feedback import serves_markdown
from clearance.reports.results.text_table import counted
from clearance.reports.results.units import length_scale, text_in_units
from clearance.reports.results.vertical import vertical_words
from clearance.reports.study.run import Study

__all__ = ["markdown"]


#: What a Markdown renderer would read as markup in running text: backslash-escaped.
_MD_PUNCTUATION = re.compile(r"([\\`*_\[\]|~])")


def _md_cell(text: str) -> str:
    r"""Text as it reads, for Markdown running text or a table cell: HTML's ``& < >`` as
    entities (a name such as ``<script>`` is shown, never run), Markdown's punctuation
    (emphasis, code, links, table cells) backslash-escaped, runs of white space as one space.

    Examples
    --------
    >>> print(_md_cell("a|b \n c"))
    a\|b c
    >>> print(_md_cell('<script>alert(1)</script> & "Q" a:b'))
    &lt;script&gt;alert(1)&lt;/script&gt; &amp; "Q" a:b
    >>> _md_cell("")
    ''
    """
    text = " ".join(text.split())
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return _MD_PUNCTUATION.sub(r"\\\1", text)


def _md_code(text: str) -> str:
    """A Markdown code span holding ``text`` exactly (ids, as the network has them): fenced by
    one backtick more than its longest run of backticks, padded where it starts or ends
    with one; a line break becomes a space.

    Examples
    --------
    >>> print(_md_code("turn:J:a_0->b_0"))
    `turn:J:a_0->b_0`
    >>> print(_md_code("odd`id"))
    ``odd`id``
    >>> print(_md_code("`x"))
    `` `x ``
    """
    text = " ".join(text.splitlines())
    runs = [len(m) for m in re.findall(r"`+", text)]
    fence = "`" * (max(runs, default=0) + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def _rel(path: Path, folder: Path) -> str:
    return path.relative_to(folder).as_posix()


def _fmt_margin(m: float, units: str) -> str:
    return f"{m / length_scale(units):+.2f} {units}" if math.isfinite(m) else "n/a"


def _md_head(study: Study, sections: list[Section], units: str) -> list[str]:
    """The title and opening paragraphs: what was run, how to read the verdicts, margins
    and the matrices' symbols."""
    return [f"# Clearance report ({study.method})", "",
            f"{counted(len(study.records), 'run')}: {counted(len(study.table), 'vehicle')} "
            f"× the curves of {counted(len(sections), 'network')}; clearance offset "
            f"{text_in_units(f'{study.clearance_m:g} m', units)}. "
            "Verdicts, worst first: cannot-turn (the steered axle cannot follow the centre "
            "line within the lock and steering rate), fails (the swept path leaves the "
            "pavement), encroaches (it leaves its own lanes), clear. Margins in "
            f"{'metres' if units == 'm' else 'feet'}: the gap to the own lanes (negative: "
            "how far beyond).", "",
            "Symbols in the matrices: ✓ clear, ~ encroaches, ✗ fails, ⊘ cannot-turn"
            + ("; (waived): accepted by a waiver, listed with its reason under each "
               "network." if any(x.waived for x in sections) else "."), ""]


def _md_not_clear(sections: list[Section], units: str) -> list[str]:
    """Every curve not clear, worst first over the networks, as report.html opens
    (:mod:`clearance.reports.documents.not_clear`): a row per curve with its worst run."""
    rows = not_clear_first((s.name, c.curve_id, c.runs) for s in sections for c in s.curves)
    lines = ["## Not clear, worst first", ""]
    if not rows:
        return lines + ["Every vehicle clears every curve.", ""]
    lines += [f"{counted(len(rows), 'curve')} not clear for at least one vehicle, the worst "
              "first: by the verdict of its worst run, then by that run's margin to its "
              "lanes.", "",
              "| # | network | curve | worst run | verdict | margins | not clear for | "
              "the worst run rests on |", "|" + "---|" * 8]
    for i, r in enumerate(rows, start=1):
        w = r.worst
        lines.append(f"| {i} | {_md_cell(r.network)} | {_md_code(r.curve_id)} | "
                     f"{_md_cell(w.vehicle)} | {w.verdict} | "
                     f"{_md_cell(margins_words(w, units))} | {_md_cell(not_clear_for(r))} | "
                     f"{_md_cell(rests_words(getattr(w, 'geometry', ''), units))} |")
    return lines + [""]


def _md_overview(s: Section, folder: Path) -> list[str]:
    """The top of a network's section: heading, counts by verdict, the plan, the notes and
    lost outputs, and what its curves serve."""
    lines = [f"## {_md_cell(s.name)}", "",
             "| " + " | ".join(s.counts) + " |", "|" + "---|" * len(s.counts),
             "| " + " | ".join(str(v) for v in s.counts.values()) + " |", "",
             f"![plan of {_md_cell(s.name)}]({_rel(s.plan, folder)})", ""]
    lines += [x for t in [*s.notes, *s.lost] for x in (_md_cell(t), "")]
    if s.serves:
        lines += serves_markdown(s.serves, _md_cell)
    return lines


def _md_worst(s: Section, units: str) -> list[str]:
    """The section's worst curves as numbered on the plan, or that every curve is clear
    with room to spare."""
    worst = []
    for i, r in enumerate(s.worst.head(8).itertuples(), start=1):
        if r.verdict == "clear" and r.margin_m > TIGHT_M:
            break
        worst.append(f"{i}. {_md_code(r.curve_id)}: {_md_cell(r.vehicle)} {r.verdict}, "
                     f"{margin_words(r.margin_m, units)}")
    if worst:
        return ["Worst curves (numbered on the plan):", "", *worst]
    return ["Every curve is clear for every vehicle with at least "
            f"{text_in_units(f'{TIGHT_M} m', units)} to spare."]


def _md_matrix(s: Section, units: str) -> list[str]:
    """The section's vehicle × curve matrix: heading, then one row per failing or tight
    curve (a symbol and margin per vehicle)."""
    lines = ["", f"### Vehicle × curve matrix ({len(s.matrix)} failing or tight curves; "
             f"{s.all_clear} curves clear for every vehicle with at least "
             f"{text_in_units(f'{TIGHT_M} m', units)} to spare are left out)", ""]
    if len(s.matrix):
        heads = ["curve", *map(_md_cell, s.matrix.columns)]
        lines += ["| " + " | ".join(heads) + " |", "|" + "---|" * len(heads)]
        for cid, row in s.matrix.iterrows():
            cells = []
            for c in row:
                if not isinstance(c, str):  # no run of this vehicle on this curve
                    cells.append("–")
                    continue
                verdict, margin, *w = c.split("|")
                cells.append(f"{SYMBOL[verdict]} {cell_margin(margin)}"
                             + (" (waived)" if w else ""))
            lines.append(f"| {_md_code(cid)} | " + " | ".join(cells) + " |")
    lines.append("")
    return lines


def _md_waived(s: Section, units: str) -> list[str]:
    """The section's waived runs as a table (nothing when none is waived)."""
    if not s.waived:
        return []
    lines = [f"### Waived runs ({len(s.waived)})", "",
             "| curve | vehicle | verdict | margin | reason | waiver |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {_md_code(cid)} | {_md_cell(v)} | {verdict} | {_fmt_margin(m, units)} | "
              f"{_md_cell(reason)} | {_md_cell(where)} |"
              for cid, v, verdict, m, reason, where in s.waived]
    lines.append("")
    return lines


def _md_curves(s: Section, folder: Path, units: str) -> list[str]:
    """The failing and tight curves with a figure (or a lost one): the figure or why it is
    missing, then every vehicle's run in words, worst first."""
    lines: list[str] = []
    for c in s.curves:
        if c.figure is None and not c.missing:
            continue
        lines += [f"### {_md_code(c.curve_id)}", ""]
        if c.serves:
            lines += [_md_cell(c.serves), ""]
        lines += ([f"![{_md_cell(c.curve_id)}]({_rel(c.figure, folder)})", "",
                   f"Every vehicle, worst first (the figure draws "
                   f"{counted(len(c.drawn), 'envelope')}):", ""] if c.figure is not None
                  else [_md_cell(c.missing), "", "Every vehicle, worst first:", ""])
        lines += [f"- {_md_cell(run_words(r, units))}"
                  + (" (drawn)" if r.vehicle in c.drawn else "") for r in c.runs]
        lines.append("")
    return lines


def _md_vertical(s: Section, folder: Path, units: str) -> list[str]:
    """The section's vertical checks: each curve's profile figure and its runs' findings
    (nothing when there are none)."""
    if not s.vertical:
        return []
    lines = ["### Vertical checks", ""]
    for v in s.vertical:
        lines += [f"#### {_md_code(v.curve_id)} (vertical)", ""]
        if v.figure is not None:
            lines += [f"![{_md_cell(v.curve_id)} profile]({_rel(v.figure, folder)})", ""]
        lines += [f"- {_md_cell(r.vehicle)}: "
                  f"{_md_cell(vertical_words(r, units) or 'clear')}"
                  for r in v.runs]
        lines.append("")
    return lines


def _md_tail(s: Section, units: str) -> list[str]:
    """The end of a section: the swung runs on the other curves, and how many failing or
    tight curves have no figure (each part only when there is something to say)."""
    lines: list[str] = []
    if s.swung:
        lines += [f"### Swung paths on the other curves ({len(s.swung)})", ""]
        lines += [f"- {_md_code(r.curve_id)}: {_md_cell(run_words(r, units))}"
                  for r in s.swung]
        lines.append("")
    if s.omitted:
        lines += [f"({s.omitted} more failing or tight curves are in the matrix and "
                  "in clearance.csv, without a figure.)", ""]
    return lines


def _md_section(s: Section, folder: Path, units: str) -> list[str]:
    """One network's part of ``report.md``, from its heading to its last note."""
    return (_md_overview(s, folder) + _md_worst(s, units) + _md_matrix(s, units)
            + _md_waived(s, units) + _md_curves(s, folder, units)
            + _md_vertical(s, folder, units) + _md_tail(s, units))


def _md_files() -> list[str]:
    """The closing list of the files beside the report."""
    return ["## Files", "",
            "- `clearance.csv`: one row per network × vehicle × curve",
            "- `summary.json`: counts by verdict per network and vehicle, inputs with "
            "SHA-256, versions",
            "- `exports/`: per network `NET.add.xml` (`sumo-gui -n NET -a "
            "exports/NET.add.xml`), `NET.dxf` (CAD: base plan, layers per vehicle) and "
            "`NET.geojson` (GIS; `NET.local-metres.geojson` without a projection)",
            "- `figures/`: every figure as PNG and SVG", ""]


def markdown(study: Study, sections: list[Section], folder: Path, units: str = "m") -> str:
    """``report.md``: the same content as the HTML, figures linked as PNG (SVG beside)."""
    lines = _md_head(study, sections, units) + _md_not_clear(sections, units)
    for s in sections:
        lines += _md_section(s, folder, units)
    lines += _md_files()
    return "\n".join(lines)
