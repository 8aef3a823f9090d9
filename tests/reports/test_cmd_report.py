"""``clearance report``'s drawings in worker processes
(:class:`clearance.reports.cli.report.Drawings`):
a worker that dies while drawing costs at most that drawing, and the report says so."""

from __future__ import annotations

import logging
import os
import re
import signal
from collections.abc import Iterator
from pathlib import Path

import pytest

from clearance.networks.samples.build import sample_networks
from clearance.reports.cli import report as cmd_report
from clearance.reports.cli.main import main
from clearance.reports.documents.drawings import Drawing
from clearance.reports.study.executor import LocalExecutor

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
#: A small report: the T junction's curves (three figures), analytic (fast), two workers.
ARGS = ["report", "-n", str(NET), "--vehicle", "P", "--vehicle", "CITY-BUS",
        "--method", "analytic", "--junction", "T", "--workers", "2"]
#: The curve whose figure's worker dies (failing or tight for the bus: it has a figure).
VICTIM = "turn:T:TW_in_0->TS_out_0"


def crash_drawing(fn, victims: frozenset[str], once: str, *args):
    """Run ``fn(*args)``, but kill this worker when it draws a figure of a curve in
    ``victims`` or a network part (``"exports"``, ``"sheets"``) in ``victims``: with a
    segmentation fault every time, or when ``once`` names a file, only the first time
    (the file marks it done)."""
    task = args[0]
    if isinstance(task, Drawing) and (task.curve_id or task.part) in victims:
        if not once:
            os.kill(os.getpid(), signal.SIGSEGV)
        if not os.path.exists(once):
            Path(once).touch()
            os._exit(1)
    return fn(*args)


class CrashingExecutor(LocalExecutor):
    """Local workers that die drawing the ``victims`` (:func:`crash_drawing`)."""

    def __init__(self, workers: int, victims: frozenset[str], once: str = "") -> None:
        super().__init__(workers)
        self.victims, self.once = victims, once

    def submit(self, fn, *args):
        return super().submit(crash_drawing, fn, self.victims, self.once, *args)


class Kept(logging.Handler):
    """Keeps the messages the command logs (which it prints on stderr: ``WARNING: ...``)."""

    def __init__(self) -> None:
        super().__init__(logging.INFO)
        self.lines: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.lines.append(f"{record.levelname}: {record.getMessage()}")


def report(out: Path, executor: LocalExecutor | None = None) -> tuple[int, list[str]]:
    """``clearance report ARGS -o out`` with ``executor`` in place of the usual one: the
    exit status and the warnings."""
    kept = Kept()
    logger = logging.getLogger("clearance.reports")
    logger.addHandler(kept)
    try:
        with pytest.MonkeyPatch.context() as mp:
            if executor is not None:
                mp.setattr(cmd_report, "make_executor", lambda *a, **k: executor)
            status = main([*ARGS, "-o", str(out)])
    finally:
        logger.removeHandler(kept)
    return status, [line for line in kept.lines if line.startswith("WARNING")]


def files(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in folder.rglob("*") if p.is_file()}


@pytest.fixture(scope="module")
def normal(tmp_path_factory) -> dict[str, bytes]:
    out = tmp_path_factory.mktemp("normal") / "report"
    assert report(out) == (0, [])
    return files(out)


@pytest.fixture(scope="module")
def always(tmp_path_factory) -> Iterator[tuple[int, list[str], Path]]:
    """A report whose workers die each time they draw the victim's figure or the exports."""
    out = tmp_path_factory.mktemp("always") / "report"
    status, warnings = report(out, CrashingExecutor(2, frozenset({VICTIM, "exports"})))
    yield status, warnings, out


def test_a_drawing_that_always_kills_its_worker_is_lost_and_said(normal, always):
    status, warnings, out = always
    assert status == 0
    got = files(out)
    victim_files = {r for r in normal if r.startswith("figures/") and "TW_in_0" in r}
    assert len(victim_files) == 1  # its PNG (no SVG without --svg)
    exports = {r for r in normal if r.startswith("exports/")}
    assert len(exports) == 3
    # nothing else is lost: every other figure, the sheets, the tables, byte for byte
    assert set(got) == set(normal) - victim_files - exports
    for rel in set(got) - {"report.html", "report.md"}:
        assert got[rel] == normal[rel], rel
    assert sum(r.startswith("figures/") and r.endswith(".png") for r in got) == 3  # 2 + plan
    # the loss is said on stderr, naming the curve and the files, and the exports
    lost = [w for w in warnings if "not drawn" in w]
    assert len(lost) == 2, warnings
    # the others: run_isolated's own, one per drawing it gave up
    assert len(warnings) == 4 and all("crashed its worker" in w for w in warnings
                                      if w not in lost)
    [fig] = [w for w in lost if VICTIM in w]
    assert fig.startswith("WARNING: intersection: figure of curve " + VICTIM)
    assert "intersection__curve__turn_T_TW_in_0" in fig and "not drawn" in fig
    assert "died" in fig
    [exp] = [w for w in lost if w is not fig]
    assert "exports (exports/intersection.add.xml, exports/intersection.dxf" in exp
    # ... in report.md, under the curve's heading, with no link to the missing figure
    md = got["report.md"].decode()
    part = md.split(f"### `{VICTIM}`")[1].split("###")[0]
    assert "\n\nFigure not drawn: the worker process died, also when it drew nothing else (a " \
           "worker process died (" in part
    assert "![" not in part and "Every vehicle, worst first:" in part
    assert "- CITY-BUS" in part and "(drawn)" not in part
    links = re.findall(r"\]\(([^)]+)\)", md)
    assert len(links) == 3 and all((out / link).is_file() for link in links)
    assert "Exports (exports/intersection.add.xml" in md.split("## Files")[0]
    # ... and in report.html: the curve's section says so instead of an image
    text = got["report.html"].decode()
    section = text.split(f"<code>{VICTIM.replace('>', '&gt;')}</code></h4>")[1]
    section = section.split("<h4")[0]
    assert "<p>Figure not drawn: the worker process died" in section
    assert "<img" not in section and "<li>CITY-BUS" in section
    normal_html = normal["report.html"].decode()
    assert text.count("<img") == normal_html.count("<img") - 1 == 3
    # every image embedded, nothing linked outside the page
    assert not re.findall(r'src="(?!data:image/png;base64,)', text)
    assert not re.findall(r'href="(?!#)', text)
    assert '<p class="lost">Exports (exports/intersection.add.xml' in text
    assert "<code>exports/intersection.dxf</code>" in normal_html
    assert "<code>exports/" not in text  # the Files list names no export not written


