"""The report's data files: ``clearance.csv`` and ``summary.json``.

Both are deterministic: identical inputs give byte-identical files (fixed column order and
rounding, sorted keys, no timestamps).
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from importlib import metadata
from pathlib import Path

import pandas as pd

from reports.study import VERDICT_ORDER, Study

VERDICTS = tuple(sorted(VERDICT_ORDER, key=VERDICT_ORDER.get))  # worst first


def clearance_csv(study: Study) -> str:
    """``clearance.csv``: one row per network × vehicle × curve, lengths rounded to mm."""
    frame = study.frame()
    for col in frame.columns:
        if frame[col].dtype.kind == "f":
            frame[col] = frame[col].round(3)
    return frame.to_csv(index=False, lineterminator="\n", na_rep="")


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


def summary(study: Study, vehicle_tables: list[Path]) -> dict[str, object]:
    """The ``summary.json`` content."""
    frame = study.frame()
    worst = frame.assign(_o=frame.verdict.map(VERDICT_ORDER)).sort_values(
        ["_o", "margin_m", "network", "curve_id", "vehicle"], kind="stable")
    return {
        "method": study.method,
        "clearance_m": study.clearance_m,
        "runs": len(frame),
        "verdicts": {v: int((frame.verdict == v).sum()) for v in VERDICTS},
        "by_network": counts(frame, "network"),
        "by_vehicle": counts(frame, "vehicle"),
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
                          "curves": len(n.curves)} for n in study.networks],
            "vehicle_tables": [{"path": str(p), "sha256": sha256_of(p)}
                               for p in vehicle_tables],
            "vehicles": list(study.table.names),
        },
        "versions": {"clearance": _version("sumo-clearance"),
                     "sumo": _version("eclipse-sumo"), "libsumo": _version("libsumo")},
    }


def summary_json(study: Study, vehicle_tables: list[Path]) -> str:
    """``summary.json`` as text (sorted keys, two-space indent, trailing newline)."""
    return json.dumps(summary(study, vehicle_tables), indent=2, sort_keys=True) + "\n"
