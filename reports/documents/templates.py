"""Turning templates: each model driven through a 90° and a 180° turn at its minimum radius.

A template is what a designer lays over a plan: the swept envelope of the body (and
trailer), the wheel tracks and the path of the steered-axle centre, for a turn from a
straight approach through a steering transition (a clothoid, as long as the steering needs
to reach lock at its rate) onto an arc of the vehicle's own minimum centre-line turning
radius (CTR) and back out the same way to a straight exit: the template is drawn at the CTR
its title gives. The vehicle is driven with the kinematic model (analysis/), within
its steering lock and steering rate, at crawl speed; every model is drawn at one scale.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import TypedDict

import numpy as np
import shapely

from clearance.analysis.envelope import SweptPath, swept_path
from clearance.analysis.tracking import TrackingRun, TrackingSettings, simulate_batch
from clearance.reports.documents.plotting import new_figure, save
from clearance.reports.results.units import length_scale
from clearance.vehicles.table import VehicleTable
from clearance.vehicles.vehicle import Vehicle

__all__ = ["TRANSITION_FACTOR", "turn_centre", "TEMPLATE_PANEL_MM", "TEMPLATE_PAPER_MM",
           "TEMPLATE_SCALES", "Template", "TemplateDimensions", "arc_centre", "build_templates",
           "plot_templates", "steady_words", "template_dimensions", "template_envelope_area",
           "template_path", "template_sheet", "write_template_sheets"]

#: The steering transition is this many times the distance the steered axle covers at crawl
#: speed while the wheels turn from straight to lock at the steering rate: the follower then
#: keeps to the arc of the minimum CTR itself (about 5 cm off it, measured on P, SU-30,
#: CITY-BUS and WB-62).
TRANSITION_FACTOR = 1.5


def template_path(radius_m: float, angle_deg: float, straight_m: float, step_m: float = 0.25,
                  transition_m: float = 0.0) -> np.ndarray:
    """A left turn: ``straight_m`` along +x, a clothoid of ``transition_m`` from straight to
    the curvature of ``radius_m``, the arc, a clothoid back, a straight; ``angle_deg`` in all.

    The turn starts at the origin; the approach comes from ``x = -straight_m``. Where the
    two clothoids alone would turn more than ``angle_deg`` they are shortened to meet.

    Examples
    --------
    >>> p = template_path(10.0, 90.0, 5.0)
    >>> p[0].tolist(), [round(float(v), 9) for v in p[-1]]
    ([-5.0, 0.0], [10.0, 15.0])
    >>> q = template_path(10.0, 90.0, 5.0, transition_m=4.0)  # heading 90 at the end
    >>> [round(float(v), 6) for v in q[-1] - q[-2]]
    [0.0, 0.25]
    >>> template_path(10.0, 0.0, 5.0)[-1].tolist()       # zero angle: straight through
    [5.0, 0.0]
    """
    xs = np.arange(-straight_m, 0.0, step_m)
    approach = np.column_stack([xs, np.zeros_like(xs)])
    a = math.radians(angle_deg)
    arc, _ = _turn(radius_m, a, min(transition_m, a * radius_m), step_m)
    end, heading = arc[-1], a
    k = np.arange(step_m, straight_m + step_m / 2, step_m)
    exit_ = end + np.column_stack([np.cos(heading) * k, np.sin(heading) * k])
    return np.vstack([approach, arc, exit_])


def turn_centre(radius_m: float, angle_deg: float, transition_m: float = 0.0) -> np.ndarray:
    """The centre of the arc of :func:`template_path`'s turn (a clothoid moves it).

    Examples
    --------
    >>> turn_centre(12.5, 90.0).tolist()
    [0.0, 12.5]
    >>> c = turn_centre(12.5, 90.0, 4.0)  # the clothoid's shift: about L^2 / (24 R) outward
    >>> bool(1.9 < c[0] < 2.1 and 12.5 < c[1] < 12.6)
    True
    """
    a = math.radians(angle_deg)
    return _turn(radius_m, a, min(transition_m, a * radius_m), 0.05)[1]


def _turn(radius_m: float, angle_rad: float, spiral_m: float, step_m: float
          ) -> tuple[np.ndarray, np.ndarray]:
    """The turn itself from the origin heading +x: clothoid, arc, clothoid (curvature linear
    in arc length over each clothoid), sampled every ``step_m`` or finer (the last point
    exactly at the end of the turn), and the arc's centre."""
    arc_m = max(radius_m * angle_rad - spiral_m, 0.0)  # two spirals turn spiral_m / radius
    total = arc_m + 2 * spiral_m
    n = max(2, int(math.ceil(total / step_m)) + 1)
    if spiral_m <= 0.0:  # a plain arc, exactly
        t = np.linspace(0.0, angle_rad, n)
        return (np.column_stack([radius_m * np.sin(t), radius_m * (1 - np.cos(t))]),
                np.array([0.0, radius_m]))
    s = np.linspace(0.0, total, 8 * n)  # fine for the integration, thinned below
    k = np.minimum.reduce([np.full_like(s, 1.0 / radius_m),
                           s / max(spiral_m, 1e-12) / radius_m,
                           (total - s) / max(spiral_m, 1e-12) / radius_m])
    ds = np.diff(s)
    theta = np.concatenate([[0.0], np.cumsum((k[1:] + k[:-1]) / 2 * ds)])
    mid = (theta[1:] + theta[:-1]) / 2
    x = np.concatenate([[0.0], np.cumsum(np.cos(mid) * ds)])
    y = np.concatenate([[0.0], np.cumsum(np.sin(mid) * ds)])
    keep = np.unique(np.linspace(0, len(s) - 1, n).round().astype(int))
    i = min(int(np.searchsorted(s, spiral_m)), len(s) - 1)  # where the arc begins
    centre = np.array([x[i] - radius_m * math.sin(theta[i]),
                       y[i] + radius_m * math.cos(theta[i])])
    return np.column_stack([x[keep], y[keep]]), centre


