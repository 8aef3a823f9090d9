"""The columns a vehicle table's row does not give, derived from those it does.

:func:`derive` takes one row's values as read and checked (in SI units) and completes them:
the steering lock from whichever lock column the row gives (inner-wheel angle, curb-to-curb
or wall-to-wall diameter, CTR; two given must agree within
:data:`vehicles.table.LOCK_TOLERANCE`), the outer wheel and bicycle angles through the
steering mechanism, the rear overhang from the length, the steering rate, the trailer's
body, and the checks that only the derived values allow (a rear overhang that comes out
negative, an outer wheel at or past straight ahead at full lock, a hitch at or ahead of the
front axle). Problems and warnings are appended to the lists given, naming the row.
"""

from __future__ import annotations

import math

from vehicles.errors import InputError
from vehicles.lock import rho_from_ctr, rho_from_curb_to_curb, rho_from_wall_to_wall
from vehicles.schema import LOCK_NAMES, RACK_NAMES, TRAILER_NAMES, default_vclass
from vehicles.steering import Breakpoints, RackPinion, Schedule, Steering
from vehicles.underside import UNDERSIDE_COLUMNS, underside_from

__all__ = ["LOCK_TOLERANCE", "derive", "schedule_text"]

#: Relative disagreement allowed between two given lock columns (published values are
#: rounded, e.g. a CTR to 0.1 ft).
LOCK_TOLERANCE = 0.01


