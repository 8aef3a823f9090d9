"""Shared figure helpers: a headless backend, one style, PNG and SVG written atomically
(the PNG on a palette, the SVG's paths to a hundredth of a point),
one colour per vehicle, plan axes, scale bars and north arrows in the report's units."""

from __future__ import annotations

import io
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

from clearance.reports.documents.palette_png import quantised_png  # noqa: E402
from clearance.reports.output.atomic import write_bytes_atomic  # noqa: E402
from clearance.reports.results.units import length_scale  # noqa: E402

if TYPE_CHECKING:
    from matplotlib.typing import RcKeyType

__all__ = ["PALETTE", "PNG", "PNG_SVG", "STYLE", "add_north_arrow", "add_scale_bar", "new_figure",
           "nice_length", "nice_step", "plan_axes", "save", "svg_rounded", "unit_name",
           "vehicle_colours"]

STYLE: dict[RcKeyType, Any] = {
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "legend.fontsize": 7,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "svg.hashsalt": "clearance",  # stable SVG ids: identical inputs, identical files
}


def new_figure(width_in: float = 7.0, height_in: float = 4.5) -> tuple[Figure, Axes]:
    """A figure at print size (inches) in the project's style."""
    with plt.rc_context(STYLE):
        fig, ax = plt.subplots(figsize=(width_in, height_in), dpi=150)
    return fig, ax


#: A report's figures: PNG; with ``clearance report --svg``, SVG beside each.
PNG: tuple[str, ...] = ("png",)
PNG_SVG: tuple[str, ...] = ("png", "svg")


def save(fig: Figure, path_stem: str | Path, formats: tuple[str, ...] = PNG_SVG
         ) -> list[Path]:
    """Write ``path_stem.png`` (and ``.svg``) atomically; close the figure. The PNG is on a
    palette of 256 colours, the verdicts' and the vehicles' (:data:`PALETTE`) exact
    (:func:`~clearance.reports.documents.palette_png.quantised_png`); the SVG's path
    coordinates are written to a hundredth of a point (:func:`svg_rounded`)."""
    out = []
    with plt.rc_context(STYLE):
        for fmt in formats:
            buf = io.BytesIO()
            metadata = {"Date": None} if fmt == "svg" else {"Software": None}
            fig.savefig(buf, format=fmt, bbox_inches="tight", metadata=metadata)
            data = buf.getvalue()
            if fmt == "svg":
                data = svg_rounded(data)
            elif fmt == "png":  # a third of the size, the meaningful colours exact
                data = quantised_png(data, kept=PALETTE, fast=True)
            out.append(write_bytes_atomic(Path(f"{path_stem}.{fmt}"), data))
    plt.close(fig)
    return out


_PATH_DATA = re.compile(rb' d="([^"]*)"')
_LONG_NUMBER = re.compile(rb"(-?\d+\.\d{2})\d+")


def svg_rounded(svg: bytes) -> bytes:
    """An SVG with the numbers of its path data cut to two decimals.

    matplotlib writes path coordinates in points to six decimals; a hundredth of a point
    (3.5 micrometres on paper) is finer than any printer, and the default study's SVG
    figures are an eighth smaller (13.1 MB to 11.5 MB). Only ``d`` attributes change:
    text, transforms and styles are left as they are.

    Examples
    --------
    >>> svg_rounded(b'<path d="M 196.760936 209.328038 L 198.1 -206.64745 z" '
    ...             b'transform="scale(0.015625)"/>')
    b'<path d="M 196.76 209.32 L 198.1 -206.64 z" transform="scale(0.015625)"/>'
    >>> svg_rounded(b"<svg/>")  # nothing to cut
    b'<svg/>'
    """
    return _PATH_DATA.sub(lambda m: b' d="' + _LONG_NUMBER.sub(rb"\1", m.group(1)) + b'"',
                          svg)


#: Vehicle colours: distinguishable on a grey plan and in print, none of them the
#: conflict hatches' red and orange or the plan's greys. A vehicle keeps its colour
#: (:func:`vehicle_colours`) in every figure and sheet of a report.
PALETTE = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#000075",
           "#808000", "#f032e6", "#469990", "#7b4173", "#636363", "#31a354", "#756bb1",
           "#6a3d9a", "#2f4f4f", "#0e6655", "#1b9e77", "#a55194", "#3182bd")


