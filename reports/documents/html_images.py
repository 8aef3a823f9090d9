"""The figures of ``report.html``, made small: compact PNG copies embedded as data URIs.

``report.html`` embeds its plans and its worst curves' figures, up to a budget
(:mod:`clearance.reports.documents.embedding`); a full-resolution PNG would make the file tens
of megabytes, so each is scaled down to :data:`HTML_IMAGE_WIDTH_PX` and
quantised to :data:`HTML_IMAGE_COLOURS` colours (:func:`compact_png`). The full PNG and the
SVG stay in ``figures/``. A worker that drew a figure makes its compact copy where the PNG
is (``clearance.reports.cli.report.curve_figure_files``) and the report's process keeps it in
:data:`COMPACT_MADE`, so that it is not made twice.
"""

from __future__ import annotations

import base64
import hashlib
import html
from collections.abc import Sequence
from pathlib import Path

from clearance.reports.documents.colours import VERDICT_COLOURS
from clearance.reports.documents.palette_png import quantised_png

__all__ = ["COMPACT_MADE", "HTML_IMAGE_COLOURS", "HTML_IMAGE_WIDTH_PX", "compact_key",
           "compact_png", "img_tag"]

#: Figures in report.html: at most this wide (pixels) and quantised to this many colours.
HTML_IMAGE_WIDTH_PX = 600
HTML_IMAGE_COLOURS = 24


#: Compact copies already made (by a worker that drew the figure, which has the PNG at
#: hand), by :func:`compact_key`: :func:`compact_png` of the same bytes returns them.
COMPACT_MADE: dict[str, bytes] = {}


def compact_key(data: bytes, width_px: int = HTML_IMAGE_WIDTH_PX,
                colours: int = HTML_IMAGE_COLOURS, kept: Sequence[str] = ()) -> str:
    """The key of a full PNG's compact copy in :data:`COMPACT_MADE`: its SHA-256, the size
    asked for and the colours kept besides the verdicts'.

    >>> compact_key(b"")[-7:]
    '-600-24'
    >>> compact_key(b"", kept=["#5dade2"]) != compact_key(b"")
    True
    """
    extra = sorted(set(kept) - set(VERDICT_COLOURS.values()))
    tail = "-" + hashlib.sha256(" ".join(extra).encode()).hexdigest()[:8] if extra else ""
    return f"{hashlib.sha256(data).hexdigest()}-{width_px}-{colours}{tail}"


def compact_png(png: Path, width_px: int = HTML_IMAGE_WIDTH_PX,
                colours: int = HTML_IMAGE_COLOURS, kept: Sequence[str] = ()) -> bytes:
    """A figure made small for the HTML: scaled down to ``width_px`` and quantised to a
    palette of ``colours`` (:func:`~clearance.reports.documents.palette_png.quantised_png`:
    the verdict colours and the ``kept`` ones exactly).

    The full-resolution PNG and the SVG stay in ``figures/``.
    """
    data = Path(png).read_bytes()
    made = COMPACT_MADE.get(compact_key(data, width_px, colours, kept))
    if made is not None:
        return made
    return quantised_png(data, colours, kept, width_px)


def img_tag(png: Path, alt: str, lazy: bool = True, kept: Sequence[str] = ()) -> str:
    """An ``<img>`` element embedding the compact copy of ``png`` (:func:`compact_png`,
    keeping the ``kept`` colours); ``lazy``: loaded as it scrolls into view."""
    data = base64.b64encode(compact_png(png, kept=kept)).decode("ascii")
    loading = ' loading="lazy"' if lazy else ""
    return f'<img alt="{html.escape(alt)}"{loading} src="data:image/png;base64,{data}">'
