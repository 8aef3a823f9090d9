"""Vertical checks: does a vehicle's underside clear the ground along a path's profile?

The path's profile is its height ``z(s)`` over the plane arc length ``s`` (a developed
vertical section, piecewise linear between the points given). The vehicle stands on it with
its two axles' tyre contacts on the ground, a wheelbase ``l`` apart (measured along the
chord between them; tyres are points). In the frame of that chord (``x`` along it from the
rear contact, ``y`` up, perpendicular to it) its body's lower outline (:class:`Body`) is

- behind the rear axle (``-a_r <= x < 0``): ``max(c, -x tan(delta))``,
- between the axles: ``max(c, arc(x))``, the arc through both contacts from whose points
  the wheelbase is seen at ``pi - beta`` (a crest of that angle has its apex on it wherever
  the vehicle stands; ``(l / 2) tan(beta / 2)`` high at mid-wheelbase),
- ahead of the front axle (``l < x <= l + a_f``): ``max(c, (x - l) tan(alpha))``,

with the ground clearance ``c``, the departure, breakover and approach angles ``delta``,
``beta``, ``alpha`` (:class:`clearance.vehicles.underside.Underside`). A body of clearance ``c``
whose angles are derived from it is the flat plate ``y = c`` from its rear to its front end.

The vehicle is placed with its rear contact at every ``step_m`` (and wherever a contact
stands on a point of the profile, where the overhangs' worst cases are) while any part of
it is over the span checked. At each placement the gap between the outline and the ground
is taken at every point of the profile under the body and at every corner of the outline;
the smallest gap over the placements is the **vertical margin**: ``>= 0`` the least room
left, ``< 0`` how deep the ground cuts into the body (the run **scrapes**). Where it is
decides the part: ``underside`` (between the axles: breakover at a crest), ``front
overhang`` (approach, at a sag), ``rear overhang`` (departure, at a sag).

Beyond the profile's ends the ground goes on at the grade of its first and last pieces.

**Suspect elevation** (:func:`suspect_points`): an inner point of a profile whose height is
far off the line through its two neighbours, with steep grades of opposite sign into and
out of it (a lone bogus height in a network, such as a 218 m point on a motorway at about
40 m), is geometry to check, not a ramp; :func:`without_points` takes it out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clearance.vehicles.vehicle import Vehicle

__all__ = ["DEFAULT_STEP_M", "PARTS", "SUSPECT_GRADE_PCT", "SUSPECT_RISE_M", "Body",
           "VerticalResult", "body_clearance", "front_contact", "suspect_points",
           "without_points"]

#: Rear-contact stations are this far apart (m), beside those that put a contact on a point.
DEFAULT_STEP_M = 0.05

#: The body parts a result may name.
PARTS = ("underside", "front overhang", "rear overhang")

#: A suspect point rises or drops at least this much (m) off the line through its neighbours.
SUSPECT_RISE_M = 1.0

#: ... and the grades into and out of it are both at least this steep (percent), of
#: opposite signs. Paved ramps are built at up to about 20 %, the steepest streets about 35 %.
SUSPECT_GRADE_PCT = 40.0


@dataclass(frozen=True)
class Body:
    """A vehicle in side view for the vertical checks (metres; tangents of the angles).

    Examples
    --------
    >>> b = Body(2.7, 0.9, 1.0, 0.10, 0.10 / 0.9, 0.10 / 1.0, 0.10 / 1.35)
    >>> b.outline(np.array([-1.0, 0.0, 1.35, 2.7, 3.6])).round(3).tolist()
    [0.1, 0.1, 0.1, 0.1, 0.1]
    """

    wheelbase_m: float
    front_overhang_m: float
    rear_overhang_m: float
    clearance_m: float
    tan_approach: float
    tan_departure: float
    tan_half_breakover: float

    @classmethod
    def of(cls, vehicle: Vehicle) -> Body:
        """The body of a vehicle (its towing unit), with its underside or the class default.

        Examples
        --------
        >>> v = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.7, 0.4)
        >>> b = Body.of(v)
        >>> round(b.clearance_m, 2), round(b.tan_approach, 4)
        (0.1, 0.1111)
        """
        u = vehicle.underside_or_default()

        def tan(a: float) -> float:
            return math.inf if a >= math.pi / 2 - 1e-12 else math.tan(a)

        return cls(vehicle.wheelbase_m, vehicle.front_overhang_m, vehicle.rear_overhang_m,
                   u.ground_clearance_m, tan(u.approach_rad), tan(u.departure_rad),
                   tan(u.breakover_rad / 2))

    @property
    def length_m(self) -> float:
        """Rear end to front end."""
        return self.rear_overhang_m + self.wheelbase_m + self.front_overhang_m

    def outline(self, x: np.ndarray) -> np.ndarray:
        """Height of the lower outline above the chord at ``x`` (m from the rear contact).

        Examples
        --------
        The Hummer H3's published angles: higher than its clearance over the axles' middle
        and towards the ends:

        >>> import math
        >>> t = math.tan
        >>> b = Body(2.842, 0.781, 1.140, 0.216, t(math.radians(37.5)),
        ...          t(math.radians(34.6)), t(math.radians(23.5 / 2)))
        >>> b.outline(np.array([-1.14, 0.0, 1.421, 2.842, 3.623])).round(3).tolist()
        [0.786, 0.216, 0.296, 0.216, 0.599]
        """
        x = np.asarray(x, dtype=float)
        ell, c = self.wheelbase_m, self.clearance_m
        with np.errstate(invalid="ignore"):
            rear = np.maximum(c, np.where(x < 0, -x, 0.0) * self.tan_departure)
            front = np.maximum(c, np.where(x > ell, x - ell, 0.0) * self.tan_approach)
        mid = np.maximum(c, self._arc(x))
        return np.where(x < 0, rear, np.where(x > ell, front, mid))

    def _arc(self, x: np.ndarray) -> np.ndarray:
        """The breakover arc: through both contacts, seeing the wheelbase at ``pi - beta``
        (where a crest of that angle has its apex, wherever the vehicle stands on it)."""
        ell, th = self.wheelbase_m, self.tan_half_breakover
        beta = 2.0 * math.atan(th)
        if not 0 < beta < math.pi:
            return np.full_like(x, -math.inf)
        rho = ell / (2.0 * math.sin(beta))
        inside = np.maximum(rho ** 2 - (x - 0.5 * ell) ** 2, 0.0)
        return np.sqrt(inside) - rho * math.cos(beta)

    def corners(self) -> np.ndarray:
        """The outline's corners along ``x`` (where the ground's gap may be least between two
        of its points)."""
        ell, c = self.wheelbase_m, self.clearance_m
        xs = [-self.rear_overhang_m, 0.0, 0.5 * ell, ell, ell + self.front_overhang_m]
        for tan, base, sign, limit in ((self.tan_departure, 0.0, -1, self.rear_overhang_m),
                                       (self.tan_approach, ell, 1, self.front_overhang_m)):
            if tan > 0 and math.isfinite(tan) and c / tan < limit:
                xs.append(base + sign * c / tan)
        beta = 2.0 * math.atan(self.tan_half_breakover)
        if 0 < beta < math.pi:  # where the breakover arc rises above the clearance
            rho = ell / (2.0 * math.sin(beta))
            half = rho ** 2 - (c + rho * math.cos(beta)) ** 2
            if half > 0:
                xs += [0.5 * ell - math.sqrt(half), 0.5 * ell + math.sqrt(half)]
        return np.unique(np.asarray(xs))


@dataclass(frozen=True)
class VerticalResult:
    """The vertical check of one vehicle on one profile.

    Attributes
    ----------
    margin_m
        The smallest gap between the body's outline and the ground over every placement
        (``< 0``: the depth the ground cuts into the body).
    station_m
        Where along the profile (``s``) that gap is; NaN where no part of the body was over
        the span checked.
    rear_axle_m
        The rear contact's station at that placement.
    part
        One of :data:`PARTS`, or ``""`` where nothing comes nearer than on level ground
        (the clearance; ``station_m`` and ``rear_axle_m`` are then NaN).
    part_margins_m
        The smallest gap of each part, by :data:`PARTS` (the part's own clearance where the
        ground never comes near it).
    """

    margin_m: float
    station_m: float
    rear_axle_m: float
    part: str
    part_margins_m: dict[str, float]

    @property
    def scrapes(self) -> bool:
        """True when the ground cuts into the body somewhere."""
        return self.margin_m < 0


def _clean(s_m: np.ndarray, z_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = np.asarray(s_m, dtype=float).ravel()
    z = np.asarray(z_m, dtype=float).ravel()
    if s.shape != z.shape or not len(s):
        raise ValueError("a profile needs as many heights as stations, at least one")
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(z))):
        raise ValueError("a profile's stations and heights must be finite")
    if np.any(np.diff(s) < 0):
        raise ValueError("a profile's stations must not decrease")
    keep = np.r_[True, np.diff(s) > 1e-9]
    return s[keep], z[keep]


def front_contact(s_m: np.ndarray, z_m: np.ndarray, rear_m: np.ndarray,
                  wheelbase_m: float, iterations: int = 8) -> np.ndarray:
    """Station of the front tyre's contact a chord of ``wheelbase_m`` ahead of each rear one.

    Fixed-point iteration on ``ds = sqrt(l^2 - dz(ds)^2)`` (it converges for grades of the
    chord under 100 %).

    Examples
    --------
    On a 10 % grade the front contact is ``l cos(atan 0.1)`` ahead in plan:

    >>> s, z = np.array([0.0, 100.0]), np.array([0.0, 10.0])
    >>> round(float(front_contact(s, z, np.array([10.0]), 2.7)[0]) - 10, 4)
    2.6866
    >>> front_contact(s, z, np.array([]), 2.7).shape   # no rear contacts
    (0,)
    """
    r = np.asarray(rear_m, dtype=float)
    zr = np.interp(r, s_m, z_m)
    ds = np.full_like(r, wheelbase_m)
    for _ in range(iterations):
        dz = np.interp(r + ds, s_m, z_m) - zr
        ds = np.sqrt(np.maximum(wheelbase_m ** 2 - dz ** 2, 0.25 * wheelbase_m ** 2))
    return np.asarray(r + ds, dtype=float)


def _rear_for_front(s_m: np.ndarray, z_m: np.ndarray, front_m: np.ndarray,
                    wheelbase_m: float, iterations: int = 8) -> np.ndarray:
    """Station of the rear contact whose front contact is at ``front_m`` (as above)."""
    f = np.asarray(front_m, dtype=float)
    zf = np.interp(f, s_m, z_m)
    ds = np.full_like(f, wheelbase_m)
    for _ in range(iterations):
        dz = zf - np.interp(f - ds, s_m, z_m)
        ds = np.sqrt(np.maximum(wheelbase_m ** 2 - dz ** 2, 0.25 * wheelbase_m ** 2))
    return np.asarray(f - ds, dtype=float)


def body_clearance(s_m: np.ndarray, z_m: np.ndarray, body: Body,
                   span_m: tuple[float, float] | None = None,
                   step_m: float = DEFAULT_STEP_M) -> VerticalResult:
    """The vertical margin of ``body`` driven along the profile ``(s_m, z_m)``.

    Parameters
    ----------
    s_m, z_m
        Stations (plane arc length, not decreasing) and heights of the profile.
    body
        The vehicle in side view.
    span_m
        Only placements with some part of the body over ``[from, to]`` count (the
        feature); default the whole profile.
    step_m
        Spacing of the rear contact's stations.

    Raises
    ------
    ValueError
        An empty profile, one with stations that decrease, or with NaN or infinity.

    Examples
    --------
    A low car (0.10 m clearance, 2.7 m wheelbase, 0.9 m and 1.0 m overhangs) meeting a
    15 % ramp with no transition scrapes its front end at the foot, by ``0.9 * 0.15 - 0.10``:

    >>> s = np.array([0.0, 20.0, 40.0])
    >>> z = np.array([0.0, 0.0, 3.0])
    >>> car = Body(2.7, 0.9, 1.0, 0.10, 0.10 / 0.9, 0.10 / 1.0, 0.10 / 1.35)
    >>> r = body_clearance(s, z, car)
    >>> round(r.part_margins_m["front overhang"], 4), r.scrapes
    (-0.035, True)

    On level ground (the degenerate case) the margin is the clearance and no part is named:

    >>> r = body_clearance(np.array([0.0]), np.array([5.0]), car)
    >>> r.margin_m, r.part
    (0.1, '')
    """
    s, z = _clean(s_m, z_m)
    lo, hi = (float(s[0]), float(s[-1])) if span_m is None else map(float, span_m)
    ell, a_f, a_r = body.wheelbase_m, body.front_overhang_m, body.rear_overhang_m
    parts0 = {p: body.clearance_m for p in PARTS}
    if z.min() == z.max() or hi < lo:
        return VerticalResult(body.clearance_m, math.nan, math.nan, "", parts0)
    # the ground level beyond the ends, far enough for any placement
    pad = body.length_m + 1.0
    g0 = (z[1] - z[0]) / (s[1] - s[0])
    g1 = (z[-1] - z[-2]) / (s[-1] - s[-2])
    s = np.r_[s[0] - pad, s, s[-1] + pad]
    z = np.r_[z[0] - g0 * pad, z, z[-1] + g1 * pad]
    r_lo, r_hi = lo - ell - a_f, hi + a_r
    inner = s[1:-1]
    rears = np.r_[np.arange(r_lo, r_hi, step_m), r_hi, inner,
                  _rear_for_front(s, z, inner, ell)]
    rears = np.unique(rears[(rears >= r_lo) & (rears <= r_hi)])
    fronts = front_contact(s, z, rears, ell)
    zr, zf = np.interp(rears, s, z), np.interp(fronts, s, z)
    ux, uz = (fronts - rears) / ell, (zf - zr) / ell
    # the points of the profile under each placement (and one either side)
    first = np.maximum(np.searchsorted(s, rears - a_r, "right") - 1, 0)
    last = np.minimum(np.searchsorted(s, fronts + a_f, "left"), len(s) - 1)
    width = int((last - first).max()) + 1
    idx = first[:, None] + np.arange(width)[None, :]
    valid = idx <= last[:, None]
    idx = np.minimum(idx, len(s) - 1)
    ds, dz = s[idx] - rears[:, None], z[idx] - zr[:, None]
    gx = ds * ux[:, None] + dz * uz[:, None]
    gy = dz * ux[:, None] - ds * uz[:, None]
    gx = np.where(valid, gx, np.inf)  # sorted along each row, padding last
    # the ground's height under each corner of the outline (linear between points)
    cx = body.corners()
    k = np.clip((gx[:, :, None] <= cx[None, None, :]).sum(axis=1) - 1, 0, width - 2)
    k1 = np.minimum(k + 1, (valid.sum(axis=1) - 1)[:, None])
    x0, x1 = np.take_along_axis(gx, k, 1), np.take_along_axis(gx, k1, 1)
    y0, y1 = np.take_along_axis(gy, k, 1), np.take_along_axis(gy, k1, 1)
    span = np.where(x1 - x0 > 1e-12, x1 - x0, 1.0)
    t = np.clip((cx[None, :] - x0) / span, 0.0, 1.0)
    cy = y0 + t * (y1 - y0)
    cs = rears[:, None] + cx[None, :] * ux[:, None]  # station under each corner (near enough)
    # gaps at the profile's points and at the corners, where the body is
    inside = valid & (gx >= -a_r - 1e-9) & (gx <= ell + a_f + 1e-9)
    gap_pts = np.where(inside, body.outline(np.where(inside, gx, 0.0)) - gy, np.inf)
    gap_cnr = np.broadcast_to(body.outline(cx)[None, :], cy.shape) - cy
    gaps = np.concatenate([gap_pts, gap_cnr], axis=1)
    xs = np.concatenate([np.where(inside, gx, np.nan), np.broadcast_to(cx, cy.shape)], axis=1)
    stations = np.concatenate([s[idx], cs], axis=1)
    parts = np.where(xs < 0, 2, np.where(xs > ell, 1, 0))
    part_min = {p: float(np.where(parts == i, gaps, np.inf).min()) for i, p in enumerate(PARTS)}
    part_min = {p: (v if math.isfinite(v) else body.clearance_m) for p, v in part_min.items()}
    flat = int(np.argmin(gaps))
    row, col = divmod(flat, gaps.shape[1])
    if gaps[row, col] >= body.clearance_m - 1e-9:  # nothing nearer than on level ground
        return VerticalResult(body.clearance_m, math.nan, math.nan, "", part_min)
    return VerticalResult(float(gaps[row, col]), float(stations[row, col]), float(rears[row]),
                          PARTS[int(parts[row, col])], part_min)


def suspect_points(s_m: np.ndarray, z_m: np.ndarray, rise_m: float = SUSPECT_RISE_M,
                   grade_pct: float = SUSPECT_GRADE_PCT) -> np.ndarray:
    """Indices of the lone points of a profile: inner points at least ``rise_m`` off the line
    through their neighbours, with grades into and out of them of opposite signs, both at
    least ``grade_pct`` steep. A profile's first and last points have one neighbour and are
    never suspect.

    Examples
    --------
    A motorway at about 40 m with one point at 218 m:

    >>> s = np.array([0.0, 50.0, 122.0, 200.0])
    >>> z = np.array([40.0, 40.2, 218.0, 40.6])
    >>> suspect_points(s, z).tolist()
    [2]

    A real 15 % ramp (the grade changes, but not to and fro) and a line of two points:

    >>> suspect_points(np.array([0.0, 10, 30, 40]), np.array([0.0, 0, 3, 3])).tolist()
    []
    >>> suspect_points(np.array([0.0, 1.0]), np.array([0.0, 9.0])).tolist()
    []
    """
    s = np.asarray(s_m, dtype=float)
    z = np.asarray(z_m, dtype=float)
    if len(s) < 3:
        return np.zeros(0, dtype=np.int64)
    ds = np.diff(s)
    g = np.diff(z) / np.where(ds > 1e-9, ds, np.nan)
    g_in, g_out = g[:-1], g[1:]
    w = np.where(ds[:-1] + ds[1:] > 0, ds[:-1] / np.maximum(ds[:-1] + ds[1:], 1e-12), 0.5)
    off = z[1:-1] - (z[:-2] + w * (z[2:] - z[:-2]))
    with np.errstate(invalid="ignore"):
        lone = ((np.sign(g_in) * np.sign(g_out) < 0)
                & (np.minimum(np.abs(g_in), np.abs(g_out)) >= grade_pct / 100.0)
                & (np.abs(off) >= rise_m))
    return np.flatnonzero(lone) + 1


def without_points(s_m: np.ndarray, z_m: np.ndarray, drop: np.ndarray) -> np.ndarray:
    """The heights with the points ``drop`` replaced by the line between the points kept.

    Examples
    --------
    >>> without_points(np.array([0.0, 50, 122, 200]), np.array([40.0, 40.2, 218, 40.6]),
    ...                np.array([2])).round(3).tolist()
    [40.0, 40.2, 40.392, 40.6]
    >>> without_points(np.array([0.0, 1]), np.array([3.0, 4]), np.array([], dtype=int)).tolist()
    [3.0, 4.0]
    """
    z = np.array(z_m, dtype=float)
    if not len(drop):
        return z
    keep = np.ones(len(z), dtype=bool)
    keep[drop] = False
    s = np.asarray(s_m, dtype=float)
    z[~keep] = np.interp(s[~keep], s[keep], z[keep])
    return z
