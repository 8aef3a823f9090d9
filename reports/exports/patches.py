"""Patches SUMO takes: netconvert plain-XML files that hand a study's findings back to SUMO.

Written per network under ``patches/`` by ``clearance report``, each a proposal for a designer
to check (its header comment says what it proposes and why):

``NET.fit.edg.xml`` and ``NET.fit.nod.xml``
    The lane widths and corner radii the study's vehicles need on the curves where they fail
    or cannot turn, only where the width or the corner is netconvert's default
    (:mod:`clearance.networks.provenance`): never narrowing a lane, never touching data.
    ``netconvert -s NET -e NET.fit.edg.xml -n NET.fit.nod.xml -o fitted.net.xml`` builds the
    fitted network, which a study judges again.
``NET.restrict.con.xml``
    For each connection where a vehicle fails or cannot turn, its SUMO class taken off that
    connection (the other classes keep what they had), so that SUMO and duarouter route that
    class around it: ``netconvert -s NET -x NET.restrict.con.xml -o restricted.net.xml``.
``NET.vtypes.xml``
    A ``vType`` per vehicle of the table (length, width, minGap, vClass, guiShape; the
    trailer as a carriage), loadable with ``sumo -a``.

How much room a vehicle needs
-----------------------------
A lane of the feature (a ring, a bend, a ramp) is made as wide as the vehicle's swept width
there and :data:`LANE_MARGIN_M` either side; an approach or exit lane as wide as the vehicle
and that margin either side, or its width plus the extra width the pavement needs at the
run's worst conflict (and the margin on the edge where that conflict lies). A failing
turn's computed junction (a turn of 30° or more, or a passage drawn tighter than the
vehicle's own minimum radius: a kink or a jog, which a larger junction spreads over a longer
internal lane) gets the radius of the vehicle's inside path through a 90° design turn at
full lock (:func:`clearance.analysis.design_turn.design_turn_inside_radius`) and the same
margin, rounded up to half a metre, and at most :data:`MAX_EDGE_SHARE` of the shortest road
edge meeting there (a larger junction swallows that edge and bends its neighbours' turns:
on Hamburg's bus lines 8.5 m corners without this cap made four passages next to them
fail). Widths are capped (:data:`MAX_FEATURE_WIDTH_M`, :data:`MAX_LANE_WIDTH_M`): beyond
them the fix is a redesign, not a wider default.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

from clearance.analysis.design_turn import design_turn_inside_radius
from clearance.networks.curves import Curve
from clearance.networks.model import ROAD_VCLASSES, Network
from clearance.networks.places import feature_ends, place_of
from clearance.networks.provenance import (
    CORNER_TURN_DEG,
    BuildHeader,
    corner_computed,
    feature_edges,
    lane_width_is_default,
    read_header,
)
from clearance.networks.sumo.placement import edge_of_lane, lane_index, shape_class
from clearance.reports.exports.sumo import sumo_id
from clearance.reports.output.atomic import write_text_atomic
from clearance.reports.results.records import RunRecord
from clearance.vehicles.table import VehicleTable
from clearance.vehicles.vehicle import Vehicle

__all__ = ["FAILING", "LANE_MARGIN_M", "MAX_EDGE_SHARE", "MAX_FEATURE_WIDTH_M",
           "MAX_LANE_WIDTH_M", "Fit", "fit_edges_xml", "fit_nodes_xml", "gui_shape",
           "inside_radii_m", "patch_names", "plan_fit", "restrict_xml", "vtypes_xml",
           "write_patches"]

#: The verdicts a patch answers.
FAILING = ("fails", "cannot-turn")

#: Room left either side of a vehicle in a fitted lane, and inside its path at a corner (m).
LANE_MARGIN_M = 0.5

#: The widest lane a fit proposes on a ring, a bend or a ramp, and elsewhere (m).
MAX_FEATURE_WIDTH_M = 7.0
MAX_LANE_WIDTH_M = 4.5

#: SUMO's ``minGap`` for every road class (m).
MIN_GAP_M = 2.5


@dataclass
class Fit:
    """One network's proposals: new lane widths and corner radii, and the classes to take off
    connections, each with the runs that ask for it."""

    #: lane id -> (proposed width, width now, runs asking)
    widths: dict[str, tuple[float, float, list[str]]] = field(default_factory=dict)
    #: junction id -> (proposed radius, runs asking)
    radii: dict[str, tuple[float, list[str]]] = field(default_factory=dict)
    #: (from edge, to edge, from lane index, to lane index) -> (classes allowed now, classes to
    #: take off, runs asking)
    restrict: dict[tuple[str, str, int, int], tuple[frozenset[str], set[str], list[str]]] = \
        field(default_factory=dict)

    def widen(self, lane: str, width_m: float, now_m: float, why: str) -> None:
        old = self.widths.get(lane)
        if old is None:
            self.widths[lane] = (width_m, now_m, [why])
        else:
            self.widths[lane] = (max(old[0], width_m), now_m, old[2] + [why])

    def round_corner(self, junction: str, radius_m: float, why: str) -> None:
        old = self.radii.get(junction)
        self.radii[junction] = ((max(old[0], radius_m), old[1] + [why]) if old
                                else (radius_m, [why]))


def _up(x: float, step: float) -> float:
    """``x`` rounded up to a multiple of ``step``.

    >>> _up(3.61, 0.1), _up(7.0, 0.5), _up(7.01, 0.5)
    (3.7, 7.0, 7.5)
    """
    return round(math.ceil(round(x / step, 6)) * step, 3)


def inside_radii_m(table: VehicleTable) -> dict[str, float]:
    """Each vehicle's inside radius through a 90° design turn at full lock (m), the whole
    vehicle (a trailer's inside path where it cuts in further)."""
    out = design_turn_inside_radius(table.frame, angle_deg=90.0)
    return dict(zip(table.names, out["inside_radius_m"].astype(float), strict=True))


#: A corner's radius takes at most this share of the shortest road edge meeting there: a
#: larger junction would swallow that edge and move its neighbours' turns.
MAX_EDGE_SHARE = 0.4


def _room_m(net: Network, junction: str) -> float:
    """The largest corner radius a junction has room for (m): :data:`MAX_EDGE_SHARE` of the
    shortest road edge that meets it, rounded down to half a metre."""
    lengths = [min((net.lane_line(k)[1] for k in e.lanes if k in net.lanes), default=math.inf)
               for e in net.edges.values()
               if junction in (e.from_junction, e.to_junction) and e.function == "normal"
               and any(k in net.lanes and net.lanes[k].allows_road_vehicles() for k in e.lanes)]
    shortest = min(lengths, default=math.inf)
    return math.floor(MAX_EDGE_SHARE * shortest * 2) / 2 if math.isfinite(shortest) else math.inf


def plan_fit(net: Network, curves: Mapping[str, Curve], records: Sequence[RunRecord],
             vehicles: Mapping[str, Vehicle], inside_m: Mapping[str, float],
             header: BuildHeader) -> Fit:
    """The fit and restrictions one network's failing runs ask for (see the module
    docstring)."""
    fit = Fit()
    for rec in records:
        curve = curves.get(rec.curve_id)
        if rec.verdict not in FAILING or curve is None or rec.vehicle not in vehicles:
            continue
        v = vehicles[rec.vehicle]
        why = f"{rec.vehicle} {rec.verdict} on {rec.curve_id}"
        _fit_widths(fit, net, curve, rec, v, header, why)
        if curve.kind == "turn" and (abs(curve.turn_angle_deg) >= CORNER_TURN_DEG
                                     or curve.min_radius_m < v.min_radius_m):
            j = net.junctions.get(curve.junction)
            r = inside_m.get(rec.vehicle, math.nan)
            if j is not None and corner_computed(j) and math.isfinite(r):
                need = min(_up(r + LANE_MARGIN_M, 0.5), _room_m(net, curve.junction))
                if need > header.corner_radius_m:
                    fit.round_corner(curve.junction, need, why)
        if curve.kind in ("turn", "uturn"):
            _restrict(fit, net, curve, v.vclass, why)
    return fit


def _fit_widths(fit: Fit, net: Network, curve: Curve, rec: RunRecord, v: Vehicle,
                header: BuildHeader, why: str) -> None:
    core = set(curve.core_lanes)
    swept = rec.swept_width_m if math.isfinite(rec.swept_width_m) else v.width_m
    place = place_of(net, curve, rec.overreach_station_m)
    conflict_edge = (net.lanes[place.lane].edge if place is not None
                     and place.part != "feature" and place.lane in net.lanes else "")
    for e in feature_edges(net, curve):
        for lane_id in net.edges[e].lanes:
            lane = net.lanes.get(lane_id)
            if lane is None or lane.allowed.isdisjoint(ROAD_VCLASSES) \
                    or not lane_width_is_default(lane, header):
                continue
            if lane_id in core:  # the feature's own lane holds the swept path
                need = min(swept + 2 * LANE_MARGIN_M, MAX_FEATURE_WIDTH_M)
            else:
                need = v.width_m + 2 * LANE_MARGIN_M
                if math.isfinite(rec.extra_width_m):  # the pavement's shortfall, and a margin
                    more = rec.extra_width_m + (LANE_MARGIN_M if e == conflict_edge else 0.0)
                    need = max(need, lane.width_m + more)
                need = min(need, MAX_LANE_WIDTH_M)
            need = _up(need, 0.1)
            if need > lane.width_m + 0.05:
                fit.widen(lane_id, need, lane.width_m, why)


def _restrict(fit: Fit, net: Network, curve: Curve, vclass: str, why: str) -> None:
    a, b = feature_ends(net, curve)
    if a is None or b is None:
        return
    key = (edge_of_lane(a), edge_of_lane(b), lane_index(a), lane_index(b))
    via = next((k for k in curve.core_lanes if k in net.lanes), None)
    allowed = net.lanes[via].allowed if via is not None else net.lanes[a].allowed
    if vclass not in allowed:
        return
    old = fit.restrict.get(key)
    if old is None:
        fit.restrict[key] = (allowed, {vclass}, [why])
    else:
        old[1].add(vclass)
        old[2].append(why)


def _header(what: str, network: str, why: str, apply: str) -> str:
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<!--\n  {what} for {network}, proposed '
            f"by clearance.\n  {why}\n  Apply: {apply}\n  A proposal for a designer to check "
            "against the street, not a survey.\n-->\n")


