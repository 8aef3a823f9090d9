"""One batch of a study's runs, as a worker process runs it: vehicles x curves -> records.

A :class:`Batch` is picklable and self-contained: the vehicles, the curves (without
their areas: :func:`bare`), the method and the clearance offset. A worker reads the
network once per process (:func:`worker_network`) and builds the areas of its batch's
curves itself (:func:`with_areas`): the areas of a curve are the same whichever batch
builds them (:mod:`clearance.networks.areas`), so the parent builds none, and a batch pickles
centre lines, not polygons. A record goes back with the parts of its envelope outside its
lanes and its pavement (:attr:`RunRecord.conflict`), which the exports draw, so that the
parent never needs a curve's areas.

Nothing one run does stops the others: a curve whose centre line cannot be driven, a
model or geometry error, anything the run raises, becomes that run's ``error`` record with
the reason (:func:`isolate`, which retries the failing part in halves in this process);
a crash of the whole worker (SUMO's segmentation faults) is isolated by
:func:`clearance.reports.study.executor.run_isolated` in the same way, across processes.
"""

from __future__ import annotations

import copy
import hashlib
import logging
import math
import os
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from shapely.geometry.base import BaseGeometry

from clearance.analysis.failures import GEOMETRY_FAILURES
from clearance.networks.area_book import curve_levels, network_is_flat
from clearance.networks.area_groups import AreaIndex
from clearance.networks.areas import build_areas
from clearance.networks.collector import kept_for_good
from clearance.networks.curves import Curve
from clearance.networks.driving.analytic import minimum_ctr_m, run_analytic
from clearance.networks.driving.drive import DrivenRun, DriveOptions, drive
from clearance.networks.driving.judging import encroaches_on
from clearance.networks.model import Network
from clearance.networks.reader import read_network
from clearance.reports.exports.envelopes import conflict_parts
from clearance.reports.output.file_names import file_name
from clearance.reports.results.feedback import set_overreach
from clearance.reports.results.records import RunRecord
from clearance.reports.study.executor import SharedFile
from clearance.reports.study.lifetime import in_worker
from clearance.vehicles.errors import NetworkError
from clearance.vehicles.vehicle import Vehicle

