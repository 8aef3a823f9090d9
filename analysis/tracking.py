"""Path following: the front-axle centre drives a centre line within the steering limits.

Controller
----------
A Stanley-type law on the front-axle centre (the steering point)::

    phi_cmd = wrap(theta_path - theta) - psi_a(e)

``theta_path`` is the centre line's smooth tangent at the front axle's projection, ``e`` the
front axle's signed lateral offset (left positive), ``v_f`` its speed. The first term is the
path's curvature feed-forward: on a circle of radius ``R`` followed exactly it equals
``asin(l / R)``, the steady-state steering angle, and it grows while the path turns ahead
of the body; the second steers the front wheels toward the line at the approach angle
``psi_a(e) = atan(k e / (v_f + v_soft))`` (``k`` the gain, 1/s), so that
``e' = -v_f sin(psi_a) ~ -k e``, but no steeper than the wheel can take back: approaching
at ``psi_a(e)`` the wheel turns at ``psi_a'(e) v_f sin(psi_a)``, held to half the steering
rate (:func:`clearance.analysis.tracking_loop.approach_angle`).

A wheel turned at a finite rate (a car's road wheels go lock to lock in about 4 s) reaches a
command only later, while the body goes on turning: asked for what the state needs now,
the wheel comes too late, and after a corner tighter than the lock the plain law swings from
lock to lock. So the command is the steering ``c`` that the law asks for at the moment the
wheel reaches it (:func:`clearance.analysis.tracking_loop.predictive_stanley`): the body's turn and
the front axle's drift while the wheel turns from ``phi`` to ``c`` at the rate, the path's
heading there, and, where ``c`` lies beyond the path's steady steering there, the body's
turn while the wheel comes back to it. These corrections are of second order in the
steering's change: on a smooth path, and in the steady state, the law is Stanley's; after
a corner tighter than the lock the vehicle rejoins the centre line without crossing it.

The command passes the steering-rate limit and the lock
(:func:`clearance.analysis.kinematics.limit_steering`); over the step the wheel turns linearly from
its old angle to the new one, and the step is integrated to second order in the time step
(:func:`clearance.analysis.kinematics.ramp_step`: exact while the steering is held); a trailer's
articulation follows along the same arc by RK4
(:func:`clearance.analysis.trailer.advance_articulation`).

Runs, speed and ending
----------------------
The vehicle starts with its front axle on the path's first point, heading along the path,
in the steady state of the path's first two metres (:func:`start_pose`): straight on a
straight start; on a curve of radius ``R`` its rear axle on ``sqrt(R^2 - l^2)`` and the
trailer at its steady articulation. The speed profile gives the front axle's speed; the rear
axle of a front-steered vehicle moves at ``v_f cos(phi)``. A run ends when the front axle's
projection reaches the end of the path (the last step is shortened to land on it), when the
lateral error exceeds ``abort_factor * tolerance_m`` (no point driving on), when the
trailer's articulation exceeds its maximum (jackknife), or after ``max_steps`` steps, bounded
by the path length in every case.

Verdict of the tracking: a run is *followed* when it reached the end, its largest lateral
error stayed within ``tolerance_m`` and no jackknife occurred; otherwise the curve is
``cannot-turn`` for that vehicle and ``reason`` says why.

Rear-steered vehicles
---------------------
The kinematics always integrate the *unsteered* axle's centre (the reference point, on
whose line the centre of rotation lies): ``theta' = (v / l) tan(phi)`` with ``v`` that
axle's speed and ``phi`` the bicycle-equivalent angle, left turns positive (for a rear
steered axle the wheels then point to the right). For a rear-steered vehicle the front axle
is that reference point, it still is the steering point that follows the centre line, and
its velocity lies along the body, so the Stanley law does not apply; a curvature law on
the front axle does (path curvature feed-forward, heading and lateral feedback, critically
damped over ``L = v_f / k`` of travel)::

    kappa_cmd = kappa_path cos(theta_e) / (1 - kappa_path e) - 2 theta_e / L - e / L^2
    phi_cmd = atan(l kappa_cmd),    theta_e = theta - theta_path

Its rear swings out: the rear axle runs outside the front axle's path. A rear-steered
vehicle with a trailer is refused (the hitch would slide sideways with the steered axle).

Batches
-------
:func:`simulate_batch` prepares many (vehicle, path) runs as arrays (paths padded to one
length), advances them all in one compiled loop (:func:`clearance.analysis.tracking_loop.run_loop`)
and returns one :class:`TrackingRun` per pair.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from clearance.analysis.kinematics import CRAWL_SPEED_M_S, SpeedProfile, as_speed_profile
from clearance.analysis.polyline import DEFAULT_SPACING_M, Path, prepare_path
from clearance.analysis.tracking_loop import run_loop
from clearance.analysis.trailer import steady_articulation_rad, trailer_axle_point
from clearance.vehicles.vehicle import Vehicle

__all__ = ["MAX_COMMAND_RAD", "SOFT_SPEED_M_S", "TrackingRun", "TrackingSettings", "Trajectory",
           "check_vehicle", "simulate", "simulate_batch", "simulate_grid", "start_pose"]

FloatArray = NDArray[np.float64]

SOFT_SPEED_M_S = 0.1
"""Softening speed of the Stanley cross-track term (avoids dividing by a vanishing speed)."""

MAX_COMMAND_RAD = math.radians(89.0)
"""Commands are clipped here before the limits (a heading error near 180 degrees)."""


@dataclass(frozen=True)
class TrackingSettings:
    """How a run is driven and judged.

    Attributes
    ----------
    dt_s
        Time step (s): how often the controller acts (0.1 s: every 0.2 m at crawl speed).
        A held steering is integrated exactly, a turning one to second order in the step.
    speed
        Front-axle speed: a constant (m/s) or a
        :class:`~clearance.analysis.kinematics.SpeedProfile`.
    tolerance_m
        Largest lateral offset of the front-axle centre from the centre line that still
        counts as following it (beyond it: ``cannot-turn``).
    gain_1_s
        Stanley cross-track gain ``k`` (1/s).
    abort_factor
        A run stops once the lateral offset exceeds ``abort_factor * tolerance_m``.
    spacing_m
        Resampling step of the centre lines (m).
    trailer_substeps
        RK4 sub-steps of the articulation per time step.
    max_steps
        Hard cap on the number of steps; ``None`` derives one from the longest path and the
        lowest speed (twice the steps the path needs, plus 50).

    Examples
    --------
    >>> TrackingSettings().tolerance_m
    0.5
    >>> TrackingSettings(dt_s=0.1, speed=1.0).profile.speed_m_s
    (1.0,)
    """

    dt_s: float = 0.1
    speed: float | SpeedProfile = CRAWL_SPEED_M_S
    tolerance_m: float = 0.5
    gain_1_s: float = 2.5
    abort_factor: float = 4.0
    spacing_m: float = DEFAULT_SPACING_M
    trailer_substeps: int = 1
    max_steps: int | None = None
    profile: SpeedProfile = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "profile", as_speed_profile(self.speed))
        for name in ("dt_s", "tolerance_m", "gain_1_s", "spacing_m"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ValueError(f"tracking settings: {name} must be a positive number, "
                                 f"got {value!r}")
        if not self.abort_factor >= 1:
            raise ValueError(f"tracking settings: abort_factor must be >= 1, "
                             f"got {self.abort_factor!r}")
        if self.trailer_substeps < 1:
            raise ValueError(f"tracking settings: trailer_substeps must be >= 1, "
                             f"got {self.trailer_substeps!r}")
        if self.max_steps is not None and self.max_steps < 1:
            raise ValueError(f"tracking settings: max_steps must be >= 1, got {self.max_steps!r}")


@dataclass(frozen=True)
class Trajectory:
    """Sampled states of one run; every array has one entry per sample.

    Sample ``k`` is the state at time ``t_s[k]``, ``phi_rad[k]`` the steering then; from
    ``t_s[k]`` to ``t_s[k + 1]`` the wheel turns linearly from ``phi_rad[k]`` to
    ``phi_rad[k + 1]`` (:func:`clearance.analysis.kinematics.ramp_step`). Trailer arrays are
    ``None`` for a
    vehicle without a trailer.

    Attributes
    ----------
    t_s
        Time from the start (s).
    s_m
        Station of the front axle's projection on the centre line (m).
    x_m, y_m, theta_rad
        Rear-axle centre and body heading.
    phi_rad
        Bicycle-equivalent steering angle (left positive).
    xf_m, yf_m
        Front-axle centre (the steering point).
    error_m
        Signed lateral offset of the front-axle centre from the centre line (left positive).
    speed_m_s
        Front-axle speed.
    xt_m, yt_m, theta_t_rad, psi_rad
        Trailer axle centre, trailer heading and articulation ``theta - theta_t``.
    """

    t_s: FloatArray
    s_m: FloatArray
    x_m: FloatArray
    y_m: FloatArray
    theta_rad: FloatArray
    phi_rad: FloatArray
    xf_m: FloatArray
    yf_m: FloatArray
    error_m: FloatArray
    speed_m_s: FloatArray
    xt_m: FloatArray | None = None
    yt_m: FloatArray | None = None
    theta_t_rad: FloatArray | None = None
    psi_rad: FloatArray | None = None

    def __len__(self) -> int:
        return len(self.t_s)


@dataclass(frozen=True)
class TrackingRun:
    """One vehicle driven along one centre line.

    Attributes
    ----------
    vehicle, path
        What was driven where.
    trajectory
        The sampled states.
    settings
        The settings of the run.
    reached_end
        The front axle reached the end of the path.
    max_error_m
        Largest absolute lateral offset of the front-axle centre (m).
    jackknife_time_s
        When the articulation first exceeded the trailer's maximum, else ``None``.
    steps_at_lock, steps_rate_limited
        Steps where the lock, or the steering rate, cut the command.
    reason
        Why the path could not be followed; empty when it was.
    """

    vehicle: Vehicle
    path: Path
    trajectory: Trajectory
    settings: TrackingSettings
    reached_end: bool
    max_error_m: float
    jackknife_time_s: float | None
    steps_at_lock: int
    steps_rate_limited: int
    reason: str

    @property
    def followed(self) -> bool:
        """The front axle followed the whole centre line within the tolerance."""
        return not self.reason

    @property
    def cannot_turn(self) -> bool:
        """The verdict ``cannot-turn`` applies (the opposite of :attr:`followed`)."""
        return bool(self.reason)


def check_vehicle(vehicle: Vehicle) -> None:
    """Refuse vehicles the tracking model cannot drive, naming the vehicle and the field.

    Examples
    --------
    >>> v = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> check_vehicle(v) is None
    True
    """
    name = f"vehicle {vehicle.name!r}"
    if vehicle.steered_axle not in ("front", "rear"):
        raise ValueError(f"{name}: steered_axle must be 'front' or 'rear', "
                         f"got {vehicle.steered_axle!r}")
    if vehicle.steered_axle == "rear" and vehicle.trailer is not None:
        raise ValueError(f"{name}: a rear-steered vehicle towing a trailer is not supported "
                         "(its hitch would slide sideways with the steered axle)")
    checks: list[tuple[str, float, Callable[[float], bool]]] = [
        ("wheelbase_m", vehicle.wheelbase_m, lambda v: v > 0),
        ("track_m", vehicle.track_m, lambda v: v >= 0),
        ("width_m", vehicle.width_m, lambda v: v > 0),
        ("front_overhang_m", vehicle.front_overhang_m, lambda v: v >= 0),
        ("rear_overhang_m", vehicle.rear_overhang_m, lambda v: v >= 0),
        ("max_steer_rad", vehicle.max_steer_rad, lambda v: 0 < v < math.pi / 2),
        ("max_steer_rate_rad_s", vehicle.max_steer_rate_rad_s, lambda v: v > 0),
    ]
    t = vehicle.trailer
    if t is not None:
        checks += [
            ("trailer.hitch_offset_m", t.hitch_offset_m, math.isfinite),
            ("trailer.wheelbase_m", t.wheelbase_m, lambda v: v > 0),
            ("trailer.width_m", t.width_m, lambda v: v > 0),
            ("trailer.front_overhang_m", t.front_overhang_m, lambda v: v >= 0),
            ("trailer.rear_overhang_m", t.rear_overhang_m, lambda v: v >= 0),
            ("trailer.max_articulation_rad", t.max_articulation_rad,
             lambda v: 0 < v <= math.pi),
        ]
    for field_name, value, ok in checks:
        if not isinstance(value, int | float) or math.isnan(value) or not ok(value):
            raise ValueError(f"{name}: {field_name} = {value!r} is out of range")


def _as_path(path: Path | ArrayLike, spacing_m: float, index: int) -> Path:
    if isinstance(path, Path):
        return path
    return prepare_path(path, spacing_m=spacing_m, name=f"path {index}")


def simulate_batch(
    vehicles: Sequence[Vehicle],
    paths: Sequence[Path | ArrayLike],
    settings: TrackingSettings | None = None,
) -> list[TrackingRun]:
    """Drive ``vehicles[i]`` along ``paths[i]`` for every ``i``, all runs in one loop.

    Parameters
    ----------
    vehicles
        The vehicles; a single vehicle is paired with every path.
    paths
        Centre lines, as :class:`~clearance.analysis.polyline.Path` or ``(N, 2)``/``(N, 3)`` arrays
        in metres; a single path is paired with every vehicle.
    settings
        Time step, speed, tolerance and controller gain (defaults: 0.05 s, 2 m/s, 0.5 m).

    Returns
    -------
    list of TrackingRun
        One per (vehicle, path) pair, in order.

    Examples
    --------
    Straight ahead: no steering, no error, the front axle ends on the last point.

    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate_batch([car], [[(0.0, 0.0), (20.0, 0.0)]])[0]
    >>> run.followed, round(float(abs(run.trajectory.phi_rad).max()), 12)
    (True, 0.0)
    >>> round(run.max_error_m, 12)
    0.0
    >>> round(float(run.trajectory.xf_m[-1]), 9), round(float(run.trajectory.t_s[-1]), 9)
    (20.0, 10.0)
    """
    settings = settings or TrackingSettings()
    vehicles = list(vehicles)
    paths = list(paths)
    if not vehicles or not paths:
        return []
    if len(vehicles) == 1 and len(paths) > 1:
        vehicles = vehicles * len(paths)
    if len(paths) == 1 and len(vehicles) > 1:
        paths = paths * len(vehicles)
    if len(vehicles) != len(paths):
        raise ValueError(
            f"simulate_batch: {len(vehicles)} vehicles and {len(paths)} paths cannot be paired"
        )
    for v in vehicles:
        check_vehicle(v)
    prepared = [_as_path(p, settings.spacing_m, i) for i, p in enumerate(paths)]
    return _run(vehicles, prepared, settings)


def simulate_grid(
    vehicles: Sequence[Vehicle],
    paths: Sequence[Path | ArrayLike],
    settings: TrackingSettings | None = None,
) -> list[list[TrackingRun]]:
    """Drive every vehicle along every path in one batch; ``result[i][j]`` is vehicle i, path j.

    Examples
    --------
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> grid = simulate_grid([car, car], [[(0, 0), (5, 0)], [(0, 0), (0, 5)]])
    >>> [[r.reached_end for r in row] for row in grid]
    [[True, True], [True, True]]
    """
    settings = settings or TrackingSettings()
    vehicles = list(vehicles)
    prepared = [_as_path(p, settings.spacing_m, i) for i, p in enumerate(paths)]
    if not vehicles or not prepared:
        return [[] for _ in vehicles]
    flat = simulate_batch(
        [v for v in vehicles for _ in prepared], [p for _ in vehicles for p in prepared], settings
    )
    n = len(prepared)
    return [flat[i * n:(i + 1) * n] for i in range(len(vehicles))]


def simulate(
    vehicle: Vehicle, path: Path | ArrayLike, settings: TrackingSettings | None = None
) -> TrackingRun:
    """Drive one vehicle along one centre line (see :func:`simulate_batch`).

    Examples
    --------
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> simulate(car, [(0, 0), (0, 0)])
    Traceback (most recent call last):
    ...
    clearance.vehicles.errors.GeometryError: path 0: centre line needs at least two distinct points
    """
    return simulate_batch([vehicle], [path], settings)[0]


def _start_curvature(curvature: FloatArray, spacing: FloatArray, n_pts: NDArray[np.intp]
                     ) -> FloatArray:
    """Median curvature of each path over its first two metres (straight start: 0)."""
    k = np.maximum(np.round(2.0 / spacing).astype(np.intp), 1)
    return np.array([float(np.median(c[:min(int(k[i]) + 1, int(n_pts[i]))]))
                     for i, c in enumerate(curvature)])


def start_pose(k0: ArrayLike, heading0: ArrayLike, wheelbase_m: ArrayLike,
               lock_rad: ArrayLike, rear_steer: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Steering and body heading of a vehicle whose front axle starts on a circle.

    The front-axle centre starts on the path heading along it, on a curve of curvature
    ``k0``. A front-steered vehicle's front axle runs on radius ``R = 1 / k0`` when its rear
    axle runs on ``rho = sqrt(R^2 - l^2)``, so ``sin(phi) = l / R`` (``tan(phi) = l / rho``)
    and the body points ``phi`` to the inside of the front axle's heading. A rear-steered
    vehicle's front axle is its reference point: ``tan(phi) = l k0`` and the body points
    along the path. A curve tighter than the lock starts at the lock.

    Returns
    -------
    phi_rad, theta_rad

    Examples
    --------
    A car of wheelbase 3 m starting on a 5 m circle: its rear axle is on the 4 m circle.

    >>> phi, th = start_pose(0.2, 0.0, 3.0, 0.7, False)
    >>> round(float(3.0 / np.tan(phi)), 9), round(float(th), 6)
    (4.0, -0.643501)

    Straight (the degenerate case), or tighter than the lock:

    >>> [float(v) for v in start_pose(0.0, 0.5, 3.0, 0.7, False)]
    [0.0, 0.5]
    >>> float(start_pose(1.0, 0.0, 3.0, 0.7, False)[0])
    0.7
    """
    k = np.asarray(k0, dtype=float)
    l = np.asarray(wheelbase_m, dtype=float)  # noqa: E741
    lock = np.asarray(lock_rad, dtype=float)
    rear = np.asarray(rear_steer, dtype=bool)
    front_phi = np.arcsin(np.clip(l * k, -1.0, 1.0))
    phi = np.clip(np.where(rear, np.arctan(l * k), front_phi), -lock, lock)
    th = np.asarray(heading0, dtype=float) - np.where(rear, 0.0, phi)
    return phi, th


