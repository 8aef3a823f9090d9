"""Design feedback: which vehicles a curve serves, and where and by how much a run overreaches.

docs/design.md §6, *Design feedback*:

- **Serves up to.** For each curve of a study, the largest vehicle of the study that
  *clears* it (verdict ``clear``: ``serves_up_to``) and the largest that stays on the
  pavement (``clear`` or ``encroaches``: ``serves_encroaching_up_to``). Vehicles are
  ordered by their curb-to-curb turning diameter at full lock (``curb_to_curb`` of
  ``clearance vehicles``, :func:`clearance.analysis.turning.turning_metrics`; a combination's is its
  tractor's, as that command reports it), ties by overall length, then by the table's
  order (:func:`size_order`). Only the vehicles run on the curve count (not those its
  lanes do not admit, nor ``error`` runs). "Largest that clears" does not say that every
  smaller vehicle clears: where a smaller one does not (a long-wheelbase car that cannot
  swing where a bus can), :func:`not_served_below` names it and the report says so.
- **Worst overreach.** For each run not clear (``fails`` or ``encroaches``), the point of
  its measured envelope (grown by the clearance offset) farthest beyond the area its
  verdict is decided on: the paved area for ``fails``, its own lanes for ``encroaches``
  (:func:`clearance.analysis.overreach.worst_overreach`), with its station along the curve's centre
  line, and the extra width that area needs there (:func:`overreach_of`).
"""

from __future__ import annotations

import html
import math
from collections.abc import Callable, Iterable, Sequence

import pandas as pd

from clearance.analysis.overreach import Overreach, worst_overreach
from clearance.analysis.turning import turning_metrics
from clearance.networks.curves import Curve
from clearance.reports.results.records import RunRecord
from clearance.vehicles.table import VehicleTable

__all__ = ["ENCROACHING", "SERVES_NOTE", "SERVING", "beyond_words", "not_served_below",
           "overreach_of", "overreach_point", "overreach_words", "serves", "serves_counts",
           "serves_html", "serves_markdown", "serves_sentence", "set_overreach",
           "set_serves_up_to", "size_order"]

#: Verdicts with which a vehicle is served: clear, and on the pavement.
SERVING = ("clear",)
ENCROACHING = ("clear", "encroaches")


def size_order(table: VehicleTable) -> list[str]:
    """The table's vehicle names, smallest first: by curb-to-curb turning diameter at full
    lock, then overall length, then the table's order.

    Examples
    --------
    >>> from clearance.vehicles.table import bundled_table, load_tables
    >>> size_order(load_tables([bundled_table("aashto_green_book")], ["WB-62", "SU-30", "P"]))
    ['P', 'SU-30', 'WB-62']
    """
    metrics = turning_metrics(table)
    lengths = {v.name: v.overall_length_m for v in table.vehicles()}
    # a diameter that is not a number (no lock data) sorts last, by length among those
    keyed = [(float(d) if math.isfinite(float(d)) else math.inf, lengths[name], i, name)
             for i, (name, d) in enumerate(zip(metrics["vehicle"], metrics["curb_to_curb_m"],
                                               strict=True))]
    return [name for *_, name in sorted(keyed)]


def serves(verdicts: dict[str, str], order: Sequence[str], ok: Iterable[str] = SERVING
           ) -> str:
    """The largest vehicle of ``order`` (smallest first) whose verdict is in ``ok``; ``""``
    when none is.

    Examples
    --------
    >>> order = ["P", "SU-30", "WB-62"]
    >>> serves({"P": "clear", "SU-30": "encroaches", "WB-62": "fails"}, order)
    'P'
    >>> serves({"P": "clear", "SU-30": "encroaches", "WB-62": "fails"}, order, ENCROACHING)
    'SU-30'
    >>> serves({"P": "fails", "SU-30": "clear"}, order), serves({"P": "fails"}, order)
    ('SU-30', '')
    """
    allowed = set(ok)
    best = ""
    for name in order:
        if verdicts.get(name) in allowed:
            best = name
    return best


def not_served_below(verdicts: dict[str, str], order: Sequence[str], served: str,
                     ok: Iterable[str] = SERVING) -> list[str]:
    """The vehicles smaller than ``served`` that are run on the curve and not served.

    Examples
    --------
    >>> not_served_below({"P": "fails", "SU-30": "clear", "WB-62": "fails"},
    ...                  ["P", "SU-30", "WB-62"], "SU-30")
    ['P']
    >>> not_served_below({"P": "clear"}, ["P"], "")
    []
    """
    if not served:
        return []
    allowed = set(ok)
    smaller = order[:list(order).index(served)]
    return [n for n in smaller if n in verdicts and verdicts[n] not in allowed]


