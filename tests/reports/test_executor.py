"""The executor: worker processes, crash isolation, identical results on every engine."""

from __future__ import annotations

import ctypes
import os

import pytest

from clearance.networks.samples.build import sample_networks
from clearance.reports.results.tables import clearance_csv
from clearance.reports.study.executor import LocalExecutor, WorkerLost, cores, run_isolated
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table_paths, load_tables

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))


def segfault() -> None:
    """Crash this process as libsumo does: a segmentation fault."""
    ctypes.string_at(0)


def squares_or_crash(task: list[int], bad: frozenset[int]) -> list[int]:
    """Squares of ``task``; a segmentation fault when it holds a ``bad`` number."""
    if bad & set(task):
        segfault()
    return [x * x for x in task]


def halves(task: list[int]) -> list[list[int]]:
    return [] if len(task) < 2 else [task[: len(task) // 2], task[len(task) // 2:]]


def test_cores_is_positive_and_follows_the_environment(monkeypatch):
    monkeypatch.setenv("CLEARANCE_WORKERS", "3")
    assert cores() == 3
    monkeypatch.setenv("CLEARANCE_WORKERS", "zero")
    assert 1 <= cores() <= (os.cpu_count() or 1)


def test_a_crashing_item_is_isolated_and_the_rest_is_kept():
    tasks = [list(range(k, k + 8)) for k in range(0, 64, 8)]
    bad = frozenset({13, 50})
    with LocalExecutor(2) as ex:
        got = list(run_isolated(ex, squares_or_crash, tasks, halves,
                                lambda t, why: [("lost", x, why) for x in t], bad))
    values = [v for _, out in got for v in out]
    lost = sorted(v[1] for v in values if isinstance(v, tuple))
    kept = sorted(v for v in values if not isinstance(v, tuple))
    assert lost == [13, 50]  # exactly the crashing items, each found alone
    assert kept == sorted(x * x for x in range(64) if x not in bad)
    assert all("died" in v[2] for v in values if isinstance(v, tuple))


def test_a_worker_crash_raises_worker_lost_and_the_pool_recovers():
    with LocalExecutor(1) as ex:
        future = ex.submit(squares_or_crash, [1], frozenset({1}))
        with pytest.raises(WorkerLost):
            ex.outcome(future)
        ex.recover()
        assert ex.outcome(ex.submit(squares_or_crash, [3], frozenset())) == [9]


# ---------------------------------------------------------------- whole studies

TABLE = None


def _table():
    global TABLE
    if TABLE is None:
        TABLE = load_tables(bundled_table_paths(), ["P", "CITY-BUS", "WB-62"])
    return TABLE


def crash_on_curve(fn, curve_id: str, batch, shared):
    """Run ``fn(batch, shared)``, crashing the worker when the batch drives ``curve_id``."""
    if any(c.curve_id == curve_id for _, c in batch.pairs):
        segfault()
    return fn(batch, shared)


class CrashingExecutor(LocalExecutor):
    """Local workers that crash on every batch with one given curve (as libsumo does)."""

    def __init__(self, workers: int, curve_id: str) -> None:
        super().__init__(workers)
        self.curve_id = curve_id

    def submit(self, fn, *args):
        return super().submit(crash_on_curve, fn, self.curve_id, *args)


@pytest.fixture(scope="module")
def one_worker_csv() -> str:
    return clearance_csv(run_study([NET], _table(), workers=1))


def test_two_workers_give_the_same_csv_as_one(one_worker_csv):
    assert clearance_csv(run_study([NET], _table(), workers=2)) == one_worker_csv
    assert one_worker_csv.count("\n") > 30


def test_a_dask_cluster_gives_the_same_csv(one_worker_csv):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        csv_text = clearance_csv(run_study([NET], _table(), client=client))
    assert csv_text == one_worker_csv


def test_a_curve_that_crashes_sumo_is_an_error_and_the_study_completes(one_worker_csv):
    normal = run_study([NET], _table(), workers=1)
    victim = normal.records[len(normal.records) // 2].curve_id
    with CrashingExecutor(2, victim) as ex:
        study = run_study([NET], _table(), executor=ex)
    assert len(study.records) == len(normal.records)
    for got, want in zip(study.records, normal.records, strict=True):
        assert (got.curve_id, got.vehicle) == (want.curve_id, want.vehicle)
        if got.curve_id == victim:
            assert got.verdict == "error" and "worker process died" in got.reason
        else:
            assert (got.verdict, got.margin_m) == (want.verdict, want.margin_m)


def test_a_network_named_twice_is_studied_once(caplog):
    study = run_study([NET, str(NET)], load_tables(bundled_table_paths(), ["P"]),
                      method="analytic", workers=1)
    assert [n.name for n in study.networks] == [NET.name.split(".")[0]]
    assert "named twice" in caplog.text
