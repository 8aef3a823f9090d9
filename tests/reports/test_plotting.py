"""Figures written by plotting.save: the SVG's path data to a hundredth of a point."""

from __future__ import annotations

import io
import re

import matplotlib.pyplot as plt
import numpy as np
from lxml import etree

from clearance.reports.documents.plotting import STYLE, new_figure, save, svg_rounded


def _numbers(svg: bytes) -> list[np.ndarray]:
    tree = etree.fromstring(svg)
    return [np.array([float(x) for x in re.findall(r"-?\d+(?:\.\d+)?", p.get("d"))])
            for p in tree.iter("{http://www.w3.org/2000/svg}path") if p.get("d")]


def test_saved_svg_paths_are_the_figures_to_a_hundredth_of_a_point(tmp_path):
    """A polygon of 400 vertices and text: the written SVG parses, holds the same paths
    with the same numbers to 0.01 pt as matplotlib's own, and is smaller."""
    fig, ax = new_figure()
    t = np.linspace(0.0, 2.0 * np.pi, 400)
    ax.fill(np.cos(t) * 37.123456, np.sin(3 * t) * 11.987654, alpha=0.4)
    ax.set_title("ring 37.123456 m")
    raw = io.BytesIO()
    with plt.rc_context(STYLE):
        fig.savefig(raw, format="svg", bbox_inches="tight", metadata={"Date": None})
    _, svg_path = save(fig, tmp_path / "fig")
    written = svg_path.read_bytes()
    assert written == svg_rounded(raw.getvalue())
    before, after = _numbers(raw.getvalue()), _numbers(written)
    assert len(before) == len(after) > 0
    for a, b in zip(before, after, strict=True):
        assert a.shape == b.shape and np.abs(a - b).max() < 0.01
    assert b"37.123456" in written  # the title's text is not touched
    assert len(written) < 0.95 * len(raw.getvalue())


def test_saved_png_is_on_a_palette_that_keeps_verdict_and_vehicle_colours(tmp_path):
    """A figure of thin vehicle lines and verdict fills on a smooth background: the PNG is
    palette-based, a third of matplotlib's or less, and every vehicle and verdict colour
    drawn is in it exactly."""
    from PIL import Image

    from clearance.reports.documents.colours import VERDICT_COLOURS
    from clearance.reports.documents.plotting import PALETTE

    fig, ax = new_figure()
    ax.imshow(np.linspace(0.0, 1.0, 400 * 300).reshape(300, 400), cmap="Greys",
              extent=(0, 40, 0, 30))
    for k, colour in enumerate(PALETTE[:8]):
        ax.plot([1, 39], [1 + k, 2 + k], color=colour, lw=0.8)
    for k, colour in enumerate(VERDICT_COLOURS.values()):
        ax.fill([5 + 6 * k, 9 + 6 * k, 9 + 6 * k], [15, 15, 25], color=colour)
    raw = io.BytesIO()
    with plt.rc_context(STYLE):
        fig.savefig(raw, format="png", bbox_inches="tight")
    png, _ = save(fig, tmp_path / "fig")
    with Image.open(png) as im:
        assert im.mode == "P"
        found = {"#" + bytes(c[1]).hex() for c in im.convert("RGB").getcolors(1 << 16)}
    assert set(PALETTE[:8]) <= found and "#ffffff" in found  # the paper stays white
    assert set(VERDICT_COLOURS.values()) - {"#000000"} <= found
    assert png.stat().st_size < 0.5 * len(raw.getvalue())
