"""The columns a vehicle table's row does not give, derived from those it does.

:func:`derive` takes one row's values as read and checked (in SI units) and completes them:
the steering lock from whichever lock column the row gives (inner-wheel angle, curb-to-curb
or wall-to-wall diameter, CTR; two given must agree within
:data:`clearance.vehicles.table.LOCK_TOLERANCE`), the outer wheel and bicycle angles through the
steering mechanism, the rear overhang from the length, the steering rate, the trailer's
body, and the checks that only the derived values allow (a rear overhang that comes out
negative, an outer wheel at or past straight ahead at full lock, a hitch at or ahead of the
front axle). Problems and warnings are appended to the lists given, naming the row.
"""

from __future__ import annotations

import math

from clearance.vehicles.errors import InputError
from clearance.vehicles.lock import rho_from_ctr, rho_from_curb_to_curb, rho_from_wall_to_wall
from clearance.vehicles.schema import LOCK_NAMES, RACK_NAMES, TRAILER_NAMES, default_vclass
from clearance.vehicles.steering import Breakpoints, RackPinion, Schedule, Steering
from clearance.vehicles.underside import UNDERSIDE_COLUMNS, underside_from

__all__ = ["LOCK_TOLERANCE", "derive", "schedule_text"]

#: Relative disagreement allowed between two given lock columns (published values are
#: rounded, e.g. a CTR to 0.1 ft).
LOCK_TOLERANCE = 0.01


def derive(v: dict[str, object], where: str, problems: list[str], warnings: list[str],
            units: str, scale: float) -> dict[str, object] | None:
    l, B, a_f, L = (_num(v, k) for k in ("wheelbase", "width", "front_overhang", "length"))
    w = _num(v, "track", B)
    has_trailer = any(k in v for k in TRAILER_NAMES)
    n_before = len(problems)

    # Trailer and overhangs.
    trailer: dict[str, float] = {}
    if has_trailer:
        body = _trailer_body(v, where, problems, units, scale, l, B, a_f, L)
        if body is None:
            return None
        a_r, trailer = body
    else:
        a_r = _rigid_rear_overhang(v, where, problems, units, scale, l, a_f, L)
    if w > B + 1e-9:
        warnings.append(f"{where}: track {w / scale:g} {units} is wider than the body "
                        f"width {B / scale:g} {units}")

    # Steering mechanism.
    kind = str(v.get("steering", "ackermann"))
    axle = str(v.get("steered_axle", "front"))
    ratio: Schedule = v.get("steering_ratio", 16.0)  # type: ignore[assignment]
    pct: Schedule = v.get("ackermann_pct", 100.0)  # type: ignore[assignment]
    rack = _rack(v, where, problems, kind, w)
    if axle == "rear" and has_trailer:
        problems.append(f"{where}: column steered_axle: a rear-steered vehicle towing a "
                        "trailer is not supported (its hitch would slide sideways with the "
                        "steered axle)")
    if len(problems) > n_before:
        return None
    deadband = math.radians(_num(v, "deadband_deg", 0.0))
    user_range = "steering_range_deg" in v
    sw_range = math.radians(_num(v, "steering_range_deg")) if user_range else 8 * math.pi
    steering = Steering(kind, l, w, ratio, pct, sw_range, deadband, axle, rack)

    # Steering lock: each given form gives rho; they must agree.
    a_s = a_f if axle == "front" else (L - l - a_f if not has_trailer
                                       else _num(v, "rear_overhang", 0))
    given = [k for k in LOCK_NAMES if k in v]
    lock = _steering_lock(v, where, problems, units, scale, steering, given, l, w, B, a_s)
    if lock is None:
        return None
    inner, outer, rho = lock
    phi = math.atan(l / rho)
    wheel_range = _steering_range(v, where, problems, steering, inner, sw_range, user_range)
    if wheel_range is None:
        return None
    rate = _steer_rate(v, phi)
    _check_w_l(v, where, warnings, w, l)

    out: dict[str, object] = {
        "name": v["name"], "category": v["category"], "source": v["source"], "units": units,
        "length_m": L, "width_m": B, "wheelbase_m": l, "front_overhang_m": a_f,
        "rear_overhang_m": a_r, "track_m": w, "steering": kind, "steered_axle": axle,
        "steering_ratio": schedule_text(ratio), "ackermann_pct": schedule_text(pct),
        "steering_range_rad": wheel_range, "deadband_rad": deadband,
        "max_inner_steer_rad": inner, "max_outer_steer_rad": outer, "max_steer_rad": phi,
        "min_radius_m": rho, "max_steer_rate_rad_s": rate,
        "lock_given": ",".join(given),
        "vclass": v.get("vclass") or default_vclass(str(v["category"])),
    }
    _add_passed_columns(v, out, l, a_f, a_r, trailer)
    return out


