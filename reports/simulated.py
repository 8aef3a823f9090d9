"""The simulate method of a study: every run driven through libsumo (:mod:`networks.driver`).

Runs go to the driver in chunks (one SUMO simulation each, up to a hundred vehicles in
flight), so that the progress bar moves and FCD files stay a manageable size.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

from networks.driver import DrivenRun, DriveOptions, drive
from reports.analytic import minimum_ctr_m
from reports.study import NetworkCurves, RunRecord
from vehicles.vehicle import Vehicle

#: Runs handed to one SUMO simulation.
CHUNK = 400


def _record(nc: NetworkCurves, r: DrivenRun, clearance_m: float) -> RunRecord:
    res, curve, v = r.result, r.curve, r.vehicle
    nan = math.nan
    return RunRecord(
        network=nc.name, vehicle=v.name, curve_id=curve.curve_id, kind=curve.kind,
        junction=curve.junction, verdict=r.verdict,
        margin_m=res.clearance.margin_m if res else nan,
        paved_margin_m=res.clearance.paved_margin_m if res else nan,
        curve_radius_m=curve.min_radius_m, vehicle_min_radius_m=minimum_ctr_m(v),
        swept_width_m=res.swept.max_swept_width_m if res else nan,
        available_width_m=curve.lane_width_m,
        max_offtracking_m=res.swept.max_offtracking_m if res else nan,
        max_tracking_error_m=r.run.max_error_m if r.run else nan,
        turn_angle_deg=curve.turn_angle_deg, max_grade_pct=curve.max_grade_pct,
        method="simulate", clearance_m=clearance_m, reason=r.reason,
        envelope=res.measured if res else None,
    )


def simulated_records(nc: NetworkCurves, vehicles: list[Vehicle], clearance_m: float,
                      update: Callable[[int], None], fcd_dir: Path | None = None
                      ) -> list[RunRecord]:
    """Drive every vehicle through every curve of ``nc`` in libsumo."""
    pairs = [(v, c) for c in nc.curves for v in vehicles]
    records: list[RunRecord] = []
    for k in range(0, len(pairs), CHUNK):
        chunk = pairs[k:k + CHUNK]
        fcd = None
        if fcd_dir is not None:
            fcd_dir.mkdir(parents=True, exist_ok=True)
            fcd = fcd_dir / f"{nc.name}_{k // CHUNK:03d}.fcd.xml"
        options = DriveOptions(offset_m=clearance_m, fcd_output=fcd)
        records += [_record(nc, r, clearance_m) for r in drive(nc.network, chunk,
                                                               options=options)]
        update(len(chunk))
    return records
