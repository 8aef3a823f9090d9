"""The report's vertical checks: a curve's profile with the vehicle in side view.

For every curve where a run scrapes or is too steep, and for every ramp, the report draws
(:func:`plot_profile`) the centre line's height along it (stations from the feature's
start; the feature shaded; heights exaggerated to show the grades) and, below, at true
scale, the worst vehicle at its worst placement: the ground, the wheels on it, the body
with its lower outline (the one :mod:`clearance.analysis.vertical` checks), and the point where the
ground comes closest or cuts in, marked and labelled. :func:`vertical_entries` picks the
curves and their runs for a network.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Polygon

from clearance.analysis.vertical import Body, front_contact
from clearance.networks.curves import Curve
from clearance.reports.documents.plotting import PNG, STYLE, save
from clearance.reports.output.file_names import file_name
from clearance.reports.results.records import RunRecord
from clearance.reports.results.units import length_scale
from clearance.reports.results.vertical import profile_of, vertical_result, vertical_words
from clearance.vehicles.vehicle import Vehicle

__all__ = ["MAX_PROFILE_FIGURES", "VerticalEntry", "plot_profile", "vertical_entries"]

#: At most this many profile figures per network (the worst curves first).
MAX_PROFILE_FIGURES = 8

#: Body height drawn where the table gives none (m): a car's roof (schematic).
DEFAULT_HEIGHT_M = 1.5


@dataclass
class VerticalEntry:
    """A curve of the report's vertical checks: its figure and its runs, worst first."""

    curve_id: str
    figure: Path | None
    runs: list[RunRecord]


