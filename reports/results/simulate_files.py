"""The files of ``clearance simulate -o DIR``: results.csv, one trajectory CSV per run, the
envelopes as GeoJSON; the rows filled by the same definitions as ``clearance report``'s
clearance.csv (:func:`run_records`, :mod:`clearance.reports.results.feedback`); with
``--fcd`` the runs' chosen paths as a sumo-gui additional file (:func:`paths_additional`)."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np
from lxml import etree
from shapely.geometry import LineString

from clearance.networks.driving.drive import (
    DrivenRun,
)
from clearance.networks.model import Network
from clearance.networks.sumo.placement import front_bumper
from clearance.reports.exports.envelopes import VERDICT_RGBA, EnvelopeRecord
from clearance.reports.exports.geojson import write_geojson
from clearance.reports.exports.sumo import VERDICT_LAYER, sumo_id
from clearance.reports.output.atomic import write_bytes_atomic, write_text_atomic
from clearance.reports.output.file_names import file_name
from clearance.reports.output.output_dir import Layout
from clearance.reports.results.feedback import set_serves_up_to
from clearance.reports.results.records import RunRecord
from clearance.reports.study.batch import (
    driven_record,
)
from clearance.reports.study.run import network_name
from clearance.vehicles.table import VehicleTable

__all__ = ["LAYOUT", "PATH_LINE_WIDTH_M", "PATH_POINT", "PATHS_FILE", "RESULT_COLUMNS",
           "TRAILER_COLUMNS", "TRAJECTORY_COLUMNS", "csv_text", "envelope_records",
           "paths_additional", "result_row", "run_records", "trajectory_csv",
           "trajectory_files", "write_outputs", "write_paths"]


#: Columns of ``results.csv``.
RESULT_COLUMNS = (
    "vehicle",
    "curve_id",
    "kind",
    "verdict",
    "margin_m",
    "paved_margin_m",
    "max_offtracking_m",
    "max_tracking_error_m",
    "swept_width_m",
    "sumo_max_deviation_m",
    "sumo_steps",
    "lane_verdict",
    "lane_margin_m",
    "path",
    "encroaches_on",
    "reason",
    "serves_up_to",
    "serves_encroaching_up_to",
    "overreach_station_m",
    "overreach_x",
    "overreach_y",
    "extra_width_m",
)


#: Columns of a trajectory CSV (the trailer's only for a vehicle with one).
TRAJECTORY_COLUMNS = ("t_s", "s_m", "x_m", "y_m", "theta_rad", "phi_rad", "xf_m", "yf_m",
                      "error_m", "speed_m_s")


TRAILER_COLUMNS = ("xt_m", "yt_m", "theta_t_rad", "psi_rad")


#: What simulate writes into its output folder (the folder it may replace holds nothing else).
LAYOUT = Layout(
    "simulate",
    files=frozenset({"results.csv", "envelopes.geojson", "fcd.xml", "replay.sumocfg",
                     "replay.sh", "paths.add.xml"}),
    folders={"trajectories": (".csv",)},
    signature=("results.csv", ",".join(RESULT_COLUMNS[:4])),
)


def _num(value: float | None, digits: int = 3) -> str:
    """A fixed-point number; ``nan``/``None`` is empty, ``-0.000`` is ``0.000``."""
    if value is None or not math.isfinite(value):
        return "" if value is None or math.isnan(value) else str(value)
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def run_records(runs: Sequence[DrivenRun], table: VehicleTable, clearance_m: float,
                network: str = "") -> list[RunRecord]:
    """The runs as ``clearance report`` records them
    (:func:`clearance.reports.study.batch.driven_record`):
    each run's worst overreach (said in its reason) and, per curve over ``table``'s vehicles
    run on it, the largest it serves
    (:func:`clearance.reports.results.feedback.set_serves_up_to`)."""
    records = [driven_record(network, r, clearance_m, conflict=False) for r in runs]
    set_serves_up_to(records, table)
    return records


def result_row(r: DrivenRun, rec: RunRecord) -> dict[str, str]:
    """One ``results.csv`` row (metres to the millimetre): the run's measures, and its
    record's (:func:`run_records`) reason and design feedback."""
    res = r.result
    return {
        "vehicle": r.vehicle.name,
        "curve_id": r.curve.curve_id,
        "kind": r.curve.kind,
        "verdict": r.verdict,
        "margin_m": _num(res.clearance.margin_m if res else None),
        "paved_margin_m": _num(res.clearance.paved_margin_m if res else None),
        "max_offtracking_m": _num(res.swept.max_offtracking_m if res else None),
        "max_tracking_error_m": _num(r.run.max_error_m if r.run else None),
        "swept_width_m": _num(res.swept.max_swept_width_m if res else None),
        "sumo_max_deviation_m": _num(r.sumo_max_deviation_m, 4),
        "sumo_steps": str(r.sumo_steps),
        "lane_verdict": r.lane_verdict,
        "lane_margin_m": _num(r.lane_margin_m),
        "path": r.path,
        "encroaches_on": r.encroaches_on,
        "reason": rec.reason,
        "serves_up_to": rec.serves_up_to,
        "serves_encroaching_up_to": rec.serves_encroaching_up_to,
        "overreach_station_m": _num(rec.overreach_station_m),
        "overreach_x": _num(rec.overreach_x),
        "overreach_y": _num(rec.overreach_y),
        "extra_width_m": _num(rec.extra_width_m),
    }


