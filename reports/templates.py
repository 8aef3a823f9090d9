"""Turning templates: each model driven through a 90° and a 180° turn at its minimum radius.

A template is what a designer lays over a plan: the swept envelope of the body (and
trailer), the wheel tracks and the path of the steered-axle centre, for a turn from a
straight approach onto an arc of the vehicle's own minimum centre-line turning radius and
back to a straight exit. The vehicle is driven with the kinematic model (analysis/), within
its steering lock and steering rate, at crawl speed; every model is drawn at one scale.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from analysis.envelope import SweptPath, swept_path
from analysis.tracking import TrackingRun, TrackingSettings, simulate_batch
from reports.plotting import new_figure, save
from reports.units import length_scale
from vehicles.table import VehicleTable
from vehicles.vehicle import Vehicle

__all__ = ["RADIUS_MARGIN", "Template", "build_templates", "plot_templates",
           "template_envelope_area", "template_path"]

#: The arc is this much wider than the minimum CTR, so that the steering rate limit lets the
#: steered axle stay on it while the wheels turn to lock.
RADIUS_MARGIN = 1.03


def template_path(radius_m: float, angle_deg: float, straight_m: float, step_m: float = 0.25
                  ) -> np.ndarray:
    """A left turn: ``straight_m`` along +x, an arc of ``radius_m`` by ``angle_deg``, a straight.

    The arc starts at the origin; the approach comes from ``x = -straight_m``.

    Examples
    --------
    >>> p = template_path(10.0, 90.0, 5.0)
    >>> p[0].tolist(), [round(float(v), 9) for v in p[-1]]
    ([-5.0, 0.0], [10.0, 15.0])
    >>> template_path(10.0, 0.0, 5.0)[-1].tolist()       # zero angle: straight through
    [5.0, 0.0]
    """
    xs = np.arange(-straight_m, 0.0, step_m)
    approach = np.column_stack([xs, np.zeros_like(xs)])
    a = math.radians(angle_deg)
    n = max(2, int(math.ceil(radius_m * a / step_m)) + 1)
    t = np.linspace(0.0, a, n)
    arc = np.column_stack([radius_m * np.sin(t), radius_m * (1 - np.cos(t))])
    end, heading = arc[-1], a
    k = np.arange(step_m, straight_m + step_m / 2, step_m)
    exit_ = end + np.column_stack([np.cos(heading) * k, np.sin(heading) * k])
    return np.vstack([approach, arc, exit_])


@dataclass
class Template:
    """One model's template for one turn angle."""

    vehicle: Vehicle
    angle_deg: float
    radius_m: float
    run: TrackingRun
    swept: SweptPath


def build_templates(table: VehicleTable, angle_deg: float,
                    settings: TrackingSettings | None = None) -> list[Template]:
    """Drive every model of ``table`` through its own template turn (one vectorised batch)."""
    vehicles = table.vehicles()
    settings = settings or TrackingSettings(tolerance_m=1.0)
    paths, radii = [], []
    for v in vehicles:
        ctr = math.hypot(v.min_radius_m, v.wheelbase_m)
        radius = ctr * RADIUS_MARGIN
        straight = v.overall_length_m + 5.0
        paths.append(template_path(radius, angle_deg, straight))
        radii.append(radius)
    runs = simulate_batch(vehicles, paths, settings)
    return [Template(v, angle_deg, r, run, swept_path(run))
            for v, r, run in zip(vehicles, radii, runs, strict=True)]


def plot_templates(table: VehicleTable, folder: str | Path, units: str = "m",
                   angles: tuple[float, ...] = (90.0, 180.0)) -> list[Path]:
    """``templates_90`` and ``templates_180`` figures (PNG and SVG), every model at one scale."""
    written: list[Path] = []
    for angle in angles:
        written += _plot(build_templates(table, angle), Path(folder) / f"templates_{angle:g}",
                         units)
    return written


def _plot(templates: list[Template], stem: Path, units: str) -> list[Path]:
    scale = length_scale(units)
    n = len(templates)
    ncols = min(n, 4)
    nrows = math.ceil(n / ncols)
    # One scale: every panel spans the same extent (the largest template's).
    bounds = np.array([t.swept.envelope.bounds for t in templates])
    half = 0.55 * float(max((bounds[:, 2] - bounds[:, 0]).max(),
                            (bounds[:, 3] - bounds[:, 1]).max())) / scale
    fig, _ = new_figure(2.1 * ncols + 0.4, 2.2 * nrows + 0.6)
    fig.clf()
    axes = fig.subplots(nrows, ncols, squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax, t in zip(axes.flat, templates, strict=False):
        env = t.swept.envelope
        cx, cy = [(a + b) / 2 / scale for a, b in zip(env.bounds[:2], env.bounds[2:],
                                                         strict=True)]
        for poly in getattr(env, "geoms", [env]):
            x, y = np.asarray(poly.exterior.coords).T / scale
            ax.fill(x, y, color="#f5b7b1", lw=0, label="swept envelope")
            ax.plot(x, y, color="#c0392b", lw=0.8)
        for _name, track in sorted(t.swept.wheel_tracks.items()):
            x, y = np.asarray(track.coords).T / scale
            ax.plot(x, y, color="#2e86c1", lw=0.5, label="wheel tracks")
        tr = t.run.trajectory
        ax.plot(tr.xf_m / scale, tr.yf_m / scale, color="black", lw=0.6, ls="--",
                label="steered-axle centre")
        ax.set_xlim(cx - half, cx + half)
        ax.set_ylim(cy - half, cy + half)
        ax.set_aspect("equal")
        ax.set_title(f"{t.vehicle.name}\nCTR {t.radius_m / scale:.1f} {units}, "
                     f"swept {t.swept.max_swept_width_m / scale:.1f} {units}", fontsize=7)
        ax.tick_params(labelsize=6)
        ax.grid(alpha=0.3)
    first = axes.flat[0]
    handles, labels = first.get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=True))
    fig.legend(unique.values(), unique.keys(), loc="upper center", ncol=3, fontsize=7,
               frameon=False, bbox_to_anchor=(0.5, 1.0))
    angle = templates[0].angle_deg if templates else 0.0
    fig.suptitle(f"{angle:g}° turning templates at each model's minimum radius "
                 f"(one scale; axes in {units})", y=1.03, fontsize=10)
    fig.tight_layout()
    return save(fig, stem)


def template_envelope_area(t: Template) -> float:
    """Area of a template's envelope (m²), for tests and summaries."""
    return float(shapely.area(t.swept.envelope))
