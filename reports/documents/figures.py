"""Figures of a clearance report: network plans with the worst curves, swept paths.

Every figure is a plan (x east, y north) with axes, a scale bar and numbers in the report's
units (metres or feet), a north arrow and a legend, written as PNG and SVG at print size.
The swept paths are drawn by :mod:`clearance.reports.documents.drawing`; each vehicle keeps its
colour (:func:`clearance.reports.documents.plotting.vehicle_colours`) in every figure.

A report's curve figures are drawn in the study's worker processes (:class:`CurveFigure`,
:func:`draw_curve_figure`): each worker has its own copy of the network
(:func:`clearance.reports.study.batch.worker_network`), builds the areas of the one curve it draws
and returns the figure's files as bytes (:func:`scratch_files`), which the report's process
writes; so a figure is the same file wherever it is drawn, and a cluster's workers need no
shared disk.
"""

from __future__ import annotations

import gc
import math
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np
import pandas as pd
import shapely
from matplotlib.lines import Line2D

from clearance.networks.curves import Curve
from clearance.networks.plot import plot_plan
from clearance.reports.documents.colours import VERDICT_COLOURS
from clearance.reports.documents.drawing import (
    Shown,
    angle_text,
    draw_curve,
    length_text,
    rerun,
    view_bounds,
)
from clearance.reports.documents.plotting import (
    PNG,
    add_north_arrow,
    add_scale_bar,
    new_figure,
    plan_axes,
    save,
    vehicle_colours,
)
from clearance.reports.study.batch import with_areas, worker_network
from clearance.reports.study.executor import SharedFile
from clearance.reports.study.run import VERDICT_ORDER, NetworkCurves, RunRecord
from clearance.vehicles.table import VehicleTable

if TYPE_CHECKING:
    from numpy.typing import NDArray

__all__ = ["COLOURS", "CurveFigure", "core_points", "draw_curve_figure", "plot_curve",
           "plot_network", "scratch_files", "shown_runs", "sites", "worst_by_curve"]

COLOURS = VERDICT_COLOURS


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
                   shapely.points(np.array([core_points(c).mean(axis=0) for c in curves])))
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


