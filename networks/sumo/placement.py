"""What SUMO is told about a run: vTypes, routes, lane hints, placements, replay.

Helpers of :mod:`clearance.networks.driving.drive`, free of libsumo: a vehicle's vType parameters
and shape class, the edges and lanes of a curve, where each lane ends along a centre line, the
points SUMO places (front-bumper centre of the towing unit, front of the trailer), and the SUMO
configuration that replays FCD output in sumo-gui.
"""

from __future__ import annotations

import math
import os
import shlex
import sys
from collections.abc import Sequence

import numpy as np
import shapely

from clearance.analysis.polyline import Path
from clearance.analysis.tracking import TrackingRun
from clearance.networks.curves import Curve
from clearance.networks.sumo.tools import sumo_home
from clearance.vehicles.errors import GeometryError
from clearance.vehicles.vehicle import Vehicle

__all__ = ["replay_command", "replay_script", "REPLAY_COMMAND", "centre_stations",
           "edge_of_lane", "first_on", "front_bumper", "lane_boundaries_m", "lane_index",
           "replay_config", "route_edges", "shape_class", "trailer_front", "vtype_parameters"]

REPLAY_COMMAND = 'python "$SUMO_HOME/tools/fcdReplay.py" -k {config} -f {fcd}'
"""How to replay an FCD file in sumo-gui (format with the config and FCD paths)."""


def replay_config(net_path: str | os.PathLike[str], dt_s: float,
                  additional: Sequence[str | os.PathLike[str]] = ()) -> str:
    """A SUMO configuration for replaying FCD output over ``net_path`` (XML text), with
    sumo-gui's ``additional`` files (relative paths are the configuration's folder's).

    Examples
    --------
    >>> print(replay_config("x.net.xml", 0.1))  # doctest: +NORMALIZE_WHITESPACE
    <?xml version="1.0" encoding="UTF-8"?> <configuration>
        <input><net-file value="x.net.xml"/></input>
        <time><step-length value="0.1"/></time>
    </configuration>
    >>> print(replay_config("x.net.xml", 0.2, ["paths.add.xml"]))
    ... # doctest: +NORMALIZE_WHITESPACE
    <?xml version="1.0" encoding="UTF-8"?> <configuration>
        <input><net-file value="x.net.xml"/>
            <additional-files value="paths.add.xml"/></input>
        <time><step-length value="0.2"/></time>
    </configuration>
    """
    from xml.sax.saxutils import quoteattr

    extra = ""
    if additional:
        files = ",".join(os.fspath(a) for a in additional)
        extra = f"\n        <additional-files value={quoteattr(files)}/>"
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<configuration>\n'
            f'    <input><net-file value={quoteattr(os.fspath(net_path))}/>{extra}</input>\n'
            f'    <time><step-length value="{dt_s!r}"/></time>\n</configuration>\n')


def edge_of_lane(lane_id: str) -> str:
    """The edge id of a lane id (``E1_0`` -> ``E1``; ``:J_3_0`` -> ``:J_3``).

    Examples
    --------
    >>> edge_of_lane("XN_in_1"), edge_of_lane(":X_0_0")
    ('XN_in', ':X_0')
    """
    edge, sep, index = lane_id.rpartition("_")
    if not sep or not index.isdigit():
        raise ValueError(f"lane id {lane_id!r} does not end in _<index>")
    return edge


def lane_index(lane_id: str) -> int:
    """The index of a lane within its edge (``E1_2`` -> 2).

    Examples
    --------
    >>> lane_index(":X_0_1")
    1
    """
    edge_of_lane(lane_id)
    return int(lane_id.rpartition("_")[2])


def route_edges(curve: Curve) -> list[str]:
    """The curve's normal (non-internal) edges in driving order, without repeats in a row."""
    edges: list[str] = []
    for lane in curve.lanes:
        e = edge_of_lane(lane)
        if not e.startswith(":") and (not edges or edges[-1] != e):
            edges.append(e)
    if not edges:
        raise GeometryError(f"curve {curve.curve_id}: no normal edge to route a vehicle on")
    return edges


