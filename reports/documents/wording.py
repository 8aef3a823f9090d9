"""A run and its margins in words, as the report documents say them.

``report.html`` and ``report.md`` (:mod:`clearance.reports.documents.report`,
:mod:`clearance.reports.documents.markdown`) and the opening list of what is not clear
(:mod:`clearance.reports.documents.not_clear`) use the same words: a margin is how far
inside or beyond its lanes or the pavement, a run is its vehicle, verdict, margins and why.
"""

from __future__ import annotations

import math

from clearance.reports.results.units import length_scale, text_in_units

__all__ = ["MAX_ID_CHARS", "SYMBOL", "VERDICT_CLASS", "cell_margin", "margin_words",
           "margins_words", "rests_words", "run_words", "short_id"]

#: Each verdict's sign in a matrix cell and a list.
SYMBOL = {"clear": "✓", "encroaches": "~", "fails": "✗", "cannot-turn": "⊘", "error": "!"}
#: Each verdict's class in ``report.html`` (one letter: a matrix has thousands of cells;
#: no other class of the page is one of them), whose style gives the cell the verdict's
#: colour.
VERDICT_CLASS = {"clear": "c", "encroaches": "e", "fails": "f", "cannot-turn": "t",
                 "error": "x"}

def cell_margin(text: str) -> str:
    """A matrix cell's margin: signed, two decimals; "n/a" when the run has none."""
    value = float(text)
    return f"{value:+.2f}" if math.isfinite(value) else "n/a"


def margin_words(m: float, units: str = "m", what: str = "its lanes") -> str:
    """A margin in words: how far inside or beyond ``what``.

    Examples
    --------
    >>> margin_words(-0.2749), margin_words(0.41)
    ('0.27 m beyond its lanes', '0.41 m inside its lanes')
    >>> margin_words(float("nan"))
    'no margin (the run did not get through)'
    >>> margin_words(0.001, "m", "the pavement"), margin_words(-1.0, "ft")
    ('0.00 m inside the pavement', '3.28 ft beyond its lanes')
    """
    if not math.isfinite(m):
        return "no margin (the run did not get through)"
    value = abs(m) / length_scale(units)
    return f"{value:.2f} {units} {'beyond' if m < 0 else 'inside'} {what}"


def margins_words(r, units: str = "m") -> str:
    """A run's margin to its lanes and, where it has one, to the pavement, in words.

    >>> from types import SimpleNamespace as R
    >>> margins_words(R(margin_m=-0.2749, paved_margin_m=0.1))
    '0.27 m beyond its lanes, 0.10 m inside the pavement'
    >>> margins_words(R(margin_m=0.5))
    '0.50 m inside its lanes'
    """
    text = margin_words(r.margin_m, units)
    paved = getattr(r, "paved_margin_m", math.nan)
    if math.isfinite(paved):
        text += f", {margin_words(paved, units, 'the pavement')}"
    return text


def rests_words(geometry: str, units: str = "m") -> str:
    """What a run's verdict rests on (the ``geometry`` column), in words: the network's
    data, or the netconvert defaults it names.

    >>> rests_words("data"), rests_words("lane width default 3.2 m", "ft")
    ("the network's data", 'lane width default 10.5 ft')
    """
    if not geometry or geometry == "data":
        return "the network's data"
    return text_in_units(geometry, units)


def run_words(r, units: str = "m") -> str:
    """One run for a caption: vehicle, verdict, lane margin and paved margin in words, and
    for a swung or not clear run its reason (the path it took, how far it reaches beyond
    which area, where the worst overreach is and the extra width there)."""
    text = f"{r.vehicle}: {r.verdict}, {margins_words(r, units)}"
    reason = getattr(r, "reason", "")
    if reason and (getattr(r, "path", "lane") == "swung" or r.verdict != "clear"):
        text += f": {text_in_units(reason, units)}"
    where = getattr(r, "conflict_at", "")
    if where and r.verdict != "clear":
        text += f"; worst conflict {text_in_units(where, units)}"
    rests = getattr(r, "geometry", "")
    if rests and rests != "data" and r.verdict != "clear":
        text += f"; rests on {text_in_units(rests, units)}"
    return text


#: A curve id longer than this many characters is shortened in the matrix (the full id on
#: hover): a 190-character OSM cluster id pushed every verdict column off the screen.
MAX_ID_CHARS = 48


def short_id(curve_id: str, limit: int = MAX_ID_CHARS) -> str:
    """``curve_id`` shortened in its middle to ``limit`` characters, its kind and junction
    start and its lanes' end kept.

    >>> short_id("turn:cluster_1_2_3_4_5_6_7_8_9:a_0->b_0", 24)
    'turn:cluster_1…:a_0->b_0'
    >>> short_id("turn:J:a_0->b_0")
    'turn:J:a_0->b_0'
    """
    if len(curve_id) <= limit:
        return curve_id
    tail = curve_id[curve_id.rfind(":"):] if ":" in curve_id else ""
    tail = tail if len(tail) < limit // 2 else tail[-(limit // 2):]
    return curve_id[:limit - len(tail) - 1] + "…" + tail