def plot_network(nc: NetworkCurves, frame: pd.DataFrame, stem: Path, marked: int = 8,
                 units: str = "m", formats: tuple[str, ...] = PNG) -> list[Path]:
    """The network's plan, every curve's centre line coloured by its worst verdict (the
    files of ``formats``, PNG first).

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
        plot_plan(nc.network, ax, title, (cx - half, cx + half, cy - half, cy + half),
                  decorate=False)
        plan_axes(ax, units)
        add_scale_bar(ax, units)
        add_north_arrow(ax)
        # a curve no vehicle of the table may use (not permitted) has no verdict
        judged = [c for c in group if c.curve_id in verdict]
        for c in sorted(judged, key=lambda c: -VERDICT_ORDER[verdict[c.curve_id]]):
            v = verdict[c.curve_id]
            core = core_points(c)
            ax.plot(core[:, 0], core[:, 1], color=COLOURS[v],
                    lw=1.0 if v == "clear" else 2.2, zorder=6, alpha=0.9)
        for c in group:
            if c.curve_id in rank:
                core = core_points(c)
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
    return save(fig, stem, formats)


def core_points(curve: Curve) -> np.ndarray:
    pts = np.asarray(curve.centerline)[:, :2]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    keep = (s >= curve.core_start_m - 1e-6) & (s <= curve.core_end_m + 1e-6)
    return pts[keep] if keep.sum() >= 2 else pts


def shown_runs(nc: NetworkCurves, curve: Curve, records: Sequence[RunRecord],
               table: VehicleTable | None) -> list[Shown]:
    """The records with their vehicles' colours and, for a simulated run whose vehicle the
    table has, the run driven again for its trajectory
    (:func:`clearance.reports.documents.drawing.rerun`)."""
    colours = vehicle_colours(table.names if table is not None else
                              [r.vehicle for r in records])
    shown = [Shown(r, colours.get(r.vehicle, "#555555")) for r in records]
    if table is None:
        return shown
    by_name = {v.name: v for v in table.vehicles()}
    # the analytic method drives nothing: its runs are drawn by their envelopes alone
    todo = [s for s in shown if s.record.verdict != "error" and s.record.vehicle in by_name
            and s.record.method == "simulate"]
    offsets = {s.record.clearance_m for s in todo}
    for off in sorted(offsets):
        group = [s for s in todo if s.record.clearance_m == off]
        runs = rerun(nc, curve, [by_name[s.record.vehicle] for s in group],
                     [s.record for s in group], off)
        for s, d in zip(group, runs, strict=True):
            s.driven = d
    return shown


def plot_curve(nc: NetworkCurves, curve: Curve, records: list[RunRecord], stem: Path,
               units_note: str = "", table: VehicleTable | None = None, units: str = "m",
               formats: tuple[str, ...] = PNG) -> list[Path]:
    """The swept paths of ``records`` (one curve) over the plan
    (:mod:`clearance.reports.documents.drawing`); the files of ``formats``, PNG first.

    With the study's vehicle ``table`` each run is driven again (model only) for its
    trajectory: the vehicle at intervals, wheel paths, dimensions, where it stops; the
    vehicles keep the table's colours. Without it only the envelopes are drawn. Every
    length is in ``units``.
    """
    shown = shown_runs(nc, curve, records, table)
    fig, ax = new_figure(7.0, 7.6)
    bounds = view_bounds(curve, shown)
    handles = draw_curve(ax, nc, curve, shown, units, bounds)
    angle = angle_text(curve.turn_angle_deg)
    radius = (f", R min {length_text(curve.min_radius_m, units, 1)}"
              if math.isfinite(curve.min_radius_m) else "")
    ax.set_title(f"{nc.name}: {curve.curve_id}\n{curve.kind} at junction {curve.junction}, "
                 f"{angle}{radius}{units_note}", fontsize=9)
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.07), ncol=3,
              fontsize=6.5, frameon=False, handlelength=3.2)
    return save(fig, stem, formats)


def scratch_files(make: Callable[[Path], object]) -> dict[str, bytes]:
    """The files ``make(folder)`` writes into a fresh temporary folder, by their paths
    relative to it (``/``-separated); the folder is removed, and what ``make`` left for the
    garbage collector is collected.

    Examples
    --------
    >>> scratch_files(lambda d: (d / "a").mkdir() or (d / "a" / "x.txt").write_text("1"))
    {'a/x.txt': b'1'}
    >>> scratch_files(lambda d: None)
    {}
    """
    with tempfile.TemporaryDirectory(prefix="clearance-draw-") as tmp:
        root = Path(tmp)
        make(root)
        # a closed figure is a web of reference cycles: free it now, not at some later
        # collection (a worker drawing 30 figures grew by about 6 MB a figure)
        gc.collect()
        return {p.relative_to(root).as_posix(): p.read_bytes()
                for p in sorted(root.rglob("*")) if p.is_file()}


@dataclass(frozen=True)
class CurveFigure:
    """One curve figure of a report, to draw in a worker (:func:`draw_curve_figure`).

    ``curve`` comes without its areas (:func:`clearance.reports.study.batch.bare`); ``stem`` is the
    figure's path relative to the report's folder, without suffix."""

    network: str
    path: str
    curve: Curve
    records: tuple[RunRecord, ...]
    stem: str
    table: VehicleTable | None
    units: str = "m"
    formats: tuple[str, ...] = PNG


def draw_curve_figure(task: CurveFigure, shared: SharedFile) -> dict[str, bytes]:
    """Draw ``task``'s figure (:func:`plot_curve`) in this process, on its own copy of the
    network; the files (PNG, and SVG when asked) by their paths relative to the report's
    folder."""
    net = worker_network(shared)
    with_areas(net, [task.curve])
    nc = NetworkCurves(task.network, Path(task.path), net, [task.curve])
    return scratch_files(lambda root: plot_curve(nc, task.curve, list(task.records),
                                                 root / task.stem, table=task.table,
                                                 units=task.units, formats=task.formats))
