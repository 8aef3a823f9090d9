"""The verdict colours: one palette for every figure, sheet, badge, table cell and map.

Defined once here; the report's embedded images keep them exactly when they are reduced to a
small palette (:func:`clearance.reports.documents.html_images.compact_png`), so ``encroaches``
orange and ``fails`` red never merge into one colour. Dark enough to carry white text on a
badge.

Examples
--------
>>> sorted(VERDICT_COLOURS) == ["cannot-turn", "clear", "encroaches", "error", "fails"]
True
>>> len(set(VERDICT_COLOURS.values())) == len(VERDICT_COLOURS)  # each verdict its own
True
"""

from __future__ import annotations

__all__ = ["VERDICT_COLOURS"]

#: Colour (``#rrggbb``) of each verdict.
VERDICT_COLOURS = {"clear": "#1e8449", "encroaches": "#d35400", "fails": "#c0392b",
                   "cannot-turn": "#7d3c98", "error": "#000000"}
