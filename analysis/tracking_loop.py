"""The compiled time loop of :func:`clearance.analysis.tracking.simulate_batch` (numba).

One pass over the time steps advances every run of a batch: project the steering point
onto its path (:func:`clearance.analysis.kernels.project_near`), read the speed profile, steer by
the Stanley law ahead of the wheel (:func:`predictive_stanley`; for a rear-steered vehicle, by
path curvature and heading error), limit the steering by its rate and lock, record the
sample, then move the unit over the step while the wheel turns from its old angle to the
new one (one arc, second order in the step) and advance the trailer's articulation along
that arc. The step's formulas are those of :func:`clearance.analysis.kinematics.ramp_step`,
:func:`clearance.analysis.kinematics.limit_steering` and
:func:`clearance.analysis.trailer.advance_articulation`,
written here for one run at a time so that the loop runs compiled;
``tests/analysis/test_tracking_loop.py`` checks that they agree. What the loop means
(settings, verdicts, the recorded quantities) is documented in
:mod:`clearance.analysis.tracking`."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from clearance.analysis.kernels import project_near

__all__ = ["APPROACH_SHARE", "BISECT_TO_RAD", "RECORD", "approach_angle", "articulation_one",
           "limit_one", "predictive_stanley", "ramp_step_one", "run_loop", "stanley_residual"]

#: Row of each recorded quantity in the loop's ``(9, steps, runs)`` record.
RECORD = ("t_s", "s_m", "x_m", "y_m", "theta_rad", "phi_rad", "error_m", "speed_m_s",
          "psi_rad")


BISECT_TO_RAD = 1e-3
"""The steering command's bisection stops at a bracket this narrow (rad); regula falsi
finds the root within it (:func:`predictive_stanley`)."""


@njit(cache=True)
def ramp_step_one(x: float, y: float, theta: float, phi0: float, phi1: float,
                  wheelbase: float, distance: float, front_steered: bool
                  ) -> tuple[float, float, float, float, float]:  # pragma: no cover
    """:func:`clearance.analysis.kinematics.ramp_step` for one unit, with the arc it took.

    Returns the new ``x, y, theta`` and the reference axle's travel ``ds`` and turn
    ``dtheta`` (:func:`clearance.analysis.kinematics.ramp_arc`).

    Examples
    --------
    >>> ramp_step_one(0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 2.0, True)
    (2.0, 0.0, 0.0, 2.0, 0.0)
    """
    pm = 0.5 * (phi0 + phi1)
    if front_steered:
        ds = distance * (math.cos(phi0) + 4.0 * math.cos(pm) + math.cos(phi1)) / 6.0
        g = (math.sin(phi0) + 4.0 * math.sin(pm) + math.sin(phi1)) / 6.0
    else:
        ds = distance
        g = (math.tan(phi0) + 4.0 * math.tan(pm) + math.tan(phi1)) / 6.0
    dtheta = distance * g / wheelbase
    half = 0.5 * dtheta
    chord = ds * (math.sin(half) / half if half != 0.0 else 1.0)
    mid = theta + half
    return (x + chord * math.cos(mid), y + chord * math.sin(mid), theta + dtheta, ds,
            dtheta)


@njit(cache=True)
def limit_one(prev: float, command: float, lock: float, max_change: float
              ) -> float:  # pragma: no cover - compiled
    """:func:`clearance.analysis.kinematics.limit_steering` for one unit (``max_change = rate dt``).

    Examples
    --------
    >>> round(limit_one(0.1, 0.5, 0.6, 0.02), 12)
    0.12
    """
    change = min(max(command - prev, -max_change), max_change)
    return min(max(prev + change, -lock), lock)


@njit(cache=True)
def _dpsi_ds(psi: float, k: float, e: float, lt: float) -> float:  # pragma: no cover
    return k - (math.sin(psi) - e * k * math.cos(psi)) / lt


@njit(cache=True)
def articulation_one(psi: float, k: float, ds: float, e: float, lt: float,
                     substeps: int) -> float:  # pragma: no cover - compiled
    """:func:`clearance.analysis.trailer.advance_articulation` for one unit (RK4, ``substeps``).

    Examples
    --------
    >>> articulation_one(0.0, 0.0, 0.1, -0.5, 10.0, 1)
    0.0
    """
    h = ds / substeps
    for _ in range(substeps):
        k1 = _dpsi_ds(psi, k, e, lt)
        k2 = _dpsi_ds(psi + 0.5 * h * k1, k, e, lt)
        k3 = _dpsi_ds(psi + 0.5 * h * k2, k, e, lt)
        k4 = _dpsi_ds(psi + h * k3, k, e, lt)
        psi = psi + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return psi


APPROACH_SHARE = 0.5
"""Share of the steering rate the approach to the centre line may ask of the wheel."""


@njit(cache=True)
def _wrap(a: float) -> float:  # pragma: no cover - compiled
    return (a + math.pi) % (2.0 * math.pi) - math.pi


@njit(cache=True)
def _heading_at(s: float, station: np.ndarray, heading: np.ndarray,
                n_pts: int) -> float:  # pragma: no cover - compiled
    # the stations are uniform but for the last step: index by the first spacing
    if s <= 0.0:
        return float(heading[0])
    if s >= station[n_pts - 1]:
        return float(heading[n_pts - 1])
    j = min(int(s / (station[1] - station[0])), n_pts - 2)
    while j > 0 and station[j] > s:
        j -= 1
    while j < n_pts - 2 and station[j + 1] < s:
        j += 1
    f = (s - station[j]) / (station[j + 1] - station[j])
    return float(heading[j] + f * (heading[j + 1] - heading[j]))


@njit(cache=True)
def _ramp_turn(v: float, wheelbase: float, rate: float, a: float,
               b: float) -> float:  # pragma: no cover - compiled
    # the body's turn while the wheel goes from a to b at the rate: v sin(phi) / l over it
    t = v / (wheelbase * rate) * (math.cos(a) - math.cos(b))
    return t if b >= a else -t


@njit(cache=True)
def stanley_residual(c: float, s_f: float, err: float, theta: float, phi: float, v: float,
                     wheelbase: float, lock: float, rate: float, gain: float,
                     soft_speed: float, station: np.ndarray, heading: np.ndarray,
                     curvature: np.ndarray, n_pts: int,
                     th_path: float) -> float:  # pragma: no cover - compiled
    """The Stanley law at the state where the wheel reaches ``c``, less ``c``.

    The wheel turns from ``phi`` to ``c`` at the steering rate in ``tau = |c - phi| / rate``
    while the front axle moves ``v tau`` along the path: the body turns meanwhile by
    ``(v / (l rate)) |cos(phi) - cos(c)|`` toward the steering (``v sin(phi(t)) / l``
    integrated over the ramp), and the front axle's offset changes by ``v tau sin(psi)``
    with ``psi`` the mean of its heading across the path at either end of the turn. Where
    ``c`` lies beyond the path's steady steering ``phi_ss`` there (toward straight from it:
    a wheel at lock where the path straightens), the wheel must then come back to
    ``phi_ss``, and the body goes on turning while it does: the heading term counts that
    turn too, against the path's heading where the wheel is back. Zero at the command the
    law would give once the wheel got there; the corrections are of second order in the
    steering's change, so on a smooth path, and in the steady state, the law is Stanley's.
    """
    tau = abs(c - phi) / rate
    turn = _ramp_turn(v, wheelbase, rate, phi, c)
    s1 = s_f + v * tau
    th1 = _heading_at(s1, station, heading, n_pts)
    phi_ss = math.asin(min(max(wheelbase * _heading_at(s1, station, curvature, n_pts), -1.0),
                           1.0))
    phi_ss = min(max(phi_ss, -lock), lock)
    # the wheel comes back from c toward straight, as far as the steady steering there: never
    # on beyond c (entering a curve it goes on turning with the path, nothing to come back)
    back = min(max(phi_ss, 0.0), c) if c >= 0.0 else max(min(phi_ss, 0.0), c)
    turn_back = _ramp_turn(v, wheelbase, rate, c, back)
    th_back = _heading_at(s1 + v * abs(back - c) / rate, station, heading, n_pts)
    psi0 = _wrap(theta + phi - th_path)
    psi1 = _wrap(theta + turn + c - th1)
    e_ahead = err + v * tau * math.sin(0.5 * (psi0 + psi1))
    return (_wrap(th_back - theta - turn - turn_back)
            - approach_angle(e_ahead, v, gain, soft_speed, rate) - c)


@njit(cache=True)
def approach_angle(e: float, v: float, gain: float, soft_speed: float,
                   rate: float) -> float:  # pragma: no cover - compiled
    """Heading of the front axle toward the centre line at an offset ``e`` (left positive).

    Stanley's ``atan(k e / (v + v_soft))``, but no steeper than the wheel can take back:
    approaching at ``psi(e)`` the wheel must turn at ``psi'(e) v sin(psi)``, which stays
    within ``APPROACH_SHARE`` of the steering rate while ``1 - cos(psi) <= share rate |e| / v``.

    Examples
    --------
    On the line (the degenerate case) nothing to approach; close to it Stanley's angle; a
    metre off, a wheel of 0.28 rad/s at 2 m/s approaches at 21 degrees, not Stanley's 50:

    >>> approach_angle(0.0, 2.0, 2.5, 0.1, 0.28)
    0.0
    >>> round(approach_angle(-0.01, 2.0, 2.5, 0.1, 0.28), 6), round(-math.atan(0.025 / 2.1), 6)
    (-0.011904, -0.011904)
    >>> round(math.degrees(approach_angle(1.0, 2.0, 2.5, 0.1, 0.28)), 1)
    21.0
    """
    a = abs(e)
    psi = math.atan(gain * a / (v + soft_speed))
    if math.isfinite(rate):
        q = 1.0 - APPROACH_SHARE * rate * a / (v + soft_speed)
        if q > -1.0:
            psi = min(psi, math.acos(q))
    return psi if e >= 0.0 else -psi


@njit(cache=True)
def predictive_stanley(s_f: float, err: float, theta: float, phi: float, v: float,
                       wheelbase: float, lock: float, rate: float, gain: float,
                       soft_speed: float, station: np.ndarray, heading: np.ndarray,
                       curvature: np.ndarray, n_pts: int, th_path: float,
                       max_change: float = math.inf) -> float:  # pragma: no cover - compiled
    """Steering command of a front-steered vehicle: the Stanley law, ahead of the wheel.

    The plain law ``wrap(theta_path - theta) - atan(k e / (v + v_soft))`` asks for the
    steering the state needs now; a wheel turned at a finite rate gets there only later,
    while the body goes on turning and the front axle goes on drifting, so that the plain
    law swings too late and overshoots. This one asks for the steering ``c`` that the law
    asks for at the moment the wheel reaches it (:func:`stanley_residual` is zero), found
    by bisection within the lock down to a bracket of :data:`BISECT_TO_RAD`, then by regula
    falsi (Illinois) within it to 1e-13 rad. Where the wheel unwinds from lock the residual
    has several roots; the bisection picks one, and the bracket it leaves holds only that
    one, so the command is the one a bisection all the way gives, to 1e-11 rad, in about 15
    residuals rather than 43. Where the wheel is already there (a steady curve, or an
    unlimited rate) the two laws are the same.

    ``max_change`` is how far the wheel can turn in the step (``rate dt``): once the
    bracket lies wholly further than that from ``phi``, the step turns the wheel by
    exactly ``max_change`` whichever point of the bracket is the root, and the search stops
    there (any point of the bracket then steps, limits and counts alike in
    :func:`run_loop`; on DRT's swung candidates 18 % of the steps are rate-limited).

    Examples
    --------
    On a straight line, on it and along it, the wheel stays straight; 0.1 m right of it,
    straight, it asks for less than the plain law's ``atan(2.5 * 0.1 / 2.1) = 0.118`` rad:
    the front axle drifts toward the line while the wheel turns.

    >>> st = np.arange(0.0, 20.05, 0.1); hd = np.zeros_like(st)
    >>> predictive_stanley(5.0, 0.0, 0.0, 0.0, 2.0, 3.0, 0.55, 0.28, 2.5, 0.1, st, hd, hd,
    ...                    len(st), 0.0)
    0.0
    >>> c = predictive_stanley(5.0, -0.1, 0.0, 0.0, 2.0, 3.0, 0.55, 0.28, 2.5, 0.1, st, hd,
    ...                        hd, len(st), 0.0)
    >>> round(c, 3)
    0.077
    """
    if not math.isfinite(rate):
        return _wrap(th_path - theta) - math.atan(gain * err / (v + soft_speed))
    if stanley_residual(phi, s_f, err, theta, phi, v, wheelbase, lock, rate, gain,
                        soft_speed, station, heading, curvature, n_pts, th_path) == 0.0:
        return phi  # where the wheel is (a straight, a steady circle)
    lo, hi = -lock, lock
    f_lo = stanley_residual(lo, s_f, err, theta, phi, v, wheelbase, lock, rate, gain,
                            soft_speed, station, heading, curvature, n_pts, th_path)
    if f_lo <= 0.0:
        return lo + f_lo  # beyond the lock: what the law asks for there, for the limits
    f_hi = stanley_residual(hi, s_f, err, theta, phi, v, wheelbase, lock, rate, gain,
                            soft_speed, station, heading, curvature, n_pts, th_path)
    if f_hi >= 0.0:
        return hi + f_hi
    while hi - lo > BISECT_TO_RAD:
        mid = 0.5 * (lo + hi)
        f_mid = stanley_residual(mid, s_f, err, theta, phi, v, wheelbase, lock, rate, gain,
                                 soft_speed, station, heading, curvature, n_pts, th_path)
        if f_mid > 0.0:
            lo, f_lo = mid, f_mid
        else:
            hi, f_hi = mid, f_mid
        if lo - phi > max_change or phi - hi > max_change:
            return 0.5 * (lo + hi)
    # the Illinois variant of regula falsi in the last small bracket
    side = 0
    for _ in range(60):
        if hi - lo < 1e-13:
            break
        mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        if not lo < mid < hi:
            mid = 0.5 * (lo + hi)
        f_mid = stanley_residual(mid, s_f, err, theta, phi, v, wheelbase, lock, rate, gain,
                                 soft_speed, station, heading, curvature, n_pts, th_path)
        if f_mid > 0.0:
            lo, f_lo = mid, f_mid
            if side > 0:
                f_hi *= 0.5
            side = 1
        elif f_mid < 0.0:
            hi, f_hi = mid, f_mid
            if side < 0:
                f_lo *= 0.5
            side = -1
        else:
            return mid
        if abs(f_mid) < 1e-15:
            return mid
    return 0.5 * (lo + hi)


@njit(cache=True)
def run_loop(
    x: np.ndarray, y: np.ndarray, th: np.ndarray, phi: np.ndarray, psi: np.ndarray,
    wb: np.ndarray, lock: np.ndarray, rate: np.ndarray, has_tr: np.ndarray, e: np.ndarray,
    lt: np.ndarray, psi_max: np.ndarray, rear_steer: np.ndarray, ahead: np.ndarray,
    xy: np.ndarray, station: np.ndarray, heading: np.ndarray, curvature: np.ndarray,
    n_pts: np.ndarray, length: np.ndarray,
    prof_at: np.ndarray, prof_speed: np.ndarray, by_station: bool,
    dt: float, gain: float, soft_speed: float, max_command: float, abort_m: float,
    window: int, max_steps: int, substeps: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
           np.ndarray]:  # pragma: no cover - compiled
    """Advance every run until it reaches its path's end, aborts, jackknifes or runs out.

    The state arrays (``x, y, th, phi, psi``) are the runs' initial states, advanced in
    place. Returns the ``(9, max_steps + 1, n)`` record (rows :data:`RECORD`; a run's
    samples are its first ``count`` columns) and per run: ``count``, ``reached``,
    ``aborted``, the jackknife time (NaN: none), steps at lock, steps rate-limited.

    A numba kernel that must be one piece: the steps of a run (look-ahead point, control
    law, steering limits, arc step, articulation) share a dozen scalars per run that the
    compiler keeps in registers; the steps that stand alone are already the njit helpers
    above (:func:`ramp_step_one`, :func:`limit_one`, :func:`articulation_one`,
    :func:`predictive_stanley`).
    """
    n = x.shape[0]
    rec = np.full((9, max_steps + 1, n), np.nan)
    count = np.zeros(n, dtype=np.int64)
    reached = np.zeros(n, dtype=np.bool_)
    aborted = np.zeros(n, dtype=np.bool_)
    jack_t = np.full(n, np.nan)
    at_lock = np.zeros(n, dtype=np.int64)
    rate_limited = np.zeros(n, dtype=np.int64)
    seg = np.zeros(n, dtype=np.int64)
    xf = np.empty(n)
    yf = np.empty(n)
    for i in range(n):
        t = 0.0
        finishing = False
        for k in range(max_steps + 1):
            xf[0] = x[i] + ahead[i] * math.cos(th[i])
            yf[0] = y[i] + ahead[i] * math.sin(th[i])
            s_one, along, err_one = project_near(xf[:1], yf[:1], xy[i:i + 1],
                                                 n_pts[i:i + 1], seg[i:i + 1], window)
            sg = s_one[0]
            seg[i] = sg
            err = err_one[0]
            s_f = station[i, sg] + along[0]
            v_f = np.interp(s_f if by_station else t, prof_at, prof_speed)
            seg_len = station[i, sg + 1] - station[i, sg]
            frac = min(max(along[0] / seg_len, 0.0), 1.0)
            th_path = heading[i, sg] + frac * (heading[i, sg + 1] - heading[i, sg])
            heading_err = (th_path - th[i] + math.pi) % (2.0 * math.pi) - math.pi
            if rear_steer[i]:
                k_path = curvature[i, sg] + frac * (curvature[i, sg + 1] - curvature[i, sg])
                settle = max((v_f + soft_speed) / gain, wb[i])
                k_cmd = (k_path * math.cos(heading_err) / max(1.0 - k_path * err, 0.1)
                         + 2.0 * heading_err / settle - err / settle ** 2)
                cmd = math.atan(wb[i] * k_cmd)
            else:
                cmd = predictive_stanley(s_f, err, th[i], phi[i], v_f, wb[i], lock[i], rate[i],
                                         gain, soft_speed, station[i], heading[i],
                                         curvature[i], n_pts[i], th_path, rate[i] * dt)
            cmd = min(max(cmd, -max_command), max_command)
            new_phi = limit_one(phi[i], cmd, lock[i], rate[i] * dt)
            rec[0, k, i] = t
            rec[1, k, i] = s_f
            rec[2, k, i] = x[i]
            rec[3, k, i] = y[i]
            rec[4, k, i] = th[i]
            rec[5, k, i] = phi[i]
            rec[6, k, i] = err
            rec[7, k, i] = v_f
            rec[8, k, i] = psi[i]
            count[i] += 1
            at_end = finishing or s_f >= length[i] - 1e-9
            if at_end:
                reached[i] = True
                break
            if abs(err) > abort_m:
                aborted[i] = True
                break
            if k == max_steps:
                break
            free = limit_one(phi[i], cmd, np.inf, rate[i] * dt)
            if abs(free) > lock[i]:
                at_lock[i] += 1
            if abs(cmd - phi[i]) > rate[i] * dt:
                rate_limited[i] += 1
            phi0 = phi[i]
            phi[i] = new_phi
            remaining = length[i] - s_f
            step_dt = dt
            if remaining < v_f * dt:
                step_dt = max(remaining, 0.0) / v_f
                finishing = True
            # the wheel turns from phi0 to new_phi over the step (it acts at the middle)
            x[i], y[i], th[i], ds_r, dtheta = ramp_step_one(
                x[i], y[i], th[i], phi0, new_phi, wb[i], v_f * step_dt, not rear_steer[i])
            if has_tr[i]:
                k_step = dtheta / ds_r if ds_r > 0.0 else 0.0
                psi[i] = articulation_one(psi[i], k_step, ds_r, e[i], lt[i], substeps)
                if math.isnan(jack_t[i]) and abs(psi[i]) > psi_max[i]:
                    jack_t[i] = t + step_dt
            t = t + step_dt
            # a jackknife ends the run after recording the offending state
            if not math.isnan(jack_t[i]):
                finishing = True
    return rec, count, reached, aborted, jack_t, at_lock, rate_limited
