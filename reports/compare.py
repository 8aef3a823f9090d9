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

from analysis.turning import steering_sweep, turning_metrics
from reports.plotting import new_figure, save
from reports.units import length_scale, to_output_units
from vehicles.table import VehicleTable

COLUMNS = ["vehicle", "category", "wheelbase", "width", "length", "max_steer_deg",
           "ackermann_angle_deg", "min_radius", "ctr", "curb_to_curb", "wall_to_wall",
           "inside_radius", "swept_width", "offtracking"]


def comparison_table(table: VehicleTable, units: str = "m") -> pd.DataFrame:
    """One row per model, in ``units``, sorted by wall-to-wall diameter."""
    m = to_output_units(turning_metrics(table), units)
    m.insert(1, "category", table.frame["category"].to_numpy())
    out = m[COLUMNS].sort_values("wall_to_wall", kind="stable").reset_index(drop=True)
    out.insert(len(out.columns), "units", units)
    return out


def _sweeps(table: VehicleTable, n: int = 200) -> dict[str, pd.DataFrame]:
    return {name: steering_sweep(table, name, n).iloc[1:] for name in table.names}


def _colours(n: int) -> list[tuple[float, float, float, float]]:
    import matplotlib

    cmap = matplotlib.colormaps["tab20"]
    return [cmap(i % 20) for i in range(n)]


def _line_styles(n: int) -> list[str]:
    return ["-", "--", ":", "-."][: max(1, (n + 19) // 20)] * 20


def _plot_over_theta(table: VehicleTable, stem: str | Path, units: str, column: str,
                     ylabel: str, title: str, clip: bool) -> list[Path]:
    """One line per model of ``column`` (metres) against the Ackermann angle, to full lock.

    ``clip`` leaves out the first 0.2 degrees (where rho tends to infinity) and limits the
    axis to six times the smallest value of any model.
    """
    scale = length_scale(units)
    fig, ax = new_figure(7.5, 4.8)
    sweeps = _sweeps(table)
    styles = _line_styles(len(sweeps))
    top = 0.0
    for i, ((name, s), colour) in enumerate(zip(sweeps.items(), _colours(len(sweeps)),
                                                strict=True)):
        theta = np.degrees(s.ackermann_angle_rad.to_numpy())
        keep = theta > 0.2 if clip else np.ones(len(theta), dtype=bool)
        values = s[column].to_numpy()[keep] / scale
        ax.plot(theta[keep], values, color=colour, linestyle=styles[i // 20], lw=1.2,
                label=name)
        top = max(top, float(values.min()) * 6)
    ax.set_xlabel("Ackermann angle ϑ = δ_inner − δ_outer (degrees)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    if clip:
        ax.set_ylim(0, top)
    ax.set_xlim(left=0)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), ncol=1 + len(sweeps) // 26,
              frameon=False)
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
