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

from clearance.reports.documents.colours import VERDICT_COLOURS

__all__ = ["quantised_png"]


def quantised_png(data: bytes, colours: int = 256, kept: Sequence[str] = (),
                  width_px: int | None = None, fast: bool = False) -> bytes:
    """The PNG ``data`` on a palette of ``colours`` (with Pillow, which matplotlib
    requires), the verdict colours and the ``kept`` ones (``#rrggbb``) exactly; scaled down
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
    >>> out.mode, out.convert("RGB").getpixel((5, 5)), out.size
    ('P', (211, 84, 0), (40, 10))
    >>> Image.open(io.BytesIO(quantised_png(buf.getvalue(), width_px=20))).size
    (20, 5)
    """
    from PIL import Image

    kept = list(dict.fromkeys([*VERDICT_COLOURS.values(), *kept]))
    with Image.open(io.BytesIO(data)) as opened:
        im = opened.convert("RGB")
    if width_px is not None and im.width > width_px:
        im = im.resize((width_px, round(im.height * width_px / im.width)),
                       Image.Resampling.LANCZOS)
    # the median cut's palette less room for the kept colours, then those exactly
    cut = im.quantize(colours - len(kept), method=Image.Quantize.MEDIANCUT,
                      dither=Image.Dither.NONE)
    entries = (cut.getpalette() or [])[:3 * (colours - len(kept))]
    entries += [b for c in kept for b in bytes.fromhex(c.lstrip("#"))]
    palette = Image.new("P", (1, 1))
    palette.putpalette(entries + entries[:3] * (256 - len(entries) // 3))
    im = im.quantize(palette=palette, dither=Image.Dither.NONE)
    buf = io.BytesIO()
    im.save(buf, "PNG", optimize=not fast)
    return buf.getvalue()