def _runs_comment(runs: list[str]) -> str:
    shown = "; ".join(dict.fromkeys(runs))
    return "<!-- " + shown.replace("--", "- -")[:600] + " -->"


def fit_edges_xml(fit: Fit, network: str, net_file: str) -> str:
    """``NET.fit.edg.xml``: the widened default lanes, by edge."""
    by_edge: dict[str, list[str]] = {}
    for lane_id in sorted(fit.widths):
        by_edge.setdefault(edge_of_lane(lane_id), []).append(lane_id)
    out = [_header("Lane widths", network,
                   "Default-width lanes (no width in the network) widened to what the "
                   "study's vehicles need where they fail or cannot turn; lanes whose width "
                   "is data are never touched, no lane is narrowed.",
                   f"netconvert -s {net_file} -e {network}.fit.edg.xml -n "
                   f"{network}.fit.nod.xml -o {network}.fitted.net.xml"), "<edges>\n"]
    for edge in sorted(by_edge):
        out.append(f"    <edge id={quoteattr(edge)}>\n")
        for lane_id in by_edge[edge]:
            width, now, runs = fit.widths[lane_id]
            out.append(f'        <lane index="{lane_index(lane_id)}" width="{width:.2f}"/> '
                       f"<!-- was {now:.2f} m (default) --> {_runs_comment(runs)}\n")
        out.append("    </edge>\n")
    out.append("</edges>\n")
    return "".join(out)