def _side_view(curve: Curve, vehicle: Vehicle, rear_m: float
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Body polygon, lower outline, wheel centres and the chord frame (u, n) in (s, z)."""
    s, z = profile_of(curve)
    s, z = np.asarray(s), np.asarray(z)
    body = Body.of(vehicle)
    ell = body.wheelbase_m
    front = float(front_contact(s, z, np.array([rear_m]), ell)[0])
    p_r = np.array([rear_m, np.interp(rear_m, s, z)])
    p_f = np.array([front, np.interp(front, s, z)])
    u = (p_f - p_r) / ell
    n = np.array([-u[1], u[0]])
    x = np.unique(np.r_[np.linspace(-body.rear_overhang_m, ell + body.front_overhang_m, 200),
                        body.corners()])
    y = body.outline(x)
    lower = p_r + x[:, None] * u + y[:, None] * n
    height = vehicle.height_m or DEFAULT_HEIGHT_M
    top = p_r + x[::-1, None] * u + np.full_like(x, height)[:, None] * n
    wheel = min(max(0.11 * ell, 0.30), 0.55)
    centres = np.array([p_r + wheel * n, p_f + wheel * n])
    return np.vstack([lower, top]), lower, centres, (u, n)


def plot_profile(curve: Curve, vehicle: Vehicle, record: RunRecord, stem: Path,
                 units: str = "m", formats: tuple[str, ...] = PNG) -> Path:
    """Draw the profile of ``curve`` with ``vehicle`` at its worst placement (the files of
    ``formats``, PNG first); the PNG."""
    k = length_scale(units)
    s, z = profile_of(curve)
    s, z = np.asarray(s), np.asarray(z)
    res = vertical_result(vehicle, curve)
    x0 = curve.core_start_m
    with plt.rc_context(STYLE):
        fig, (top, low) = plt.subplots(2, 1, figsize=(7.0, 6.4), dpi=150,
                                       gridspec_kw={"height_ratios": [1, 1.4]})
    top.plot((s - x0) / k, z / k, color="#333", lw=1.2)
    top.axvspan(0, (curve.core_end_m - x0) / k, color="#f0c36d", alpha=0.3, lw=0,
                label="feature")
    top.set_xlabel(f"station from the feature's start [{units}]")
    top.set_ylabel(f"height [{units}]")
    top.set_title(f"{curve.curve_id}: profile (heights exaggerated), max grade "
                  f"{curve.max_grade_pct:.1f} %", fontsize=9)
    scrapes = res.margin_m < 0
    colour = "#c0392b" if scrapes else "#2e86c1"
    if math.isfinite(res.station_m):
        top.axvline((res.station_m - x0) / k, color=colour, lw=0.8, ls="--",
                    label=f"worst station ({vehicle.name})")
    top.legend(loc="best")
    # the close-up at true scale
    if math.isfinite(res.rear_axle_m):
        rear = res.rear_axle_m
    else:  # a level curve: the vehicle at the feature's middle
        rear = 0.5 * (curve.core_start_m + curve.core_end_m) - 0.5 * vehicle.wheelbase_m
    poly, lower, centres, _ = _side_view(curve, vehicle, rear)
    lo = rear - vehicle.rear_overhang_m - 2.5
    hi = rear + vehicle.wheelbase_m + vehicle.front_overhang_m + 2.5
    pick = (s >= lo) & (s <= hi)
    gs = np.r_[lo, s[pick], hi]
    gz = np.interp(gs, s, z)
    low.fill_between((gs - x0) / k, gz / k, (gz.min() - 1.0) / k, color="#bbb", lw=0)
    low.plot((gs - x0) / k, gz / k, color="#333", lw=1.2, label="ground (centre line)")
    low.add_patch(Polygon(np.c_[(poly[:, 0] - x0) / k, poly[:, 1] / k], closed=True,
                          fc=colour, alpha=0.18, ec=colour, lw=1.0))
    low.plot((lower[:, 0] - x0) / k, lower[:, 1] / k, color=colour, lw=1.4,
             label="underside checked")
    wheel = min(max(0.11 * vehicle.wheelbase_m, 0.30), 0.55)
    for c in centres:
        low.add_patch(Circle(((c[0] - x0) / k, c[1] / k), wheel / k, fc="#222", ec="#222",
                             zorder=3))
    if math.isfinite(res.station_m):
        zs = float(np.interp(res.station_m, s, z))
        low.plot([(res.station_m - x0) / k], [zs / k], "o", ms=7, mfc="none", mec=colour,
                 mew=2)
        depth = abs(res.margin_m) / k
        text = (f"{res.part}: {depth:.3f} {units} into the ground" if scrapes
                else f"{res.part}: {depth:.3f} {units} to spare")
        low.annotate(text, ((res.station_m - x0) / k, zs / k), xytext=(0, -22),
                     textcoords="offset points", ha="center", color=colour, fontsize=8,
                     arrowprops={"arrowstyle": "-", "color": colour})
    low.set_aspect("equal")
    low.set_xlim((lo - x0) / k, (hi - x0) / k)
    low.set_ylim((gz.min() - 1.0) / k, (gz.max() + (vehicle.height_m or DEFAULT_HEIGHT_M)
                                        + 0.6) / k)
    low.set_xlabel(f"station from the feature's start [{units}] (true scale)")
    low.set_ylabel(f"height [{units}]")
    words = vertical_words(record, units) or "vertical clear"
    u = vehicle.underside_or_default()
    source = ("\nunderside: the class default, no source" if u.defaulted
              else "" if u.note == "given" else "\nunderside: angles derived from the clearance")
    low.set_title(f"{vehicle.name} at its worst placement: {words}"[:110] + source,
                  fontsize=8)
    low.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    return save(fig, stem, formats)[0]


def vertical_entries(curves: Sequence[Curve], records: Sequence[RunRecord],
                     vehicles: dict[str, Vehicle], figures: Path,
                     network: str, units: str = "m", formats: tuple[str, ...] = PNG
                     ) -> list[VerticalEntry]:
    """The curves of one network the vertical section shows (a run scrapes or is too
    steep, or the curve is a ramp), worst first, the first :data:`MAX_PROFILE_FIGURES`
    with a profile figure of their worst run (the files of ``formats``)."""
    by_curve: dict[str, list[RunRecord]] = {}
    for r in records:
        by_curve.setdefault(r.curve_id, []).append(r)
    kinds = {c.curve_id: c for c in curves}
    shown = []
    for cid, runs in by_curve.items():
        found = any(r.vertical not in ("", "clear") for r in runs)
        if found or kinds[cid].kind == "ramp" or kinds[cid].suspect_elevation:
            runs.sort(key=lambda r: (r.vertical in ("", "clear"), r.vertical_margin_m))
            shown.append((cid, runs))
    shown.sort(key=lambda x: (x[1][0].vertical in ("", "clear"), x[1][0].vertical_margin_m))
    out = []
    for i, (cid, runs) in enumerate(shown):
        png = None
        if i < MAX_PROFILE_FIGURES:
            worst = runs[0]
            stem = figures / file_name([network, "profile", cid], room=4)
            png = plot_profile(kinds[cid], vehicles[worst.vehicle], worst, stem, units,
                               formats)
        out.append(VerticalEntry(cid, png, runs))
    return out