def shape_class(category: str) -> str:
    """SUMO ``guiShape`` for a table category.

    Semitrailer combinations get ``truck``: their SUMO vehicle is the tractor alone (the
    trailer is a second vehicle), and ``truck/semitrailer`` would draw a trailer on it.

    Examples
    --------
    >>> shape_class("passenger car"), shape_class("school bus"), shape_class("SUV")
    ('passenger', 'bus', 'passenger/van')
    """
    c = category.lower()
    if "bus" in c:
        return "bus"
    if "truck" in c or "semitrailer" in c or "trailer" in c or "tractor" in c:
        return "truck"
    if "van" in c or "suv" in c or "pickup" in c:
        return "passenger/van"
    return "passenger"


def vtype_parameters(vehicle: Vehicle) -> dict[str, str]:
    """Our geometry as vType parameters (SUMO has no such attributes); metres, degrees.

    Examples
    --------
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> p = vtype_parameters(car)
    >>> p["wheelbase_m"], p["max_steer_deg"], "trailer_wheelbase_m" in p
    ('2.7', '34.3775', False)
    """
    def f(v: float) -> str:
        return f"{v:.6g}"

    p = {
        "wheelbase_m": f(vehicle.wheelbase_m),
        "track_m": f(vehicle.track_m),
        "front_overhang_m": f(vehicle.front_overhang_m),
        "rear_overhang_m": f(vehicle.rear_overhang_m),
        "max_steer_deg": f(math.degrees(vehicle.max_steer_rad)),
        "max_inner_steer_deg": f(math.degrees(vehicle.max_inner_steer_rad)),
        "max_steer_rate_deg_s": f(math.degrees(vehicle.max_steer_rate_rad_s)),
        "steered_axle": vehicle.steered_axle,
    }
    t = vehicle.trailer
    if t is not None:
        p.update({
            "trailer_hitch_offset_m": f(t.hitch_offset_m),
            "trailer_wheelbase_m": f(t.wheelbase_m),
            "trailer_width_m": f(t.width_m),
            "trailer_front_overhang_m": f(t.front_overhang_m),
            "trailer_rear_overhang_m": f(t.rear_overhang_m),
            "trailer_max_articulation_deg": f(math.degrees(t.max_articulation_rad)),
        })
    return p


def lane_boundaries_m(curve: Curve, path: Path, lane_ends: Sequence[np.ndarray]) -> np.ndarray:
    """Stations on ``path`` where each lane of the curve but the last ends.

    ``lane_ends[i]`` is the (x, y, z) end point of ``curve.lanes[i]``. Each is matched to
    the path's nearest point in 3-D past the previous boundary (a helix passes over itself
    in plan; its levels differ in z).
    """
    pts = np.column_stack([path.xy, path.z if path.z is not None else np.zeros(len(path.xy))])
    out = []
    start = 0
    for end in lane_ends[:-1]:
        p = np.asarray(end, dtype=float)
        if p.shape[0] == 2:
            p = np.append(p, 0.0 if path.z is None else pts[start, 2])
        d = np.linalg.norm(pts[start:] - p, axis=1)
        k = start + int(np.argmin(d))
        out.append(float(path.station_m[k]))
        start = k
    return np.asarray(out)


def first_on(area, x: np.ndarray, y: np.ndarray) -> int:
    """Index of the first point inside ``area`` (shapely), or ``len(x)`` when none is."""
    inside = shapely.contains_xy(area, x, y)
    hits = np.flatnonzero(inside)
    return int(hits[0]) if len(hits) else len(x)


