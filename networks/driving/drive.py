"""Drive vehicles through a network's curves in libsumo, each along its kinematic model.

How a run is driven
-------------------
The kinematic model (:func:`clearance.analysis.tracking.simulate_batch`) decides where a vehicle is:
SUMO has no wheelbase, steering lock or trailer dynamics, so it cannot compute that itself.
SUMO is the stage: every run becomes one SUMO vehicle of its own vType, placed at every
SUMO step with ``vehicle.moveToXY(..., keepRoute=2)`` at the model's front-bumper centre
and heading (navigational degrees) at that instant, with the edge and lane the curve's
centre line runs on at that station as the hint and a small ``matchThreshold``. SUMO steps
every :attr:`DriveOptions.sumo_step_s` (0.2 s: every second sample of the model's 0.1 s
step, 0.4 m at crawl speed); the model computes at its own step whatever SUMO's, so SUMO's
step changes neither the swept paths nor the verdicts, only how often SUMO shows them.
Its route is the curve's normal edges. After each step SUMO's reported position
(``vehicle.getPosition``, the front-bumper centre) is read back for every vehicle in flight
and compared with the model: the largest deviation of each run is recorded
(:attr:`DrivenRun.sumo_max_deviation_m`), and one beyond
:attr:`DriveOptions.deviation_tolerance_m` is logged as a warning.

Up to :attr:`DriveOptions.batch_size` runs are in flight at once (one vehicle per vehicle x
curve run); a run that has played its last sample is removed and the next queued run's
vehicle is added in its place. The model is computed a batch ahead. Every run has a bounded
number of samples (the model's step cap), so the simulation ends.

Which path SUMO shows
---------------------
Without FCD output SUMO checks the lane pass: every run is placed along its lane's centre
line while the model computes it, before the verdicts and the swing pass
(:mod:`clearance.networks.driving.swing`). With FCD output
(:attr:`DriveOptions.fcd_output`, ``clearance simulate --fcd``) the lane pass runs without
SUMO, and every run is placed after the swing pass along the path its verdict rests on
(:attr:`DrivenRun.chosen_run`: the swung path's trajectory where one was taken, the lane's
otherwise), so that the replay in sumo-gui shows the swing the verdict describes; the check
(:attr:`DrivenRun.sumo_steps`, :attr:`DrivenRun.sumo_max_deviation_m`) is then that of this
placement, and a run SUMO fails keeps its verdict's reason beside SUMO's in ``error``.

The SUMO side (vTypes, trailers as vehicles of their own, replay in sumo-gui, SUMO's errors)
is :mod:`clearance.networks.sumo.session`.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Iterator, Sequence
from pathlib import Path as FilePath

from clearance.analysis.clearance import Areas, evaluate
from clearance.analysis.failures import GEOMETRY_FAILURES
from clearance.analysis.polyline import Path, prepare_path
from clearance.analysis.tracking import TrackingSettings, simulate_batch
from clearance.networks.curves import Curve
from clearance.networks.driving.runs import (  # noqa: F401 - re-exported
    DEFAULT_SUMO_STEP_S,
    DrivenRun,
    DriveOptions,
    DriveStats,
    curve_areas,
    select_curves,
)
from clearance.networks.driving.swing import swing_pass
from clearance.networks.model import Network
from clearance.networks.sumo.placement import replay_config  # noqa: F401 - re-exported
from clearance.networks.sumo.session import SumoSession
from clearance.vehicles.errors import NetworkError
from clearance.vehicles.vehicle import Vehicle

__all__ = ["DriveOptions", "DriveStats", "DrivenRun", "curve_areas", "drive", "replay_config",
           "select_curves"]

log = logging.getLogger(__name__)


def drive(
    net: Network,
    pairs: Sequence[tuple[Vehicle, Curve]],
    settings: TrackingSettings | None = None,
    options: DriveOptions | None = None,
    stats: DriveStats | None = None,
) -> list[DrivenRun]:
    """Drive every (vehicle, curve) pair: model, SUMO replay and check, envelope, verdict.

    Parameters
    ----------
    net
        The network the curves came from (SUMO loads ``net.path``).
    pairs
        Vehicle and curve of each run; curves need their areas
        (``extract_curves(net, ..., areas=True)``).
    settings
        Tracking settings of the model (SUMO's step is a whole multiple of its time
        step, :attr:`DriveOptions.sumo_step_s`).
    options
        Batch size, FCD output (SUMO then places each run along its chosen path, after
        the swing pass), clearance offset, with or without SUMO.
    stats
        Filled with the time spent in each part, when given.

    Returns
    -------
    list of DrivenRun
        One per pair, in order. A run SUMO failed has ``error`` set; the others are kept.
    """
    settings = settings or TrackingSettings()
    options = options or DriveOptions()
    options.samples_per_step(settings.dt_s)  # refuses a SUMO step that does not fit
    if options.use_sumo and not FilePath(net.path).is_file():
        raise NetworkError(f"{net.path}: no such network file")
    everything = [DrivenRun(v, c) for v, c in pairs]
    # A curve whose areas or centre line cannot be used fails its own runs, never the others.
    areas: dict[str, Areas] = {}
    paths: dict[str, Path] = {}
    bad: dict[str, str] = {}
    for d in everything:
        c = d.curve
        if c.curve_id in areas or c.curve_id in bad:
            continue
        try:
            areas[c.curve_id] = curve_areas(c)
            paths[c.curve_id] = prepare_path(c.centerline, settings.spacing_m,
                                             name=c.curve_id, smooth=True)
        except GEOMETRY_FAILURES as exc:
            bad[c.curve_id] = f"the curve cannot be driven: {exc}"
            log.warning("%s: %s", c.curve_id, bad[c.curve_id])
    for d in everything:
        d.error = bad.get(d.curve.curve_id, "")
    out = [d for d in everything if not d.error]

    stats = stats if stats is not None else DriveStats()
    after = options.use_sumo and options.fcd_output is not None
    batches = _modelled(out, paths, settings, options, stats)
    if options.use_sumo and not after:  # SUMO checks the lane pass as the model goes
        _in_sumo(net, out, paths, settings, options, stats, batches)
    else:
        for _ in batches:
            pass
    _judge(out, areas, options, stats)
    if options.swing:  # the best path within the pavement, for the runs not clear
        swing_pass(out, paths, areas, settings, options, stats)
    if after:  # the FCD output shows each run along the path its verdict rests on
        placed = [i for i, d in enumerate(out) if d.chosen_run is not None]
        _in_sumo(net, out, paths, settings, options, stats, iter([placed]), chosen=True)
    return everything


def _modelled(out: list[DrivenRun], paths: dict[str, Path], settings: TrackingSettings,
              options: DriveOptions, stats: DriveStats) -> Iterator[list[int]]:
    """Model the lane runs of ``out`` batch by batch (``run`` set); yields each batch's
    indices once it is modelled."""
    for lo in range(0, len(out), options.batch_size):
        t0, c0 = time.perf_counter(), time.process_time()
        idx = list(range(lo, min(lo + options.batch_size, len(out))))
        runs = simulate_batch([out[i].vehicle for i in idx],
                              [paths[out[i].curve.curve_id] for i in idx], settings)
        for i, r in zip(idx, runs, strict=True):
            out[i].run = r
        stats.model_s += time.perf_counter() - t0
        stats.model_cpu_s += time.process_time() - c0
        yield idx


def _in_sumo(net: Network, out: list[DrivenRun], paths: dict[str, Path],
             settings: TrackingSettings, options: DriveOptions, stats: DriveStats,
             batches: Iterator[list[int]], chosen: bool = False) -> None:
    """Place the runs of ``batches`` in one SUMO session (:class:`SumoSession`; with
    ``chosen``, along their chosen paths); SUMO's time in ``stats`` (without the model's)."""
    t0, c0 = time.perf_counter(), time.process_time()
    curves = {d.curve.curve_id: d.curve for d in out}
    ends = {k: net.lanes[k].shape[-1] for c in curves.values() for k in c.lanes
            if k in net.lanes}
    before, cpu_before = stats.model_s, stats.model_cpu_s
    SumoSession(net.path, out, paths, settings, options, ends, stats, chosen).run(batches)
    stats.sumo_s += time.perf_counter() - t0 - (stats.model_s - before)
    stats.sumo_cpu_s += time.process_time() - c0 - (stats.model_cpu_s - cpu_before)


def _judge(out: list[DrivenRun], areas: dict[str, Areas], options: DriveOptions,
           stats: DriveStats) -> None:
    """Envelope and verdict of every modelled run of ``out`` on its lane path (``result``)."""
    t0 = time.perf_counter()
    for d in out:
        if d.run is None:  # pragma: no cover - every queued run is modelled
            d.error = d.error or "the model did not run"
            continue
        try:
            # judged by its feature: the sweep while the vehicle is in it
            d.result = evaluate(d.run, areas[d.curve.curve_id], options.offset_m,
                                feature_m=(d.curve.core_start_m, d.curve.core_end_m))
        except GEOMETRY_FAILURES as exc:
            # one run's bad geometry must not lose the others' results
            d.error = (d.error + "; " if d.error else "") + f"envelope or verdict failed: {exc}"
            log.warning("%s x %s: %s", d.vehicle.name, d.curve.curve_id, d.error)
    stats.evaluate_s += time.perf_counter() - t0
