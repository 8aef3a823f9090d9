"""Golden verdict files for ``clearance check --expect`` and ``--write-golden``.

A golden file lists the verdicts the networks are meant to produce, one row per network ×
vehicle × curve, with the csv module's quoting (:mod:`clearance.reports.results.csv_rows`): columns
``network, vehicle, curve_id, verdict`` (required) and ``kind, junction, margin_m``
(written for information and for selections; optional when read). Comment lines (``#`` in
the first column) may come before the header only; after it every line is data, so curve
ids with ``#`` (most ids of OpenStreetMap networks) read back as written.

:func:`compare` sorts the runs of a study against a golden file: verdicts worse than
expected (and expected runs missing on a curve that is still there), better ones, curves
the golden file does not know (*new*), and known curves the study no longer has (*gone*).
"""

from __future__ import annotations

import io
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from clearance.networks.selection import Selection
from clearance.reports.results.csv_rows import read_rows
from clearance.reports.results.records import VERDICT_ORDER
from clearance.vehicles.errors import InputError

__all__ = ["Comparison", "GOLDEN_COLUMNS", "HEADER", "Key", "WRITTEN_COLUMNS", "compare",
           "golden_text", "read_golden", "relevant"]

GOLDEN_COLUMNS = ["network", "vehicle", "curve_id", "verdict"]
#: Columns a golden file is written with.
WRITTEN_COLUMNS = GOLDEN_COLUMNS + ["kind", "junction", "margin_m"]

HEADER = ("# Verdicts the networks are designed to produce (clearance check --expect).\n"
          "# Regenerate with: clearance check ... --write-golden FILE\n")

#: A run's key: network, vehicle, curve id.
Key = tuple[str, str, str]


def read_golden(path: Path) -> pd.DataFrame:
    """A golden file as a frame with ``network, vehicle, curve_id, verdict, kind,
    junction, line`` (``kind`` from the id's prefix and ``junction`` empty when the file
    has no such column).

    Raises
    ------
    InputError
        A missing or malformed file, an unknown verdict, an empty field, or the same
        network, vehicle and curve twice: the message names the file and line.
    """
    header, rows = read_rows(path, "golden file", GOLDEN_COLUMNS)
    seen: dict[Key, int] = {}
    records = []
    for line, row in rows:
        for col in GOLDEN_COLUMNS:
            if not row[col].strip():
                raise InputError(f"{path}:{line}: empty {col}")
        if row["verdict"] not in VERDICT_ORDER:
            raise InputError(f"{path}:{line}: unknown verdict {row['verdict']!r}; use one of "
                             f"{', '.join(VERDICT_ORDER)}")
        key = (row["network"], row["vehicle"], row["curve_id"])
        if key in seen:
            raise InputError(f"{path}:{line}: the same network, vehicle and curve as line "
                             f"{seen[key]}")
        seen[key] = line
        kind = row.get("kind") or row["curve_id"].split(":", 1)[0]
        records.append((*key, row["verdict"], kind, row.get("junction", ""), line))
    return pd.DataFrame(records, columns=GOLDEN_COLUMNS + ["kind", "junction", "line"])


def _margin(m: float) -> str:
    return f"{m:.2f}" if math.isfinite(m) else ""


def golden_text(frame: pd.DataFrame) -> str:
    """The golden file of a study frame (kind, junction and margin kept for information).

    Examples
    --------
    >>> f = pd.DataFrame({"network": ["n"], "vehicle": ["P"], "verdict": ["clear"],
    ...                   "curve_id": ["turn:1:a#2_0->b_0"], "kind": ["turn"],
    ...                   "junction": ["1"], "margin_m": [0.123]})
    >>> print(golden_text(f).splitlines()[-1])
    n,P,turn:1:a#2_0->b_0,clear,turn,1,0.12
    """
    import csv

    out = io.StringIO()
    out.write(HEADER)
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(WRITTEN_COLUMNS)
    for r in frame.itertuples(index=False):
        writer.writerow([r.network, r.vehicle, r.curve_id, r.verdict, r.kind, r.junction,
                         _margin(float(r.margin_m))])
    return out.getvalue()


@dataclass
class Comparison:
    """A study's runs against a golden file (each list: one line of text per finding)."""

    expected: int = 0
    worse: list[str] = field(default_factory=list)
    worse_waived: list[str] = field(default_factory=list)
    better: list[str] = field(default_factory=list)
    new_curves: list[str] = field(default_factory=list)
    new_runs: list[str] = field(default_factory=list)
    gone_curves: list[str] = field(default_factory=list)
    gone_runs: int = 0  # the golden runs of the gone curves

    @property
    def as_expected(self) -> int:
        """Expected runs found with their golden verdict."""
        return (self.expected - len(self.worse) - len(self.worse_waived) - len(self.better)
                - self.gone_runs)


