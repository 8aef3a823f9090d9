"""Exports of the clearance report: swept envelopes for GIS, sumo-gui and CAD.

Each writer takes plain :class:`EnvelopeRecord` objects (one per vehicle and curve), checks
them, and writes one file atomically. All three sort the records by network, vehicle and
curve id, so identical inputs give identical files.

- :func:`write_geojson` (``reports.export_geojson``): a GeoJSON FeatureCollection in WGS84
  longitude/latitude when every network has a projection, in local metres otherwise;
- :func:`write_sumo_additional` (``reports.export_sumo``): SUMO ``<poly>`` shapes for
  ``sumo-gui -n NET -a swept.add.xml``;
- :func:`write_dxf` (``reports.export_dxf``): a DXF drawing in metres, one layer per
  vehicle.

This module holds the record and the checks the writers share.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient

from analysis.clearance import VERDICTS
from vehicles.errors import InputError

if TYPE_CHECKING:  # pragma: no cover - only for type checkers
    from reports.export_dxf import write_dxf
    from reports.export_geojson import write_geojson
    from reports.export_sumo import write_sumo_additional

__all__ = [
    "EnvelopeRecord",
    "VERDICT_RGBA",
    "checked_records",
    "polygon_parts",
    "write_dxf",
    "write_geojson",
    "write_sumo_additional",
]

#: Colour of each verdict as (red, green, blue, alpha), 0-255; alpha makes fills see-through.
VERDICT_RGBA: dict[str, tuple[int, int, int, int]] = {
    "clear": (0, 170, 0, 128),
    "encroaches": (255, 140, 0, 128),
    "fails": (220, 0, 0, 128),
    "cannot-turn": (140, 0, 200, 128),
}


@dataclass(frozen=True)
class EnvelopeRecord:
    """The swept envelope of one vehicle through one curve, with its verdict.

    Attributes
    ----------
    network
        Network name (the file stem).
    vehicle
        Vehicle name as in the vehicle table (may hold spaces, ``&``, quotes...).
    curve_id
        Stable id of the curve.
    kind
        ``turn``, ``roundabout``, ``ramp`` or ``bend``.
    verdict
        ``clear``, ``encroaches``, ``fails`` or ``cannot-turn``.
    margin_m
        Signed margin that decides the verdict (m); NaN when there is none.
    envelope
        The swept envelope, a shapely Polygon or MultiPolygon in SUMO plane coordinates
        (metres, after the network's ``netOffset``).
    """

    network: str
    vehicle: str
    curve_id: str
    kind: str
    verdict: str
    margin_m: float
    envelope: Any

    @property
    def label(self) -> str:
        """``network/vehicle/curve_id``, to name the record in messages."""
        return f"{self.network}/{self.vehicle}/{self.curve_id}"

    @property
    def margin_mm(self) -> float | None:
        """``margin_m`` rounded to the millimetre; None when it is not finite."""
        m = float(self.margin_m)
        return round(m, 3) + 0.0 if math.isfinite(m) else None


def _check(record: EnvelopeRecord) -> None:
    """Raise :class:`InputError` naming ``record`` when it cannot be exported."""
    if not isinstance(record, EnvelopeRecord):
        raise InputError(f"export: expected an EnvelopeRecord, got {type(record).__name__}")
    for name in ("network", "vehicle", "curve_id", "kind", "verdict"):
        value = getattr(record, name)
        if not isinstance(value, str) or not value.strip():
            raise InputError(f"record {record.label}: {name} must be a non-empty string")
    if record.verdict not in VERDICT_RGBA:
        raise InputError(
            f"record {record.label}: unknown verdict {record.verdict!r} "
            f"(expected one of {', '.join(VERDICTS)})"
        )
    try:
        float(record.margin_m)
    except (TypeError, ValueError):
        raise InputError(
            f"record {record.label}: margin_m {record.margin_m!r} is not a number"
        ) from None
    env = record.envelope
    if not isinstance(env, Polygon | MultiPolygon):
        raise InputError(
            f"record {record.label}: the envelope must be a Polygon or MultiPolygon, "
            f"got {type(env).__name__}"
        )
    if env.is_empty or env.area <= 0.0:
        raise InputError(f"record {record.label}: the envelope is empty")
    coords = shapely.get_coordinates(env)
    if not np.isfinite(coords).all():
        raise InputError(f"record {record.label}: the envelope has non-finite coordinates")
    if not env.is_valid:
        reason = shapely.is_valid_reason(env)
        raise InputError(f"record {record.label}: the envelope is not a valid polygon ({reason})")


def _sort_key(r: EnvelopeRecord) -> tuple[Any, ...]:
    margin = r.margin_mm
    return (
        r.network,
        r.vehicle,
        r.curve_id,
        r.kind,
        r.verdict,
        margin is None,
        margin or 0.0,
        shapely.to_wkb(r.envelope, hex=True),
    )


def checked_records(records: Iterable[EnvelopeRecord]) -> list[EnvelopeRecord]:
    """The records, checked, in a stable order (network, vehicle, curve id, then the rest).

    Raises
    ------
    InputError
        A record has an empty, invalid or non-polygonal envelope, an unknown verdict, a
        blank name or a margin that is not a number; the message names the record.
    """
    out = list(records)
    for r in out:
        _check(r)
    return sorted(out, key=_sort_key)


def polygon_parts(envelope: Polygon | MultiPolygon) -> list[Polygon]:
    """The polygons of an envelope, exteriors counter-clockwise and holes clockwise.

    Parts are in a stable order (by the lower-left corner of their bounds, then area), not
    in the order shapely happened to produce them.
    """
    parts = list(envelope.geoms) if isinstance(envelope, MultiPolygon) else [envelope]
    parts = [orient(p, sign=1.0) for p in parts if not p.is_empty]
    return sorted(parts, key=lambda p: (p.bounds[0], p.bounds[1], -p.area, p.wkb_hex))


def __getattr__(name: str) -> Any:
    """The writers, imported on first use (they import this module)."""
    if name == "write_geojson":
        from reports.export_geojson import write_geojson

        return write_geojson
    if name == "write_sumo_additional":
        from reports.export_sumo import write_sumo_additional

        return write_sumo_additional
    if name == "write_dxf":
        from reports.export_dxf import write_dxf

        return write_dxf
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
