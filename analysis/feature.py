"""The feature window: which samples of a run judge its curve, and why it cannot turn there.

A curve is judged by its feature (the junction, ring, ramp or bend; docs/design.md §6):
only the samples while some part of the vehicle, a trailer included, is in the feature
count (:func:`feature_mask`), and a tracking error, a jackknife or a stop counts only there
(:func:`feature_reason`). What happens on the lead-in and run-out belongs to the
neighbouring curves.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from clearance.analysis.tracking import TrackingRun

__all__ = ["feature_mask", "feature_reason", "slice_run"]


def feature_mask(run: TrackingRun, feature_m: tuple[float, float]) -> np.ndarray:
    """The samples of a run while any part of the vehicle is in the feature.

    ``feature_m`` is where the feature begins and ends along the centre line (m). At
    sample ``k`` the front axle is at station ``s_k``; the vehicle reaches from
    ``s_k + a_f`` (front bumper) back to ``s_k + a_f - L`` (``L`` its overall length, a
    trailer included), measured along the line: the sample is in when that span meets the
    feature. Offtracking only shortens the span along the line, so the window errs on the
    long side.

    Examples
    --------
    A 4.5 m car (front overhang 0.9 m) driving stations 0..30 through a feature at 10..12:

    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 0.0), (30.0, 0.0)])
    >>> s = run.trajectory.s_m[feature_mask(run, (10.0, 12.0))]
    >>> bool(s.min() >= 10.0 - 0.9 - 0.25), bool(s.max() <= 12.0 + 4.5 - 0.9 + 0.25)
    (True, True)

    A feature beyond the end of the run has no samples:

    >>> bool(feature_mask(run, (50.0, 60.0)).any())
    False
    """
    v = run.vehicle
    s = run.trajectory.s_m
    front = s + v.front_overhang_m
    rear = front - v.overall_length_m
    return (front >= feature_m[0]) & (rear <= feature_m[1])


def slice_run(run: TrackingRun, keep: np.ndarray) -> TrackingRun:
    """The run restricted to the samples ``keep`` (indices, in order)."""
    tr = run.trajectory
    cut: dict[str, Any] = {  # each field's own type: an array or None
        f.name: (None if getattr(tr, f.name) is None else getattr(tr, f.name)[keep])
        for f in dataclasses.fields(tr)}
    return dataclasses.replace(run, trajectory=dataclasses.replace(tr, **cut))


def feature_reason(run: TrackingRun, mask: np.ndarray) -> str:
    """Why the run cannot turn *in the feature* (the samples ``mask``), or ``""``.

    The tracking's own :attr:`~clearance.analysis.tracking.TrackingRun.reason` judges the whole run,
    lead-in and run-out included; here only what happens while the vehicle is in the
    feature counts: a lateral error beyond the tolerance there, a jackknife there, or a
    run that stopped before the vehicle had left the feature (it never got through).

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 0.0), (30.0, 0.0)])
    >>> feature_reason(run, feature_mask(run, (10.0, 12.0)))
    ''
    """
    tr = run.trajectory
    st = run.settings
    if not len(tr.s_m):
        return run.reason
    reasons = []
    inside = np.flatnonzero(mask)
    if len(inside):
        err = np.abs(tr.error_m[inside])
        worst = int(np.argmax(err))
        if err[worst] > st.tolerance_m:
            reasons.append(
                f"the front axle left the centre line by {err[worst]:.2f} m (tolerance "
                f"{st.tolerance_m:.2f} m) at station {tr.s_m[inside[worst]]:.1f} m, in the "
                "feature")
        if run.jackknife_time_s is not None and run.jackknife_time_s <= tr.t_s[inside[-1]]:
            reasons.append(f"the trailer jackknifed in the feature at t = "
                           f"{run.jackknife_time_s:.2f} s")
    # stopped while the vehicle was still in the feature, or before it got there
    stopped_short = not run.reached_end and (not len(inside) or inside[-1] == len(mask) - 1)
    if stopped_short and not reasons:
        reasons.append("the run stopped before the vehicle had left the feature: "
                       + (run.reason or "it did not reach the end of the path"))
    return "; ".join(reasons)
