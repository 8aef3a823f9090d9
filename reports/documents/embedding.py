"""Which figures ``report.html`` embeds: the worst curves' first, within a budget of bytes.

``report.html`` is one file that can be mailed alone (:mod:`clearance.reports.documents.report`),
so what it embeds is bounded: the network plans and the vertical checks' profiles always
(one per network, one per ramp or curve a run scrapes on), and the curve figures in the order
the report ranks its curves (the worst first) as long as their compact copies
(:func:`clearance.reports.documents.html_images.compact_png`) total at most
:data:`FIGURE_BYTES`. A curve whose figure is beyond the budget names its full-resolution PNG
in ``figures/`` instead (as text: the page links nothing outside itself).

Each ``<img>`` carries its width and height, so that the page keeps its place for a figure
that loads lazily and a figure inside a closed ``<details>`` takes no room.
"""

from __future__ import annotations

import base64
import html
import struct
from collections.abc import Iterable
from pathlib import Path

from clearance.reports.documents.html_images import compact_png

__all__ = ["FIGURE_BYTES", "embed_within", "figure_img", "png_size"]

#: The curve figures ``report.html`` embeds total at most this many bytes (their ``<img>``
#: elements, base64 included): with the plans and the text, the default study's page stays
#: under 3 MB whatever the number of curves.
FIGURE_BYTES = 2_000_000


def png_size(data: bytes) -> tuple[int, int]:
    """A PNG's width and height in pixels, from its header.

    >>> png_size(bytes(16) + struct.pack(">II", 600, 325))
    (600, 325)
    """
    width, height = struct.unpack(">II", data[16:24])
    return int(width), int(height)


def figure_img(png: Path, alt: str, lazy: bool = True) -> str:
    """An ``<img>`` embedding the compact copy of ``png`` as a data URI, with its size;
    ``lazy``: loaded as it scrolls into view."""
    data = compact_png(png)
    width, height = png_size(data)
    loading = ' loading="lazy"' if lazy else ""
    return (f'<img alt="{html.escape(alt)}"{loading} width="{width}" height="{height}" '
            f'src="data:image/png;base64,{base64.b64encode(data).decode("ascii")}">')


def embed_within(figures: Iterable[tuple[Path, str]], budget: int = FIGURE_BYTES
                 ) -> dict[Path, str]:
    """The ``<img>`` of each figure, taken in order while they total at most ``budget``
    bytes: a figure that would go beyond it ends the list (those after it are not embedded
    either, so that what is embedded is always the first ones: the worst curves').

    ``figures``: each figure's PNG and its alternative text, in the order of priority; a
    figure given twice counts once.
    """
    out: dict[Path, str] = {}
    used = 0
    for png, alt in figures:
        if png in out:
            continue
        tag = figure_img(png, alt)
        used += len(tag)
        if used > budget:
            break
        out[png] = tag
    return out
