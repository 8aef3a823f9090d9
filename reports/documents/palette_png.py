"""PNG images on a palette that keeps the colours that mean something exactly.

A figure's PNG from matplotlib is true colour: every shade of anti-aliasing its own, about
250 kB a curve figure. On a palette of 256 colours it is a third of that and looks the
same; the verdict colours (:data:`~clearance.reports.documents.colours.VERDICT_COLOURS`) and
any others asked for (the vehicles') are in the palette whatever the median cut finds,
and the pixels nearest each of them take it exactly, so thin coloured lines on a grey
plan keep their colour and ``encroaches`` orange never merges with ``fails`` red.
:func:`clearance.reports.documents.plotting.save` writes figures so, and report.html's small
copies (:func:`clearance.reports.documents.html_images.compact_png`) are made so, smaller.
"""

from __future__ import annotations

import io
from collections.abc import Sequence

import numpy as np

from clearance.reports.documents.colours import VERDICT_COLOURS

__all__ = ["PAPER", "quantised_png"]

#: White, kept exact on every palette: the median cut averaged it with the anti-aliased
#: pixels next to it into (252, 252, 252), a grey box on a white page.
PAPER = "#ffffff"


def quantised_png(data: bytes, colours: int = 256, kept: Sequence[str] = (),
                  width_px: int | None = None, fast: bool = False) -> bytes:
    """The PNG ``data`` on a palette of ``colours`` (with Pillow, which matplotlib
    requires), white (:data:`PAPER`), the verdict colours and the ``kept`` ones
    (``#rrggbb``) exactly; scaled down
    to ``width_px`` first when it is wider. The palette is the median cut's (an octree's
    crowds the kept colours with near ones, and thin lines lose theirs), the PNG
    compressed as tightly as Pillow can; ``fast``: compressed once (a full-size figure in
    0.066 s against 0.1 s, 8 % larger).

    Examples
    --------
    >>> from PIL import Image
    >>> im = Image.new("RGB", (40, 10), "#ffffff")
    >>> im.paste((211, 84, 0), (0, 0, 20, 10))  # encroaches orange, exactly
    >>> buf = io.BytesIO(); im.save(buf, "PNG")
    >>> out = Image.open(io.BytesIO(quantised_png(buf.getvalue(), colours=8)))
    >>> rgb = out.convert("RGB")
    >>> out.mode, rgb.getpixel((5, 5)), rgb.getpixel((35, 5)), out.size
    ('P', (211, 84, 0), (255, 255, 255), (40, 10))
    >>> Image.open(io.BytesIO(quantised_png(buf.getvalue(), width_px=20))).size
    (20, 5)
    """
    from PIL import Image

    kept = list(dict.fromkeys([PAPER, *VERDICT_COLOURS.values(), *kept]))
    with Image.open(io.BytesIO(data)) as opened:
        im = opened.convert("RGB")
    if width_px is not None and im.width > width_px:
        im = im.resize((width_px, round(im.height * width_px / im.width)),
                       Image.Resampling.LANCZOS)
    # the median cut's palette less room for the kept colours, then those exactly
    cut = im.quantize(colours - len(kept), method=Image.Quantize.MEDIANCUT,
                      dither=Image.Dither.NONE)
    entries = [b for c in kept for b in bytes.fromhex(c.lstrip("#"))]
    entries += (cut.getpalette() or [])[:3 * (colours - len(kept))]
    palette = Image.new("P", (1, 1))
    palette.putpalette(entries + entries[:3] * (256 - len(entries) // 3))
    mapped = im.quantize(palette=palette, dither=Image.Dither.NONE)
    # Pillow maps a pixel to the entry nearest its cell at reduced precision (white went to
    # the median cut's 252 grey): a pixel of a kept colour takes that colour's entry
    rgb = np.asarray(im, dtype=np.uint32)
    code = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
    wanted = np.array([int(c.lstrip("#"), 16) for c in kept], dtype=np.uint32)
    order = np.argsort(wanted)
    at = np.minimum(np.searchsorted(wanted[order], code), len(kept) - 1)
    hit = wanted[order][at] == code
    index = np.array(mapped, dtype=np.uint8)
    index[hit] = order[at[hit]]
    out = Image.fromarray(index, mode="P")
    out.putpalette(palette.getpalette() or [])
    im = out
    buf = io.BytesIO()
    im.save(buf, "PNG", optimize=not fast)
    return buf.getvalue()