def relevant(golden: pd.DataFrame, vehicles: Iterable[str], networks: Iterable[str],
             found_curves: set[tuple[str, str]],
             selection: Selection | None = None) -> tuple[pd.DataFrame, int, int]:
    """The golden rows a study can judge; how many rows of its vehicles and networks lie
    outside its selection; how many could not be judged.

    A row is judged when its vehicle and network are in the study and its curve is either
    found or, when not found, would have been selected (it is then *gone*). A curve not
    found is outside the selection when its kind is not one the study extracted, or the
    selection has junctions and the file's ``junction`` column names another. With a
    bounding box, or a junction selection and a file without junctions, a curve that is
    not found and not known to be outside cannot be told apart from one outside the
    selection: its rows are not judged (counted, not gone).

    Examples
    --------
    >>> g = pd.DataFrame({"network": ["n"] * 3, "vehicle": ["P"] * 3,
    ...                   "curve_id": ["turn:J1:a", "turn:J2:b", "ramp:c"],
    ...                   "verdict": ["clear"] * 3, "kind": ["turn", "turn", "ramp"],
    ...                   "junction": ["J1", "J2", "J3"]})
    >>> judged, outside, unknown = relevant(g, ["P"], ["n"], {("n", "turn:J1:a")},
    ...                                     Selection(kinds=("turn",), junctions=("J1",)))
    >>> list(judged.curve_id), outside, unknown
    (['turn:J1:a'], 2, 0)
    >>> judged, outside, unknown = relevant(g, ["P"], ["n"], set(), Selection(kinds=("turn",)))
    >>> list(judged.curve_id), outside, unknown
    (['turn:J1:a', 'turn:J2:b'], 1, 0)
    >>> relevant(g, ["P"], ["n"], set(), Selection(bbox=(0, 0, 1, 1)))[1:]
    (0, 3)
    """
    vehicles, networks = set(vehicles), set(networks)
    g = golden[golden.vehicle.isin(vehicles) & golden.network.isin(networks)]
    found = pd.Series([(n, c) in found_curves for n, c in zip(g.network, g.curve_id,
                                                              strict=True)],
                      index=g.index, dtype=bool)
    selection = selection or Selection()
    outside = ~g.kind.isin(selection.effective_kinds())
    undecidable = pd.Series(selection.bbox is not None, index=g.index, dtype=bool)
    if selection.junctions:
        named = g.junction != ""
        outside |= named & ~g.junction.isin(selection.junctions)
        undecidable |= ~named
    outside &= ~found
    unknown = ~found & ~outside & undecidable
    keep = ~outside & ~unknown
    return g[keep], int(outside.sum()), int(unknown.sum())


def compare(found: pd.DataFrame, golden: pd.DataFrame,
            waived: Mapping[Key, str] | None = None) -> Comparison:
    """Sort the runs of ``found`` (a study frame) against the ``golden`` rows to judge.

    A run worse than its golden verdict is a regression unless ``waived`` (run key ->
    reason) waives it; an expected run missing on a curve the study has is a regression
    too. A curve of ``found`` with no golden row is new; a run of a known curve with no
    golden row (a vehicle added) is a new run; a golden curve with no run is gone.
    """
    waived = waived or {}
    key = ["network", "vehicle", "curve_id"]
    out = Comparison(expected=len(golden))
    found_curves = set(zip(found.network, found.curve_id, strict=True))
    golden_curves = set(zip(golden.network, golden.curve_id, strict=True))
    merged = golden.merge(found[key + ["verdict", "margin_m"]], on=key, how="left",
                          suffixes=("_golden", ""))
    gone: dict[tuple[str, str], list[str]] = {}
    for r in merged.itertuples():
        where = f"{r.network}: {r.curve_id}: {r.vehicle}"
        if pd.isna(r.verdict):
            if (r.network, r.curve_id) in found_curves:
                out.worse.append(f"{where}: no such run any more (expected "
                                 f"{r.verdict_golden})")
            else:
                gone.setdefault((r.network, r.curve_id), []).append(
                    f"{r.vehicle} {r.verdict_golden}")
            continue
        now, then = VERDICT_ORDER[r.verdict], VERDICT_ORDER[r.verdict_golden]
        if now < then:
            text = f"{where}: {r.verdict} ({r.margin_m:+.2f} m), expected {r.verdict_golden}"
            reason = waived.get((r.network, r.vehicle, r.curve_id))
            if reason:
                out.worse_waived.append(f"{text}; waived: {reason}")
            else:
                out.worse.append(text)
        elif now > then:
            out.better.append(f"{where}: {r.verdict} ({r.margin_m:+.2f} m), golden says "
                              f"{r.verdict_golden}")
    for (net, cid), runs in gone.items():
        out.gone_runs += len(runs)
        out.gone_curves.append(f"{net}: {cid} (expected {', '.join(runs)})")
    known = set(zip(golden.network, golden.vehicle, golden.curve_id, strict=True))
    new: dict[tuple[str, str], list[str]] = {}
    for r in found.itertuples():
        if (r.network, r.vehicle, r.curve_id) in known:
            continue
        run = f"{r.vehicle} {r.verdict} ({r.margin_m:+.2f} m)"
        if (r.network, r.curve_id) in golden_curves:
            out.new_runs.append(f"{r.network}: {r.curve_id}: {run}")
        else:
            new.setdefault((r.network, r.curve_id), []).append(run)
    for (net, cid), runs in new.items():
        out.new_curves.append(f"{net}: {cid} ({', '.join(runs)})")
    return out
