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
