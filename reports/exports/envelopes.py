"""Exports of the clearance report: swept envelopes for GIS, sumo-gui and CAD.

Each writer takes plain :class:`EnvelopeRecord` objects (one per vehicle and curve), checks
them, and writes one file atomically. All three sort the records by network, vehicle and
curve id, so identical inputs give identical files. A report writes one file of each per
network (:func:`by_network`), each in that network's own coordinates.

- :func:`write_geojson` (``clearance.reports.exports.geojson``): a GeoJSON FeatureCollection in
WGS84
  longitude/latitude when the network has a projection (or an origin is given), in local
  metres otherwise;
- :func:`write_sumo_additional` (``clearance.reports.exports.sumo``): SUMO ``<poly>`` shapes for
  ``sumo-gui -n NET -a FILE``;
- :func:`write_dxf` (``clearance.reports.exports.dxf``): a DXF drawing in metres: the network's base
  plan and, per vehicle, layers for the envelopes, the conflict and (when known) body
  outlines and wheel paths.

This module holds the record and the checks the writers share; it imports none of them
(each writer imports it), so import a writer from its own module.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient

from clearance.analysis.clearance import VERDICTS
from clearance.vehicles.errors import GeometryError

__all__ = [
    "EnvelopeRecord",
    "VERDICT_RGBA",
    "by_network",
    "checked_records",
    "conflict_parts",
    "polygon_parts",
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
        The swept envelope as measured (grown by the clearance offset ``offset_m``), a
        shapely Polygon or MultiPolygon in SUMO plane coordinates (metres, after the
        network's ``netOffset``).
    offset_m
        The clearance offset the envelope was grown by (m; 0: it is the body envelope).
    body_envelope
        The envelope of the body alone (not grown), when known; with ``offset_m`` 0 it is
        ``envelope``.
    outside_lanes, outside_pavement
        The conflict: the parts of ``envelope`` outside the own lanes (but paved) and
        outside the pavement, or None (not computed) / empty (none).
    body_outlines
        Outlines of the vehicle body (Polygons) at intervals along the path, when known.
    wheel_paths
        Paths of the wheels that bound the sweep (LineStrings), when known.
    overreach
        A run not clear: ``(x, y, station_m, extra_width_m)`` of its worst overreach
        (:mod:`clearance.reports.results.feedback`: beyond the paved area for ``fails``, its own
        lanes for ``encroaches``), in the envelope's coordinates; None otherwise.
    """

    network: str
    vehicle: str
    curve_id: str
    kind: str
    verdict: str
    margin_m: float
    envelope: Any
    offset_m: float = 0.0
    body_envelope: Any = None
    outside_lanes: Any = None
    outside_pavement: Any = None
    body_outlines: tuple[Any, ...] = ()
    wheel_paths: tuple[Any, ...] = ()
    overreach: tuple[float, float, float, float] | None = None

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
        raise ValueError(f"export: expected an EnvelopeRecord, got {type(record).__name__}")
    for name in ("network", "vehicle", "curve_id", "kind", "verdict"):
        value = getattr(record, name)
        if not isinstance(value, str) or not value.strip():
            raise ValueError(f"record {record.label}: {name} must be a non-empty string")
    if record.verdict not in VERDICT_RGBA:
        raise ValueError(
            f"record {record.label}: unknown verdict {record.verdict!r} "
            f"(expected one of {', '.join(VERDICTS)})"
        )
    try:
        float(record.margin_m)
    except (TypeError, ValueError):
        raise ValueError(
            f"record {record.label}: margin_m {record.margin_m!r} is not a number"
        ) from None
    env = record.envelope
    if not isinstance(env, Polygon | MultiPolygon):
        raise ValueError(
            f"record {record.label}: the envelope must be a Polygon or MultiPolygon, "
            f"got {type(env).__name__}"
        )
    if env.is_empty or env.area <= 0.0:
        raise GeometryError(f"record {record.label}: the envelope is empty")
    coords = shapely.get_coordinates(env)
    if not np.isfinite(coords).all():
        raise GeometryError(f"record {record.label}: the envelope has non-finite coordinates")
    if not env.is_valid:
        reason = shapely.is_valid_reason(env)
        raise GeometryError(f"record {record.label}: the envelope is not a valid polygon "
                            f"({reason})")
    try:
        offset = float(record.offset_m)
    except (TypeError, ValueError):
        offset = math.nan
    if not (math.isfinite(offset) and offset >= 0):
        raise ValueError(f"record {record.label}: offset_m {record.offset_m!r} must be >= 0")
    if record.overreach is not None:
        try:
            ok = len(record.overreach) == 4 and all(math.isfinite(float(v))
                                                    for v in record.overreach)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"record {record.label}: overreach must be four finite numbers "
                             f"(x, y, station_m, extra_width_m), got {record.overreach!r}")
    extras = [record.body_envelope, record.outside_lanes, record.outside_pavement,
              *record.body_outlines, *record.wheel_paths]
    for g in extras:
        if g is None:
            continue
        if not isinstance(g, shapely.Geometry):
            raise ValueError(f"record {record.label}: expected a shapely geometry, "
                             f"got {type(g).__name__}")
        if not shapely.is_empty(g) and not np.isfinite(shapely.get_coordinates(g)).all():
            raise GeometryError(f"record {record.label}: a geometry has non-finite coordinates")


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


def conflict_parts(envelope: Any, own_lanes: Any, paved: Any) -> tuple[Any, Any]:
    """The conflict of an envelope: the part outside the own lanes but paved, and the part
    outside the pavement (either may be empty; None when its area is unknown).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> lanes, paved = box(0, 0, 10, 3), box(0, -3, 10, 3)
    >>> a, b = conflict_parts(box(2, -4, 4, 1), lanes, paved)
    >>> round(a.area, 6), round(b.area, 6)
    (6.0, 2.0)
    >>> a, b = conflict_parts(box(2, 1, 4, 2), lanes, paved)  # inside its lanes: none
    >>> a.is_empty and b.is_empty
    True
    """
    outside_pavement = shapely.difference(envelope, paved) if paved is not None else None
    outside_lanes = None
    if own_lanes is not None:
        outside_lanes = shapely.difference(envelope, own_lanes)
        if paved is not None:
            outside_lanes = shapely.intersection(outside_lanes, paved)
    return outside_lanes, outside_pavement


def by_network(records: Iterable[EnvelopeRecord]) -> dict[str, list[EnvelopeRecord]]:
    """The records grouped by network name, networks in sorted order."""
    out: dict[str, list[EnvelopeRecord]] = {}
    for r in records:
        out.setdefault(r.network, []).append(r)
    return dict(sorted(out.items()))