def fit_nodes_xml(fit: Fit, network: str, net_file: str) -> str:
    """``NET.fit.nod.xml``: the computed corners given the radius the vehicles need."""
    out = [_header("Corner radii", network,
                   "Junctions whose corners netconvert computed (no customShape, no radius) "
                   "given the radius of the failing vehicle's inside path through a 90 degree "
                   "turn plus a margin; junctions drawn by hand are never touched.",
                   f"netconvert -s {net_file} -e {network}.fit.edg.xml -n "
                   f"{network}.fit.nod.xml -o {network}.fitted.net.xml"), "<nodes>\n"]
    for j in sorted(fit.radii):
        radius, runs = fit.radii[j]
        out.append(f'    <node id={quoteattr(j)} radius="{radius:.1f}"/> '
                   f"{_runs_comment(runs)}\n")
    out.append("</nodes>\n")
    return "".join(out)


def restrict_xml(fit: Fit, network: str, net_file: str) -> str:
    """``NET.restrict.con.xml``: each failing connection allowing what it did less the
    failing vehicles' classes."""
    out = [_header("Connection restrictions", network,
                   "Each connection where a vehicle of the study fails or cannot turn no "
                   "longer admits that vehicle's SUMO class (the other classes keep it), so "
                   "that SUMO's routing and duarouter route the class around it.",
                   f"netconvert -s {net_file} -x {network}.restrict.con.xml -o "
                   f"{network}.restricted.net.xml"), "<connections>\n"]
    for (a, b, i, k), (allowed, off, runs) in sorted(fit.restrict.items()):
        keep = " ".join(sorted(allowed - off))
        # a bus lane's connection closed to buses admits nothing: netconvert refuses an
        # empty allow, and takes disallow="all"
        perm = f"allow={quoteattr(keep)}" if keep else 'disallow="all"'
        out.append(f"    <connection from={quoteattr(a)} to={quoteattr(b)} fromLane=\"{i}\" "
                   f"toLane=\"{k}\" {perm}/> <!-- off: "
                   f"{' '.join(sorted(off))} --> {_runs_comment(runs)}\n")
    out.append("</connections>\n")
    return "".join(out)