@dataclass
class Template:
    """One model's template for one turn angle."""

    vehicle: Vehicle
    angle_deg: float
    radius_m: float
    run: TrackingRun
    swept: SweptPath
    #: The steering transition (clothoid) into and out of the arc (m).
    transition_m: float = 0.0


def build_templates(table: VehicleTable, angle_deg: float,
                    settings: TrackingSettings | None = None) -> list[Template]:
    """Drive every model of ``table`` through its own template turn (one vectorised batch)."""
    vehicles = table.vehicles()
    settings = settings or TrackingSettings(tolerance_m=1.0)
    paths, radii, transitions = [], [], []
    crawl = float(np.max(settings.profile.speed_m_s))
    for v in vehicles:
        ctr = math.hypot(v.min_radius_m, v.wheelbase_m)
        transition = TRANSITION_FACTOR * crawl * v.max_steer_rad / v.max_steer_rate_rad_s
        straight = v.overall_length_m + 5.0
        paths.append(template_path(ctr, angle_deg, straight, transition_m=transition))
        radii.append(ctr)
        transitions.append(transition)
    runs = simulate_batch(vehicles, paths, settings)
    return [Template(v, angle_deg, r, run, swept_path(run), ls)
            for v, r, run, ls in zip(vehicles, radii, runs, transitions, strict=True)]


def plot_templates(table: VehicleTable, folder: str | Path, units: str = "m",
                   angles: tuple[float, ...] = (90.0, 180.0),
                   built: dict[float, list[Template]] | None = None) -> list[Path]:
    """``templates_90`` and ``templates_180`` figures (PNG and SVG), every model at one scale
    (``built``: templates already driven, by angle)."""
    written: list[Path] = []
    for angle in angles:
        ts = built[angle] if built and angle in built else build_templates(table, angle)
        written += _plot(ts, Path(folder) / f"templates_{angle:g}", units)
    return written


