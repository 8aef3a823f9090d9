"""GeoJSON export of swept envelopes (RFC 7946), for QGIS and other GIS.

Coordinates are WGS84 longitude/latitude when every network of the records has a projection
(``projParameter`` other than ``"!"``): SUMO x, y minus the ``netOffset``, then the inverse
of the network's projection with PROJ (pyproj), as sumolib's ``convertXY2LonLat`` does. A
network without a projection is placed on the globe by an ``origin`` (latitude, longitude of
its input coordinates' 0,0, i.e. SUMO x, y minus the ``netOffset``): a transverse Mercator
projection centred there (scale 1, so metres stay metres near the site). Otherwise they
are the SUMO plane metres of each network: not RFC 7946 coordinates, which the file says
in its top-level ``coordinate_system`` member (a foreign member, RFC 7946 section 6.1), the
report in its file name (``*.local-metres.geojson``), and GIS software in the file's ``crs``
member (GeoJSON 2008's, which RFC 7946 removed and GDAL still reads): a local engineering
CRS (:data:`LOCAL_CRS_WKT`), so that QGIS keeps the layer off the globe instead of reading
metres as WGS84 degrees (it put a town in the South Atlantic).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pyproj
from pyproj.exceptions import CRSError, ProjError
from shapely.geometry import Polygon

from clearance.networks.model import Location
from clearance.reports.exports.envelopes import EnvelopeRecord, checked_records, polygon_parts
from clearance.reports.output.atomic import write_text_atomic
from clearance.vehicles.errors import GeometryError, NetworkError, OptionError

__all__ = ["COORDS_LOCAL", "COORDS_LONLAT", "COORDS_MIXED", "LOCAL_CRS_WKT",
           "lonlat_transformer", "origin_transformer", "parse_origin", "write_geojson"]

COORDS_LONLAT = "WGS84 longitude/latitude (degrees, RFC 7946)"
COORDS_LOCAL = "local metres (SUMO network coordinates, no projection)"

#: The CRS of a local-metres file: SUMO's plane, an engineering CRS (WKT2) GDAL reads from
#: a ``crs`` member of type ``name``.
LOCAL_CRS_WKT = (
    'ENGCRS["SUMO network plane (local metres, no projection)",'
    'EDATUM["SUMO network origin"],CS[Cartesian,2],'
    'AXIS["easting (x)",east,ORDER[1],LENGTHUNIT["metre",1]],'
    'AXIS["northing (y)",north,ORDER[2],LENGTHUNIT["metre",1]]]')
COORDS_MIXED = (
    "local metres (SUMO network coordinates of each network: not every network has a projection)"
)
DEG_DIGITS = 7  # 1e-7 degree, about 1 cm
M_DIGITS = 3  # 1 mm


def lonlat_transformer(network: str, location: Location) -> pyproj.Transformer | None:
    """The transformer from a network's projected metres to WGS84 (lon, lat), or None.

    Parameters
    ----------
    network
        The network's name, for messages.
    location
        Its ``<location>``; ``proj_parameter`` ``"!"`` (or blank) means no projection.

    Raises
    ------
    InputError
        The ``projParameter`` is not a projection PROJ understands.
    """
    proj = (location.proj_parameter or "").strip()
    if proj in ("", "!"):
        return None
    try:
        crs = pyproj.CRS.from_user_input(proj)
        if not crs.is_projected:
            raise CRSError("not a projected coordinate system")
        return pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
    except (CRSError, ProjError) as exc:
        raise NetworkError(
            f"network {network}: cannot use its projParameter {proj!r}: {exc}"
        ) from None


def parse_origin(text: str) -> tuple[float, float]:
    """``LAT,LON`` in degrees (``--origin``), checked.

    Examples
    --------
    >>> parse_origin("52.52, 13.405")
    (52.52, 13.405)
    >>> parse_origin("95,13.4")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    clearance.vehicles.errors.OptionError: --origin '95,13.4': the longitude must be ...
    """
    parts = text.split(",")
    try:
        lat, lon = (float(p) for p in parts)
    except ValueError:
        raise OptionError(f"--origin {text!r}: expected LAT,LON in degrees "
                         "(e.g. --origin 52.52,13.405)") from None
    if not (abs(lat) <= 90 and abs(lon) <= 180):
        raise OptionError(f"--origin {text!r}: the longitude must be within ±180° and the "
                         "latitude within ±90° (write LAT,LON)")
    return lat, lon


def origin_transformer(origin: tuple[float, float]) -> pyproj.Transformer:
    """From local metres (x east, y north, 0,0 at ``origin`` = (lat, lon)) to WGS84 lon/lat.

    Examples
    --------
    >>> t = origin_transformer((45.0, 7.0))
    >>> [round(v, 9) for v in t.transform(0.0, 0.0)]
    [7.0, 45.0]
    >>> lon, lat = t.transform(0.0, 1000.0)  # 1 km north: about 0.009 degrees of latitude
    >>> round(lat - 45.0, 4)
    0.009
    """
    lat, lon = origin
    crs = pyproj.CRS.from_proj4(f"+proj=tmerc +lat_0={lat!r} +lon_0={lon!r} +k=1 +x_0=0 "
                                "+y_0=0 +datum=WGS84 +units=m +no_defs")
    return pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True)


def _ring(
    coords: Any,
    offset: tuple[float, float],
    transformer: pyproj.Transformer | None,
    exterior: bool,
    label: str,
) -> list[list[float]] | None:
    """One closed, rounded, correctly oriented ring; None for a hole that vanishes."""
    xy = np.asarray(coords, dtype=float)[:, :2]
    if transformer is None:
        out = np.round(xy, M_DIGITS)
    else:
        lon, lat = transformer.transform(xy[:, 0] - offset[0], xy[:, 1] - offset[1])
        out = np.round(np.column_stack([lon, lat]), DEG_DIGITS)
        ok = np.isfinite(out).all() and (abs(out[:, 0]) <= 180).all()
        if not ok or not (abs(out[:, 1]) <= 90).all():
            raise GeometryError(
                f"record {label}: the network's projection gives no valid longitude/latitude "
                "for its envelope (coordinates far outside the network?)"
            )
    keep = np.ones(len(out), dtype=bool)
    keep[1:] = (out[1:] != out[:-1]).any(axis=1)
    out = out[keep]
    if len(out) and (out[0] != out[-1]).any():
        out = np.vstack([out, out[:1]])
    x, y = out[:, 0], out[:, 1]
    area2 = float(np.dot(x[:-1], y[1:]) - np.dot(x[1:], y[:-1])) if len(out) >= 4 else 0.0
    if area2 == 0.0:
        if exterior:
            raise GeometryError(f"record {label}: an envelope part vanishes at the "
                                "output precision")
        return None
    if (area2 > 0) != exterior:  # RFC 7946: exteriors counter-clockwise, holes clockwise
        out = out[::-1]
    return [[float(a) + 0.0, float(b) + 0.0] for a, b in out]


def _polygon(
    part: Polygon,
    offset: tuple[float, float],
    transformer: pyproj.Transformer | None,
    label: str,
) -> list[list[list[float]]]:
    rings = [_ring(part.exterior.coords, offset, transformer, True, label)]
    for hole in part.interiors:
        ring = _ring(hole.coords, offset, transformer, False, label)
        if ring is not None:
            rings.append(ring)
    return rings  # type: ignore[return-value]


def _run_properties(r: EnvelopeRecord) -> dict[str, object]:
    """What every feature of a run says about it: network, vehicle, curve, kind, verdict."""
    return {"network": r.network, "vehicle": r.vehicle, "curve_id": r.curve_id,
            "kind": r.kind, "verdict": r.verdict}


def _overreach_feature(r: EnvelopeRecord, offset: tuple[float, float],
                       transformer: pyproj.Transformer | None) -> dict[str, Any]:
    """A Point Feature at a record's worst overreach, with the design feedback."""
    x, y, station, extra = (float(v) for v in r.overreach or (math.nan,) * 4)
    if transformer is None:
        coords = [round(x, M_DIGITS) + 0.0, round(y, M_DIGITS) + 0.0]
    else:
        lon, lat = transformer.transform(x - offset[0], y - offset[1])
        if not (math.isfinite(lon) and math.isfinite(lat) and abs(lon) <= 180
                and abs(lat) <= 90):
            raise GeometryError(f"record {r.label}: the network's projection gives no valid "
                             "longitude/latitude for its worst overreach")
        coords = [round(float(lon), DEG_DIGITS) + 0.0, round(float(lat), DEG_DIGITS) + 0.0]
    properties = {
        **_run_properties(r),
        "feature": "worst overreach",
        "beyond": "paved area" if r.verdict == "fails" else "own lanes",
        "margin_m": r.margin_mm,
        "station_m": round(station, M_DIGITS) + 0.0,
        "extra_width_m": round(extra, M_DIGITS) + 0.0,
    }
    return {"type": "Feature", "geometry": {"type": "Point", "coordinates": coords},
            "properties": properties}


