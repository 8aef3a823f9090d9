"""A run that passes over itself (a helix), drawn one storey per view.

A parking helix turns through several full circles, one storey above the other; in plan
every turn lies on the one before, and a drawing of the whole run shows every storey's
bodies and wheel paths on top of each other. A sheet of such a run shows one storey per
view instead (:func:`storey_stretches`): the run cut where its heading has turned another
full circle since the curve's feature began, each stretch drawn alone
(:func:`storey_shown`) with its own envelope and wheel paths, on the same plan and at the
same scale. Only a curve that climbs at least a storey
(:data:`clearance.networks.stacking.STOREY_M`) while turning more than a full circle is
cut; any other run is one view.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
import shapely

from clearance.analysis.envelope import swept_path
from clearance.networks.curves import Curve
from clearance.networks.stacking import STOREY_M
from clearance.reports.documents.drawing import Shown

__all__ = ["LAST_TURN_RAD", "storey_heights", "storey_shown", "storey_stretches"]

#: A last stretch that turns less than this past the last full circle (a run-out) is
#: drawn with the storey before it.
LAST_TURN_RAD = math.radians(30.0)


def storey_stretches(curve: Curve, theta_rad: np.ndarray, s_m: np.ndarray
                     ) -> list[tuple[int, int]]:
    """The sample ranges ``(start, stop)`` (``stop`` exclusive, consecutive stretches
    sharing their boundary sample) of a run with headings ``theta_rad`` at stations
    ``s_m``: cut each time the heading has turned another full circle since the curve's
    feature began (``curve.core_start_m``). One range, the whole run, on a curve that does
    not climb :data:`~clearance.networks.stacking.STOREY_M` or turns less than a circle.

    Examples
    --------
    Three circles climbing 9 m, sampled every 10 degrees from the feature's start:

    >>> from types import SimpleNamespace as S
    >>> th = np.radians(np.arange(0, 1081, 10.0))
    >>> line = np.array([[0, 0, 0.0], [1, 0, 9.0]])
    >>> helix = S(centerline=line, core_start_m=0.0, turn_angle_deg=1080.0)
    >>> storey_stretches(helix, th, np.linspace(0, 1, th.size))
    [(0, 37), (36, 73), (72, 109)]

    A flat turn, or none at all (the degenerate case), is one view:

    >>> flat = S(centerline=line * [1, 1, 0], core_start_m=0.0, turn_angle_deg=1080.0)
    >>> storey_stretches(flat, th, np.linspace(0, 1, th.size))
    [(0, 109)]
    >>> storey_stretches(helix, np.zeros(1), np.zeros(1))
    [(0, 1)]
    """
    n = len(theta_rad)
    z = np.asarray(curve.centerline, dtype=float)[:, 2]
    if n < 2 or float(z.max() - z.min()) < STOREY_M or abs(curve.turn_angle_deg) <= 360.0:
        return [(0, n)]
    th = np.unwrap(np.asarray(theta_rad, dtype=float))
    i0 = min(int(np.searchsorted(s_m, curve.core_start_m)), n - 1)
    turned = np.abs(th - th[i0])
    turned[:i0] = 0.0
    total = float(turned.max())
    cuts = []
    k = 1
    while total - 2 * math.pi * k > LAST_TURN_RAD:
        cuts.append(int(np.argmax(turned >= 2 * math.pi * k)))
        k += 1
    bounds = [0, *cuts, n - 1]
    return [(a, b + 1) for a, b in zip(bounds[:-1], bounds[1:], strict=True)]


def storey_heights(curve: Curve, s_m: np.ndarray, stretch: tuple[int, int]
                   ) -> tuple[float, float]:
    """The lowest and highest height (m) of the curve's centre line at the stations of
    ``stretch`` (a range of :func:`storey_stretches`).

    >>> from types import SimpleNamespace as S
    >>> c = S(centerline=np.array([[0, 0, 0.0], [10, 0, 5.0]]))
    >>> storey_heights(c, np.array([0.0, 4.0, 8.0]), (1, 3))
    (2.0, 4.0)
    """
    line = np.asarray(curve.centerline, dtype=float)
    st = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(line[:, :2], axis=0).T))))
    z = np.interp(np.asarray(s_m)[stretch[0]:stretch[1]], st, line[:, 2])
    return float(z.min()), float(z.max())


def storey_shown(s: Shown, stretch: tuple[int, int], offset_m: float) -> Shown:
    """``s`` (driven again) with only the samples of ``stretch``: its trajectory, its
    envelope and wheel paths (:func:`clearance.analysis.envelope.swept_path` of the
    stretch), its measured envelope (grown by ``offset_m``, within the run's); the stop
    and its reason only on the stretch where the run stopped. The verdict and margins
    stay the whole run's. ``s`` itself when it was not driven again.

    Examples
    --------
    >>> from types import SimpleNamespace as S
    >>> s = Shown(S(vehicle="P"), "k")
    >>> storey_shown(s, (0, 5), 0.0) is s
    True
    """
    d = s.driven
    if d is None or d.result is None:
        return s
    res = d.result
    run, tr = res.run, res.run.trajectory
    a, b = stretch
    cut: dict[str, Any] = {f: (None if getattr(tr, f) is None else getattr(tr, f)[a:b])
                           for f in tr.__dataclass_fields__}
    last = b >= len(tr)
    part = replace(run, trajectory=replace(tr, **cut),
                   reason=run.reason if last else "", reached_end=run.reached_end or not last,
                   jackknife_time_s=run.jackknife_time_s if last else None)
    swept = swept_path(part)
    grown = shapely.buffer(swept.envelope, offset_m) if offset_m > 0 else swept.envelope
    measured = shapely.intersection(grown, res.measured)
    result = replace(res, run=part, swept=swept, measured=measured)
    return Shown(s.record, s.colour, replace(d, result=result))