def _pad(
    paths: list[Path],
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
    n_pts = np.array([len(p.xy) for p in paths], dtype=np.intp)
    m = int(n_pts.max())
    xy = np.empty((len(paths), m, 2))
    station = np.empty((len(paths), m))
    heading = np.empty((len(paths), m))
    curvature = np.zeros((len(paths), m))
    for i, p in enumerate(paths):
        k = n_pts[i]
        xy[i, :k], xy[i, k:] = p.xy, p.xy[-1]
        station[i, :k], station[i, k:] = p.station_m, p.station_m[-1] + np.arange(1, m - k + 1)
        heading[i, :k], heading[i, k:] = p.heading_rad, p.heading_rad[-1]
        curvature[i, :k] = p.curvature_1_m
    return xy, station, heading, curvature, n_pts


def _run(vehicles: list[Vehicle], paths: list[Path], st: TrackingSettings) -> list[TrackingRun]:
    n = len(vehicles)
    wb = np.array([v.wheelbase_m for v in vehicles])
    lock = np.array([v.max_steer_rad for v in vehicles])
    rate = np.array([v.max_steer_rate_rad_s for v in vehicles])
    has_tr = np.array([v.trailer is not None for v in vehicles])
    e = np.array([v.trailer.hitch_offset_m if v.trailer else 0.0 for v in vehicles])
    lt = np.array([v.trailer.wheelbase_m if v.trailer else 1.0 for v in vehicles])
    psi_max = np.array([v.trailer.max_articulation_rad if v.trailer else np.inf
                        for v in vehicles])
    rear_steer = np.array([v.steered_axle == "rear" for v in vehicles])
    # the reference point is the unsteered axle's centre; the front axle is `ahead` of it
    ahead = np.where(rear_steer, 0.0, wb)
    xy, station, heading, curvature, n_pts = _pad(paths)
    length = np.array([p.length_m for p in paths])
    spacing = np.array([p.spacing_m for p in paths])
    profile, dt = st.profile, st.dt_s
    window = math.ceil(profile.max_speed_m_s * dt / float(spacing.min())) + 2
    if st.max_steps is not None:
        max_steps = st.max_steps
    else:
        max_steps = 2 * math.ceil(float(length.max()) / (profile.min_speed_m_s * dt)) + 50
    abort_m = st.abort_factor * st.tolerance_m

    # Start in the steady state of the path's first two metres: a run that begins inside a curve
    # (a helix, a roundabout ring) starts on its steady circle, wheels turned, within the lock.
    phi, th = start_pose(k0=_start_curvature(curvature, spacing, n_pts), heading0=heading[:, 0],
                         wheelbase_m=wb, lock_rad=lock, rear_steer=rear_steer)
    x = xy[:, 0, 0] - ahead * np.cos(th)
    y = xy[:, 0, 1] - ahead * np.sin(th)
    with np.errstate(divide="ignore", invalid="ignore"):
        rho0 = np.where(phi != 0.0, wb / np.tan(phi), np.inf)
    psi = np.where(has_tr, np.nan_to_num(steady_articulation_rad(rho0, e, lt)), 0.0)
    psi = np.clip(psi, -psi_max, psi_max)
    rec, count, reached, aborted, jack_t, at_lock, rate_limited = run_loop(
        x, y, th, phi, psi, wb, lock, rate, has_tr, e, lt, psi_max, rear_steer, ahead,
        xy, station, heading, curvature, n_pts.astype(np.int64), length,
        np.asarray(profile.at, dtype=float), np.asarray(profile.speed_m_s, dtype=float),
        profile.by == "station", float(dt), float(st.gain_1_s), SOFT_SPEED_M_S,
        MAX_COMMAND_RAD, float(abort_m), int(window), int(max_steps),
        int(st.trailer_substeps))

    runs = []
    for i in range(n):
        runs.append(_collect(vehicles[i], paths[i], st, rec[:, :count[i], i], bool(reached[i]),
                             bool(aborted[i]), float(jack_t[i]), int(at_lock[i]),
                             int(rate_limited[i]), abort_m))
    return runs


def _collect(
    vehicle: Vehicle,
    path: Path,
    st: TrackingSettings,
    rec: FloatArray,
    reached: bool,
    aborted: bool,
    jack_t: float,
    at_lock: int,
    rate_limited: int,
    abort_m: float,
) -> TrackingRun:
    t, s, x, y, th, phi, err, v, psi = (np.ascontiguousarray(r) for r in rec)
    wb = vehicle.wheelbase_m
    xf, yf = x, y
    if vehicle.steered_axle == "rear":  # the state is the front axle's: rear axle behind it
        x, y = xf - wb * np.cos(th), yf - wb * np.sin(th)
    else:
        xf, yf = x + wb * np.cos(th), y + wb * np.sin(th)
    trailer = vehicle.trailer
    extra = {}
    jackknifed = not math.isnan(jack_t)
    if jackknifed:
        reached = False  # the run was stopped at the jackknife, not at the path's end
    if trailer is not None:
        theta_t = th - psi
        xt, yt = trailer_axle_point(x, y, th, theta_t, trailer.hitch_offset_m,
                                    trailer.wheelbase_m)
        extra = dict(xt_m=xt, yt_m=yt, theta_t_rad=theta_t, psi_rad=psi)
    traj = Trajectory(t, s, x, y, th, phi, xf, yf, err, v, **extra)
    max_err = float(np.max(np.abs(err))) if len(err) else 0.0
    reasons = []
    if max_err > st.tolerance_m:
        worst = int(np.argmax(np.abs(err)))
        reasons.append(
            f"the front axle left the centre line by {max_err:.2f} m (tolerance "
            f"{st.tolerance_m:.2f} m) at station {s[worst]:.1f} m"
            + (f"; run stopped beyond {abort_m:.2f} m" if aborted else "")
        )
    if jackknifed and trailer is not None:  # psi_max is infinite without a trailer
        reasons.append(
            f"the articulation exceeded the trailer's maximum "
            f"{math.degrees(trailer.max_articulation_rad):.0f} deg at t = {jack_t:.2f} s"
        )
    if not reached and not aborted and not jackknifed:
        reasons.append(f"the front axle did not reach the end of the path in {len(t)} samples")
    if reasons and (at_lock or rate_limited):
        reasons.append(f"steering at lock in {at_lock} steps, rate-limited in "
                       f"{rate_limited} steps")
    return TrackingRun(vehicle, path, traj, st, reached, max_err,
                       None if not jackknifed else jack_t, at_lock, rate_limited,
                       "; ".join(reasons))
