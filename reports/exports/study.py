"""A study's export files, per network: the runs as envelope records, the bodies and wheel
paths of the worst runs, and the sumo-gui, DXF and GeoJSON files written from them."""

from __future__ import annotations

from pathlib import Path

from clearance.reports.documents.figures import (
    worst_by_curve,
)
from clearance.reports.exports.envelopes import EnvelopeRecord, conflict_parts
from clearance.reports.exports.geojson import lonlat_transformer
from clearance.reports.output.file_names import file_name
from clearance.reports.results.feedback import overreach_point
from clearance.reports.study.run import (
    NetworkCurves,
    Study,
)

__all__ = ["DRAWN_RUNS", "drawn_geometry", "envelope_records", "export_names", "georeferenced",
           "write_exports", "write_network_exports"]


#: Runs whose vehicle bodies and wheel paths the CAD export draws, per network: the worst
#: run of each of the worst curves, as many as the report draws (they are driven again).
DRAWN_RUNS = 60


def drawn_geometry(study: Study, limit: int = DRAWN_RUNS
                   ) -> dict[tuple[str, str, str], tuple[tuple, tuple]]:
    """Body outlines and wheel paths of the worst run of each of the ``limit`` worst curves
    of every network (not clear ones first; see
    :func:`clearance.reports.documents.drawing.run_geometry`), by
    (network, vehicle, curve id). The runs are driven again without SUMO (the same model,
    so the same paths)."""
    from clearance.reports.documents.drawing import rerun, run_geometry

    out: dict[tuple[str, str, str], tuple[tuple, tuple]] = {}
    if study.method != "simulate":
        return out
    frame = study.frame()
    vehicles = {v.name: v for v in study.table.vehicles()}
    for nc in study.networks:
        f = frame[(frame.network == nc.name) & (frame.verdict != "error")]
        if f.empty:
            continue
        by_id = {c.curve_id: c for c in nc.curves}
        records = {(r.vehicle, r.curve_id): r for r in study.records if r.network == nc.name}
        for row in worst_by_curve(f).head(limit).itertuples():
            curve = by_id[row.curve_id]
            [driven] = rerun(nc, curve, [vehicles[row.vehicle]],
                             [records[(row.vehicle, row.curve_id)]], study.clearance_m)
            out[(nc.name, row.vehicle, row.curve_id)] = run_geometry(curve, driven)
    return out


def envelope_records(study: Study,
                     drawn: dict[tuple[str, str, str], tuple[tuple, tuple]] | None = None
                     ) -> list[EnvelopeRecord]:
    """The exportable runs of ``study``: envelope, offset, conflict with the curve's areas,
    and the body outlines and wheel paths of the runs in ``drawn``
    (:func:`drawn_geometry`)."""
    curves = {(n.name, c.curve_id): c for n in study.networks for c in n.curves}
    drawn = drawn or {}
    out = []
    for r in study.records:
        if r.verdict == "error" or r.envelope is None or r.envelope.is_empty:
            continue
        if r.conflict is not None:  # measured by the worker that ran it
            outside_lanes, outside_pavement = r.conflict
        else:
            curve = curves.get((r.network, r.curve_id))
            lanes, paved = (curve.own_lanes, curve.paved) if curve is not None else (None, None)
            outside_lanes, outside_pavement = conflict_parts(r.envelope, lanes, paved)
        out.append(EnvelopeRecord(
            r.network, r.vehicle, r.curve_id, r.kind, r.verdict, r.margin_m, r.envelope,
            offset_m=r.clearance_m, outside_lanes=outside_lanes,
            outside_pavement=outside_pavement,
            body_outlines=drawn.get((r.network, r.vehicle, r.curve_id), ((), ()))[0],
            wheel_paths=drawn.get((r.network, r.vehicle, r.curve_id), ((), ()))[1],
            overreach=overreach_point(r)))
    return out


def export_names(network: str, georeferenced: bool) -> dict[str, str]:
    """The export files of one network under ``exports/``: sumo-gui, DXF, GeoJSON.

    >>> export_names("roundabout", False)["geojson"]
    'roundabout.local-metres.geojson'
    """
    return {"sumo": file_name([network], ".add.xml"), "dxf": file_name([network], ".dxf"),
            "geojson": file_name([network], ".geojson" if georeferenced
                                 else ".local-metres.geojson")}


def georeferenced(nc: NetworkCurves, origin: tuple[float, float] | None) -> bool:
    return origin is not None or lonlat_transformer(nc.name, nc.network.location) is not None


def write_network_exports(out: Path, records: list[EnvelopeRecord], nc: NetworkCurves,
                           names: dict[str, str], origin: tuple[float, float] | None) -> None:
    from clearance.reports.exports.dxf import write_dxf
    from clearance.reports.exports.geojson import write_geojson
    from clearance.reports.exports.sumo import write_sumo_additional

    write_sumo_additional(out / names["sumo"], records)
    write_dxf(out / names["dxf"], records, nc.network)
    write_geojson(out / names["geojson"], records, {nc.name: nc.network.location}, origin)


def write_exports(study: Study, folder: Path, origin: tuple[float, float] | None = None
                  ) -> dict[str, dict[str, str]]:
    """Each network's sumo-gui additional file, DXF and GeoJSON under ``folder/exports``
    (:func:`export_names`); returns the names written by network."""
    from clearance.reports.exports.envelopes import by_network

    groups = by_network(envelope_records(study, drawn_geometry(study)))
    written = {}
    for nc in study.networks:
        names = export_names(nc.name, georeferenced(nc, origin))
        write_network_exports(folder / "exports", groups.get(nc.name, []), nc, names, origin)
        written[nc.name] = names
    return written