def centre_stations(centre: Path, line: Path, x: np.ndarray, y: np.ndarray,
                    along_m: np.ndarray) -> np.ndarray:
    """Stations on ``centre`` (m) of the points ``(x, y)`` that lie about ``along_m`` along
    ``line``, a line that leaves ``centre`` and rejoins it: a swung path (a kept part of the
    centre line moved sideways, :mod:`clearance.networks.driving.shapes`).

    Each point is matched to ``centre``'s nearest point within a band around its station
    mapped from ``line`` in proportion (``line``'s ends matched to ``centre``'s nearest
    points, in 3-D where both have levels), so that a point is never matched to another
    part of a centre line that passes near itself (a roundabout's arms, a helix's levels).
    The edge and lane hints of SUMO's placements are looked up at these stations.

    Examples
    --------
    A line swung 2 m to the left over the middle of a straight centre line:

    >>> from clearance.analysis.polyline import prepare_path
    >>> centre = prepare_path([(0.0, 0.0), (20.0, 0.0)], spacing_m=1.0)
    >>> line = prepare_path([(5.0, 0.0), (10.0, 2.0), (15.0, 0.0)], spacing_m=1.0)
    >>> st = centre_stations(centre, line, np.array([10.0, 14.0]), np.array([1.9, 0.3]),
    ...                      np.array([5.4, 9.9]))
    >>> st.round(3).tolist()
    [10.0, 14.0]
    """
    from clearance.networks.driving.shapes import nearest_on

    def points(p: Path, k: slice | list[int]) -> np.ndarray:
        if p.z is None or centre.z is None or line.z is None:
            return np.asarray(p.xy[k], dtype=float)
        return np.column_stack([p.xy[k], p.z[k]])

    ends = points(line, [0, -1])
    pts = points(centre, slice(None))
    near = np.argmin(np.linalg.norm(pts[None, :, :] - ends[:, None, :], axis=2), axis=1)
    s0, s1 = (float(centre.station_m[k]) for k in near)
    scale = (s1 - s0) / line.length_m if line.length_m > 0 else 0.0
    guess = s0 + np.asarray(along_m, dtype=float) * scale
    band = abs(line.length_m - (s1 - s0)) + 3.0
    xy = np.column_stack([np.asarray(x, dtype=float), np.asarray(y, dtype=float)])
    return nearest_on(np.asarray(centre.xy, dtype=float), xy, guess, band)[0]


def front_bumper(run: TrackingRun) -> tuple[np.ndarray, np.ndarray]:
    """SUMO's reference point: the front-bumper centre, ahead of the front axle.

    Examples
    --------
    >>> from clearance.analysis.polyline import prepare_path
    >>> from clearance.analysis.tracking import simulate
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> x, y = front_bumper(simulate(car, prepare_path([(0.0, 0.0), (10.0, 0.0)])))
    >>> round(float(x[0]), 3), round(float(y[0]), 3)
    (0.9, 0.0)
    """
    tr = run.trajectory
    a = run.vehicle.front_overhang_m
    return tr.xf_m + a * np.cos(tr.theta_rad), tr.yf_m + a * np.sin(tr.theta_rad)


def trailer_front(run: TrackingRun) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The trailer body's front-centre and heading (for its own SUMO vehicle)."""
    tr, v = run.trajectory, run.vehicle
    t = v.trailer
    assert t is not None and tr.xt_m is not None and tr.yt_m is not None
    assert tr.theta_t_rad is not None
    reach = t.wheelbase_m + t.front_overhang_m
    return (tr.xt_m + reach * np.cos(tr.theta_t_rad), tr.yt_m + reach * np.sin(tr.theta_t_rad),
            tr.theta_t_rad)


def replay_command(config: str | os.PathLike[str], fcd: str | os.PathLike[str]) -> str:
    """The shell command that replays ``fcd`` in sumo-gui with SUMO's ``fcdReplay.py``: it
    sets ``SUMO_HOME`` to the installed eclipse-sumo package (a pip install sets none) and
    runs the script with this Python, which has sumolib and traci.

    >>> from pathlib import PurePath
    >>> cmd = replay_command(PurePath("out/replay.sumocfg"), PurePath("out/fcd.xml"))
    >>> cmd.startswith("SUMO_HOME=") and cmd.endswith("-k out/replay.sumocfg -f out/fcd.xml")
    True
    """
    home = sumo_home()
    return (f"SUMO_HOME={shlex.quote(str(home))} {shlex.quote(sys.executable)} "
            f"{shlex.quote(str(home / 'tools' / 'fcdReplay.py'))} "
            f"-k {shlex.quote(str(config))} -f {shlex.quote(str(fcd))}")


def replay_script() -> str:
    """``replay.sh``: the replay of :func:`replay_command`, from the folder it lies in."""
    home = sumo_home()
    return ("#!/bin/sh\n# Replays fcd.xml in sumo-gui (written by clearance simulate --fcd).\n"
            'cd "$(dirname "$0")" || exit 1\n'
            f"SUMO_HOME={shlex.quote(str(home))} exec {shlex.quote(sys.executable)} "
            f"{shlex.quote(str(home / 'tools' / 'fcdReplay.py'))} "
            '-k replay.sumocfg -f fcd.xml "$@"\n')
