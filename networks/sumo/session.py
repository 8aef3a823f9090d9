"""The libsumo session of a drive: SUMO is the stage every run is placed on, step by step.

:func:`clearance.networks.driving.drive.drive` computes where each vehicle is with its
kinematic model; a :class:`SumoSession` adds every run to one libsumo simulation as a
vehicle of its own vType, places it at every SUMO step with ``vehicle.moveToXY`` and reads
SUMO's position back. This is the only module that imports libsumo.

vTypes
------
One vType per vehicle model: length (the towing unit's body), width, height, a shape class
by category (:func:`shape_class`), and our geometry as parameters (:func:`vtype_parameters`:
wheelbase, overhangs, track, steering lock and rate, steered axle, trailer dimensions).
Its action step length is a day (:data:`NO_DECISIONS_S`): SUMO's driver model never acts on
a vehicle the model places.

Trailers
--------
A SUMO vehicle is one rigid body, so an articulated vehicle is shown as two SUMO vehicles:
the towing unit ``<id>`` (its vType carries the trailer's dimensions as parameters) and the
trailer ``<id>.trailer``, a vehicle of its own vType (the trailer body: hitch-to-rear
length, width) placed at the model's trailer front (the kingpin plus the trailer's front
overhang) and heading. SUMO knows nothing of the coupling; both positions come from the
model and both are checked.

Which path
----------
:func:`drive` runs a session in one of two places. Without FCD output, during the lane pass:
each run is placed along its lane's centre line (:attr:`DrivenRun.run`), the model computed a
batch ahead. With FCD output, after the swing pass (``chosen=True``): each run is placed along
the path its verdict rests on (:attr:`DrivenRun.chosen_run`: the swung path where one was
taken, the lane's otherwise), so that the replay shows the swing the verdict describes. The
edge and lane hints of a swung path's placements are those of the centre line where its
front-bumper centre is nearest (:func:`~clearance.networks.sumo.placement.centre_stations`).

Replay in sumo-gui
-----------------
With ``DriveOptions(fcd_output=...)`` (``clearance simulate --fcd``) SUMO writes its FCD
output (every vehicle's front-bumper centre and angle at every step; a run's vehicle id is
:attr:`DrivenRun.sumo_vehicle`). SUMO's
``tools/fcdReplay.py`` plays it back in sumo-gui (as moving points of interest) over the
network named in a SUMO configuration (:func:`replay_config` writes one)::

    python "$SUMO_HOME/tools/fcdReplay.py" -k replay.sumocfg -f fcd.xml

(``SUMO_HOME`` is ``python -c "import sumo; print(sumo.SUMO_HOME)"``). Time in the FCD is
the replay's: runs follow each other through the batch slots, and a run's last step,
shortened by the model to land on the curve's end, takes a whole SUMO step.

Errors
------
A SUMO error while placing one vehicle (``libsumo.TraCIException``) fails that run only: it
is removed and recorded with the reason (:attr:`DrivenRun.error`); the others go on. An
error in a simulation step, or a ``FatalTraCIError``, fails the runs then in flight; SUMO is
restarted for the runs still queued (at most :attr:`DriveOptions.max_restarts` times).
libsumo runs one simulation per process; :func:`drive` always closes it.

A SUMO vehicle is added only from the first sample that lies on the curve's own lanes (a
trailer behind the centre line's start joins later): libsumo 1.28 crashes (segmentation
fault) writing FCD output for a vehicle whose first placement is off every lane. Never call
``vehicle.getRoadID`` on a placed vehicle: it crashes for one off every lane.

The libsumo-free helpers (vType parameters, lane hints, placement points, the replay
configuration) are in :mod:`clearance.networks.sumo.placement`.
"""

from __future__ import annotations

import logging
import math
import os
import sys
import tempfile
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from itertools import repeat

import numpy as np

from clearance.analysis.polyline import Path
from clearance.analysis.tracking import TrackingRun, TrackingSettings
from clearance.networks.curves import Curve
from clearance.networks.driving.runs import DrivenRun, DriveOptions, DriveStats
from clearance.networks.geometry import heading_rad_to_navigational
from clearance.networks.sumo.placement import (
    centre_stations,
    edge_of_lane,
    first_on,
    front_bumper,
    lane_boundaries_m,
    lane_index,
    route_edges,
    shape_class,
    trailer_front,
    vtype_parameters,
)
from clearance.vehicles.errors import ClearanceError, NetworkError
from clearance.vehicles.vehicle import Vehicle

__all__ = ["NO_DECISIONS_S", "SumoSession"]