def set_serves_up_to(records: Sequence[RunRecord], table: VehicleTable) -> None:
    """Fill ``serves_up_to`` and ``serves_encroaching_up_to`` on every record, per curve
    (network and curve id) over the vehicles run on it."""
    order = size_order(table)
    by_curve: dict[tuple[str, str], dict[str, str]] = {}
    for r in records:
        if r.verdict != "error":
            by_curve.setdefault((r.network, r.curve_id), {})[r.vehicle] = r.verdict
    for r in records:
        verdicts = by_curve.get((r.network, r.curve_id), {})
        r.serves_up_to = serves(verdicts, order)
        r.serves_encroaching_up_to = serves(verdicts, order, ENCROACHING)


def overreach_of(verdict: str, envelope: object, curve: Curve) -> Overreach | None:
    """The worst overreach of a run's measured envelope (see the module docstring): beyond
    the paved area for ``fails``, beyond its own lanes for ``encroaches``; ``None`` for
    the other verdicts, without an envelope or areas."""
    area = {"fails": curve.paved, "encroaches": curve.own_lanes}.get(verdict)
    if area is None or envelope is None or getattr(envelope, "is_empty", True):
        return None
    return worst_overreach(envelope, area, curve.centerline)  # type: ignore[arg-type]


def beyond_words(verdict: str) -> str:
    """What a verdict's overreach is measured beyond.

    >>> beyond_words("fails"), beyond_words("encroaches"), beyond_words("clear")
    ('the paved area', 'its own lanes', '')
    """
    return {"fails": "the paved area", "encroaches": "its own lanes"}.get(verdict, "")


def overreach_words(o: Overreach, verdict: str) -> str:
    """Where the worst overreach is and the extra width there, for a reason.

    >>> print(overreach_words(Overreach(0.62, 101.234, -5.0, 41.26, 0.65), "fails"))
    ... # doctest: +NORMALIZE_WHITESPACE
    worst at station 41.3 m of the curve (x 101.23, y -5.00): the paved area needs 0.65 m
    more width there
    """
    where = (f"station {o.station_m:.1f} m of the curve " if math.isfinite(o.station_m)
             else "")
    need = "needs" if verdict == "fails" else "need"
    return (f"worst at {where}(x {o.x:.2f}, y {o.y:.2f}): {beyond_words(verdict)} "
            f"{need} {o.extra_width_m:.2f} m more width there")


def set_overreach(record: RunRecord, curve: Curve) -> None:
    """Fill a record's overreach columns from its envelope and say where in its reason."""
    o = overreach_of(record.verdict, record.envelope, curve)
    if o is None:
        return
    record.overreach_station_m = round(o.station_m, 3)
    record.overreach_x = round(o.x, 3)
    record.overreach_y = round(o.y, 3)
    record.extra_width_m = o.extra_width_m
    record.reason = f"{record.reason}; {overreach_words(o, record.verdict)}"


def serves_counts(frame: pd.DataFrame, order: Sequence[str]) -> list[tuple[str, int, int]]:
    """Per vehicle of ``order`` (smallest first, ``""`` first for none): how many curves
    of ``frame`` (``clearance.csv`` rows) it is the largest vehicle that clears, and that
    stays paved on; vehicles no curve names are left out.

    Examples
    --------
    >>> f = pd.DataFrame({"curve_id": ["a", "a", "b", "c"], "vehicle": ["P", "SU-30", "P", "P"],
    ...                   "serves_up_to": ["P", "P", "", "P"],
    ...                   "serves_encroaching_up_to": ["SU-30", "SU-30", "P", "P"]})
    >>> serves_counts(f, ["P", "SU-30"])
    [('', 1, 0), ('P', 2, 2), ('SU-30', 0, 1)]
    """
    per_curve = frame.drop_duplicates(["network", "curve_id"] if "network" in frame
                                      else ["curve_id"])
    clear = per_curve["serves_up_to"].fillna("").value_counts()
    paved = per_curve["serves_encroaching_up_to"].fillna("").value_counts()
    out = []
    for name in ["", *order]:
        a, b = int(clear.get(name, 0)), int(paved.get(name, 0))
        if a or b:
            out.append((name, a, b))
    return out