def gui_shape(v: Vehicle) -> str:
    """sumo-gui's shape of a vehicle: its class's, an articulated one drawn with its
    trailer.

    >>> gui_shape(Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5))
    'passenger'
    """
    base = shape_class(v.category)
    if v.trailer is None:
        return base
    if base == "bus":
        return "bus/flexible"
    return "truck/semitrailer" if "semi" in v.category.lower() else "truck/trailer"


def vtypes_xml(table: VehicleTable) -> str:
    """``NET.vtypes.xml``: one ``vType`` per vehicle, ids made SUMO-safe
    (:func:`~clearance.reports.exports.sumo.sumo_id`), the table's name kept as a parameter.

    An articulated vehicle is one SUMO vehicle of its overall length drawn in two carriages:
    the towing unit (``locomotiveLength``) and the trailer (``carriageLength``), with the gap
    between their bodies (``carriageGap``, 0 where they overlap).
    """
    out = [_header("Vehicle types", "the study's vehicle table",
                   "One vType per vehicle of the table: its length, width, SUMO class and "
                   "shape.", "sumo -n NET -a vtypes.xml (or list it in a configuration's "
                   "additional-files)"), "<additional>\n"]
    for v in table.vehicles():
        attrs = {"id": sumo_id(v.name), "vClass": v.vclass, "length": f"{v.overall_length_m:.2f}",
                 "width": f"{v.width_m:.2f}", "minGap": f"{MIN_GAP_M:.2f}",
                 "guiShape": gui_shape(v)}
        if v.height_m is not None:
            attrs["height"] = f"{v.height_m:.2f}"
        if v.trailer is not None:
            trailer = v.trailer.length_m
            gap = max(0.0, v.overall_length_m - v.length_m - trailer)
            attrs.update(locomotiveLength=f"{v.overall_length_m - trailer - gap:.2f}",
                         carriageLength=f"{trailer:.2f}", carriageGap=f"{gap:.2f}")
        text = " ".join(f"{k}={quoteattr(x)}" for k, x in attrs.items())
        out.append(f"    <vType {text}>\n        <param key=\"clearance.name\" "
                   f"value={quoteattr(v.name)}/>\n    </vType>\n")
    out.append("</additional>\n")
    return "".join(out)


def patch_names(network: str) -> dict[str, str]:
    """The patch files of a network under ``patches/``."""
    return {"edges": f"{network}.fit.edg.xml", "nodes": f"{network}.fit.nod.xml",
            "restrict": f"{network}.restrict.con.xml", "vtypes": f"{network}.vtypes.xml"}


def write_patches(folder: Path, network: str, net: Network, curves: Sequence[Curve],
                  records: Sequence[RunRecord], table: VehicleTable) -> dict[str, Path]:
    """Write one network's patches under ``folder`` (see the module docstring); their
    paths by kind."""
    folder.mkdir(parents=True, exist_ok=True)
    header = read_header(net.path)
    vehicles = {v.name: v for v in table.vehicles()}
    fit = plan_fit(net, {c.curve_id: c for c in curves}, records, vehicles,
                   inside_radii_m(table), header)
    names = patch_names(network)
    net_file = Path(net.path).name
    texts = {"edges": fit_edges_xml(fit, network, net_file),
             "nodes": fit_nodes_xml(fit, network, net_file),
             "restrict": restrict_xml(fit, network, net_file), "vtypes": vtypes_xml(table)}
    out = {}
    for kind, text in texts.items():
        out[kind] = folder / names[kind]
        write_text_atomic(out[kind], text)
    return out