log = logging.getLogger(__name__)

NO_DECISIONS_S = 86400.0
"""Action step length of our vTypes (s): SUMO's driver model decides once, when a vehicle
is added, and never again during a run. The model places every vehicle at every step, so
SUMO's car-following and lane-change decisions would be computed only to be overridden;
skipping them makes a SUMO step about five times cheaper."""



@dataclass
class _Unit:
    """One SUMO vehicle of a run (the towing unit, or the trailer), sample by sample.

    ``start`` is the first sample whose point lies on the curve's own lanes: the vehicle is
    added to SUMO and placed from then on, never before (libsumo 1.28 crashes writing FCD
    output for a vehicle whose first placement is off every lane). The samples are plain
    Python lists, ``moves`` the ready argument tuples of ``vehicle.moveToXY`` (vehicle,
    edge hint, lane hint, x, y, angle, keepRoute 2, match threshold): the loop passes them
    to libsumo one by one.
    """

    vid: str
    vtype: str
    x: list[float]
    y: list[float]
    start: int
    moves: list[tuple]
    added: bool = False


@dataclass
class _Plan:
    """Everything the SUMO loop needs of one run (``run``: the model's run it places)."""

    index: int
    route: str
    units: list[_Unit]
    n: int
    samples: np.ndarray
    run: TrackingRun
    k: int = 0
    max_dev: float = 0.0

    @property
    def vid(self) -> str:
        return self.units[0].vid


def _start_sumo(traci, cmd: list[str], net_path: str) -> None:  # noqa: ANN001 - libsumo
    """``traci.start(cmd)``; SUMO's refusal (a network it cannot load) is an
    :class:`InputError` in SUMO's words.

    libsumo's exception says only "Process Error": SUMO writes why to the standard error
    stream (not to its ``--error-log``), so that stream is caught while SUMO starts and
    passed on unchanged when it starts.
    """
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as caught:
        os.dup2(caught.fileno(), 2)
        try:
            traci.start(cmd)
        except traci.TraCIException as exc:
            os.dup2(saved, 2)
            caught.seek(0)
            lines = caught.read().decode(errors="replace").splitlines()
            said = " ".join(ln.strip() for ln in lines if ln.startswith("Error:")) or str(exc)
            raise NetworkError(f"{net_path}: SUMO cannot load the network: {said[:500]}") from None
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        caught.seek(0)
        if text := caught.read():
            os.write(2, text)


