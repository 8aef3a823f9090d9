"""Figures of a clearance report: network plans with the worst curves, swept paths.

Every figure is a plan in metres (x east, y north) with labelled axes, a scale bar, a north
arrow and a legend, written as PNG and SVG at print size.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np
import pandas as pd
import shapely
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from networks.curves import Curve
from networks.plot import _fill, plot_plan
from reports.plotting import new_figure, save
from reports.study import VERDICT_ORDER, NetworkCurves, RunRecord

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from numpy.typing import NDArray

__all__ = ["COLOURS", "plot_curve", "plot_network", "sites", "worst_by_curve"]

COLOURS = {"clear": "#1e8449", "encroaches": "#e67e22", "fails": "#c0392b",
           "cannot-turn": "#7d3c98", "error": "#000000"}


def worst_by_curve(frame: pd.DataFrame) -> pd.DataFrame:
    """Per curve: the worst verdict over the vehicles and its smallest margin.

    Examples
    --------
    >>> f = pd.DataFrame({"curve_id": ["a", "a", "b"], "vehicle": ["x", "y", "x"],
    ...                   "verdict": ["clear", "fails", "clear"], "margin_m": [0.5, -1, 0.2]})
    >>> worst_by_curve(f)[["curve_id", "verdict", "margin_m", "vehicle"]].values.tolist()
    [['a', 'fails', -1.0, 'y'], ['b', 'clear', 0.2, 'x']]
    """
    f = frame.assign(_o=frame["verdict"].map(VERDICT_ORDER))
    f = f.sort_values(["_o", "margin_m", "curve_id", "vehicle"], kind="stable")
    return f.drop_duplicates("curve_id").drop(columns="_o").reset_index(drop=True)


def sites(curves: list[Curve], gap_m: float = 80.0, max_sites: int = 4) -> list[list[Curve]]:
    """Group curves whose feature centres lie within ``gap_m`` of each other (one plan each).

    More than ``max_sites`` groups (a city network) make one group: a single overview.

    Examples
    --------
    >>> sites([])
    []
    """
    if not curves:
        return []
    # an (N, 2) array of coordinates gives an array of N points
    centres = cast("NDArray[np.object_]",
                   shapely.points(np.array([_core_points(c).mean(axis=0) for c in curves])))
    pairs = shapely.STRtree(centres).query(centres, predicate="dwithin", distance=gap_m)
    parent = list(range(len(curves)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in pairs.T:
        ri, rj = root(int(i)), root(int(j))
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)
    groups: dict[int, list[int]] = {}
    for i in range(len(curves)):
        groups.setdefault(root(i), []).append(i)
    ordered = sorted(groups.values(), key=lambda g: g[0])
    if len(ordered) > max_sites:
        return [list(curves)]
    return [[curves[i] for i in g] for g in ordered]


def plot_network(nc: NetworkCurves, frame: pd.DataFrame, stem: Path, marked: int = 8
                 ) -> list[Path]:
    """The network's plan, every curve's centre line coloured by its worst verdict.

    One panel per site (curves close together); the ``marked`` worst curves are numbered,
    and the numbers match the report's list of worst curves.
    """
    worst = worst_by_curve(frame)
    rank = {r.curve_id: i for i, r in enumerate(worst.head(marked).itertuples(), start=1)
            if not (r.verdict == "clear" and r.margin_m > 0.25)}
    verdict = dict(zip(worst.curve_id, worst.verdict, strict=True))
    groups = sites(nc.curves) or [[]]
    n = len(groups)
    fig, _ = new_figure(min(6.0 * n, 13.0), 6.0)
    fig.clf()
    axes = fig.subplots(1, n, squeeze=False)[0]
    for ax, group in zip(axes, groups, strict=True):
        pts = np.vstack([c.centerline[:, :2] for c in group]) if group else np.zeros((1, 2))
        half = max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1])) / 2 + 8.0
        cx, cy = (pts.max(axis=0) + pts.min(axis=0)) / 2
        title = (f"{nc.name}: around junction {group[0].junction}" if len(groups) > 1
                 else f"{nc.name}: every curve")
        plot_plan(nc.network, ax, title, (cx - half, cx + half, cy - half, cy + half))
        # a curve no vehicle of the table may use (not permitted) has no verdict
        judged = [c for c in group if c.curve_id in verdict]
        for c in sorted(judged, key=lambda c: -VERDICT_ORDER[verdict[c.curve_id]]):
            v = verdict[c.curve_id]
            core = _core_points(c)
            ax.plot(core[:, 0], core[:, 1], color=COLOURS[v],
                    lw=1.0 if v == "clear" else 2.2, zorder=6, alpha=0.9)
        for c in group:
            if c.curve_id in rank:
                core = _core_points(c)
                x, y = core[len(core) // 2]
                ax.annotate(str(rank[c.curve_id]), (x, y), fontsize=7, fontweight="bold",
                            ha="center", va="center", zorder=8,
                            bbox=dict(boxstyle="circle,pad=0.2", fc="white",
                                      ec=COLOURS[verdict[c.curve_id]], lw=1.2))
    present = set(worst.verdict)
    handles = [Line2D([], [], color=COLOURS[v], lw=2.2, label=v)
               for v in sorted(COLOURS, key=VERDICT_ORDER.__getitem__)
               if v != "error" or v in present]
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=8, frameon=False,
               title="worst verdict over the vehicles (numbers: the worst curves, in order)",
               title_fontsize=8, bbox_to_anchor=(0.5, -0.02))
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return save(fig, stem)


def _core_points(curve: Curve) -> np.ndarray:
    pts = np.asarray(curve.centerline)[:, :2]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    keep = (s >= curve.core_start_m - 1e-6) & (s <= curve.core_end_m + 1e-6)
    return pts[keep] if keep.sum() >= 2 else pts


def plot_curve(nc: NetworkCurves, curve: Curve, records: list[RunRecord], stem: Path,
               units_note: str = "") -> list[Path]:
    """The swept paths of ``records`` (one curve) over the lanes, junction and curbs."""
    core = _core_points(curve)
    envs = [r.envelope for r in records if r.envelope is not None and not r.envelope.is_empty]
    b = np.array([e.bounds for e in envs] + [[*core.min(axis=0), *core.max(axis=0)]])
    x0, y0 = b[:, 0].min(), b[:, 1].min()
    x1, y1 = b[:, 2].max(), b[:, 3].max()
    half = max(x1 - x0, y1 - y0) / 2 + 6.0
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    fig, ax = new_figure(6.5, 6.0)
    plot_plan(nc.network, ax, None, (cx - half, cx + half, cy - half, cy + half))
    if curve.paved is not None:
        for poly in getattr(curve.paved, "geoms", [curve.paved]):
            for ring in [poly.exterior, *poly.interiors]:
                xy = np.asarray(ring.coords)
                ax.plot(xy[:, 0], xy[:, 1], color="black", lw=1.6, zorder=4)
    if curve.own_lanes is not None:
        for poly in getattr(curve.own_lanes, "geoms", [curve.own_lanes]):
            xy = np.asarray(poly.exterior.coords)
            ax.plot(xy[:, 0], xy[:, 1], color="#2471a3", lw=1.0, ls="--", zorder=5)
    handles: list[Artist] = [
        Line2D([], [], color="black", lw=1.6, label="edge of pavement (curb)"),
        Line2D([], [], color="#2471a3", lw=1.0, ls="--", label="own lanes")]
    palette = ["#c0392b", "#7d3c98", "#e67e22", "#1e8449", "#2e86c1", "#7f8c8d"]
    for r, colour in zip(records, palette, strict=False):
        if r.envelope is None:
            continue
        _fill(ax, r.envelope, facecolor=colour, alpha=0.25, edgecolor=colour, lw=1.0, zorder=6)
        handles.append(Patch(facecolor=colour, alpha=0.5, edgecolor=colour,
                             label=f"{r.vehicle}: {r.verdict} ({r.margin_m:+.2f} m)"))
    ax.plot(curve.centerline[:, 0], curve.centerline[:, 1], color="black", lw=0.6, ls=":",
            zorder=7)
    handles.append(Line2D([], [], color="black", lw=0.6, ls=":", label="centre line followed"))
    angle = f"{curve.turn_angle_deg:+.0f}°"
    radius = f"R min {curve.min_radius_m:.1f} m" if math.isfinite(curve.min_radius_m) else ""
    ax.set_title(f"{nc.name}: {curve.curve_id}\n{curve.kind}, {angle}, {radius}{units_note}",
                 fontsize=9)
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2,
              fontsize=7, frameon=False)
    return save(fig, stem)
