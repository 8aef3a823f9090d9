"""The report's drawing phase (clearance.reports.documents.drawings): every drawing written
and counted on the phase's own progress bar, as the study's bar counts its runs."""

from __future__ import annotations

from pathlib import Path

from clearance.reports.documents import drawings as drawings_module
from clearance.reports.documents.drawings import Drawing, Drawings
from clearance.reports.study.executor import LocalExecutor

NET = Path(__file__).resolve().parents[2] / "networks" / "samples" / "intersection" / \
    "intersection.net.xml"


def one_file(task: str, shared: object) -> dict[str, bytes]:
    """A drawing of a worker: one small file named by its task."""
    return {f"figures/{task}.txt": task.encode()}


def test_the_drawing_phase_has_its_own_progress_bar(tmp_path, monkeypatch):
    bars: list[tuple[int, str, str]] = []
    counted: list[int] = []

    def bar(total: int, desc: str, unit: str = "run"):
        bars.append((total, desc, unit))
        return counted.append

    monkeypatch.setattr(drawings_module, "progress_bar", bar)
    with LocalExecutor(1) as ex:
        d = Drawings(ex, tmp_path)
        for k in range(5):
            d.submit(Drawing(one_file, f"f{k}", "intersection", "figure", f"figure {k}"), NET)
        d.finish()
    assert bars == [(5, "drawing figures, sheets, exports", "drawing")]
    assert sum(counted) == 5  # each drawing counted once it is written
    assert sorted(p.name for p in (tmp_path / "figures").iterdir()) == [
        f"f{k}.txt" for k in range(5)]