def _num(v: dict[str, object], key: str, default: float = math.nan) -> float:
    """The row's value of column ``key`` as a float, or ``default`` when it is not given."""
    return float(v[key]) if key in v else default  # type: ignore[arg-type]


def _trailer_body(v: dict[str, object], where: str, problems: list[str], unit: str,
                  scale: float, l: float, B: float, a_f: float,
                  L: float) -> tuple[float, dict[str, float]] | None:
    """The tractor's rear overhang and the towed unit's dimensions of a combination.

    Returns None when the towed unit cannot be placed (a column missing, a bad hitch).
    """
    n_before = len(problems)
    for key in ("hitch_offset", "trailer_wheelbase"):
        if key not in v:
            problems.append(f"{where}: column {key}: empty: a towed unit needs it")
    if len(problems) > n_before:
        return None
    e, lt = _num(v, "hitch_offset"), _num(v, "trailer_wheelbase")
    if e <= -l:
        problems.append(f"{where}: column hitch_offset: {e / scale:g} {unit}: puts the "
                        f"hitch at or ahead of the front axle (wheelbase {l / scale:g} "
                        f"{unit}); a towed unit is hitched behind it")
        return None
    a_tf = _num(v, "trailer_front_overhang", 0.0)
    rest = L - a_f - l - e - lt
    a_tr = _num(v, "trailer_rear_overhang", rest)
    if "trailer_rear_overhang" in v and abs(a_tr - rest) > 0.01 * L + 0.05:
        problems.append(
            f"{where}: column trailer_rear_overhang: {a_tr / scale:g} {unit}: disagrees "
            f"with length - front_overhang - wheelbase - hitch_offset - trailer_wheelbase "
            f"= {rest / scale:g} {unit}")
    if a_tr < 0:
        problems.append(f"{where}: column length: {L / scale:g} {unit}: too short for "
                        f"the combination: the trailer's rear overhang comes out "
                        f"{a_tr / scale:g} {unit}")
    if e + a_tf < -l - a_f + 1e-9 and a_tf > 0:
        pass  # a trailer nose ahead of the tractor's front is odd but not impossible
    a_r = _num(v, "rear_overhang", 0.0)
    trailer = dict(hitch_offset_m=e, trailer_wheelbase_m=lt,
                   trailer_width_m=_num(v, "trailer_width", B), trailer_front_overhang_m=a_tf,
                   trailer_rear_overhang_m=a_tr,
                   max_articulation_rad=_num(v, "max_articulation_deg", math.radians(90.0)))
    return a_r, trailer


def _rigid_rear_overhang(v: dict[str, object], where: str, problems: list[str], unit: str,
                         scale: float, l: float, a_f: float, L: float) -> float:
    """The rear overhang of a single unit, from its length; checked against the column."""
    a_r = L - l - a_f
    if "rear_overhang" in v and abs(_num(v, "rear_overhang") - a_r) > 0.01 * L + 0.05:
        problems.append(f"{where}: column rear_overhang: {_num(v, 'rear_overhang') / scale:g} "
                        f"{unit}: disagrees with length - wheelbase - front_overhang = "
                        f"{a_r / scale:g} {unit}")
    if a_r < 0:
        problems.append(f"{where}: column length: {L / scale:g} {unit}: shorter than "
                        f"wheelbase + front_overhang: the rear overhang comes out "
                        f"{a_r / scale:g} {unit}")
    return a_r


def _rack(v: dict[str, object], where: str, problems: list[str], kind: str,
          w: float) -> RackPinion | None:
    """The rack-and-pinion linkage, if any, after checking the columns the mechanism takes."""
    if kind != "ackermann" and "ackermann_pct" in v:
        problems.append(f"{where}: column ackermann_pct: given for {kind} steering, which "
                        "has no Ackermann percentage")
    rack = None
    if kind == "rack_pinion":
        missing = [k for k in RACK_NAMES if k not in v]
        if missing:
            problems.append(f"{where}: column steering: rack_pinion needs the linkage "
                            f"columns {', '.join(missing)}")
        else:
            try:
                rack = RackPinion(w, _num(v, "rack_length"), _num(v, "steering_arm"),
                                  _num(v, "tie_rod"), _num(v, "rack_offset"),
                                  _num(v, "pinion_radius"))
            except InputError as exc:
                problems.append(f"{where}: column steering: {exc}")
    return rack


