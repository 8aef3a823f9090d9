"""What ``report.html`` opens with: every curve that is not clear, worst first.

One row per curve that some vehicle does not clear, over every network of the study: the
curve (linked to its section), its worst run (vehicle, verdict, margins in words), the
vehicles it is not clear for and what the worst run's verdict rests on (the network's data
or netconvert's defaults, :mod:`clearance.networks.provenance`). The rows are ordered as the
verdicts are (:data:`clearance.reports.results.records.VERDICT_ORDER`: an error, then
cannot-turn, fails, encroaches), then by the margin to the lanes, the smallest first.
"""

from __future__ import annotations

import html
import math
from collections.abc import Collection, Iterable
from dataclasses import dataclass

from clearance.reports.documents.wording import (
    SYMBOL,
    VERDICT_CLASS,
    margins_words,
    rests_words,
    short_id,
)
from clearance.reports.results.records import VERDICT_ORDER
from clearance.reports.results.text_table import counted

__all__ = ["MAX_NAMED", "NOT_CLEAR_ID", "NotClear", "not_clear_first", "not_clear_for",
           "not_clear_html", "run_rank"]

#: The HTML id of the list (the contents link to it).
NOT_CLEAR_ID = "not-clear"
#: At most this many vehicles are named in a row's "not clear for" (then how many more).
MAX_NAMED = 3


def run_rank(r) -> tuple[int, float]:
    """How bad a run is, for sorting (smaller is worse): its verdict's rank, then its margin
    to its lanes (a run without one, which did not get through, first).

    >>> from types import SimpleNamespace as R
    >>> runs = [R(verdict="fails", margin_m=-0.5), R(verdict="cannot-turn", margin_m=0.2),
    ...         R(verdict="fails", margin_m=-1.5), R(verdict="fails", margin_m=math.nan)]
    >>> [(r.verdict, r.margin_m) for r in sorted(runs, key=run_rank)]
    [('cannot-turn', 0.2), ('fails', nan), ('fails', -1.5), ('fails', -0.5)]
    """
    m = float(r.margin_m)
    return VERDICT_ORDER[r.verdict], m if math.isfinite(m) else -math.inf


@dataclass(frozen=True)
class NotClear:
    """A curve that a vehicle does not clear: its network, its id and every run on it."""

    network: str
    curve_id: str
    runs: tuple  # RunRecord

    @property
    def worst(self):
        """The worst run on the curve (:func:`run_rank`)."""
        return min(self.runs, key=run_rank)

    @property
    def not_clear(self) -> list:
        """The runs on the curve that are not clear, worst first."""
        return sorted((r for r in self.runs if r.verdict != "clear"), key=run_rank)


def not_clear_first(curves: Iterable[tuple[str, str, Iterable]]) -> list[NotClear]:
    """The curves (network, curve id, runs) with a run that is not clear, worst first: by
    their worst runs (:func:`run_rank`); curves as bad as each other in the order given.

    >>> from types import SimpleNamespace as R
    >>> rows = not_clear_first([
    ...     ("a", "ok", [R(verdict="clear", margin_m=0.1)]),
    ...     ("a", "wide", [R(verdict="clear", margin_m=0.3), R(verdict="encroaches",
    ...                                                        margin_m=-0.4)]),
    ...     ("b", "bad", [R(verdict="fails", margin_m=-0.2)])])
    >>> [(r.network, r.curve_id, r.worst.verdict) for r in rows]
    [('b', 'bad', 'fails'), ('a', 'wide', 'encroaches')]
    """
    rows = [NotClear(network, cid, tuple(runs)) for network, cid, runs in curves]
    rows = [r for r in rows if any(run.verdict != "clear" for run in r.runs)]
    return sorted(rows, key=lambda r: run_rank(r.worst))


def not_clear_for(row: NotClear) -> str:
    """The vehicles a curve is not clear for, worst first: how many of the vehicles run on
    it, and at most :data:`MAX_NAMED` named, then how many more.

    >>> from types import SimpleNamespace as R
    >>> runs = [R(vehicle=v, verdict="fails", margin_m=-i) for i, v in enumerate("ABCDE")]
    >>> not_clear_for(NotClear("n", "c", (*runs, R(vehicle="F", verdict="clear",
    ...                                             margin_m=1.0))))
    '5 of 6: E, D, C and 2 more'
    """
    names = [r.vehicle for r in row.not_clear]
    more = len(names) - MAX_NAMED
    return (f"{len(names)} of {len(row.runs)}: " + ", ".join(names[:MAX_NAMED])
            + (f" and {more} more" if more > 0 else ""))


def _row_html(i: int, row: NotClear, link: str, units: str, networks: bool,
              waived: Collection[tuple[str, str, str]]) -> str:
    """One curve's row of the list (its worst run marked when a waiver accepts it)."""
    e = html.escape
    w = row.worst
    mark = " (waived)" if (row.network, row.curve_id, w.vehicle) in waived else ""
    network = f'<td class="id">{e(row.network)}</td>' if networks else ""
    return (f"<tr><td>{i}</td>{network}"
            f'<td class="id" title="{e(row.curve_id)}"><a href="#{link}">'
            f"{e(short_id(row.curve_id))}</a></td>"
            f'<td class="tx">{e(w.vehicle)}{mark}</td>'
            f'<td class="{VERDICT_CLASS[w.verdict]}">{SYMBOL[w.verdict]} {e(w.verdict)}</td>'
            f'<td class="wrap">{e(margins_words(w, units))}</td>'
            f'<td class="wrap">{e(not_clear_for(row))}</td>'
            f'<td class="wrap">{e(rests_words(getattr(w, "geometry", ""), units))}</td></tr>')


def not_clear_html(rows: list[NotClear], links: dict[tuple[str, str], str], units: str,
                   networks: int, tight: str = "",
                   waived: Collection[tuple[str, str, str]] = ()) -> list[str]:
    """The list as the opening section of ``report.html``: a heading, how to read it and
    the table (in a box that scrolls, its heading row in view); ``links``: each curve's
    section id by (network, curve id); ``networks``: how many the study has (the network
    column only with more than one); ``tight``: a sentence on the curves clear with little
    to spare, which the list leaves out; ``waived``: the runs (network, curve id, vehicle)
    a waiver accepts."""
    out = [f'<h2 id="{NOT_CLEAR_ID}">Not clear, worst first</h2>']
    if not rows:
        return out + [f"<p>Every vehicle clears every curve. {html.escape(tight)}</p>"]
    runs = sum(len(r.not_clear) for r in rows)
    out.append(f"<p>{counted(len(rows), 'curve')} not clear for at least one vehicle "
               f"({counted(runs, 'run')}), the worst first: by the verdict of its worst run "
               "(cannot-turn, fails, encroaches), then by that run's margin to its lanes. "
               "Click a curve for its section: its figure and every vehicle's run in "
               f"words. {html.escape(tight)}</p>")
    head = "".join(f"<th>{h}</th>" for h in (
        "#", *(["network"] if networks > 1 else []), "curve", "worst run", "verdict",
        "margins", "not clear for", "the worst run rests on"))
    out.append(f'<div class="first"><table><thead><tr>{head}</tr></thead><tbody>')
    out += [_row_html(i, r, links[r.network, r.curve_id], units, networks > 1, waived)
            for i, r in enumerate(rows, start=1)]
    out.append("</tbody></table></div>")
    return out