def _plot(templates: list[Template], stem: Path, units: str) -> list[Path]:
    """Small multiples of the templates at one scale, each model drawn at the start, the
    middle and the end of its turn (drawn in metres, ticks in ``units``)."""
    from clearance.reports.documents.drawing import draw_bodies
    from clearance.reports.documents.plotting import plan_axes, vehicle_colours

    scale = length_scale(units)
    n = len(templates)
    ncols = min(n, 4)
    nrows = math.ceil(n / ncols)
    colours = vehicle_colours([t.vehicle.name for t in templates])
    # One scale: every panel spans the same extent (the largest template's).
    bounds = np.array([t.swept.envelope.bounds for t in templates])
    half = 0.55 * float(max((bounds[:, 2] - bounds[:, 0]).max(),
                            (bounds[:, 3] - bounds[:, 1]).max()))
    fig, _ = new_figure(2.1 * ncols + 0.4, 2.2 * nrows + 0.6)
    fig.clf()
    axes = fig.subplots(nrows, ncols, squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax, t in zip(axes.flat, templates, strict=False):
        env = t.swept.envelope
        colour = colours[t.vehicle.name]
        cx, cy = [(a + b) / 2 for a, b in zip(env.bounds[:2], env.bounds[2:], strict=True)]
        for poly in getattr(env, "geoms", [env]):
            x, y = np.asarray(poly.exterior.coords).T
            ax.fill(x, y, color=colour, alpha=0.12, lw=0)
            ax.plot(x, y, color=colour, lw=0.8, label="swept envelope")
        for _name, track in sorted(t.swept.wheel_tracks.items()):
            x, y = np.asarray(track.coords).T
            ax.plot(x, y, color="#555555", lw=0.4, label="wheel tracks")
        tr = t.run.trajectory
        ax.plot(tr.xf_m, tr.yf_m, color="black", lw=0.6, ls="--",
                label="steered-axle centre")
        draw_bodies(ax, t.run, colour, 3)
        ax.set_xlim(cx - half, cx + half)
        ax.set_ylim(cy - half, cy + half)
        ax.set_aspect("equal")
        plan_axes(ax, units, labels=False)
        ax.set_title(f"{t.vehicle.name}\nCTR {t.radius_m / scale:.1f} {units}, "
                     f"swept {t.swept.max_swept_width_m / scale:.1f} {units}", fontsize=7)
        ax.tick_params(labelsize=6)
        ax.grid(alpha=0.3)
    first = axes.flat[0]
    handles, labels = first.get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=False))
    fig.legend(unique.values(), unique.keys(), loc="upper center", ncol=3, fontsize=7,
               frameon=False, bbox_to_anchor=(0.5, 1.0))
    angle = templates[0].angle_deg if templates else 0.0
    fig.suptitle(f"{angle:g}° turning templates at each model's minimum radius, the vehicle "
                 f"at start, middle and end (one scale; axes in {units}; one sheet each in "
                 "templates.pdf)", y=1.03, fontsize=9)
    fig.tight_layout()
    return save(fig, stem)


def template_envelope_area(t: Template) -> float:
    """Area of a template's envelope (m²), for tests and summaries."""
    return float(shapely.area(t.swept.envelope))


# ------------------------------------------------------------------ template sheets

#: Template sheets: A3 landscape (mm), two panels (90° and 180°) and a data block.
TEMPLATE_PAPER_MM = (420.0, 297.0)
TEMPLATE_PANEL_MM = (190.0, 185.0)
TEMPLATE_SCALES = (100, 200, 250, 500, 1000)


def arc_centre(t: Template) -> np.ndarray:
    """The centre of a template's arc (the turn is a left turn from the origin along +x).

    Examples
    --------
    >>> from types import SimpleNamespace as T
    >>> arc_centre(T(radius_m=12.5, angle_deg=90.0, transition_m=0.0)).tolist()
    [0.0, 12.5]
    """
    return turn_centre(t.radius_m, t.angle_deg, t.transition_m)


class TemplateDimensions(TypedDict):
    """What :func:`template_dimensions` measures (m, degrees; ``swept``: inner point, outer
    point, width)."""

    ctr_m: float
    inside_radius_m: float
    trailer_inside_radius_m: float
    swept: tuple[np.ndarray, np.ndarray, float]
    max_articulation_deg: float


def template_dimensions(t: Template) -> TemplateDimensions:
    """What a template sheet dimensions, measured on the driven template (m, degrees).

    ``ctr_m`` (the arc of the steered-axle centre), ``inside_radius_m`` (closest approach
    of the body to the arc's centre, negative when the body passes over it),
    ``trailer_inside_radius_m`` (the trailer's alone, NaN without one), ``swept`` (the
    inner and outer points on the ray from the centre through the three-quarter point of
    the arc, and the width between them), ``max_articulation_deg``.
    """
    c = arc_centre(t)
    centre = shapely.Point(*c)
    env = t.swept.envelope

    def inside(geom) -> float:
        if geom is None or geom.is_empty:
            return math.nan
        d = float(shapely.distance(centre, geom.boundary))
        return -d if shapely.contains(geom, centre) else d

    a = math.radians(0.75 * t.angle_deg)
    direction = np.array([math.sin(a), -math.cos(a)])  # the arc point C + R(sin a, -cos a)
    ray = shapely.LineString([c, c + direction * 4 * max(t.radius_m, 10.0)])
    cut = shapely.intersection(ray, env)
    pts = shapely.get_coordinates(cut)
    if len(pts):
        r = (pts - c) @ direction
        inner, outer = c + direction * r.min(), c + direction * r.max()
        width = float(r.max() - r.min())
    else:
        inner = outer = c
        width = math.nan
    psi = t.run.trajectory.psi_rad
    return {"ctr_m": t.radius_m, "inside_radius_m": inside(env),
            "trailer_inside_radius_m": inside(t.swept.trailer),
            "swept": (inner, outer, width),
            "max_articulation_deg": (math.degrees(float(np.max(np.abs(psi))))
                                     if psi is not None and len(psi) else math.nan)}