def _steering_lock(v: dict[str, object], where: str, problems: list[str], unit: str,
                   scale: float, steering: Steering, given: list[str], l: float, w: float,
                   B: float, a_s: float) -> tuple[float, float, float] | None:
    """The inner and outer wheel angles and the radius at full lock, from the lock columns.

    Returns None when the lock columns are missing, impossible or disagree.
    """
    rhos = _lock_radii(v, where, problems, steering, given, l, w, B, a_s)
    if rhos is None or not _lock_radii_agree(v, where, problems, unit, scale, steering,
                                             rhos, l, w):
        return None
    return _full_lock(v, where, problems, steering, rhos, given, l)


def _lock_radii(v: dict[str, object], where: str, problems: list[str], steering: Steering,
                given: list[str], l: float, w: float, B: float,
                a_s: float) -> dict[str, float] | None:
    """The rear-axle-centre radius at full lock from each given lock column.

    Returns None when no lock column is given or the inner-wheel angle is out of reach.
    """
    rhos: dict[str, float] = {}
    if not given:
        problems.append(f"{where}: column max_steer_deg: empty: the steering lock needs one "
                        f"of {', '.join(LOCK_NAMES)}")
        return None
    if "max_steer_deg" in v:
        inner = _num(v, "max_steer_deg")
        outer = float(steering.outer_for_inner(inner))
        if not math.isfinite(outer):
            problems.append(f"{where}: column max_steer_deg: {math.degrees(inner):g}: "
                            "beyond what the rack-and-pinion linkage can reach")
            return None
        phi = float(steering.max_bicycle_for_inner(inner))
        rhos["max_steer_deg"] = l / math.tan(phi)
    if "ctr" in v:
        rhos["ctr"] = float(rho_from_ctr(_num(v, "ctr"), l))
    if "curb_to_curb" in v:
        rhos["curb_to_curb"] = float(rho_from_curb_to_curb(_num(v, "curb_to_curb"), l, w))
    if "wall_to_wall" in v:
        rhos["wall_to_wall"] = float(rho_from_wall_to_wall(_num(v, "wall_to_wall"), l, B, a_s))
    return rhos


def _lock_radii_agree(v: dict[str, object], where: str, problems: list[str], unit: str,
                      scale: float, steering: Steering, rhos: dict[str, float], l: float,
                      w: float) -> bool:
    """Whether every lock radius is a possible one and all agree within the tolerance."""
    n_before = len(problems)
    for key, rho in rhos.items():
        if key == "max_steer_deg":
            continue
        shown = f"{_num(v, key) / scale:g} {unit}"
        if not math.isfinite(rho) or rho <= 0:
            problems.append(f"{where}: column {key}: {shown}: too small for a wheelbase of "
                            f"{l / scale:g} {unit}: no such turning circle exists")
        elif rho <= w / 2 + 1e-9 and steering.kind != "parallel":
            problems.append(f"{where}: column {key}: {shown}: implies an inner wheel lock of "
                            "90 degrees or more")
    if len(problems) > n_before:
        return False
    if len(rhos) > 1:
        lo, hi = min(rhos.values()), max(rhos.values())
        if hi - lo > LOCK_TOLERANCE * hi:
            detail = ", ".join(f"{k} gives {r / scale:.2f} {unit}" for k, r in rhos.items())
            problems.append(f"{where}: columns {', '.join(rhos)}: the steering lock columns "
                            f"disagree (radius of the rear-axle centre: {detail})")
            return False
    return True


def _full_lock(v: dict[str, object], where: str, problems: list[str], steering: Steering,
               rhos: dict[str, float], given: list[str],
               l: float) -> tuple[float, float, float] | None:
    """The full lock from the lock radii: the inner-wheel angle when given, else the first radius.

    Returns None when the mechanism cannot reach it or the outer wheel comes out wrong.
    """
    if "max_steer_deg" in v:
        inner = _num(v, "max_steer_deg")
        rho = rhos["max_steer_deg"]
    else:
        rho = rhos[given[0]]
        phi_target = math.atan(l / rho)
        inner = _inner_for_bicycle(steering, phi_target)
        if not math.isfinite(inner):
            problems.append(f"{where}: column {given[0]}: the mechanism cannot reach this lock")
            return None
    outer = float(steering.outer_for_inner(inner))
    if not 0.0 < outer < math.pi / 2:
        problems.append(f"{where}: column "
                        f"{'ackermann_pct' if 'ackermann_pct' in v else steering.kind}: "
                        f"the outer wheel comes out at {math.degrees(outer):.1f} degrees at "
                        f"full lock (inner {math.degrees(inner):.1f}): it must turn the same "
                        "way, by less than 90 degrees")
        return None
    return inner, outer, rho