class SumoSession:
    """The libsumo side of :func:`drive`: vTypes, routes, placements, checks, errors.

    ``chosen``: place each run along its chosen path (:attr:`DrivenRun.chosen_run`, after
    the swing pass) instead of its lane's (:attr:`DrivenRun.run`).
    """

    def __init__(self, net_path, out: list[DrivenRun], paths: dict[str, Path],
                 settings: TrackingSettings, options: DriveOptions,
                 lane_ends: dict[str, np.ndarray], stats: DriveStats,
                 chosen: bool = False) -> None:
        self.stats = stats
        self.chosen = chosen
        self.net_path = str(net_path)
        self.out = out
        self.paths = paths
        self.settings = settings
        self.options = options
        self.lane_ends = lane_ends
        self.every = options.samples_per_step(settings.dt_s)
        self.traci = _import_libsumo()
        self.vtypes: dict[str, str] = {}
        self.routes: dict[str, str] = {}
        self.free_routes: set[str] = set()
        self.bounds: dict[str, np.ndarray] = {}
        self.restarts = 0

    # -- lifecycle
    def _start(self) -> None:
        cmd = ["sumo", "-n", self.net_path, "--no-step-log", "true", "--no-warnings", "true",
               "--collision.action", "none", "--time-to-teleport", "-1",
               "--step-length", repr(self.every * self.settings.dt_s)]
        if self.options.fcd_output is not None:
            cmd += ["--fcd-output", os.fspath(self.options.fcd_output),
                    "--fcd-output.attributes", "x,y,z,angle,type,speed"]
        _start_sumo(self.traci, cmd, self.net_path)
        self.move_to_xy = self.traci.vehicle.moveToXY
        self.get_position = self.traci.vehicle.getPosition
        self.vtypes.clear()
        self.routes.clear()
        self.free_routes.clear()

    def run(self, batches: Iterator[list[int]]) -> None:
        """Drive every run the batches yield (the model computed a batch ahead)."""
        pending: deque[int] = deque()
        active: dict[int, _Plan] = {}
        source = iter(batches)
        self._start()
        try:
            self._loop(source, pending, active)
        except _GiveUp as exc:
            reason = f"not driven: {exc} (SUMO restarted {self.options.max_restarts} times)"
            for i in pending:
                self._fail(i, f"v{i}", reason, 0, math.nan, remove=False)
            for idx in source:  # the model still runs; SUMO does not
                for i in idx:
                    self._fail(i, f"v{i}", reason, 0, math.nan, remove=False)
        finally:
            try:
                self.traci.close()
            except Exception:  # noqa: BLE001 - closing a dead simulation must not mask
                pass

    def _loop(self, source: Iterator[list[int]], pending: deque[int],
              active: dict[int, _Plan]) -> None:
        """Fill the free slots, place everyone, step, check; until nothing is left.

        Every iteration advances each run in flight by one sample or ends it, and a run
        has at most the model's step cap of samples, so the loop ends.
        """
        t = self.traci
        exhausted = False
        while True:
            while len(active) < self.options.batch_size:
                if not pending and not exhausted:
                    nxt = next(source, None)
                    if nxt is None:
                        exhausted = True
                    else:
                        pending.extend(nxt)
                if not pending:
                    break
                i = pending.popleft()
                plan = self._add(i)
                if plan is not None:
                    active[i] = plan
            if not active:
                return
            self._place_all(active)
            try:
                self.stats.sumo_steps += 1
                t.simulationStep()
            except (t.TraCIException, t.FatalTraCIError) as exc:
                self._step_failed(active, exc)
                active.clear()
                continue
            self._check_all(active)

    def _step_failed(self, active: dict[int, _Plan], exc: Exception) -> None:
        t = self.traci
        reason = f"SUMO simulation step failed: {exc}"
        for plan in active.values():
            d = self.out[plan.index]
            why = f"{reason} (with {len(active)} vehicles in flight)"
            d.error = f"{d.error}; {why}" if d.error else why
            d.sumo_steps = plan.k
            d.sumo_max_deviation_m = plan.max_dev
            log.warning("%s x %s: %s", d.vehicle.name, d.curve.curve_id, d.error)
        try:
            t.close()
        except Exception:  # noqa: BLE001
            pass
        self.restarts += 1
        if self.restarts > self.options.max_restarts:
            raise _GiveUp(reason)
        self._start()

    # -- one run
    def _vtype(self, v: Vehicle) -> tuple[str, str | None]:
        t = self.traci
        key = v.name
        if key not in self.vtypes:
            tid = f"vt{len(self.vtypes)}"
            t.vehicletype.copy("DEFAULT_VEHTYPE", tid)
            t.vehicletype.setLength(tid, v.length_m)
            t.vehicletype.setWidth(tid, v.width_m)
            if v.height_m is not None and math.isfinite(v.height_m):
                t.vehicletype.setHeight(tid, v.height_m)
            t.vehicletype.setShapeClass(tid, shape_class(v.category))
            t.vehicletype.setVehicleClass(tid, v.vclass)
            t.vehicletype.setParameter(tid, "model", v.name)
            t.vehicletype.setActionStepLength(tid, NO_DECISIONS_S, True)
            for k, val in vtype_parameters(v).items():
                t.vehicletype.setParameter(tid, k, val)
            if v.trailer is not None:
                tt = f"{tid}.trailer"
                t.vehicletype.copy("DEFAULT_VEHTYPE", tt)
                t.vehicletype.setLength(tt, v.trailer.length_m)
                t.vehicletype.setWidth(tt, v.trailer.width_m)
                if v.height_m is not None and math.isfinite(v.height_m):
                    t.vehicletype.setHeight(tt, v.height_m)
                t.vehicletype.setShapeClass(tt, "truck")
                # the whole combination is of the vehicle's class: a trailer of the
                # passenger class SUMO would not place on a bus lane (the articulated bus)
                t.vehicletype.setVehicleClass(tt, v.vclass)
                t.vehicletype.setParameter(tt, "model", f"{v.name} (trailer)")
                t.vehicletype.setActionStepLength(tt, NO_DECISIONS_S, True)
            self.vtypes[key] = tid
        tid = self.vtypes[key]
        return tid, (f"{tid}.trailer" if v.trailer is not None else None)

    def _route(self, curve: Curve) -> str:
        if curve.curve_id not in self.routes:
            rid = f"r{len(self.routes)}"
            # Only the first edge: the vehicle is placed with keepRoute=2, which follows it
            # onto the next edges; a whole route would need SUMO to see every edge pair
            # connected for this vehicle, which real networks do not always do.
            self.traci.route.add(rid, route_edges(curve))
            self.routes[curve.curve_id] = rid
        return self.routes[curve.curve_id]

    def _hints(self, curve: Curve, stations: np.ndarray) -> tuple[list[str], list[int]]:
        lanes = curve.lanes
        if curve.curve_id not in self.bounds:
            ends = [self.lane_ends.get(k) for k in lanes]
            known = [e for e in ends if e is not None]
            if len(known) < len(ends):
                self.bounds[curve.curve_id] = np.full(len(lanes) - 1, np.inf)
            else:
                self.bounds[curve.curve_id] = lane_boundaries_m(
                    curve, self.paths[curve.curve_id], known)
        which = np.searchsorted(self.bounds[curve.curve_id], stations, side="right").tolist()
        edge_names = [edge_of_lane(k) for k in lanes]
        indices = [lane_index(k) for k in lanes]
        return [edge_names[w] for w in which], [indices[w] for w in which]

    def _stations(self, d: DrivenRun, run: TrackingRun, x: np.ndarray, y: np.ndarray,
                  at: np.ndarray) -> np.ndarray:
        """The centre line's stations of the front-bumper centres ``(x, y)`` of samples
        ``at`` (where the edge and lane hints are looked up): on the lane's run, its own
        stations ahead by the front overhang; on a swung path, the nearest."""
        along = run.trajectory.s_m[at] + d.vehicle.front_overhang_m
        if run is d.run:
            return along
        return centre_stations(self.paths[d.curve.curve_id], run.path, x, y, along)

    def _add(self, i: int) -> _Plan | None:
        d = self.out[i]
        run = d.chosen_run if self.chosen else d.run
        assert run is not None
        vid = f"v{i}"
        d.sumo_vehicle = vid
        try:
            tid, ttid = self._vtype(d.vehicle)
            rid = self._route(d.curve)
        except self.traci.TraCIException as exc:
            self._fail(i, vid, f"SUMO refused the vehicle type or route: {exc}", 0, 0.0,
                       remove=False)
            return None
        own = d.curve.own_lanes
        # the model's samples SUMO shows: one per SUMO step, and the last
        n = len(run.trajectory.t_s)
        at = np.arange(0, n, self.every)
        if at[-1] != n - 1:
            at = np.append(at, n - 1)
        x, y = (c[at] for c in front_bumper(run))
        angle = np.asarray(heading_rad_to_navigational(run.trajectory.theta_rad[at]))
        edges, lanes = self._hints(d.curve, self._stations(d, run, x, y, at))
        thr = self.options.match_threshold_m

        def unit(uid: str, vtype: str, ux: np.ndarray, uy: np.ndarray, angles: np.ndarray,
                 edge_hints: list[str], lane_hints: list[int]) -> _Unit:
            xs, ys = ux.tolist(), uy.tolist()
            # keepRoute=2: exactly here, also off the route and inside junctions
            moves = list(zip(repeat(uid), edge_hints, lane_hints, xs, ys, angles.tolist(),
                             repeat(2), repeat(thr)))
            return _Unit(uid, vtype, xs, ys, first_on(own, ux, uy), moves)

        units = [unit(vid, tid, x, y, angle, edges, lanes)]
        if ttid is not None:  # no hint for the trailer: SUMO matches it to the nearest lane
            tx, ty, th_t = (c[at] for c in trailer_front(run))
            units.append(unit(vid + ".trailer", ttid, tx, ty,
                              np.asarray(heading_rad_to_navigational(th_t)),
                              [""] * len(tx), [-1] * len(tx)))
        return _Plan(i, rid, units, len(at), at, run)

    def _add_vehicle(self, vid: str, route: str, vtype: str) -> None:
        """Add a vehicle on its route; where SUMO refuses that route, on its first edge; where
        the class may not depart on the route's first edge (a lead-in over a bus lane), on
        the first edge that admits it.

        The vType has the vehicle's own SUMO class, and only curves whose lanes admit it are
        driven, so SUMO's permissions hold. There is no fallback to vClass ``ignoring``:
        vehicles of that class, free to be matched onto sidewalks and walking areas by
        ``moveToXY``, made libsumo 1.28 crash (a segmentation fault in ``simulationStep``)
        on real networks (Wildau's roundabouts). A vehicle SUMO still refuses fails its run
        with SUMO's reason.
        """
        t = self.traci
        try:
            t.vehicle.add(vid, route, typeID=vtype, departPos="0")
            return
        except t.TraCIException as exc:
            refused = exc
            if "no valid route" in str(exc):
                first = f"{route}.first"
                if first not in self.free_routes:
                    t.route.add(first, list(t.route.getEdges(route))[:1])
                    self.free_routes.add(first)
                t.vehicle.add(vid, first, typeID=vtype, departPos="0")
                return
            if "not allowed to depart" not in str(exc):
                raise
        # a lead-in over a lane the class may not use (a bus lane before a car's turn):
        # depart on the first edge of the route that admits it; the model places it
        edges = list(t.route.getEdges(route))
        for k in range(1, len(edges)):
            tail = f"{route}.from{k}"
            if tail not in self.free_routes:
                t.route.add(tail, edges[k:])
                self.free_routes.add(tail)
            try:
                t.vehicle.add(vid, tail, typeID=vtype, departPos="0")
                return
            except t.TraCIException as exc:
                if "not allowed to depart" not in str(exc):
                    raise
        raise refused

    def _place_all(self, active: dict[int, _Plan]) -> None:
        """Place every vehicle in flight at its current sample; drop the runs SUMO refuses."""
        move = self.move_to_xy
        refused = self.traci.TraCIException
        for i, plan in list(active.items()):
            k = plan.k
            try:
                for u in plan.units:
                    if k < u.start:
                        continue
                    if not u.added:
                        self._add_vehicle(u.vid, plan.route, u.vtype)
                        u.added = True
                    move(*u.moves[k])
            except refused as exc:
                sample = int(plan.samples[k])
                t_s = float(plan.run.trajectory.t_s[sample])
                self._fail(plan.index, plan.vid,
                           f"SUMO could not place vehicle {plan.vid} at t = {t_s:.2f} s "
                           f"(sample {sample}): {exc}", k, plan.max_dev, plan)
                del active[i]

    def _check_all(self, active: dict[int, _Plan]) -> None:
        """Read SUMO's positions back after a step; finish the runs that played their last."""
        get = self.get_position
        lost = self.traci.TraCIException
        hypot = math.hypot
        checked = 0
        for i, plan in list(active.items()):
            k = plan.k
            try:
                for u in plan.units:
                    if u.added:
                        checked += 1
                        px, py = get(u.vid)
                        dev = hypot(px - u.x[k], py - u.y[k])
                        if dev > plan.max_dev:
                            plan.max_dev = dev
            except lost as exc:
                self._fail(plan.index, plan.vid, f"SUMO lost vehicle {plan.vid} at sample "
                           f"{int(plan.samples[k])}: {exc}", k, plan.max_dev, plan)
                del active[i]
                continue
            plan.k = k + 1
            if plan.k >= plan.n:
                self._finish(plan)
                del active[i]
        self.stats.vehicle_steps += checked

    def _finish(self, plan: _Plan) -> None:
        d = self.out[plan.index]
        d.sumo_steps = plan.k
        d.sumo_max_deviation_m = plan.max_dev
        if plan.max_dev > self.options.deviation_tolerance_m:
            log.warning("%s x %s: SUMO's position left the model's by %.3f m (tolerance "
                        "%.3f m)", d.vehicle.name, d.curve.curve_id, plan.max_dev,
                        self.options.deviation_tolerance_m)
        self._remove(plan)

    def _fail(self, i: int, vid: str, reason: str, steps: int, dev: float,
              plan: _Plan | None = None, remove: bool = True) -> None:
        d = self.out[i]
        # a session after the swing pass keeps an error found before it (a verdict's)
        d.error = f"{d.error}; {reason}" if d.error else reason
        d.sumo_steps = steps
        d.sumo_max_deviation_m = dev
        log.warning("%s x %s: %s", d.vehicle.name, d.curve.curve_id, reason)
        if remove and plan is not None:
            self._remove(plan)

    def _remove(self, plan: _Plan) -> None:
        for u in plan.units:
            if u.added:
                try:
                    self.traci.vehicle.remove(u.vid)
                except self.traci.TraCIException:
                    pass  # already gone
                u.added = False


class _GiveUp(Exception):
    """SUMO failed more often than the restarts allow."""


def _import_libsumo():
    """libsumo with SUMO_HOME set from the ``eclipse-sumo`` package."""
    from clearance.networks.sumo.tools import sumo_home

    try:
        os.environ.setdefault("SUMO_HOME", str(sumo_home()))
        if not os.environ["SUMO_HOME"]:
            os.environ["SUMO_HOME"] = str(sumo_home())
        import libsumo
    except (ImportError, FileNotFoundError) as exc:
        raise ClearanceError(f"libsumo is not available: {exc} (pip install libsumo)") from None
    return libsumo