def serves_sentence(verdicts: dict[str, str], order: Sequence[str]) -> str:
    """What a curve serves, in words (``verdicts`` by vehicle, ``order`` smallest first).

    Examples
    --------
    >>> order = ["P", "SU-30", "WB-62"]
    >>> print(serves_sentence({"P": "clear", "SU-30": "encroaches", "WB-62": "fails"}, order))
    Serves up to P (clear); up to SU-30 staying on the pavement (encroaching).
    >>> print(serves_sentence({"P": "fails", "SU-30": "clear", "WB-62": "fails"}, order))
    ... # doctest: +NORMALIZE_WHITESPACE
    Serves up to SU-30 (clear), though the smaller P does not clear it; no larger vehicle
    stays on the pavement.
    >>> print(serves_sentence({"P": "encroaches"}, order))
    No vehicle of the study clears it; up to P staying on the pavement (encroaching).
    >>> print(serves_sentence({"P": "fails"}, order))
    Serves no vehicle of the study: none clears it, none stays on the pavement.
    """
    clear = serves(verdicts, order)
    paved = serves(verdicts, order, ENCROACHING)
    if not paved:
        return "Serves no vehicle of the study: none clears it, none stays on the pavement."
    text = f"Serves up to {clear} (clear)" if clear else "No vehicle of the study clears it"
    gaps = not_served_below(verdicts, order, clear)
    if gaps:
        text += (f", though the smaller {', '.join(gaps)} "
                 f"{'does' if len(gaps) == 1 else 'do'} not clear it")
    if paved != clear:
        text += f"; up to {paved} staying on the pavement (encroaching)"
        gaps = [g for g in not_served_below(verdicts, order, paved, ENCROACHING)
                if g not in not_served_below(verdicts, order, clear)]
        if gaps:
            verb = "leaves" if len(gaps) == 1 else "leave"
            text += f", though the smaller {', '.join(gaps)} {verb} the pavement"
    elif clear:
        text += "; no larger vehicle stays on the pavement"
    return text + "."


def overreach_point(record: RunRecord) -> tuple[float, float, float, float] | None:
    """A record's worst overreach as the exports take it: ``(x, y, station_m,
    extra_width_m)``, or None (a run clear, cannot-turn, error, or without one).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> overreach_point(NS(overreach_x=1.0, overreach_y=2.0, overreach_station_m=3.0,
    ...                    extra_width_m=0.4))
    (1.0, 2.0, 3.0, 0.4)
    >>> overreach_point(NS(overreach_x=math.nan, overreach_y=math.nan,
    ...                    overreach_station_m=math.nan, extra_width_m=math.nan)) is None
    True
    """
    values = (record.overreach_x, record.overreach_y, record.overreach_station_m,
              record.extra_width_m)
    if not all(math.isfinite(v) for v in values):
        return None
    return values


#: What the per-network table of design feedback counts (its caption, in words).
SERVES_NOTE = ("the largest vehicle of the study (by curb-to-curb turning diameter) that "
               "clears the curve, and that stays on the pavement (clear or encroaching); a "
               "smaller vehicle may still not clear it (the curve's section says so)")


def _serves_rows(serves: Sequence[tuple[str, int, int]]) -> list[tuple[str, int, int]]:
    return [(name or "none", a, b) for name, a, b in serves]


def serves_html(serves: Sequence[tuple[str, int, int]]) -> str:
    """The report's table of curves by what they serve up to (:func:`serves_counts`)."""
    e = html.escape
    rows = "".join(f'<tr><td class="id">{e(name)}</td><td>{a}</td><td>{b}</td></tr>'
                   for name, a, b in _serves_rows(serves))
    return (f"<p>Design feedback: curves by what they serve up to ({SERVES_NOTE}).</p>"
            '<table><tr><th class="id">vehicle</th><th>curves it is the largest to clear'
            "</th><th>to stay paved on</th></tr>" + rows + "</table>")


def serves_markdown(serves: Sequence[tuple[str, int, int]],
                    cell: Callable[[str], str]) -> list[str]:
    """The same table as markdown lines (``cell`` escapes a cell's text)."""
    return [f"Design feedback: curves by what they serve up to ({SERVES_NOTE}).", "",
            "| vehicle | curves it is the largest to clear | to stay paved on |",
            "|---|---|---|",
            *(f"| {cell(name)} | {a} | {b} |" for name, a, b in _serves_rows(serves)), ""]
