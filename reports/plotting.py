"""Shared figure helpers: a headless backend, one style, PNG and SVG written atomically."""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from reports.atomic import write_bytes_atomic  # noqa: E402

if TYPE_CHECKING:
    from matplotlib.typing import RcKeyType

__all__ = ["STYLE", "add_north_arrow", "add_scale_bar", "new_figure", "nice_length", "save"]

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


def save(fig: Figure, path_stem: str | Path, formats: tuple[str, ...] = ("png", "svg")
         ) -> list[Path]:
    """Write ``path_stem.png`` (and ``.svg``) atomically; close the figure."""
    out = []
    with plt.rc_context(STYLE):
        for fmt in formats:
            buf = io.BytesIO()
            metadata = {"Date": None} if fmt == "svg" else {"Software": None}
            fig.savefig(buf, format=fmt, bbox_inches="tight", metadata=metadata)
            out.append(write_bytes_atomic(Path(f"{path_stem}.{fmt}"), buf.getvalue()))
    plt.close(fig)
    return out


def add_scale_bar(ax: Axes, length_m: float, label: str | None = None) -> None:
    """A scale bar in the lower-left corner of a plan in metres."""
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    bx = x0 + 0.05 * (x1 - x0)
    by = y0 + 0.05 * (y1 - y0)
    ax.plot([bx, bx + length_m], [by, by], color="black", linewidth=3, solid_capstyle="butt")
    ax.text(bx + length_m / 2, by + 0.015 * (y1 - y0), label or f"{length_m:g} m",
            ha="center", va="bottom", fontsize=7)


def add_north_arrow(ax: Axes) -> None:
    """A north arrow in the upper-right corner (plans are in SUMO's x-east, y-north)."""
    ax.annotate("N", xy=(0.95, 0.95), xytext=(0.95, 0.85), xycoords="axes fraction",
                ha="center", va="center", fontsize=9, fontweight="bold",
                arrowprops=dict(arrowstyle="-|>", color="black", lw=1.2))


def nice_length(span: float) -> float:
    """A round scale-bar length of about a fifth of ``span``."""
    target = span / 5
    for step in (1, 2, 5, 10, 20, 25, 50, 100, 200, 250, 500, 1000, 2000, 5000):
        if step >= target:
            return float(step)
    return float(round(target, -3))
