"""The report's data files: ``clearance.csv`` and ``summary.json``.

Both are deterministic: identical inputs give byte-identical files (fixed column order and
rounding, sorted keys, no timestamps).
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from collections.abc import Mapping
from importlib import metadata
from pathlib import Path

import pandas as pd

from clearance.networks.provenance import read_header
from clearance.reports.results.provenance import header_summary, provenance_summary
from clearance.reports.results.units import to_output_units
from clearance.reports.results.waivers import Waived
from clearance.reports.study.run import VERDICT_ORDER, Study

__all__ = ["VERDICTS", "clearance_csv", "counts", "sha256_of", "summary", "summary_json",
           "waived_column"]

VERDICTS = tuple(sorted(VERDICT_ORDER, key=VERDICT_ORDER.__getitem__))  # worst first


def clearance_csv(study: Study, waived: Waived | None = None, units: str = "m") -> str:
    """``clearance.csv``: one row per network × vehicle × curve, lengths in ``units``
    rounded to three decimals (the millimetre in metres).

    In feet the length columns are named ``*_ft`` and the lengths in the reasons are in
    feet too (:func:`clearance.reports.results.units.to_output_units`). With ``waived`` (a report
    given ``--waivers``) a last column ``waived`` holds each waived run's reason (empty for the
    others), as its waiver file wrote it."""
    frame = study.frame()
    if waived is not None:
        frame["waived"] = waived_column(frame, waived)
    frame = to_output_units(frame, units, suffix=True)
    for col in frame.columns:
        if frame[col].dtype.kind == "f":
            frame[col] = frame[col].round(3)
    return frame.to_csv(index=False, lineterminator="\n", na_rep="")


def waived_column(frame: pd.DataFrame, waived: Waived) -> list[str]:
    """Each row's waiver reason, empty where the run is not waived."""
    return [waived.reasons.get(k, "") for k in zip(frame.network, frame.vehicle,
                                                   frame.curve_id, strict=True)]


def sha256_of(path: Path) -> str:
    """Hex SHA-256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "unknown"


def counts(frame: pd.DataFrame, by: str) -> dict[str, dict[str, int]]:
    """Verdict counts per value of ``by``, every verdict listed (worst first)."""
    out: dict[str, dict[str, int]] = {}
    for key, group in frame.groupby(by, sort=True):
        vc = group["verdict"].value_counts()
        out[str(key)] = {v: int(vc.get(v, 0)) for v in VERDICTS}
    return out


def paths(frame: pd.DataFrame) -> dict[str, object]:
    """How many runs took a swung path (:mod:`clearance.networks.driving.swing`), what those
    encroach on, and how many runs the search made better than their lane's verdict.

    Examples
    --------
    >>> f = pd.DataFrame({"path": ["lane", "swung", "swung"],
    ...                   "verdict": ["clear", "encroaches", "fails"],
    ...                   "lane_verdict": ["clear", "fails", "fails"],
    ...                   "encroaches_on": ["", "opposing lanes", "shoulder"]})
    >>> paths(f)
    {'swung': 2, 'better_than_lane': 1, 'swung_encroaches_on': {'opposing lanes': 1, 'shoulder': 1}}
    """
    swung = frame[frame.path == "swung"]
    better = swung.verdict.map(VERDICT_ORDER) > swung.lane_verdict.map(VERDICT_ORDER)
    on = Counter(x for x in swung.encroaches_on if x)
    return {"swung": len(swung), "better_than_lane": int(better.sum()),
            "swung_encroaches_on": dict(sorted(on.items()))}


def summary(study: Study, vehicle_tables: list[Path],
            waived: Waived | None = None,
            routes: Mapping[str, object] | None = None) -> dict[str, object]:
    """The ``summary.json`` content (with ``waived`` counts when given waivers, and per
    route and vehicle when given a route study's summary)."""
    frame = study.frame()
    worst = frame.assign(_o=frame.verdict.map(VERDICT_ORDER)).sort_values(
        ["_o", "margin_m", "network", "curve_id", "vehicle"], kind="stable")
    out: dict[str, object] = {
        "method": study.method,
        "clearance_m": study.clearance_m,
        "runs": len(frame),
        "verdicts": {v: int((frame.verdict == v).sum()) for v in VERDICTS},
        "by_network": counts(frame, "network"),
        "by_vehicle": counts(frame, "vehicle"),
        "paths": paths(frame),
        "geometry": provenance_summary(frame),
        "vertical": {
            "max_grade_pct": study.max_grade_pct,
            "findings": {f: int(frame.vertical.str.contains(f, regex=False).sum())
                         for f in ("scrapes", "too-steep")},
            "suspect_elevation_curves": int(frame[frame.suspect_elevation != ""]
                                            .drop_duplicates(["network", "curve_id"]).shape[0]),
        },
        "not_permitted": {
            "runs": len(study.not_permitted),
            "by_vehicle": dict(sorted(Counter(v for _, v, _ in study.not_permitted).items())),
        },
        "worst": [
            {"network": r.network, "vehicle": r.vehicle, "curve_id": r.curve_id,
             "verdict": r.verdict, "margin_m": round(float(r.margin_m), 3)}
            for r in worst.head(10).itertuples()
        ],
        "inputs": {
            "networks": [{"name": n.name, "path": str(n.path), "sha256": sha256_of(n.path),
                          "junctions": sum(not j.startswith(":")
                                           for j in n.network.junctions),
                          "curves": len(n.curves),
                          **header_summary(read_header(n.path))} for n in study.networks],
            "vehicle_tables": [{"path": str(p), "sha256": sha256_of(p)}
                               for p in vehicle_tables],
            "vehicles": list(study.table.names),
        },
        "versions": {"clearance": _version("sumo-clearance"),
                     "sumo": _version("eclipse-sumo"), "libsumo": _version("libsumo")},
    }
    if waived is not None:
        is_waived = [bool(r) for r in waived_column(frame, waived)]
        w = frame[pd.Series(is_waived, index=frame.index, dtype=bool)]
        out["waived"] = {
            "runs": len(w),
            "verdicts": {v: int((w.verdict == v).sum()) for v in VERDICTS},
            "by_vehicle": {str(k): int(n) for k, n in w.vehicle.value_counts().items()},
            "not_clear_and_not_waived": int(((frame.verdict != "clear")
                                             & ~frame.index.isin(w.index)).sum()),
            "unused_waivers": [x.where for x in waived.unused],
        }
    if routes is not None:
        out["routes"] = routes
    return out


def summary_json(study: Study, vehicle_tables: list[Path],
                 waived: Waived | None = None, routes: Mapping[str, object] | None = None) -> str:
    """``summary.json`` as text (sorted keys, two-space indent, trailing newline)."""
    return json.dumps(summary(study, vehicle_tables, waived, routes), indent=2,
                      sort_keys=True) + "\n"
