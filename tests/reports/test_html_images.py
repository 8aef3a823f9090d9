"""Compact figures for report.html keep the verdict colours exactly (documents/html_images)."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from clearance.reports.documents.colours import VERDICT_COLOURS  # noqa: E402
from clearance.reports.documents.html_images import HTML_IMAGE_COLOURS, compact_png  # noqa: E402


def _rgb(hex_colour: str) -> tuple[int, int, int]:
    r, g, b = bytes.fromhex(hex_colour.lstrip("#"))
    return r, g, b


def test_every_verdict_colour_survives_the_small_palette(tmp_path):
    """A figure of many colours (a smooth background the median cut spends its palette on)
    with a thin line of each verdict colour, near each other as orange and red are: the
    compact copy has each verdict colour exactly, and still few colours in all."""
    fig, ax = plt.subplots(figsize=(8, 6), dpi=100)
    ax.imshow(np.linspace(0, 1, 256 * 64).reshape(64, 256), cmap="viridis",
              extent=(0, 10, 0, 10), aspect="auto")
    for k, colour in enumerate(VERDICT_COLOURS.values()):
        ax.plot([1, 9], [2 + 1.5 * k, 2 + 1.5 * k], color=colour, lw=2.5)
    png = tmp_path / "f.png"
    fig.savefig(png)
    plt.close(fig)
    small = compact_png(png)
    with Image.open(io.BytesIO(small)) as im:
        assert im.mode == "P"
        rgb = im.convert("RGB")
        colours = {c for _, c in rgb.getcolors(1 << 16)}
    assert len(colours) <= HTML_IMAGE_COLOURS
    for verdict, colour in VERDICT_COLOURS.items():
        assert _rgb(colour) in colours, verdict