def test_a_drawing_whose_worker_dies_once_is_drawn_again_and_nothing_is_lost(
        normal, tmp_path):
    out = tmp_path / "report"
    once = tmp_path / "crashed-once"
    status, warnings = report(out, CrashingExecutor(2, frozenset({VICTIM}), str(once)))
    assert status == 0 and warnings == []
    assert once.exists()  # the worker did die, once
    got = files(out)
    assert sorted(got) == sorted(normal)
    for rel, data in got.items():
        assert data == normal[rel], rel
    assert "not drawn" not in got["report.md"].decode()


def exports_then(fn, record: str, crash: bool, *args):
    """Run ``fn(*args)``; for the exports drawing, note in the file ``record`` the names
    of the files it sent back, then with ``crash`` kill this worker (its files written,
    its result never sent)."""
    result = fn(*args)
    task = args[0]
    if isinstance(task, Drawing) and task.part == "exports":
        Path(record).write_text(",".join(sorted(result)))
        if crash:
            os.kill(os.getpid(), signal.SIGSEGV)
    return result


class ExportsWatched(LocalExecutor):
    """Local workers that note what the exports drawing sends back (:func:`exports_then`),
    and die after it with ``crash``; ``shares_disk`` as given."""

    def __init__(self, record: Path, crash: bool = False, shares_disk: bool = True) -> None:
        super().__init__(2)
        self.record, self.crash, self.shares_disk = str(record), crash, shares_disk

    def submit(self, fn, *args):
        return super().submit(exports_then, fn, self.record, self.crash, *args)


def exports_of(got: dict[str, bytes]) -> dict[str, bytes]:
    return {rel: data for rel, data in got.items() if rel.startswith("exports/")}


def test_local_workers_write_the_exports_in_place_the_same_as_sent_back(normal, tmp_path):
    # in place: the worker sends no file back, and the files are the usual ones ...
    sent = tmp_path / "sent.txt"
    assert report(tmp_path / "here", ExportsWatched(sent)) == (0, [])
    assert sent.read_text() == ""
    here = files(tmp_path / "here")
    assert len(exports_of(here)) == 3 and exports_of(here) == exports_of(normal)
    # ... byte for byte those a worker elsewhere (a cluster's) sends back
    assert report(tmp_path / "back", ExportsWatched(sent, shares_disk=False)) == (0, [])
    assert sent.read_text().split(",") == sorted(exports_of(normal))
    assert exports_of(files(tmp_path / "back")) == exports_of(normal)


def test_exports_a_worker_wrote_in_place_before_it_died_are_taken_out(normal, tmp_path):
    out = tmp_path / "report"
    status, warnings = report(out, ExportsWatched(tmp_path / "sent.txt", crash=True))
    assert status == 0
    got = files(out)
    # the lost exports leave no file behind (each was complete, but the report says they
    # are not drawn); everything else is as usual
    assert exports_of(got) == {}
    assert set(got) == set(normal) - set(exports_of(normal))
    assert any("exports (exports/intersection.add.xml" in w and "not drawn" in w
               for w in warnings), warnings


def dxf_blocked(fn, *args):
    """Run ``fn(*args)``, but first put a folder where the exports drawing's DXF goes (a
    file the worker cannot write in place)."""
    task = args[0]
    if isinstance(task, Drawing) and task.part == "exports" and task.task.into:
        name = dict(task.task.names)["dxf"]
        (Path(task.task.into) / "exports" / name).mkdir(parents=True)
    return fn(*args)


class DxfBlocked(LocalExecutor):
    def submit(self, fn, *args):
        return super().submit(dxf_blocked, fn, *args)


def test_an_export_a_worker_cannot_write_in_place_is_exit_2_naming_it(tmp_path, capsys):
    out = tmp_path / "report"
    status, _ = report(out, DxfBlocked(2))
    assert status == 2
    err = capsys.readouterr().err
    assert "intersection.dxf: is a directory" in err and "Traceback" not in err
    assert not out.exists()  # nothing swapped in: the folder is as it was (absent)