def steady_words(metrics_row, units: str) -> str:
    """The steady state of a combination at full lock, in words.

    Examples
    --------
    >>> import pandas as pd
    >>> steady_words(pd.Series({"steady_state": False, "articulation_limited": True}), "m")
    'no steady state at full lock: the trailer would keep cutting in until it jackknifes'
    """
    from clearance.reports.documents.drawing import length_text

    if not bool(metrics_row.get("steady_state", True)):
        return "no steady state at full lock: the trailer would keep cutting in until it jackknifes"
    psi = metrics_row.get("trailer_articulation_rad", math.nan)
    if psi is None or not math.isfinite(psi):
        return ""
    limited = " (limited by the maximum articulation)" if metrics_row.get(
        "articulation_limited") else ""
    return (f"steady state{limited}: articulation {math.degrees(psi):.1f}°, trailer inside "
            f"radius {length_text(metrics_row['trailer_inside_radius_m'], units)}")


def _template_panel(ax, t: Template, units: str, colour: str) -> TemplateDimensions:
    from clearance.reports.documents.drawing import dimension, draw_bodies, length_text

    dims = template_dimensions(t)
    c = arc_centre(t)
    env = t.swept.envelope
    for poly in getattr(env, "geoms", [env]):
        xy = np.asarray(poly.exterior.coords)
        ax.fill(xy[:, 0], xy[:, 1], color=colour, alpha=0.08, lw=0)
        ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=1.1)
    tracks = t.swept.wheel_tracks
    for name, style in (("front_right", "-"), ("rear_left", (0, (3, 1.5))),
                        ("trailer_left", (0, (1, 1)))):
        if name in tracks:
            xy = np.asarray(tracks[name].coords)
            ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=0.7, ls=style)
    tr = t.run.trajectory
    ax.plot(tr.xf_m, tr.yf_m, color="black", lw=0.6, ls=(0, (8, 2)))
    if tr.xt_m is not None:
        ax.plot(tr.xt_m, tr.yt_m, color=colour, lw=0.7, ls=(0, (6, 1.5, 1, 1.5)))
    draw_bodies(ax, t.run, colour, 7 if t.angle_deg <= 90 else 9)
    ax.plot(*c, marker="+", ms=9, color="black", mew=1.0)
    a = math.radians(0.3 * t.angle_deg)
    on_arc = c + t.radius_m * np.array([math.sin(a), -math.cos(a)])
    dimension(ax, c, on_arc, f"CTR {length_text(t.radius_m, units)}", "black", (4, 4))
    r_in = dims["inside_radius_m"]
    if math.isfinite(r_in) and r_in > 0.05:
        q = np.asarray(shapely.shortest_line(shapely.Point(*c), env.boundary).coords)[1]
        dimension(ax, c, q, f"inside radius {length_text(r_in, units)}", "#7d3c98", (-80, 10))
    elif math.isfinite(r_in):
        ax.annotate("the body passes over the turn's centre", c, xytext=(8, -14),
                    textcoords="offset points", fontsize=6.5)
    inner, outer, width = dims["swept"]
    if math.isfinite(width):
        dimension(ax, inner, outer, f"swept width {length_text(width, units)}", "#c0392b",
                  (6, -16))
    return dims