def _steering_range(v: dict[str, object], where: str, problems: list[str], steering: Steering,
                    inner: float, sw_range: float, user_range: bool) -> float | None:
    """The steering-wheel range: the given one if it reaches the lock, else the lock's own.

    Returns None when a given range falls short of the steering lock.
    """
    sw_lock = float(steering.steering_for_inner(inner))
    if user_range and not math.isfinite(sw_lock):
        problems.append(f"{where}: column steering_range_deg: "
                        f"{_num(v, 'steering_range_deg'):g}: the steering wheel cannot reach "
                        "the steering lock within this range")
        return None
    if not user_range:
        sw_range = sw_lock if math.isfinite(sw_lock) and sw_lock > 0 else sw_range
    return sw_range


def _steer_rate(v: dict[str, object], phi: float) -> float:
    """The largest steering rate (rad/s): given, or full lock ``phi`` each way in lock_to_lock_s."""
    if "max_steer_rate_deg_s" in v:
        return math.radians(_num(v, "max_steer_rate_deg_s"))
    return 2 * phi / _num(v, "lock_to_lock_s", 4.0)


def _check_w_l(v: dict[str, object], where: str, warnings: list[str], w: float,
               l: float) -> None:
    """Warn when a published w/l (Table 1 of the paper) disagrees with track / wheelbase."""
    if "w_l" in v:
        published = _num(v, "w_l")
        text = f"{published:g}"
        decimals = len(text.split(".")[1]) if "." in text else 0
        if abs(w / l - published) > 10.0 ** (-max(decimals, 2)) + 1e-9:
            warnings.append(f"{where}: column w_l: published {published:g} disagrees with "
                            f"track / wheelbase = {w / l:.3f}")


def _add_passed_columns(v: dict[str, object], out: dict[str, object], l: float, a_f: float,
                        a_r: float, trailer: dict[str, float]) -> None:
    """Add to ``out`` the linkage, clearance, reference and trailer columns (NaN if not given)."""
    for key in RACK_NAMES:
        out[f"{key}_m"] = _num(v, key)
    for key, suffix in (("height", "_m"), ("ground_clearance", "_m"), ("approach_deg", ""),
                        ("departure_deg", ""), ("breakover_deg", ""),
                        ("ref_turning_radius", "_m"), ("ref_inside_radius", "_m"),
                        ("w_l", ""), ("grade_limit_pct", "")):
        out[key.replace("_deg", "_rad") + suffix] = _num(v, key)
    c, alpha, delta, beta = (_num(v, k) if k in v else None for k in UNDERSIDE_COLUMNS)
    out["underside_note"] = underside_from(c, alpha, delta, beta, l, a_f, a_r,
                                           str(out["vclass"])).note
    for key in ("hitch_offset_m", "trailer_wheelbase_m", "trailer_width_m",
                "trailer_front_overhang_m", "trailer_rear_overhang_m", "max_articulation_rad"):
        out[key] = trailer.get(key, math.nan)


def _inner_for_bicycle(steering: Steering, phi: float) -> float:
    """Inner wheel angle whose mean-cotangent bicycle angle is ``phi`` (bisection)."""
    lo, hi = 0.0, math.radians(89.9)
    if steering.kind == "parallel":
        return phi
    for _ in range(80):
        mid = (lo + hi) / 2
        got = float(steering.max_bicycle_for_inner(mid))
        if not math.isfinite(got) or got > phi:
            hi = mid
        else:
            lo = mid
    return (lo + hi) / 2


def schedule_text(value: Schedule) -> object:
    """A percent-Ackermann or ratio schedule as the table writes it: a number, or
    ``angle:value;angle:value`` over the steering-wheel angle in degrees."""
    if isinstance(value, Breakpoints):
        return ";".join(f"{math.degrees(x):g}:{y:g}" for x, y in zip(value.x, value.y,
                                                                   strict=True))
    return float(value)