def vehicle_colours(names: Sequence[str]) -> dict[str, str]:
    """One colour per vehicle, by its place in the study's table (``names`` in order).

    The same table gives the same colours in every figure; past :data:`PALETTE`'s length
    the colours repeat (a figure shows a few vehicles, told apart by the legend too).

    Examples
    --------
    >>> c = vehicle_colours(["P", "SU-30", "WB-62"])
    >>> c["P"] == PALETTE[0], len(set(c.values()))
    (True, 3)
    >>> vehicle_colours([])
    {}
    """
    return {n: PALETTE[i % len(PALETTE)] for i, n in enumerate(dict.fromkeys(names))}


def unit_name(units: str) -> str:
    """``metres`` or ``feet``."""
    return "feet" if units == "ft" else "metres"


def nice_step(span: float) -> float:
    """A round step (1, 2, 2.5, 5 x 10^k) of about a fifth of ``span``.

    Examples
    --------
    >>> nice_step(100.0), nice_step(37.0), nice_step(0.0)
    (20.0, 5.0, 1.0)
    """
    if not span > 0:
        return 1.0
    target = span / 5
    base = 10 ** math.floor(math.log10(target))
    for m in (5, 2.5, 2, 1):
        if m * base <= target:
            return float(m * base)
    return float(base)


def plan_axes(ax: Axes, units: str = "m", labels: bool = True) -> None:
    """Ticks of a plan (drawn in metres) at round values of ``units``, labelled in them."""
    from matplotlib.ticker import FuncFormatter, MultipleLocator

    scale = length_scale(units)
    for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        step = nice_step((lim[1] - lim[0]) / scale)
        axis.set_major_locator(MultipleLocator(step * scale))
        # rounded: a tick at 0 computed as -7e-15 must read "0"
        axis.set_major_formatter(FuncFormatter(lambda v, _p: f"{round(v / scale, 6) + 0.0:g}"))
    if labels:
        ax.set_xlabel(f"x [{units}] (east)")
        ax.set_ylabel(f"y [{units}] (north)")
    ax.tick_params(labelsize=7)


def add_scale_bar(ax: Axes, units: str = "m", where: tuple[float, float] = (0.04, 0.04)
                  ) -> float:
    """A chequered scale bar of a round length in ``units`` near the lower-left corner
    (axes fractions ``where``); returns its length in metres."""
    scale = length_scale(units)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    length_u = nice_step((x1 - x0) / scale)
    length = length_u * scale
    bx, by = x0 + where[0] * (x1 - x0), y0 + where[1] * (y1 - y0)
    h = 0.012 * (y1 - y0)
    ax.add_patch(Rectangle((bx - 0.01 * (x1 - x0), by - 1.2 * h), length + 0.02 * (x1 - x0),
                           5.2 * h, fc="white", ec="none", alpha=0.85, zorder=20))
    for k in range(4):
        ax.add_patch(Rectangle((bx + k * length / 4, by), length / 4, h, zorder=21,
                               fc="black" if k % 2 == 0 else "white", ec="black", lw=0.6))
    ax.text(bx, by + 1.4 * h, "0", ha="center", va="bottom", fontsize=6.5, zorder=21)
    ax.text(bx + length, by + 1.4 * h, f"{length_u:g} {units}", ha="center", va="bottom",
            fontsize=6.5, zorder=21)
    return length


def add_north_arrow(ax: Axes, where: tuple[float, float] = (0.95, 0.86)) -> None:
    """A north arrow (plans are in SUMO's x-east, y-north) at axes fractions ``where``."""
    x, y = where
    ax.annotate("", xy=(x, y + 0.09), xytext=(x, y), xycoords="axes fraction",
                arrowprops=dict(arrowstyle="-|>,head_width=0.35,head_length=0.8",
                                color="black", lw=1.4), zorder=21)
    ax.text(x, y + 0.10, "N", transform=ax.transAxes, ha="center", va="bottom",
            fontsize=9, fontweight="bold", zorder=21)


def nice_length(span: float) -> float:
    """A round scale-bar length of about a fifth of ``span``."""
    target = span / 5
    for step in (1, 2, 5, 10, 20, 25, 50, 100, 200, 250, 500, 1000, 2000, 5000):
        if step >= target:
            return float(step)
    return float(round(target, -3))
