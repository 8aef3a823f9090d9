"""Routes as SUMO users have them: route, vehicle, flow and trip files, read for a study.

A route study (``--routes FILE``) needs each selected route's edges and who drives it: the
vehicle or flow's type, that type's SUMO class and the ``line``. The files are read as
SUMO reads them:

- ``<route id edges>`` at the top level, used by ``<vehicle route=…>`` and
  ``<flow route=…>`` or standing alone;
- ``<vehicle>`` and ``<flow>`` with a nested ``<route edges=…>``;
- ``<routeDistribution>`` with nested routes (or ``refId``), named by a vehicle's
  ``route``;
- ``<trip>``, and ``<vehicle>``/``<flow>`` with ``from``/``to``/``via``: routed by SUMO's
  own router, duarouter, for the type's class (:func:`route_trips`), never by ours;
- ``<vType id vClass>`` in any of the files and in additional files (``--additional``), as
  SUMO takes them; a vehicle without a type drives SUMO's ``DEFAULT_VEHTYPE``
  (passenger).

``<stop busStop=…>`` names a place defined in files the user may not have given; the
route's edges are what the study needs, so the stopping places no file given defines are
one warning, not an error. Every route is checked
against the network as SUMO checks it: an edge the network does not have
(``The edge 'x' within the route … is not known``), and two consecutive edges with no
connection (``No connection between edge 'a' and edge 'b' found.``), each a
:class:`~clearance.vehicles.errors.RouteError` naming the file and the route.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import os
import subprocess
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lxml import etree

from clearance.networks.model import Network
from clearance.networks.safe_xml import open_binary, scan_prolog
from clearance.networks.sumo.tools import find_sumo_binary, sumo_home
from clearance.vehicles.errors import RouteError

log = logging.getLogger(__name__)

__all__ = ["DEFAULT_TYPES", "STOP_PLACES", "VCLASS_SIZES", "Route", "RouteSelection",
           "check_routes", "read_routes", "route_trips", "select_routes"]

#: SUMO's built-in vehicle types and their classes (a vehicle without ``type`` drives the
#: first).
DEFAULT_TYPES = {"DEFAULT_VEHTYPE": "passenger", "DEFAULT_BIKETYPE": "bicycle",
                 "DEFAULT_TAXITYPE": "taxi", "DEFAULT_RAILTYPE": "rail",
                 "DEFAULT_CONTAINERTYPE": "ignoring", "DEFAULT_PEDTYPE": "pedestrian"}


#: SUMO's default length and width of a vehicle type by class (m; SUMO's "Vehicle Type
#: Parameter Defaults"); any other class: the passenger car's.
VCLASS_SIZES = {"passenger": (5.0, 1.8), "taxi": (5.0, 1.8), "bus": (12.0, 2.5),
                "coach": (14.0, 2.6), "truck": (7.1, 2.4), "trailer": (16.5, 2.55),
                "delivery": (6.5, 2.16), "emergency": (6.5, 2.16)}


@dataclass(frozen=True)
class Route:
    """One route of a study: its edges and who drives it.

    ``route_id`` is the vehicle's or flow's id when its route is its own (nested, or a
    trip routed by duarouter), the ``<route>``'s id when a vehicle or flow names it or
    it stands alone. ``vtype``, ``vclass`` and ``line`` are those of its first user (empty
    for a route no vehicle uses); ``users`` lists every vehicle or flow id that drives it.
    """

    route_id: str
    edges: tuple[str, ...]
    vtype: str
    vclass: str
    line: str
    file: str
    users: tuple[str, ...] = ()
    #: The type's length and width (m): its ``length``/``width``, or SUMO's defaults for its
    #: class (:data:`VCLASS_SIZES`); NaN for a route no vehicle uses.
    size_m: tuple[float, float] = (math.nan, math.nan)


@dataclass(frozen=True)
class RouteSelection:
    """``--route-vclass``, ``--line`` and ``--route-id`` (each repeatable; empty: any)."""

    vclasses: tuple[str, ...] = ()
    lines: tuple[str, ...] = ()
    route_ids: tuple[str, ...] = ()

    @property
    def is_empty(self) -> bool:
        return not (self.vclasses or self.lines or self.route_ids)

    def describe(self) -> str:
        parts = [f"--route-vclass {v}" for v in self.vclasses]
        parts += [f"--line {v}" for v in self.lines]
        parts += [f"--route-id {v}" for v in self.route_ids]
        return " ".join(parts) or "every route"


class _Files:
    """What the files define, as they are read: types, named routes, distributions."""

    def __init__(self) -> None:
        self.vtypes: dict[str, str] = dict(DEFAULT_TYPES)
        self.sizes: dict[str, tuple[float, float]] = {}  # type id -> length, width (m)
        self.routes: dict[str, tuple[tuple[str, ...], str]] = {}  # id -> edges, file
        self.dists: dict[str, list[str]] = {}  # distribution id -> its route ids
        self.users: list[tuple[str, str, dict[str, str], tuple[str, ...] | None, str]] = []
        self.used: set[str] = set()
        self.places: set[str] = set()  # stopping places the files define
        self.stops: dict[str, str] = {}  # a stopping place a <stop> names -> its file


#: The attributes of ``<stop>`` that name a stopping place, and the elements defining one.
STOP_PLACES = ("busStop", "trainStop", "containerStop", "chargingStation", "parkingArea")


def _parse(path: Path) -> Any:
    """The file's element tree, after :func:`~clearance.networks.safe_xml.scan_prolog`
    (no entity declarations) with no network access and no DTD."""
    scan_prolog(path, error=RouteError)
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False,
                             remove_comments=True, huge_tree=False)
    try:
        with open_binary(path, error=RouteError) as fh:
            return etree.parse(fh, parser).getroot()
    except etree.XMLSyntaxError as exc:
        raise RouteError(f"malformed XML ({exc})", file=path) from None


def _edges(el: Any, path: Path, owner: str) -> tuple[str, ...]:
    text = el.get("edges")
    if text is None or not text.split():
        raise RouteError(f"{owner}: a <route> without edges", file=path, element=owner)
    return tuple(text.split())


def _size(el: Any, path: Path) -> tuple[float, float]:
    """A vType's length and width: its own, or its class's defaults."""
    length, width = VCLASS_SIZES.get(el.get("vClass", "passenger"), VCLASS_SIZES["passenger"])
    try:
        return float(el.get("length", length)), float(el.get("width", width))
    except ValueError:
        where = f"vType {el.get('id')!r}"
        raise RouteError(f"{where}: length or width is not a number", file=path,
                         element=where) from None


def _read_one(path: Path, files: _Files, routes_allowed: bool) -> None:
    root = _parse(path)
    for el in root.iter(etree.Element):
        tag = el.tag
        if tag in STOP_PLACES and el.get("id"):
            files.places.add(el.get("id"))
        elif tag == "stop":
            for a in STOP_PLACES:
                if el.get(a):
                    files.stops.setdefault(el.get(a), str(path))
        if tag == "vType" and el.get("id"):
            files.vtypes[el.get("id")] = el.get("vClass", "passenger")
            files.sizes[el.get("id")] = _size(el, path)
        elif not routes_allowed:
            continue
        elif tag == "route" and el.get("id") and el.getparent() is root:
            files.routes[el.get("id")] = (_edges(el, path, f"route {el.get('id')!r}"),
                                          str(path))
        elif tag == "routeDistribution" and el.get("id"):
            ids = []
            for k, r in enumerate(el.iter("route")):
                rid = r.get("refId") or r.get("id") or f"{el.get('id')}#{k}"
                if r.get("edges"):
                    files.routes[rid] = (_edges(r, path, f"route {rid!r}"), str(path))
                ids.append(rid)
            files.dists[el.get("id")] = ids
        elif tag in ("vehicle", "flow", "trip"):
            vid = el.get("id", "")
            nested = el.find("route")
            own = (_edges(nested, path, f"{tag} {vid!r}") if nested is not None
                   else None)
            files.users.append((tag, vid, dict(el.attrib), own, str(path)))


def read_routes(paths: Sequence[str | os.PathLike[str]],
                additional: Sequence[str | os.PathLike[str]] = (),
                net_path: str | os.PathLike[str] | None = None) -> list[Route]:
    """Every route of ``paths`` (route files, plain or gzip), with the types of ``paths``
    and ``additional`` (read as SUMO reads them; see the module docstring). Trips are
    routed by duarouter on ``net_path`` (:func:`route_trips`).

    Raises
    ------
    RouteError
        Malformed XML, a route without edges, a vehicle naming a route or type no file
        defines, a trip duarouter cannot route (in its words).
    """
    files = _Files()
    for p in additional:
        _read_one(Path(p), files, routes_allowed=True)
    for p in paths:
        _read_one(Path(p), files, routes_allowed=True)
    unknown = sorted(set(files.stops) - files.places)
    if unknown:
        log.warning("%s: %d stopping place(s) the files given do not define (%s%s); stops are "
                    "not needed: the routes' edges are studied", files.stops[unknown[0]],
                    len(unknown), ", ".join(unknown[:5]), ", ..." if len(unknown) > 5 else "")
    out: dict[str, Route] = {}
    trips: list[tuple[str, dict[str, str], str]] = []
    for tag, vid, attrib, own, file in files.users:
        vtype = attrib.get("type", "DEFAULT_VEHTYPE")
        if vtype not in files.vtypes:
            raise RouteError(f"{tag} {vid!r}: type {vtype!r} is not defined in any file given "
                             "(--routes, --additional)", file=file, element=f"{tag} {vid!r}")
        vclass, line = files.vtypes[vtype], attrib.get("line", "")
        size = files.sizes.get(vtype) or VCLASS_SIZES.get(vclass, VCLASS_SIZES["passenger"])
        if own is not None:
            _add(out, Route(vid, own, vtype, vclass, line, file, (vid,), size))
        elif attrib.get("route"):
            for rid in files.dists.get(attrib["route"], [attrib["route"]]):
                if rid not in files.routes:
                    raise RouteError(f"{tag} {vid!r}: route {rid!r} is not defined in any "
                                     "file given", file=file, element=f"{tag} {vid!r}")
                files.used.add(rid)
                edges, rfile = files.routes[rid]
                _add(out, Route(rid, edges, vtype, vclass, line, rfile, (vid,), size))
        elif attrib.get("from") or attrib.get("fromJunction"):
            trips.append((vid, attrib, file))
        else:
            raise RouteError(f"{tag} {vid!r}: no route (give route=, a nested <route> or "
                             "from/to)", file=file, element=f"{tag} {vid!r}")
    for rid, (edges, rfile) in files.routes.items():
        if rid not in files.used and rid not in out and not any(
                rid in ids for ids in files.dists.values()):
            out[rid] = Route(rid, edges, "", "", "", rfile)
    if trips:
        if net_path is None:
            raise RouteError(f"trips ({', '.join(v for v, _, _ in trips[:3])}) need the "
                             "network to be routed", file=trips[0][2])
        for route in route_trips(trips, files.vtypes, net_path):
            _add(out, dataclasses.replace(route, size_m=files.sizes.get(route.vtype) or
                                          VCLASS_SIZES.get(route.vclass,
                                                           VCLASS_SIZES["passenger"])))
    return list(out.values())


def _add(out: dict[str, Route], route: Route) -> None:
    """``route`` into ``out`` by id; a route driven by several vehicles keeps them all."""
    old = out.get(route.route_id)
    if old is None:
        out[route.route_id] = route
    else:
        out[route.route_id] = Route(old.route_id, old.edges, old.vtype or route.vtype,
                                    old.vclass or route.vclass, old.line or route.line,
                                    old.file, old.users + route.users,
                                    old.size_m if old.vtype else route.size_m)


def route_trips(trips: Sequence[tuple[str, dict[str, str], str]], vtypes: dict[str, str],
                net_path: str | os.PathLike[str]) -> list[Route]:
    """Routes for trips (``from``/``to``/``via``) by SUMO's duarouter on ``net_path``, each
    for its type's class; a trip it cannot route is a RouteError in duarouter's words."""
    root = etree.Element("routes")
    for tid, vclass in vtypes.items():
        if tid not in DEFAULT_TYPES:
            etree.SubElement(root, "vType", id=tid, vClass=vclass)
    keep = ("id", "type", "from", "to", "via", "fromJunction", "toJunction", "depart")
    for k, (_, attrib, _) in enumerate(trips):
        trip = {a: attrib[a] for a in keep if a in attrib}
        trip.setdefault("depart", "0")
        trip["id"] = f"t{k}"
        etree.SubElement(root, "trip", attrib=trip)
    with tempfile.TemporaryDirectory(prefix="clearance-trips-") as tmp:
        src, dst = Path(tmp) / "trips.rou.xml", Path(tmp) / "routed.rou.xml"
        etree.ElementTree(root).write(str(src), xml_declaration=True, encoding="UTF-8")
        proc = subprocess.run(
            [str(find_sumo_binary("duarouter")), "-n", os.fspath(net_path), "--route-files",
             str(src), "-o", str(dst), "--no-step-log", "true", "--ignore-errors", "false"],
            capture_output=True, text=True, timeout=600,
            env={**os.environ, "SUMO_HOME": str(sumo_home())})
        if proc.returncode != 0:
            said = " ".join(ln.strip() for ln in proc.stderr.splitlines()
                            if ln.startswith("Error")) or proc.stderr.strip()[-500:]
            for k, (vid, _, _) in enumerate(trips):
                said = said.replace(f"'t{k}'", repr(vid))
            raise RouteError(f"duarouter cannot route the trips: {said[:500]}",
                             file=trips[0][2])
        routed = {el.get("id"): el for el in etree.parse(str(dst)).getroot()}
    out = []
    for k, (vid, attrib, file) in enumerate(trips):
        el = routed.get(f"t{k}")
        route = el.find("route") if el is not None else None
        if route is None:
            said = " ".join(ln.strip() for ln in proc.stderr.splitlines()
                            if f"'t{k}'" in ln).replace(f"'t{k}'", repr(vid))
            raise RouteError(f"trip {vid!r}: duarouter found no route ({said or 'no reason'})",
                             file=file, element=f"trip {vid!r}")
        vtype = attrib.get("type", "DEFAULT_VEHTYPE")
        out.append(Route(vid, tuple(route.get("edges", "").split()), vtype, vtypes[vtype],
                         attrib.get("line", ""), file, (vid,)))
    return out


def check_routes(routes: Iterable[Route], net: Network) -> None:
    """Every edge of every route is the network's, and each two consecutive edges are
    connected, as SUMO checks a route (its words in the message).

    Raises
    ------
    RouteError
        Naming the file, the route and the edge(s).
    """
    linked = {(c.from_edge, c.to_edge) for c in net.connections}
    for r in routes:
        where = f"route {r.route_id!r}"
        for e in r.edges:
            if e not in net.edges:
                raise RouteError(f"{where}: the edge {e!r} within the route is not known "
                                 f"(network {net.path})", file=r.file, element=where)
        for a, b in zip(r.edges, r.edges[1:], strict=False):
            if (a, b) not in linked:
                raise RouteError(f"{where}: No connection between edge {a!r} and edge {b!r} "
                                 "found.", file=r.file, element=where)


def select_routes(routes: Sequence[Route], selection: RouteSelection) -> list[Route]:
    """The routes of ``selection``; none matching is a RouteError (nothing to study)."""
    chosen = [r for r in routes
              if (not selection.vclasses or r.vclass in selection.vclasses)
              and (not selection.lines or r.line in selection.lines)
              and (not selection.route_ids or r.route_id in selection.route_ids
                   or set(r.users) & set(selection.route_ids))]
    if not chosen:
        raise RouteError(f"no route matches the selection ({selection.describe()}; "
                         f"{len(routes)} route(s) in the files)")
    return chosen
