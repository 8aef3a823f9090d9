"""Comparing vehicle models: the side-by-side table and its figures.

- :func:`comparison_table`: turning circles and swept widths, one row per model;
- :func:`plot_rho_theta`: the radius of the rear-axle centre against the Ackermann angle,
  like the paper's Figure 5;
- :func:`plot_swept_width_theta`: the safe-pathway width against the Ackermann angle, like
  the paper's Figure 6;
- :func:`plot_turning_circles`: curb-to-curb and wall-to-wall diameters and the inside
  radius of every model.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from clearance.analysis.design_turn import design_turn_inside_radius
from clearance.analysis.turning import steering_sweep, turning_metrics
from clearance.reports.documents.plotting import new_figure, save
from clearance.reports.results.units import length_scale, to_output_units
from clearance.vehicles.table import VehicleTable

__all__ = ["COLUMNS", "COMBINATION_COLUMNS", "PANEL_LINES", "comparison_table", "panels_of",
           "plot_rho_theta", "plot_swept_width_theta", "plot_turning_circles"]

COLUMNS = ["vehicle", "category", "wheelbase", "width", "length", "max_steer_deg",
           "ackermann_angle_deg", "min_radius", "ctr", "curb_to_curb", "wall_to_wall",
           "inside_radius", "swept_width", "offtracking"]
#: A combination's own columns (empty for a single unit): ``design_inside_radius`` of the
#: 180° design turn (:mod:`clearance.analysis.design_turn`, the whole combination, transient), then
#: with its trailer at full lock in steady state, ``steady_state`` false where it has none
#: (the trailer would keep cutting in).
COMBINATION_COLUMNS = ["design_inside_radius", "steady_state", "trailer_articulation_deg",
                       "trailer_inside_radius", "combination_inside_radius",
                       "combination_swept_width"]


def comparison_table(table: VehicleTable, units: str = "m") -> pd.DataFrame:
    """One row per model, in ``units``, sorted by wall-to-wall diameter."""
    m = to_output_units(turning_metrics(table), units)
    m.insert(1, "category", table.frame["category"].to_numpy())
    cols = list(COLUMNS)
    if "steady_state" in m:  # a table with combinations
        cols += COMBINATION_COLUMNS
        design = design_turn_inside_radius(table.frame, 180.0)
        m["design_inside_radius"] = design["inside_radius_m"].to_numpy() / length_scale(units)
        single = m["trailer_inside_radius"].isna() & m["steady_state"].astype(bool)
        m["steady_state"] = m["steady_state"].where(~single, None)
    out = m[cols].sort_values("wall_to_wall", kind="stable").reset_index(drop=True)
    out.insert(len(out.columns), "units", units)
    return out


def _sweeps(table: VehicleTable, n: int = 200) -> dict[str, pd.DataFrame]:
    return {name: steering_sweep(table, name, n).iloc[1:] for name in table.names}


#: At most this many lines in one panel of a figure over the Ackermann angle.
PANEL_LINES = 8


def panels_of(names: list[str], categories: list[str], size: int = PANEL_LINES
              ) -> list[tuple[str, list[str]]]:
    """The models grouped for small multiples: by category, a category of more than
    ``size`` models cut into panels of ``size``, small categories of one kind merged.

    Examples
    --------
    >>> panels_of(["a", "b", "c"], ["car", "car", "bus"], 2)
    [('car', ['a', 'b']), ('bus', ['c'])]
    >>> [t for t, _ in panels_of([f"c{i}" for i in range(5)], ["car"] * 5, 2)]
    ['car (1 of 3)', 'car (2 of 3)', 'car (3 of 3)']
    >>> panels_of([], [])
    []
    """
    groups: dict[str, list[str]] = {}
    for n, c in zip(names, categories, strict=True):
        groups.setdefault(c or "other", []).append(n)
    # small categories (fewer than half a panel) share panels, in order
    out: list[tuple[str, list[str]]] = []
    small: list[tuple[str, str]] = []
    for cat, members in groups.items():
        if len(members) * 2 < size and len(groups) > 1:
            small += [(cat, m) for m in members]
            continue
        k = -(-len(members) // size)  # panels, filled evenly
        cuts = [round(i * len(members) / k) for i in range(k + 1)]
        chunks = [members[cuts[i]:cuts[i + 1]] for i in range(k)]
        for k, chunk in enumerate(chunks, start=1):
            out.append((cat if len(chunks) == 1 else f"{cat} ({k} of {len(chunks)})", chunk))
    for i in range(0, len(small), size):
        part = small[i:i + size]
        cats = list(dict.fromkeys(c for c, _ in part))
        out.append((", ".join(cats) if len(cats) <= 3 else "other vehicles",
                    [m for _, m in part]))
    return out


def _plot_over_theta(table: VehicleTable, stem: str | Path, units: str, column: str,
                     ylabel: str, title: str, clip: bool) -> list[Path]:
    """``column`` (metres) of every model against the Ackermann angle, to full lock: small
    multiples of at most :data:`PANEL_LINES` models (by category), each line its own
    colour within a panel and labelled at its end (full lock).

    ``clip`` leaves out the first 0.2 degrees (where rho tends to infinity) and limits the
    axis to six times the panel's smallest value.
    """
    import matplotlib

    scale = length_scale(units)
    sweeps = _sweeps(table)
    cats = list(table.frame["category"].fillna("").astype(str))
    panels = panels_of(list(sweeps), cats)
    ncols = min(3, len(panels))
    nrows = -(-len(panels) // ncols)
    fig, _ = new_figure(4.2 * ncols + 0.6, 3.3 * nrows + 0.8)
    fig.clf()
    axes = fig.subplots(nrows, ncols, squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    cmap = matplotlib.colormaps["tab10"]
    for ax, (name, members) in zip(axes.flat, panels, strict=False):
        top = 0.0
        for i, model in enumerate(members):
            s = sweeps[model]
            theta = np.degrees(s.ackermann_angle_rad.to_numpy())
            keep = theta > 0.2 if clip else np.ones(len(theta), dtype=bool)
            values = s[column].to_numpy()[keep] / scale
            ax.plot(theta[keep], values, color=cmap(i % 10), lw=1.2, label=model)
            top = max(top, float(values.min()) * 6)
        ax.set_title(name, fontsize=8.5)
        ax.set_xlim(left=0)
        if clip:
            ax.set_ylim(0, top)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=6, frameon=False, loc="upper right" if clip else "upper left")
    for ax in axes[-1]:
        ax.set_xlabel("Ackermann angle ϑ = δ_inner − δ_outer (°)", fontsize=7.5)
    for ax in axes[:, 0]:
        ax.set_ylabel(ylabel, fontsize=7.5)
    fig.suptitle(f"{title} ({len(sweeps)} models, in panels of at most {PANEL_LINES})",
                 fontsize=10)
    fig.tight_layout()
    return save(fig, stem)


def plot_rho_theta(table: VehicleTable, stem: str | Path, units: str = "m") -> list[Path]:
    """ρ(ϑ) for every model (paper Figure 5): radius of the rear-axle centre."""
    return _plot_over_theta(
        table, stem, units, "rho_m", f"radius of the rear-axle centre ρ ({units})",
        "Turning radius against the Ackermann angle (paper eq. 1), up to full lock", True)


def plot_swept_width_theta(table: VehicleTable, stem: str | Path, units: str = "m"
                           ) -> list[Path]:
    """ΔR(ϑ) for every model (paper Figure 6): steady-state swept width."""
    return _plot_over_theta(
        table, stem, units, "swept_width_m", f"swept-path width ΔR ({units})",
        "Safe-pathway width against the Ackermann angle (paper eq. 4), up to full lock",
        False)


def plot_turning_circles(table: VehicleTable, stem: str | Path, units: str = "m"
                         ) -> list[Path]:
    """Curb-to-curb and wall-to-wall diameters and the inside radius, one bar group a model."""
    t = comparison_table(table, units)
    n = len(t)
    fig, ax = new_figure(7.5, max(3.0, 0.22 * n + 1.2))
    y = np.arange(n)
    ax.barh(y + 0.27, t.wall_to_wall, height=0.27, color="#c0392b", label="wall-to-wall diameter")
    ax.barh(y, t.curb_to_curb, height=0.27, color="#2e86c1", label="curb-to-curb diameter")
    ax.barh(y - 0.27, t.inside_radius, height=0.27, color="#7f8c8d",
            label="minimum inside radius")
    ax.set_yticks(y, t.vehicle)
    ax.invert_yaxis()
    ax.set_xlabel(f"length ({units})")
    ax.set_title("Turning circles at full lock (docs/design.md §4)", pad=22)
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, frameon=False)
    ax.grid(axis="y", visible=False)
    return save(fig, stem)