def write_geojson(
    path: str | os.PathLike[str],
    records: Iterable[EnvelopeRecord],
    locations: Mapping[str, Location],
    origin: tuple[float, float] | None = None,
) -> Path:
    """Write the envelopes as a GeoJSON FeatureCollection, one Feature per record.

    Parameters
    ----------
    path
        The output file (conventionally ``*.geojson``); written atomically.
    records
        The envelopes. Features are sorted by network, vehicle and curve id.
    locations
        Each network's ``<location>`` (``read_network(path).location``), by network name;
        every network of the records must be there.
    origin
        (latitude, longitude) of the input coordinates' 0,0 of every network without a
        projection (:func:`origin_transformer`); None: such networks stay in local metres.

    Returns
    -------
    Path
        The file written.

    Notes
    -----
    Longitude/latitude (WGS84, rounded to 1e-7 degree) when every network has a projection,
    else local SUMO metres (rounded to 1 mm); the top-level ``coordinate_system`` member
    says which, and ``networks`` gives each network's ``net_offset`` and ``proj_parameter``.
    Feature properties: network, vehicle, curve_id, kind, verdict and margin_m (m, rounded to
    1 mm; null when there is none). After the envelopes, a Point Feature at the worst
    overreach of each record that has one
    (:attr:`~clearance.reports.exports.envelopes.EnvelopeRecord.overreach`),
    with ``feature`` ``"worst overreach"``, ``beyond`` (``paved area`` or ``own lanes``),
    ``station_m`` (along the curve's centre line) and ``extra_width_m``. Exterior rings are
    counter-clockwise, holes clockwise.
    Keys are sorted and there is no timestamp: identical inputs give identical bytes.

    Raises
    ------
    InputError
        A bad record (see :func:`clearance.reports.exports.envelopes.checked_records`), a network
        without a location, or a projParameter that PROJ cannot use; the message names it.
    """
    recs = checked_records(records)
    names = sorted({r.network for r in recs})
    missing = [n for n in names if n not in locations]
    if missing:
        raise OptionError(f"GeoJSON export: no location given for network(s) {', '.join(missing)}")
    transformers = {n: lonlat_transformer(n, locations[n]) for n in names}
    if origin is not None:
        transformers = {n: t or origin_transformer(origin) for n, t in transformers.items()}
    n_projected = sum(t is not None for t in transformers.values())
    if n_projected == len(names):
        system = COORDS_LONLAT
    else:
        system = COORDS_LOCAL if n_projected == 0 else COORDS_MIXED
        transformers = dict.fromkeys(names)

    features = []
    for r in recs:
        offset = locations[r.network].net_offset
        polys = [
            _polygon(p, offset, transformers[r.network], r.label) for p in polygon_parts(r.envelope)
        ]
        geometry = (
            {"type": "Polygon", "coordinates": polys[0]}
            if len(polys) == 1
            else {"type": "MultiPolygon", "coordinates": polys}
        )
        properties = {**_run_properties(r), "margin_m": r.margin_mm}
        features.append({"type": "Feature", "geometry": geometry, "properties": properties})
    # the worst overreach of each run not clear, as points after the envelopes
    for r in recs:
        if r.overreach is not None:
            features.append(_overreach_feature(r, locations[r.network].net_offset,
                                               transformers[r.network]))

    networks = {
        n: {
            "net_offset": [round(float(v), M_DIGITS) + 0.0 for v in locations[n].net_offset],
            "proj_parameter": locations[n].proj_parameter,
        }
        for n in names
    }
    if origin is not None and system == COORDS_LONLAT:
        for n in names:
            if lonlat_transformer(n, locations[n]) is None:
                networks[n]["origin_lat_lon"] = [float(origin[0]), float(origin[1])]

    def dump(obj: Any) -> str:
        return json.dumps(
            obj, sort_keys=True, ensure_ascii=False, allow_nan=False, separators=(",", ":")
        )

    # Keys in sorted order, one feature per line (readable diffs of committed examples).
    body = ",\n".join(dump(f) for f in features)
    crs = ""
    if system == COORDS_LOCAL:
        crs = dump({"properties": {"name": LOCAL_CRS_WKT}, "type": "name"})
        crs = f'"crs":{crs},\n'
    text = (
        f'{{"coordinate_system":{dump(system)},\n{crs}"features":[\n{body}\n],\n'
        f'"networks":{dump(networks)},\n"type":"FeatureCollection"}}\n'
    )
    return write_text_atomic(path, text)
