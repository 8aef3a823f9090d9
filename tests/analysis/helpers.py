"""Centre lines and vehicles shared by the analysis tests (built directly, no table)."""

from __future__ import annotations

import math

import numpy as np

from clearance.analysis.polyline import Path, prepare_path
from clearance.vehicles.vehicle import Trailer, Vehicle


def turn(radius_m: float, angle_deg: float, lead_m: float = 15.0, tail_m: float = 15.0,
         left: bool = True, step_deg: float = 1.0) -> np.ndarray:
    """Straight approach along +x to the origin, an arc, a straight exit (N x 2, metres)."""
    a = np.radians(np.arange(0.0, angle_deg + 1e-9, step_deg))
    sign = 1.0 if left else -1.0
    arc = np.c_[radius_m * np.sin(a), sign * radius_m * (1.0 - np.cos(a))]
    h = sign * math.radians(angle_deg)
    parts = [arc]
    if lead_m > 0:
        parts.insert(0, np.array([[-lead_m, 0.0]]))
    if tail_m > 0:
        parts.append(arc[-1] + tail_m * np.array([[math.cos(h), math.sin(h)]]))
    return np.concatenate(parts)


def bus(rate: float = 0.5, lock: float = 0.6) -> Vehicle:
    return Vehicle("bus", 6.0, 2.1, 2.55, 2.0, 3.0, lock, lock + 0.05, rate)


def car(rate: float = 0.6) -> Vehicle:
    return Vehicle("car", 2.7, 1.55, 1.8, 0.9, 1.0, math.radians(33.0), math.radians(36.0),
                   rate)


def semi(max_articulation_deg: float = 90.0) -> Vehicle:
    trailer = Trailer(hitch_offset_m=-0.4, wheelbase_m=10.0, width_m=2.55,
                      front_overhang_m=1.2, rear_overhang_m=2.8,
                      max_articulation_rad=math.radians(max_articulation_deg))
    return Vehicle("semi", 4.0, 2.0, 2.55, 1.4, 1.0, math.radians(35.0), math.radians(40.0),
                   0.4, trailer=trailer)


def steady_rho(path_radius_m: float, wheelbase_m: float) -> float:
    """Rear-axle radius when the front-axle centre runs on a circle of ``path_radius_m``."""
    return math.sqrt(path_radius_m**2 - wheelbase_m**2)


def corner_path(radius_m: float, lead_m: float = 25.0, smooth: bool = True
                ) -> tuple[Path, tuple[float, float]]:
    """A right-hand quarter circle between two straights of ``lead_m``; and its feature."""
    a = np.radians(np.linspace(90.0, 0.0, 46))
    arc = np.c_[radius_m * np.cos(a), lead_m + radius_m * np.sin(a)]
    pts = np.vstack([[(-lead_m, lead_m + radius_m)], arc, [(radius_m, 0.0)]])
    path = prepare_path(pts, 0.1, name="corner", smooth=smooth)
    return path, (lead_m, lead_m + math.pi * radius_m / 2)