def csv_text(rows: Iterable[dict[str, str]], columns: Sequence[str]) -> str:
    """CSV with ``\\n`` line ends."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(columns), lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    return buf.getvalue()


def trajectory_files(runs: Sequence[DrivenRun]) -> list[str]:
    """``<vehicle>__<curve>.csv`` for each run
    (:func:`clearance.reports.output.file_names.file_name`)."""
    return [file_name([r.vehicle.name, r.curve.curve_id], ".csv") for r in runs]


def trajectory_csv(r: DrivenRun) -> str:
    """The model's states of one run as CSV (4 decimals)."""
    tr = r.run.trajectory if r.run is not None else None
    assert tr is not None
    cols = list(TRAJECTORY_COLUMNS)
    if tr.xt_m is not None:
        cols += TRAILER_COLUMNS
    data = np.column_stack([getattr(tr, c) for c in cols])
    data = np.round(data, 4) + 0.0  # + 0.0 turns -0.0 into 0.0
    lines = [",".join(cols)]
    lines += [",".join(f"{v:.4f}" for v in row) for row in data]
    return "\n".join(lines) + "\n"


def envelope_records(runs: Sequence[DrivenRun], network: str) -> list[EnvelopeRecord]:
    """The runs' swept envelopes as export records (runs SUMO failed are left out)."""
    return [EnvelopeRecord(network, r.vehicle.name, r.curve.curve_id, r.curve.kind,
                           r.result.verdict, r.result.margin_m, r.result.swept.envelope)
            for r in runs if r.result is not None and not r.error]


def write_outputs(out_dir: Path, runs: Sequence[DrivenRun], rows: Sequence[dict[str, str]],
                  net: Network) -> None:
    """results.csv, envelopes.geojson and one trajectory CSV per run, each atomically."""
    for r, name in zip(runs, trajectory_files(runs), strict=True):
        if r.run is None:
            continue
        write_text_atomic(out_dir / "trajectories" / name, trajectory_csv(r))
    name = network_name(Path(net.path))
    write_geojson(out_dir / "envelopes.geojson", envelope_records(runs, name),
                  {name: net.location})
    write_text_atomic(out_dir / "results.csv", csv_text(rows, RESULT_COLUMNS))


#: The chosen paths' additional file of ``clearance simulate --fcd`` (beside ``fcd.xml``).
PATHS_FILE = "paths.add.xml"

#: Width of a drawn path in sumo-gui (m): a thin line over the lanes.
PATH_LINE_WIDTH_M = 0.15

#: What a drawn path is: SUMO's reference point, the one the FCD output places.
PATH_POINT = "front-bumper centre"

_ERROR_RGBA = (128, 128, 128, 255)


def paths_additional(runs: Sequence[DrivenRun], network: str = "") -> bytes:
    """A sumo-gui additional file that draws each run's chosen path (XML bytes).

    The path drawn is that of the **front-bumper centre** (SUMO's reference point, what the
    FCD output places; not the front axle's) along the trajectory the run's verdict rests
    on (:attr:`~clearance.networks.driving.runs.DrivenRun.chosen_run`: the swung path where
    one was taken, the lane's otherwise), in the network's coordinates, to the millimetre
    (points within 5 mm of a straight line between their neighbours left out).

    Each run is one ``<poly>``, a line (``fill="0"``, ``lineWidth`` :data:`PATH_LINE_WIDTH_M`),
    ``id="path:<vehicle>:<curve>"`` (SUMO-safe, a suffix where two come out equal),
    ``type="path:<verdict>"``, opaque in the verdict's colour
    (:data:`~clearance.reports.exports.envelopes.VERDICT_RGBA`; grey for a run with an
    error), on a layer above the swept envelopes'; its ``<param>`` children: network,
    vehicle, curve_id, kind, verdict, path (``lane`` or ``swung``), swing_m, margin_m,
    point (``front-bumper centre``) and sumo_vehicle (the run's id in the FCD output). A run
    that was not modelled is left out.

    Examples
    --------
    >>> text = paths_additional([]).decode()
    >>> text.splitlines()[1].startswith("<additional")
    True
    """
    root = etree.Element("additional")
    root.set("{http://www.w3.org/2001/XMLSchema-instance}noNamespaceSchemaLocation",
             "http://sumo.dlr.de/xsd/additional_file.xsd")
    used: set[str] = set()
    for r in runs:
        run = r.chosen_run
        if run is None:
            continue
        line = LineString(np.column_stack(front_bumper(run))).simplify(0.005)
        if line.length <= 0.0:
            continue
        base = f"path:{sumo_id(r.vehicle.name)}:{sumo_id(r.curve.curve_id)}"
        pid, k = base, 1
        while pid in used:
            k += 1
            pid = f"{base}~{k}"
        used.add(pid)
        verdict = r.verdict
        rgba = (*VERDICT_RGBA[verdict][:3], 255) if verdict in VERDICT_RGBA else _ERROR_RGBA
        poly = etree.SubElement(root, "poly", id=pid, type=f"path:{verdict}",
                                color=",".join(map(str, rgba)), fill="0",
                                lineWidth=f"{PATH_LINE_WIDTH_M:g}",
                                layer=str(VERDICT_LAYER.get(verdict, 9) + 10),
                                shape=" ".join(f"{_num(x)},{_num(y)}"
                                               for x, y, *_ in line.coords))
        params = {"network": network, "vehicle": r.vehicle.name, "curve_id": r.curve.curve_id,
                  "kind": r.curve.kind, "verdict": verdict, "path": r.path,
                  "swing_m": _num(r.swing_m),
                  "margin_m": _num(r.result.margin_m if r.result and not r.error else None),
                  "point": PATH_POINT, "sumo_vehicle": r.sumo_vehicle}
        for key, value in params.items():
            if value:
                etree.SubElement(poly, "param", key=key, value=value)
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def write_paths(path: Path, runs: Sequence[DrivenRun], network: str = "") -> Path:
    """Write :func:`paths_additional` to ``path`` atomically."""
    return write_bytes_atomic(path, paths_additional(runs, network))
