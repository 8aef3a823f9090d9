"""DXF export of swept envelopes, for CAD: one layer per vehicle, metres, SUMO plane.

Each envelope part is a closed LWPOLYLINE for its exterior and one for each hole, coloured by
verdict (AutoCAD colour index), with the record's attributes in XDATA (application
``SUMO_CLEARANCE``) and the curve id as a TEXT at a point inside the part.

Identical records give a byte-identical file, like the CSV, JSON and GeoJSON outputs: the
drawing carries no clock time and no random GUID (ezdxf's fixed metadata: dates of
2000-01-01, the null GUID, no timestamp in its own marker) and its CLASSES section is in a
fixed order (ezdxf adds the classes in use from a set, whose order varies between runs).
"""

from __future__ import annotations

import io
import os
import re
from collections import OrderedDict
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

import ezdxf
from ezdxf.enums import TextEntityAlignment

from reports.atomic import write_text_atomic
from reports.exports import EnvelopeRecord, checked_records, polygon_parts

__all__ = ["APPID", "TEXT_HEIGHT_M", "VERDICT_ACI", "dxf_layer_name", "write_dxf"]

APPID = "SUMO_CLEARANCE"
TEXT_HEIGHT_M = 0.5
#: AutoCAD colour index of each verdict: green, orange, red, magenta.
VERDICT_ACI = {"clear": 3, "encroaches": 30, "fails": 1, "cannot-turn": 6}

# Characters AutoCAD refuses in symbol-table names, plus control characters.
_BAD_LAYER_CHARS = re.compile(r"[<>/\\\":;?*|=,'`\x00-\x1f\x7f]+")
_CONTROL = re.compile(r"[\x00-\x1f\x7f]+")


def dxf_layer_name(vehicle: str) -> str:
    """A vehicle name made valid as a DXF layer name (at most 255 characters).

    >>> dxf_layer_name('Bus 12/18 m "city"')
    'Bus 12_18 m _city_'
    """
    return _BAD_LAYER_CHARS.sub("_", vehicle).strip()[:255] or "_"


def _text(value: str, limit: int = 255) -> str:
    """A string fit for a DXF TEXT or XDATA string: no control characters, bounded length."""
    return _CONTROL.sub(" ", value)[:limit]


def write_dxf(path: str | os.PathLike[str], records: Iterable[EnvelopeRecord]) -> Path:
    """Write the envelopes as a DXF drawing (R2010, UTF-8), in SUMO plane metres.

    Parameters
    ----------
    path
        The output file (conventionally ``*.dxf``); written atomically.
    records
        The envelopes, in SUMO network coordinates.

    Returns
    -------
    Path
        The file written.

    Notes
    -----
    One layer per vehicle, named by :func:`dxf_layer_name` (a suffix ``~2``, ``~3``... when
    two names clash, DXF layer names being case-insensitive), its description holding the
    vehicle's own name. ``$INSUNITS`` is 6 (metres) and ``$MEASUREMENT`` 1 (metric).
    Entities carry the verdict's colour (:data:`VERDICT_ACI`); polylines carry XDATA
    ``network=``, ``vehicle=``, ``curve_id=``, ``kind=``, ``verdict=``, ``margin_m=``,
    ``ring=exterior|hole``.

    Raises
    ------
    InputError
        A bad record (see :func:`reports.exports.checked_records`); the message names it.
    """
    recs = checked_records(records)
    with _fixed_metadata():
        doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = 6
    doc.header["$MEASUREMENT"] = 1
    doc.appids.add(APPID)
    msp = doc.modelspace()

    layers: dict[str, str] = {}
    taken = {"0", "defpoints"}
    for vehicle in sorted({r.vehicle for r in recs}):
        name, k = dxf_layer_name(vehicle), 1
        while name.casefold() in taken:
            k += 1
            name = f"{dxf_layer_name(vehicle)[:250]}~{k}"
        taken.add(name.casefold())
        layers[vehicle] = name
        doc.layers.add(name).description = _text(vehicle)

    for r in recs:
        margin = "" if r.margin_mm is None else f"{r.margin_mm:.3f}"
        tags = [
            (1000, _text(f"{key}={value}"))
            for key, value in (
                ("network", r.network),
                ("vehicle", r.vehicle),
                ("curve_id", r.curve_id),
                ("kind", r.kind),
                ("verdict", r.verdict),
                ("margin_m", margin),
            )
        ]
        attribs = {"layer": layers[r.vehicle], "color": VERDICT_ACI[r.verdict]}
        for part in polygon_parts(r.envelope):
            rings = [("exterior", part.exterior)] + [("hole", h) for h in part.interiors]
            for role, ring in rings:
                points = [(float(x), float(y)) for x, y, *_ in ring.coords[:-1]]
                line = msp.add_lwpolyline(points, format="xy", close=True, dxfattribs=attribs)
                line.set_xdata(APPID, [*tags, (1000, f"ring={role}")])
            p = part.representative_point()
            text = msp.add_text(_text(r.curve_id), height=TEXT_HEIGHT_M, dxfattribs=attribs)
            text.set_placement((p.x, p.y), align=TextEntityAlignment.MIDDLE_CENTER)
            text.set_xdata(APPID, tags)

    return write_text_atomic(path, _reproducible_text(doc))


@contextmanager
def _fixed_metadata() -> Iterator[None]:
    """ezdxf writes fixed dates and GUIDs meanwhile (its option for reproducible files)."""
    previous = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = previous


def _reproducible_text(doc: ezdxf.document.Drawing) -> str:
    """The DXF text of ``doc``, the same bytes for the same content."""
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = OrderedDict(sorted(doc.classes.classes.items()))
    stream = io.StringIO()
    with _fixed_metadata():
        doc.write(stream)
    return stream.getvalue()