__all__ = ["Batch", "bare", "detached", "driven_record", "error_record", "isolate",
           "lost_batch", "run_batch", "split_batch",
           "with_areas", "worker_network"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Batch:
    """Runs of one network that go to one worker together.

    Attributes
    ----------
    network
        The study's name of the network.
    index
        The batch's number in the network (names its FCD file); ``part`` tells the parts of
        a batch that was split after a crash apart.
    method, clearance_m
        ``simulate`` or ``analytic``, and the clearance offset (m).
    vehicles
        The vehicles the pairs refer to.
    pairs
        ``(vehicle index, curve)`` of each run, the curve with its areas.
    fcd_dir
        Folder for SUMO's FCD output, or ``None``.
    log_level
        The study's logging level, for the worker's own log.
    swing
        ``False``: judge the lane path only
        (:attr:`clearance.networks.driving.runs.DriveOptions.swing`).
    use_sumo
        ``False`` computes the simulate method's runs without replaying them in SUMO (the
        same model, envelopes and verdicts;
        :attr:`clearance.networks.driving.drive.DriveOptions.use_sumo`).
    """

    network: str
    index: int
    method: str
    clearance_m: float
    vehicles: tuple[Vehicle, ...]
    pairs: tuple[tuple[int, Curve], ...]
    fcd_dir: str | None = None
    log_level: int = logging.WARNING
    part: str = ""
    use_sumo: bool = True
    swing: bool = True

    def __len__(self) -> int:
        return len(self.pairs)

    @property
    def label(self) -> str:
        """``network#index`` (with the part after a split)."""
        return f"{self.network}#{self.index}{self.part}"


def detached(curve: Curve) -> Curve:
    """A copy of ``curve`` that holds its own areas (none of the network's area book), so
    that it can be pickled on its own."""
    out = copy.copy(curve)
    out.set_areas(curve.own_lanes, curve.roadway, curve.paved, levels=curve.levels)
    return out


def bare(curve: Curve) -> Curve:
    """A copy of ``curve`` without its areas and without the network's area book: what a
    batch sends (a worker builds the areas again, :func:`with_areas`)."""
    out = copy.copy(curve)
    out.set_areas(None, None, None)
    out.area_batch = -1
    return out


def with_areas(net: Network, curves: Sequence[Curve]) -> None:
    """Give every curve of ``curves`` that has no areas its three areas, built in this
    process from ``net`` (the same geometry as the parent's:
    :func:`clearance.networks.areas.build_areas`
    makes an area the same whichever batch builds it), with its level segments on a network
    with storeys."""
    todo = list({id(c): c for c in curves
                 if c.area_book is None and c._own is None}.values())
    if not todo:
        return
    index = _area_index(net)
    if id(net) not in _FLAT:
        _FLAT[id(net)] = network_is_flat(net)
    own, roadway, paved = build_areas(index, todo)
    for c, o, r, p in zip(todo, own, roadway, paved, strict=True):
        c.set_areas(o, r, p)  # flat: no levels (judged in plan)
        if not _FLAT[id(net)]:  # the storeys' areas too (docs/design.md §6, "Levels")
            c.set_areas(o, r, p, levels=curve_levels(index, c))


def split_batch(batch: Batch) -> list[Batch]:
    """The two halves of a batch (a single run cannot be split: ``[]``)."""
    if len(batch.pairs) < 2:
        return []
    mid = len(batch.pairs) // 2
    return [replace(batch, pairs=batch.pairs[:mid], part=batch.part + "a"),
            replace(batch, pairs=batch.pairs[mid:], part=batch.part + "b")]


def error_record(network: str, vehicle: Vehicle, curve: Curve, method: str,
                 clearance_m: float, reason: str) -> RunRecord:
    """The record of a run that could not be completed (verdict ``error``)."""
    nan = math.nan
    return RunRecord(
        network=network, vehicle=vehicle.name, curve_id=curve.curve_id, kind=curve.kind,
        junction=curve.junction, verdict="error", margin_m=nan, paved_margin_m=nan,
        curve_radius_m=curve.min_radius_m, vehicle_min_radius_m=minimum_ctr_m(vehicle),
        swept_width_m=nan, available_width_m=curve.lane_width_m, max_offtracking_m=nan,
        max_tracking_error_m=nan, turn_angle_deg=curve.turn_angle_deg,
        max_grade_pct=curve.max_grade_pct, method=method, clearance_m=clearance_m,
        reason=reason, envelope=None, lane_verdict="error")


def lost_batch(batch: Batch, reason: str) -> list[RunRecord]:
    """``error`` records for the runs of a batch whose worker died even when run alone."""
    why = ("the worker process died running this alone (SUMO crashed or memory ran out): "
           + reason)
    return [error_record(batch.network, batch.vehicles[v], c, batch.method, batch.clearance_m,
                         why) for v, c in batch.pairs]


def isolate(items: Sequence[tuple[int, Curve]],
            run: Callable[[Sequence[tuple[int, Curve]]], list[RunRecord]],
            failed: Callable[[tuple[int, Curve], str], RunRecord]) -> list[RunRecord]:
    """``run(items)``; where it raises, the same for each half, down to single items, which
    get ``failed(item, reason)``. Only one curve's geometry failing is isolated
    (:data:`~clearance.analysis.failures.GEOMETRY_FAILURES`); bad input and bugs are raised.

    Examples
    --------
    >>> from clearance.vehicles.errors import GeometryError
    >>> def run(xs):
    ...     if 3 in [x for x, _ in xs]:
    ...         raise GeometryError("three")
    ...     return [x for x, _ in xs]
    >>> isolate([(1, None), (3, None), (4, None)], run, lambda it, why: (it[0], why))
    [1, (3, 'GeometryError: three'), 4]
    >>> isolate([], run, lambda it, why: why)
    []
    """
    if not items:
        return []
    try:
        return run(items)
    except GEOMETRY_FAILURES as exc:  # one curve's geometry must not lose the others' runs
        if len(items) == 1:
            reason = f"{type(exc).__name__}: {exc}"
            log.warning("run failed: %s", reason)
            return [failed(items[0], reason)]
        mid = len(items) // 2
        return isolate(items[:mid], run, failed) + isolate(items[mid:], run, failed)


#: The networks this worker process has read, by file identity.
_NETWORKS: dict[tuple[str, str], Network] = {}
#: The area topology of each network of :data:`_NETWORKS` (by the network's id).
_INDEXES: dict[int, AreaIndex] = {}
#: Whether each network of :data:`_INDEXES` is flat (judged in plan, no levels).
_FLAT: dict[int, bool] = {}


def _area_index(net: Network) -> AreaIndex:
    if id(net) not in _INDEXES:
        _INDEXES.clear()
        _FLAT.clear()
        _INDEXES[id(net)] = AreaIndex(net)
    return _INDEXES[id(net)]


def worker_network(shared: SharedFile) -> Network:
    """The network of ``shared``, read once per worker process.

    On a cluster (the file's bytes sent along) a worker without the file at its path writes
    the bytes to a temporary folder named by their hash and reads that.
    """
    path = Path(shared[0])
    if shared[1] is not None:
        data: bytes = shared[1]
        digest = hashlib.sha256(data).hexdigest()[:24]
        key = (digest, "")
        if key not in _NETWORKS:
            if not (path.is_file() and path.stat().st_size == len(data)
                    and hashlib.sha256(path.read_bytes()).hexdigest()[:24] == digest):
                folder = Path(tempfile.gettempdir()) / f"clearance-net-{digest}"
                folder.mkdir(exist_ok=True)
                path = folder / path.name
                if not path.is_file():
                    tmp = folder / f".{path.name}.{os.getpid()}.tmp"
                    tmp.write_bytes(data)
                    os.replace(tmp, path)
            _NETWORKS[key] = _read_to_keep(path)
        return _NETWORKS[key]
    try:
        st = path.stat()
    except OSError as exc:
        raise NetworkError(f"{path}: cannot read the network in a worker: "
                              f"{exc.strerror}") from None
    key = (str(path.resolve()), f"{st.st_size}:{st.st_mtime_ns}")
    if key not in _NETWORKS:
        _NETWORKS.clear()  # one network at a time: a study goes network by network
        _INDEXES.clear()
        _NETWORKS[key] = _read_to_keep(path)
    return _NETWORKS[key]


def _read_to_keep(path: Path) -> Network:
    """The network at ``path`` for this process to keep: in a local worker it is frozen
    out of the collector's full scans (:func:`kept_for_good`)."""
    net = read_network(path)
    if in_worker():
        kept_for_good()
    return net


def _configure_logging(level: int) -> None:
    """The worker logs as the study's process does (the CLI's format, its level for our
    own packages)."""
    if not logging.getLogger().handlers:
        logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s")
    for name in ("vehicles", "analysis", "networks", "reports"):
        logging.getLogger(name).setLevel(level)


def _simulated(batch: Batch, net: Network, items: Sequence[tuple[int, Curve]]
               ) -> list[RunRecord]:
    fcd = None
    if batch.fcd_dir is not None:
        Path(batch.fcd_dir).mkdir(parents=True, exist_ok=True)
        fcd = Path(batch.fcd_dir) / file_name([batch.network, f"{batch.index:03d}{batch.part}"],
                                              ".fcd.xml")
    options = DriveOptions(offset_m=batch.clearance_m, fcd_output=fcd, use_sumo=batch.use_sumo,
                           swing=batch.swing)
    runs = drive(net, [(batch.vehicles[v], c) for v, c in items], options=options)
    return [driven_record(batch.network, r, batch.clearance_m) for r in runs]


def driven_record(network: str, r: DrivenRun, clearance_m: float, conflict: bool = True
                  ) -> RunRecord:
    """The study's record of a driven run, its worst overreach filled and said in its reason
    (:func:`clearance.reports.results.feedback.set_overreach`; ``r.curve`` must hold its areas).
    ``conflict``:
    also the envelope's parts outside its lanes and the pavement (the exports')."""
    res, curve, v = r.result, r.curve, r.vehicle
    if res is None:
        return error_record(network, v, curve, "simulate", clearance_m,
                            r.reason or "no result")
    nan = math.nan
    rec = RunRecord(
        network=network, vehicle=v.name, curve_id=curve.curve_id, kind=curve.kind,
        junction=curve.junction, verdict=r.verdict,
        margin_m=res.clearance.margin_m, paved_margin_m=res.clearance.paved_margin_m,
        curve_radius_m=curve.min_radius_m, vehicle_min_radius_m=minimum_ctr_m(v),
        swept_width_m=res.swept.max_swept_width_m, available_width_m=curve.lane_width_m,
        max_offtracking_m=res.swept.max_offtracking_m,
        max_tracking_error_m=r.run.max_error_m if r.run else nan,
        turn_angle_deg=curve.turn_angle_deg, max_grade_pct=curve.max_grade_pct,
        method="simulate", clearance_m=clearance_m, reason=r.reason,
        envelope=res.measured, lane_verdict=r.lane_verdict, lane_margin_m=r.lane_margin_m,
        path=r.path, encroaches_on=r.encroaches_on,
        conflict=_conflict(res.measured, curve) if conflict else None, line=r.line,
        trailer_offtracking_m=(nan if res.swept.max_trailer_offtracking_m is None
                               else res.swept.max_trailer_offtracking_m))
    set_overreach(rec, curve)
    return rec


def _conflict(envelope: BaseGeometry | None, curve: Curve
              ) -> tuple[BaseGeometry | None, BaseGeometry | None] | None:
    """The envelope's parts outside its lanes and outside the pavement (the exports')."""
    if envelope is None or envelope.is_empty:
        return None
    return conflict_parts(envelope, curve.own_lanes, curve.paved)


def _analytic(batch: Batch, items: Sequence[tuple[int, Curve]]) -> list[RunRecord]:
    out = []
    for vi, curve in items:
        v = batch.vehicles[vi]
        r = run_analytic(v, curve, batch.clearance_m)
        c = r.clearance
        rec = RunRecord(
            batch.network, v.name, curve.curve_id, curve.kind, curve.junction, c.verdict,
            c.margin_m, c.paved_margin_m, curve.min_radius_m, r.vehicle_min_radius_m,
            r.swept_width_m, curve.lane_width_m, r.max_offtracking_m, 0.0,
            curve.turn_angle_deg, curve.max_grade_pct, "analytic", batch.clearance_m,
            c.reason, r.envelope, lane_verdict=c.verdict, lane_margin_m=c.margin_m,
            path="lane", encroaches_on=encroaches_on(c),
            conflict=_conflict(r.envelope, curve))
        set_overreach(rec, curve)
        out.append(rec)
    return out


def run_batch(batch: Batch, shared: SharedFile | None = None) -> list[RunRecord]:
    """Every run of ``batch``, one record each in the batch's order (the task a worker runs).

    ``shared`` is the network file (needed by ``simulate``, and to build the areas of
    :func:`bare` curves).
    """
    _configure_logging(batch.log_level)

    def failed(item: tuple[int, Curve], reason: str) -> RunRecord:
        v, c = item
        return error_record(batch.network, batch.vehicles[v], c, batch.method,
                            batch.clearance_m, reason)

    net = worker_network(shared) if shared is not None else None
    missing = [c for _, c in batch.pairs if c.area_book is None and c._own is None]
    if missing:
        if net is None:
            raise ValueError(f"{batch.label}: curves without areas need the network file")
        with_areas(net, missing)
    if batch.method == "analytic":
        def run(items: Sequence[tuple[int, Curve]]) -> list[RunRecord]:
            return _analytic(batch, items)
    else:
        if net is None:
            raise ValueError(f"{batch.label}: simulate needs the network file")

        def run(items: Sequence[tuple[int, Curve]]) -> list[RunRecord]:
            return _simulated(batch, net, items)

    # analytic runs are independent: one at a time, so that a failure costs nothing twice
    if batch.method == "analytic":
        out: list[RunRecord] = []
        for item in batch.pairs:
            out += isolate([item], run, failed)
        return out
    return isolate(list(batch.pairs), run, failed)

