"""Driving chosen vehicle x curve pairs in worker processes (``clearance simulate``): a crash
of SUMO costs only the runs that cause it."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from clearance.analysis.tracking import TrackingSettings
from clearance.networks.curves import Curve
from clearance.networks.driving.drive import DrivenRun, DriveOptions, drive
from clearance.networks.model import Network
from clearance.reports.study.batch import detached, worker_network
from clearance.reports.study.executor import Executor, LocalExecutor, SharedFile, run_isolated
from clearance.vehicles.vehicle import Vehicle

__all__ = ["DriveTask", "drive_in_workers", "lost_drive", "run_drive", "split_drive"]


@dataclass(frozen=True)
class DriveTask:
    """Runs of ``clearance simulate`` for one worker: the pairs, the model's settings and
    the drive options (an FCD file among them)."""

    pairs: tuple[tuple[Vehicle, Curve], ...]
    settings: TrackingSettings
    options: DriveOptions
    part: str = ""

    def __len__(self) -> int:
        return len(self.pairs)


def split_drive(task: DriveTask) -> list[DriveTask]:
    """The two halves of a drive task, each with its own FCD file (``[]`` for one run)."""
    if len(task.pairs) < 2:
        return []
    mid = len(task.pairs) // 2
    out = []
    for half, pairs in (("a", task.pairs[:mid]), ("b", task.pairs[mid:])):
        options = task.options
        if options.fcd_output is not None:
            fcd = Path(options.fcd_output)
            options = replace(options, fcd_output=fcd.with_name(
                f"{fcd.name.removesuffix('.xml')}-{half}.xml"))
        out.append(replace(task, pairs=pairs, options=options, part=task.part + half))
    return out


def run_drive(task: DriveTask, shared: SharedFile) -> list[DrivenRun]:
    """Drive ``task``'s runs in this worker (:func:`clearance.networks.driving.drive.drive`)."""
    return drive(worker_network(shared), list(task.pairs), task.settings, task.options)


def lost_drive(task: DriveTask, reason: str) -> list[DrivenRun]:
    """Failed runs for a drive task whose worker died even when run alone."""
    why = ("the worker process died running this alone (SUMO crashed or memory ran out): "
           + reason)
    return [DrivenRun(v, c, error=why) for v, c in task.pairs]


def drive_in_workers(net: Network, pairs: Sequence[tuple[Vehicle, Curve]],
                     settings: TrackingSettings, options: DriveOptions,
                     workers: int | None = None,
                     executor: Executor | None = None) -> list[DrivenRun]:
    """:func:`clearance.networks.driving.drive.drive` in worker processes, so that a crash of SUMO
    costs only the runs that cause it (they come back failed, with the reason; see
    :func:`clearance.reports.study.executor.run_isolated`). With FCD output the runs go to one
    worker (one SUMO session writes one FCD file); otherwise they are shared between the workers.
    ``executor`` replaces the local workers (and is closed).
    """
    detached_curves = {c.curve_id: detached(c) for _, c in pairs}
    pairs = [(v, detached_curves[c.curve_id]) for v, c in pairs]
    with executor or LocalExecutor(workers) as ex:
        n = 1 if options.fcd_output is not None else ex.workers
        size = max(1, -(-len(pairs) // n))
        tasks = [DriveTask(tuple(pairs[k:k + size]), settings, options)
                 for k in range(0, len(pairs), size)]
        finished = [runs for _, runs in run_isolated(ex, run_drive, tasks, split_drive,
                                                     lost_drive, ex.share(net.path))]
    done = {(d.vehicle.name, d.curve.curve_id): d for runs in finished for d in runs}
    return [done[(v.name, c.curve_id)] for v, c in pairs]
