"""Running a study: every vehicle through every curve of every network.

:func:`run_study` reads each network, extracts its curves with lead-ins and run-outs of
a fixed :data:`APPROACH_M`, whatever the table (a vehicle's verdicts never depend on which
other vehicles are in it; the verdict is judged in the feature only), keeps for each
vehicle the curves whose lanes admit its SUMO class (:func:`permitted_groups`; the others
are counted as not permitted), and measures every vehicle on those curves by one of two
methods:

``simulate``
    Each vehicle is driven along each curve with its kinematic model within its steering
    lock and rate, placed every step in a libsumo simulation
    (:mod:`clearance.networks.driving.drive`); the
    swept envelope of the run is measured against the curve's areas.
``analytic``
    Each vehicle in the steady turn of the local radius at every station
    (:mod:`clearance.networks.driving.analytic`).

The runs go out in batches of curves (:data:`BATCH_RUNS` runs at most, a curve's vehicles
together; the curves without their areas, which each worker builds from its own copy of the
network, :func:`clearance.reports.study.batch.with_areas`) to worker processes through one executor
(:mod:`clearance.reports.study.executor`): local processes or a Dask cluster. Each batch is run by
:func:`clearance.reports.study.batch.run_batch`; a run that fails gets an ``error`` record with the
reason, and a batch whose worker dies (a crash in SUMO) is retried alone and then by halves
until the runs that crash are found, which get ``error`` records too. The batches are the
same whatever the executor and the number of workers, so the results are too.

The result is a :class:`Study`: one :class:`RunRecord` per network x vehicle x curve, in a
stable order (network, curve, vehicle table order), and the networks with their curves.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import pandas as pd

from clearance.networks.curves import Curve, CurveOptions
from clearance.networks.integrity import not_at_road_scale
from clearance.networks.loading import load_networks
from clearance.networks.model import ROAD_VCLASSES, Network
from clearance.networks.permissions import permits
from clearance.networks.selection import Selection, check_junctions, load_selected
from clearance.reports.results.feedback import set_serves_up_to
from clearance.reports.results.provenance import set_provenance
from clearance.reports.results.records import COLUMNS, VERDICT_ORDER, RunRecord
from clearance.reports.results.vertical import add_vertical
from clearance.reports.study.batch import Batch, bare, lost_batch, run_batch, split_batch
from clearance.reports.study.executor import (
    Executor,
    make_executor,
    run_isolated,
    trim_memory,
)
from clearance.vehicles.errors import LimitError, NetworkError, OptionError
from clearance.vehicles.files import env_limit
from clearance.vehicles.table import VehicleTable
from clearance.vehicles.vehicle import Vehicle

__all__ = ["APPROACH_M", "BATCH_RUNS", "COLUMNS", "DEFAULT_MAX_RUNS", "MAX_RUNS_ENV", "METHODS",
           "MIN_BATCH_RUNS", "RUN_S", "VERDICT_ORDER", "NetworkCurves", "RunRecord", "Study",
           "batch_sizes", "batches_of", "max_runs", "network_name", "permitted",
           "progress_bar", "run_study", "study_networks"]

log = logging.getLogger(__name__)

METHODS = ("simulate", "analytic")

#: Runs in one batch (one task of a worker; one SUMO session). Large enough that SUMO's
#: start (0.2-0.3 s on a city network) is a few per cent of the batch, small enough that
#: two workers share a small network and a crash costs little to isolate.
BATCH_RUNS = 400

#: The smallest batch the shrinking sizes of :func:`batch_sizes` go down to (SUMO's start
#: is then about 5 % of the batch).
MIN_BATCH_RUNS = 50


def batch_sizes(runs: int, workers: int, largest: int = BATCH_RUNS,
                smallest: int = MIN_BATCH_RUNS) -> Iterator[int]:
    """The sizes of a network's batches, in order: each the runs left shared among twice
    the workers, within ``smallest`` and ``largest``, so that the last batches are small
    and no worker waits long for another's last batch (guided scheduling). A study too
    small to give every worker ``smallest`` runs (a junction) is shared among them evenly
    instead: each worker then starts SUMO for fewer runs, but none sits idle. The sizes
    depend only on the counts, never on timing, and the results not on the sizes.

    Examples
    --------
    >>> list(batch_sizes(1000, 2))
    [250, 188, 141, 106, 79, 59, 50, 50, 50, 27]
    >>> list(batch_sizes(29, 2)), list(batch_sizes(1, 2)), list(batch_sizes(0, 2))
    ([15, 14], [1], [])
    """
    smallest = min(smallest, -(-runs // max(workers, 1)))
    left = runs
    while left > 0:
        size = min(left, max(smallest, min(largest, -(-left // (2 * workers)))))
        yield size
        left -= size


@dataclass
class NetworkCurves:
    """A network of the study with its curves."""

    name: str
    path: Path
    network: Network
    curves: list[Curve]


@dataclass
class Study:
    """The result of :func:`run_study`."""

    records: list[RunRecord]
    networks: list[NetworkCurves]
    table: VehicleTable
    method: str
    clearance_m: float
    #: (network, vehicle, curve id) of every curve whose lanes do not admit the
    #: vehicle's SUMO class: not run, not a verdict
    not_permitted: list[tuple[str, str, str]] = field(default_factory=list)
    #: The study's grade limit for every vehicle (``--max-grade-pct``), or None.
    max_grade_pct: float | None = None

    def frame(self) -> pd.DataFrame:
        """One row per network × vehicle × curve (the columns of ``clearance.csv``)."""
        return pd.DataFrame([r.row() for r in self.records], columns=COLUMNS)


def network_name(path: Path, taken: Iterable[str] = ()) -> str:
    """A short unique name of a network file: its stem without ``.net``.

    Examples
    --------
    >>> network_name(Path("a/roundabout.net.xml.gz"))
    'roundabout'
    >>> network_name(Path("b/roundabout.net.xml"), ["roundabout"])
    'roundabout-2'
    """
    name = path.name
    for suffix in (".gz", ".xml", ".net"):
        name = name.removesuffix(suffix)
    base, n = name, 2
    taken = set(taken)
    while name in taken:
        name, n = f"{base}-{n}", n + 1
    return name


#: Lead-in and run-out of every curve of a study (m): the same whatever the vehicle table.
APPROACH_M = 30.0


def study_networks(paths: Sequence[str | Path],
                  selection: Selection | None = None) -> list[NetworkCurves]:
    """Load each network (:func:`clearance.networks.loading.load_networks`: what SUMO refuses is bad
    input) and extract its curves, with :data:`APPROACH_M` lead-ins (only those of
    ``selection``, see :mod:`clearance.networks.selection`)."""
    out: list[NetworkCurves] = []
    opts = CurveOptions(approach_length_m=APPROACH_M)
    unique: dict[str, Path] = {}
    for p in paths:  # the same file named twice is studied once
        key = os.path.realpath(p)
        if key in unique:
            log.warning("%s: named twice (as %s); studied once", p, unique[key])
        unique.setdefault(key, Path(p))
    nets = list(zip(unique.values(), load_networks(list(unique.values())), strict=True))
    for path, net in nets:
        if why := not_at_road_scale(net.lanes, ROAD_VCLASSES):
            raise NetworkError(f"{path}: {why}")
    if selection is not None and selection.junctions:
        check_junctions(selection.junctions, [net for _, net in nets])
    for path, net in nets:
        curves = load_selected(net, selection, opts)
        name = network_name(path, [n.name for n in out])
        if not curves:
            log.warning("%s: no curves found", path)
        out.append(NetworkCurves(name, path, net, curves))
    if selection is not None and not selection.is_empty and not any(n.curves for n in out):
        raise OptionError(f"no curve of {', '.join(str(n.path) for n in out)} passes the "
                         f"selection ({selection.describe()})")
    return out


def progress_bar(total: int, desc: str, unit: str = "run") -> Callable[[int], None]:
    """A tqdm bar on an interactive terminal; silent in CI and when output is piped."""
    if os.environ.get("CI") or not sys.stderr.isatty() or total == 0:
        return lambda n: None
    from tqdm import tqdm

    bar = tqdm(total=total, desc=desc, unit=unit, leave=False, dynamic_ncols=True)

    def update(n: int) -> None:
        bar.update(n)
        if bar.n >= total:
            bar.close()

    return update



def batches_of(nc: NetworkCurves, vehicles: Sequence[Vehicle], method: str,
               clearance_m: float, fcd_dir: Path | None = None,
               size: int | Iterator[int] = BATCH_RUNS,
               allowed: dict[str, list[int]] | None = None,
               use_sumo: bool = True, swing: bool = True) -> Iterator[Batch]:
    """The batches of one network: consecutive curves, each with all its vehicles (those
    ``allowed`` on it, when given: vehicle indices by curve id), up to ``size`` runs (one
    curve at least); ``size`` may be the successive sizes (:func:`batch_sizes`).

    A run's result does not depend on the other runs of its batch (the model, the envelope
    and the verdict are computed run by run; SUMO only replays them), so the batches may be
    cut to suit the workers: ``tests/reports/test_executor.py`` holds 1 and 2 local workers
    and a Dask cluster byte-identical on ``clearance.csv``."""
    level = logging.getLogger("clearance.reports").getEffectiveLevel()
    vs = tuple(vehicles)
    every = list(range(len(vs)))
    sizes = None if isinstance(size, int) else iter(size)
    limit = next(sizes, BATCH_RUNS) if sizes is not None else cast(int, size)
    k = 0
    pairs: list[tuple[int, Curve]] = []
    for c in nc.curves:
        which = every if allowed is None else allowed.get(c.curve_id, [])
        if not which:
            continue
        if pairs and len(pairs) + len(which) > limit:
            yield Batch(nc.name, k, method, clearance_m, vs, tuple(pairs),
                        None if fcd_dir is None else str(fcd_dir), level, use_sumo=use_sumo,
                        swing=swing)
            k, pairs = k + 1, []
            if sizes is not None:
                limit = next(sizes, limit)
        d = bare(c)
        pairs += [(vi, d) for vi in which]
    if pairs:
        yield Batch(nc.name, k, method, clearance_m, vs, tuple(pairs),
                    None if fcd_dir is None else str(fcd_dir), level, use_sumo=use_sumo,
                    swing=swing)


def run_study(
    network_paths: Sequence[str | Path],
    table: VehicleTable,
    method: str = "simulate",
    clearance_m: float = 0.0,
    fcd_dir: Path | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    client: Any = None,
    executor: Executor | None = None,
    selection: Selection | None = None,
    use_sumo: bool = True,
    swing: bool = True,
    max_grade_pct: float | None = None,
    announce: Callable[[str], None] | None = None,
) -> Study:
    """Every vehicle of ``table`` through every curve of every network (of ``selection``).

    Parameters
    ----------
    workers
        Local worker processes (default: the cores this process may use).
    scheduler, client
        A ``dask.distributed`` scheduler address or client: the runs go to its workers.
    executor
        An :class:`~clearance.reports.study.executor.Executor` to use (and leave open) instead.
    use_sumo
        ``False``: the simulate method without replaying the runs in SUMO (the same model,
        envelopes and verdicts, faster).
    swing
        ``False``: judge every run on its lane only, no swung paths (simulate method).
    max_grade_pct
        A grade limit for every vehicle (percent; a vehicle's own ``grade_limit_pct``
        applies too, the lower counting): runs on steeper curves are ``too-steep``
        (:mod:`clearance.reports.results.vertical`).
    selection
        Only the curves of this :class:`~clearance.networks.selection.Selection` (kind, junction,
        box), chosen before any area is built.
    announce
        Told at once, before any run, how many runs the study has and about how long they
        take (default: logged at INFO).

    Raises
    ------
    InputError
        An unknown method, a negative clearance, or bad networks (named).
    LimitError
        More runs than :func:`max_runs` (said before any run).
    """
    if method not in METHODS:
        raise OptionError(f"unknown method {method!r}: use {' or '.join(METHODS)}")
    if not clearance_m >= 0:
        raise OptionError(f"--clearance must be a distance >= 0 m, not {clearance_m}")
    if max_grade_pct is not None and not 0 < max_grade_pct <= 100:
        raise OptionError(f"--max-grade-pct must be a grade in (0, 100] %, not {max_grade_pct}")
    vehicles = table.vehicles()
    nets = study_networks(network_paths, selection)
    records: list[RunRecord] = []
    refused: list[tuple[str, str, str]] = []
    allowed = {nc.name: permitted(nc, vehicles, refused) for nc in nets}
    total = sum(len(v) for a in allowed.values() for v in a.values())
    limit = max_runs()
    if total > limit:
        raise LimitError(f"refused: the study has {total:,} runs ({len(vehicles):,} vehicles on "
                         f"{sum(len(n.curves) for n in nets):,} curves), more than the limit "
                         f"of {limit:,} (about {_duration(total * _run_s(method, swing))} "
                         f"on one core); to run it anyway, set the environment variable "
                         f"{MAX_RUNS_ENV} higher, or choose curves with --kind, --junction "
                         "or --bbox")
    update = progress_bar(total, f"{method} {len(vehicles)} vehicles")
    ex = executor or make_executor(workers, scheduler, client)
    (announce or log.info)(
        f"{total:,} runs ({len(vehicles):,} vehicles on "
        f"{sum(len(n.curves) for n in nets):,} curves of {len(nets)} network(s)"
        + (f"; {len(refused):,} not permitted" if refused else "")
        + f"): about {_duration(total * _run_s(method, swing) / ex.workers)} on "
        f"{ex.workers} worker(s)")
    try:
        log.info("%d runs on %d worker(s); %d not permitted", total, ex.workers,
                 len(refused))
        for nc in nets:
            runs = sum(len(v) for v in allowed[nc.name].values())
            if not runs:
                continue
            shared = ex.share(nc.path)  # the workers build the areas from it
            t0 = time.perf_counter()
            tasks = batches_of(nc, vehicles, method, clearance_m, fcd_dir,
                               batch_sizes(runs, ex.workers), allowed[nc.name], use_sumo,
                               swing)
            for batch, recs in run_isolated(ex, run_batch, tasks, split_batch, lost_batch,
                                            shared):
                records += recs
                update(len(recs))
                errors = sum(r.verdict == "error" for r in recs)
                log.info("batch %s: %d runs (%d error) done at %.1f s", batch.label,
                         len(recs), errors, time.perf_counter() - t0)
    # stopped or failed: the workers go now (clearance.reports.study.lifetime)
    except BaseException:
        if executor is None:
            ex.abort()
        raise
    if executor is None:
        ex.close()
    else:  # what comes next (the drawings) starts from fresh workers
        ex.release()
    trim_memory()
    order = {v.name: i for i, v in enumerate(vehicles)}
    net_order = {n.name: i for i, n in enumerate(nets)}
    curve_order = {(n.name, c.curve_id): i for n in nets for i, c in enumerate(n.curves)}
    records.sort(key=lambda r: (net_order[r.network], curve_order[(r.network, r.curve_id)],
                                order[r.vehicle]))
    add_vertical(records, {(n.name, c.curve_id): c for n in nets for c in n.curves},
                 vehicles, max_grade_pct)
    set_serves_up_to(records, table)
    set_provenance(records, nets)
    return Study(records, nets, table, method, clearance_m, sorted(refused), max_grade_pct)


#: Wall time of one run on one core (s), measured on DRT x P, SU-30, CITY-BUS, WB-62 (stop
#: 24: 5,974 runs, 397 s of study on 2 workers with the swung-path search, 34 s lane only),
#: for the study's announcement; analytic runs take about a tenth of a lane run.
RUN_S = {"simulate": 0.133 * 2, "simulate-lane": 0.0114 * 2, "analytic": 0.002}

#: Default of :func:`max_runs`: about 7 h of one core with the swung-path search.
DEFAULT_MAX_RUNS = 100_000

#: The environment variable that raises the cap on a study's runs.
MAX_RUNS_ENV = "CLEARANCE_MAX_RUNS"


def max_runs() -> int:
    """How many runs a study may have: ``CLEARANCE_MAX_RUNS`` if set, else
    :data:`DEFAULT_MAX_RUNS`."""
    return env_limit(MAX_RUNS_ENV, DEFAULT_MAX_RUNS)


def _run_s(method: str, swing: bool) -> float:
    return RUN_S[method if method != "simulate" or swing else "simulate-lane"]


def _duration(seconds: float) -> str:
    """A duration in words, rounded as an estimate is.

    >>> _duration(12), _duration(95), _duration(4000), _duration(0.2)
    ('12 s', '2 min', '1.1 h', 'a second')
    """
    if seconds < 1.5:
        return "a second"
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def permitted(nc: NetworkCurves, vehicles: Sequence[Vehicle],
              refused: list[tuple[str, str, str]]) -> dict[str, list[int]]:
    """For each curve id of ``nc``, the indices of the vehicles whose SUMO class its lanes
    admit (:func:`clearance.networks.permissions.permits`); every other (network, vehicle, curve)
    is added to ``refused``.

    A vehicle is checked only on the curves it may drive; the others are not permitted,
    never a failure, and not run at all."""
    by_class: dict[str, list[int]] = {}
    for i, v in enumerate(vehicles):
        by_class.setdefault(v.vclass, []).append(i)
    out: dict[str, list[int]] = {}
    for c in nc.curves:
        ok: list[int] = []
        for vclass, members in by_class.items():
            if permits(nc.network, c, vclass):
                ok += members
            else:
                refused += [(nc.name, vehicles[i].name, c.curve_id) for i in members]
        out[c.curve_id] = sorted(ok)
    return out