def template_sheet(t90: Template, t180: Template, metrics_row, units: str, colour: str):
    """One vehicle's template sheet (a matplotlib figure, A3 landscape)."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from clearance.reports.documents.drawing import length_text
    from clearance.reports.documents.plotting import (
        STYLE,
        add_north_arrow,
        add_scale_bar,
        plan_axes,
    )
    from clearance.reports.documents.sheet_blocks import MM, vehicle_rows
    from clearance.reports.documents.sheets import fit_scale

    W, H = TEMPLATE_PAPER_MM
    pw, ph = TEMPLATE_PANEL_MM
    with plt.rc_context(STYLE):
        fig = plt.figure(figsize=(W * MM, H * MM))
    fig.add_artist(Rectangle((5 / W, 5 / H), (W - 10) / W, (H - 10) / H,
                             transform=fig.transFigure, fc="none", ec="black", lw=1.0))
    v = t90.vehicle
    # one scale for both panels: the larger extent of the two, with 3 m around
    spans = []
    for t in (t90, t180):
        b = t.swept.envelope.bounds
        spans.append((b[2] - b[0] + 6, b[3] - b[1] + 6))
    n = fit_scale(max(s[0] for s in spans), max(s[1] for s in spans), (pw, ph),
                  TEMPLATE_SCALES)
    dims: list[TemplateDimensions] = []
    for k, t in enumerate((t90, t180)):
        ax = fig.add_axes(((14 + k * (pw + 14)) / W, 78 / H, pw / W, ph / H))
        b = t.swept.envelope.bounds
        cx, cy = (b[0] + b[2]) / 2, (b[1] + b[3]) / 2
        hw, hh = pw * n / 2000, ph * n / 2000
        ax.set_xlim(cx - hw, cx + hw)
        ax.set_ylim(cy - hh, cy + hh)
        ax.set_aspect("equal")
        dims.append(_template_panel(ax, t, units, colour))
        plan_axes(ax, units, labels=False)
        add_scale_bar(ax, units)
        add_north_arrow(ax)
        ax.set_title(f"{t.angle_deg:g}° turn at the minimum radius", fontsize=8.5, loc="left")
    fig.text(14 / W, (H - 10) / H, f"Turning template: {v.name}", fontsize=12,
             fontweight="bold", va="top")
    fig.text(14 / W, (H - 17) / H,
             f"{v.category or 'vehicle'}; steered-axle centre on an arc of "
             f"{length_text(t90.radius_m, units)} (the CTR at full lock), entered and left "
             f"through a steering transition at its steering rate, crawl speed; "
             f"scale 1:{n} on A3",
             fontsize=7.5, va="top")
    rows = vehicle_rows(v, units)
    left = [f"{k}: {val}" for k, val in rows if k != "source"]
    for i, line in enumerate(left):
        col, row = divmod(i, 9)
        fig.text((14 + col * 95) / W, (66 - row * 5.0) / H, line, fontsize=7.5, va="top")
    m = metrics_row
    res = [f"curb-to-curb turning circle: {length_text(m['curb_to_curb_m'], units)}",
           f"wall-to-wall turning circle: {length_text(m['wall_to_wall_m'], units)}",
           f"inside radius, 90° / 180°: {length_text(dims[0]['inside_radius_m'], units)} / "
           f"{length_text(dims[1]['inside_radius_m'], units)}",
           f"swept width, 90° / 180°: {length_text(dims[0]['swept'][2], units)} / "
           f"{length_text(dims[1]['swept'][2], units)}"]
    if v.trailer is not None:
        res += [f"trailer inside radius, 90° / 180°: "
                f"{length_text(dims[0]['trailer_inside_radius_m'], units)} / "
                f"{length_text(dims[1]['trailer_inside_radius_m'], units)}",
                f"largest articulation, 90° / 180°: {dims[0]['max_articulation_deg']:.1f}° / "
                f"{dims[1]['max_articulation_deg']:.1f}°"]
        words = steady_words(m, units)
        if words:
            res.append(words)
    for i, line in enumerate(res):
        fig.text(218 / W, (66 - i * 5.0) / H, line, fontsize=7.5, va="top",
                 fontweight="bold" if line.startswith("no steady") else "normal",
                 color="#c0392b" if line.startswith("no steady") else "black")
    source = v.source or "-"
    fig.text(14 / W, 17 / H, textwrap.fill("source: " + (source if len(source) < 400 else
                                                         source[:399] + "…"), 190),
             fontsize=6.5, va="top", color="#333333")
    return fig


def write_template_sheets(table: VehicleTable, path: str | Path, units: str = "m",
                          built: dict[float, list[Template]] | None = None) -> Path:
    """``templates.pdf``: one A3 sheet per vehicle, its 90° and 180° templates dimensioned
    (``built``: templates already driven, by angle)."""
    import io

    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_pdf import PdfPages

    from clearance.analysis.turning import turning_metrics
    from clearance.reports.documents.plotting import vehicle_colours
    from clearance.reports.documents.sheet_blocks import PDF_METADATA
    from clearance.reports.output.atomic import write_bytes_atomic

    built = built or {}
    t90s = built.get(90.0) or build_templates(table, 90.0)
    t180s = built.get(180.0) or build_templates(table, 180.0)
    metrics = turning_metrics(table).set_index("vehicle")
    colours = vehicle_colours(table.names)
    buf = io.BytesIO()
    with PdfPages(buf, metadata=PDF_METADATA) as pdf:
        for a, b in zip(t90s, t180s, strict=True):
            fig = template_sheet(a, b, metrics.loc[a.vehicle.name], units,
                                 colours[a.vehicle.name])
            pdf.savefig(fig)
            plt.close(fig)
    return write_bytes_atomic(Path(path), buf.getvalue())