def derive(v: dict[str, object], where: str, problems: list[str], warnings: list[str],
            units: str, scale: float) -> dict[str, object] | None:
    def f(key: str, default: float = math.nan) -> float:
        return float(v[key]) if key in v else default  # type: ignore[arg-type]

    l, B, a_f, L = f("wheelbase"), f("width"), f("front_overhang"), f("length")  # noqa: E741
    w = f("track", B)
    has_trailer = any(k in v for k in TRAILER_NAMES)
    unit = units
    n_before = len(problems)

    # Trailer and overhangs.
    trailer: dict[str, float] = {}
    if has_trailer:
        for key in ("hitch_offset", "trailer_wheelbase"):
            if key not in v:
                problems.append(f"{where}: column {key}: empty: a towed unit needs it")
        if len(problems) > n_before:
            return None
        e, lt = f("hitch_offset"), f("trailer_wheelbase")
        if e <= -l:
            problems.append(f"{where}: column hitch_offset: {e / scale:g} {unit}: puts the "
                            f"hitch at or ahead of the front axle (wheelbase {l / scale:g} "
                            f"{unit}); a towed unit is hitched behind it")
            return None
        a_tf = f("trailer_front_overhang", 0.0)
        rest = L - a_f - l - e - lt
        a_tr = f("trailer_rear_overhang", rest)
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
        a_r = f("rear_overhang", 0.0)
        trailer = dict(hitch_offset_m=e, trailer_wheelbase_m=lt,
                       trailer_width_m=f("trailer_width", B), trailer_front_overhang_m=a_tf,
                       trailer_rear_overhang_m=a_tr,
                       max_articulation_rad=f("max_articulation_deg", math.radians(90.0)))
    else:
        a_r = L - l - a_f
        if "rear_overhang" in v and abs(f("rear_overhang") - a_r) > 0.01 * L + 0.05:
            problems.append(f"{where}: column rear_overhang: {f('rear_overhang') / scale:g} "
                            f"{unit}: disagrees with length - wheelbase - front_overhang = "
                            f"{a_r / scale:g} {unit}")
        if a_r < 0:
            problems.append(f"{where}: column length: {L / scale:g} {unit}: shorter than "
                            f"wheelbase + front_overhang: the rear overhang comes out "
                            f"{a_r / scale:g} {unit}")
    if w > B + 1e-9:
        warnings.append(f"{where}: track {w / scale:g} {unit} is wider than the body "
                        f"width {B / scale:g} {unit}")

    # Steering mechanism.
    kind = str(v.get("steering", "ackermann"))
    axle = str(v.get("steered_axle", "front"))
    ratio: Schedule = v.get("steering_ratio", 16.0)  # type: ignore[assignment]
    pct: Schedule = v.get("ackermann_pct", 100.0)  # type: ignore[assignment]
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
                rack = RackPinion(w, f("rack_length"), f("steering_arm"), f("tie_rod"),
                                  f("rack_offset"), f("pinion_radius"))
            except InputError as exc:
                problems.append(f"{where}: column steering: {exc}")
    if len(problems) > n_before:
        return None
    deadband = math.radians(f("deadband_deg", 0.0))
    user_range = "steering_range_deg" in v
    sw_range = math.radians(f("steering_range_deg")) if user_range else 8 * math.pi
    steering = Steering(kind, l, w, ratio, pct, sw_range, deadband, axle, rack)

    # Steering lock: each given form gives rho; they must agree.
    a_s = a_f if axle == "front" else (L - l - a_f if not has_trailer else f("rear_overhang", 0))
    rhos: dict[str, float] = {}
    given = [k for k in LOCK_NAMES if k in v]
    if not given:
        problems.append(f"{where}: column max_steer_deg: empty: the steering lock needs one "
                        f"of {', '.join(LOCK_NAMES)}")
        return None
    inner_given = f("max_steer_deg")
    if "max_steer_deg" in v:
        outer = float(steering.outer_for_inner(inner_given))
        if not math.isfinite(outer):
            problems.append(f"{where}: column max_steer_deg: {math.degrees(inner_given):g}: "
                            "beyond what the rack-and-pinion linkage can reach")
            return None
        phi = float(steering.max_bicycle_for_inner(inner_given))
        rhos["max_steer_deg"] = l / math.tan(phi)
    if "ctr" in v:
        rhos["ctr"] = float(rho_from_ctr(f("ctr"), l))
    if "curb_to_curb" in v:
        rhos["curb_to_curb"] = float(rho_from_curb_to_curb(f("curb_to_curb"), l, w))
    if "wall_to_wall" in v:
        rhos["wall_to_wall"] = float(rho_from_wall_to_wall(f("wall_to_wall"), l, B, a_s))
    for key, rho in rhos.items():
        if key == "max_steer_deg":
            continue
        shown = f"{f(key) / scale:g} {unit}"
        if not math.isfinite(rho) or rho <= 0:
            problems.append(f"{where}: column {key}: {shown}: too small for a wheelbase of "
                            f"{l / scale:g} {unit}: no such turning circle exists")
        elif rho <= w / 2 + 1e-9 and kind != "parallel":
            problems.append(f"{where}: column {key}: {shown}: implies an inner wheel lock of "
                            "90 degrees or more")
    if len(problems) > n_before:
        return None
    if len(rhos) > 1:
        lo, hi = min(rhos.values()), max(rhos.values())
        if hi - lo > LOCK_TOLERANCE * hi:
            detail = ", ".join(f"{k} gives {r / scale:.2f} {unit}" for k, r in rhos.items())
            problems.append(f"{where}: columns {', '.join(rhos)}: the steering lock columns "
                            f"disagree (radius of the rear-axle centre: {detail})")
            return None
    # The lock itself: prefer the inner-wheel angle when given, else the first radius.
    if "max_steer_deg" in v:
        inner = inner_given
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
        problems.append(f"{where}: column {'ackermann_pct' if 'ackermann_pct' in v else kind}: "
                        f"the outer wheel comes out at {math.degrees(outer):.1f} degrees at "
                        f"full lock (inner {math.degrees(inner):.1f}): it must turn the same "
                        "way, by less than 90 degrees")
        return None
    phi = math.atan(l / rho)
    sw_lock = float(steering.steering_for_inner(inner))
    if user_range and not math.isfinite(sw_lock):
        problems.append(f"{where}: column steering_range_deg: {f('steering_range_deg'):g}: "
                        "the steering wheel cannot reach the steering lock within this range")
        return None
    if not user_range:
        sw_range = sw_lock if math.isfinite(sw_lock) and sw_lock > 0 else sw_range
    if "max_steer_rate_deg_s" in v:
        rate = math.radians(f("max_steer_rate_deg_s"))
    else:
        rate = 2 * phi / f("lock_to_lock_s", 4.0)

    # Published w/l (Table 1 of the paper): a warning, never an error.
    if "w_l" in v:
        published = f("w_l")
        text = f"{published:g}"
        decimals = len(text.split(".")[1]) if "." in text else 0
        if abs(w / l - published) > 10.0 ** (-max(decimals, 2)) + 1e-9:
            warnings.append(f"{where}: column w_l: published {published:g} disagrees with "
                            f"track / wheelbase = {w / l:.3f}")

    out: dict[str, object] = {
        "name": v["name"], "category": v["category"], "source": v["source"], "units": units,
        "length_m": L, "width_m": B, "wheelbase_m": l, "front_overhang_m": a_f,
        "rear_overhang_m": a_r, "track_m": w, "steering": kind, "steered_axle": axle,
        "steering_ratio": schedule_text(ratio), "ackermann_pct": schedule_text(pct),
        "steering_range_rad": sw_range, "deadband_rad": deadband,
        "max_inner_steer_rad": inner, "max_outer_steer_rad": outer, "max_steer_rad": phi,
        "min_radius_m": rho, "max_steer_rate_rad_s": rate,
        "lock_given": ",".join(given),
        "vclass": v.get("vclass") or default_vclass(str(v["category"])),
    }
    for key in RACK_NAMES:
        out[f"{key}_m"] = f(key)
    for key, suffix in (("height", "_m"), ("ground_clearance", "_m"), ("approach_deg", ""),
                        ("departure_deg", ""), ("breakover_deg", ""),
                        ("ref_turning_radius", "_m"), ("ref_inside_radius", "_m"),
                        ("w_l", ""), ("grade_limit_pct", "")):
        out[key.replace("_deg", "_rad") + suffix] = f(key)
    c, alpha, delta, beta = (f(k) if k in v else None for k in UNDERSIDE_COLUMNS)
    out["underside_note"] = underside_from(c, alpha, delta, beta, l, a_f, a_r,
                                           str(out["vclass"])).note
    for key in ("hitch_offset_m", "trailer_wheelbase_m", "trailer_width_m",
                "trailer_front_overhang_m", "trailer_rear_overhang_m", "max_articulation_rad"):
        out[key] = trailer.get(key, math.nan)
    return out


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
