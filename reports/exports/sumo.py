"""SUMO additional file of one network's swept envelopes: ``sumo-gui -n NET -a NET.add.xml``
(a report writes one per network under ``exports/``).

One ``<poly>`` per envelope part, filled, coloured by verdict (semi-transparent), with the
record's attributes as ``<param>`` children so that sumo-gui's parameter dialog of a shape
shows them. SUMO polygons cannot have holes: a part with holes is cut into hole-free pieces
along vertical lines through its holes (the pieces fill exactly the same area).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from pathlib import Path

from lxml import etree
from shapely.geometry import LineString, Polygon
from shapely.ops import split

from clearance.reports.exports.envelopes import (
    VERDICT_RGBA,
    EnvelopeRecord,
    checked_records,
    polygon_parts,
)
from clearance.reports.output.atomic import write_bytes_atomic
from clearance.vehicles.errors import GeometryError

__all__ = ["VERDICT_LAYER", "hole_free_pieces", "sumo_id", "write_sumo_additional"]

#: Drawing layer by verdict: above the roads, worse verdicts on top.
VERDICT_LAYER = {"clear": 10, "encroaches": 11, "fails": 12, "cannot-turn": 13}

_UNSAFE_ID = re.compile(r"[^A-Za-z0-9_.+-]+")


def sumo_id(text: str) -> str:
    """``text`` made safe as a SUMO id: runs of other characters than ``A-Za-z0-9_.+-``
    become one ``_``.

    >>> sumo_id('Bus & "Co" 12 m')
    'Bus_Co_12_m'
    """
    return _UNSAFE_ID.sub("_", text).strip("_") or "_"


def hole_free_pieces(part: Polygon) -> list[Polygon]:
    """Cut a polygon into pieces without holes that together cover exactly the same area.

    Each hole is cut by a vertical line through a point inside it, which opens the hole to
    the outside of both pieces; this repeats until no piece has a hole.
    """
    # Holes under 1 cm² are slivers between the steps of a sweep, not islands: fill them.
    part = Polygon(part.exterior, [h for h in part.interiors if Polygon(h).area >= 1e-4])
    todo, done = [part], []
    while todo:
        poly = todo.pop()
        if not poly.interiors:
            done.append(poly)
            continue
        x = Polygon(poly.interiors[0]).representative_point().x
        ymin, ymax = poly.bounds[1] - 1.0, poly.bounds[3] + 1.0
        pieces = [
            g
            for g in split(poly, LineString([(x, ymin), (x, ymax)])).geoms
            if isinstance(g, Polygon) and g.area > 0.0
        ]
        if len(pieces) < 2:  # pragma: no cover - a line through a hole always splits
            raise GeometryError("SUMO export: cannot cut a hole out of an envelope")
        todo.extend(pieces)
    return sorted(done, key=lambda p: (p.bounds[0], p.bounds[1], p.wkb_hex))


def _shape(poly: Polygon) -> str:
    return " ".join(f"{x:.3f},{y:.3f}" for x, y, *_ in poly.exterior.coords).replace(
        "-0.000", "0.000"
    )


def write_sumo_additional(path: str | os.PathLike[str], records: Iterable[EnvelopeRecord]) -> Path:
    """Write the envelopes as SUMO polygons in an additional file.

    Parameters
    ----------
    path
        The output file (conventionally ``*.add.xml``); written atomically.
    records
        The envelopes, in SUMO network coordinates: one network's (a report writes a file
        per network); load it with that network.

    Returns
    -------
    Path
        The file written.

    Notes
    -----
    Each ``<poly>`` has ``id="swept:<network>:<vehicle>:<curve>:<n>"`` with the names made
    SUMO-safe (and a suffix if two come out equal), ``type="swept:<verdict>"``, the verdict's
    colour (:data:`clearance.reports.exports.envelopes.VERDICT_RGBA`), ``fill="1"``, a layer above
    the roads (worse verdicts on top, :data:`VERDICT_LAYER`) and a ``shape`` in metres to 1 mm. The
    ``<param>`` children give network, vehicle, curve_id, kind, verdict, margin_m (omitted
    when there is none) and the piece number.

    Raises
    ------
    InputError
        A bad record (see :func:`clearance.reports.exports.envelopes.checked_records`), or a name
        with characters XML cannot hold; the message names the record.
    """
    recs = checked_records(records)
    root = etree.Element("additional")
    root.set(
        "{http://www.w3.org/2001/XMLSchema-instance}noNamespaceSchemaLocation",
        "http://sumo.dlr.de/xsd/additional_file.xsd",
    )
    used: set[str] = set()
    for r in recs:
        pieces = [q for p in polygon_parts(r.envelope) for q in hole_free_pieces(p)]
        base = ":".join(["swept", sumo_id(r.network), sumo_id(r.vehicle), sumo_id(r.curve_id)])
        params = {
            "network": r.network,
            "vehicle": r.vehicle,
            "curve_id": r.curve_id,
            "kind": r.kind,
            "verdict": r.verdict,
        }
        if r.margin_mm is not None:
            params["margin_m"] = f"{r.margin_mm:.3f}"
        for n, piece in enumerate(pieces):
            pid, k = f"{base}:{n}", 1
            while pid in used:
                k += 1
                pid = f"{base}~{k}:{n}"
            used.add(pid)
            try:
                poly = etree.SubElement(root, "poly")
                poly.set("id", pid)
                poly.set("type", f"swept:{r.verdict}")
                poly.set("color", ",".join(str(c) for c in VERDICT_RGBA[r.verdict]))
                poly.set("fill", "1")
                poly.set("layer", str(VERDICT_LAYER[r.verdict]))
                poly.set("shape", _shape(piece))
                for key, value in [*params.items(), ("piece", f"{n + 1}/{len(pieces)}")]:
                    etree.SubElement(poly, "param", key=key, value=value)
            except ValueError as exc:  # lxml: control characters and the like
                raise ValueError(f"record {r.label}: cannot be written as XML: {exc}") from None
    data = etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)
    return write_bytes_atomic(path, data)
