"""Selecting the curves of one scheme inside a network: by kind, junction and bounding box.

A :class:`Selection` keeps a curve when it passes every criterion given (an empty
criterion passes everything):

``kinds``
    Its kind is one of these (any kind :data:`clearance.networks.curves.KINDS` defines). The kinds
    are the cheapest criterion: they are handed to :func:`clearance.networks.curves.extract_curves`,
    so curves of other kinds are never measured.
``junctions``
    Its ``junction`` is one of these ids (a turn's junction, the ring node a roundabout
    curve enters, the junction a ramp or a bend starts from). An id the network does not
    have is bad input (:func:`check_junctions`, with close matches).
``curve_ids``
    Its id is one of these (a route study's passages, :mod:`clearance.reports.study.routes`).
``bbox``
    Its feature (the centre line between ``core_start_m`` and ``core_end_m``, without the
    lead-in and run-out) intersects the box ``(xmin, ymin, xmax, ymax)`` in the network's
    plane coordinates (metres, as in the ``.net.xml``), edges included.

:func:`load_selected` reads the curves of a network with a selection applied before any
area is built: only the kept curves get areas, built on demand as usual.
"""

from __future__ import annotations

import difflib
import inspect
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from clearance.networks.curves import KINDS, Curve, CurveOptions, extract_curves
from clearance.networks.geometry import cut_polyline
from clearance.networks.model import Network
from clearance.vehicles.errors import OptionError

__all__ = ["BBox", "Selection", "check_junctions", "feature_line", "in_bbox", "load_selected",
           "parse_bbox", "select"]

BBox = tuple[float, float, float, float]


@dataclass(frozen=True)
class Selection:
    """Which curves of a network to keep (see the module docstring)."""

    kinds: tuple[str, ...] = ()
    junctions: tuple[str, ...] = ()
    bbox: BBox | None = None
    curve_ids: frozenset[str] | None = None

    def __post_init__(self) -> None:
        bad = [k for k in self.kinds if k not in KINDS]
        if bad:
            raise OptionError(f"unknown curve kind(s) {', '.join(bad)}; choose from "
                             f"{', '.join(KINDS)}")

    @property
    def narrows(self) -> bool:
        """Whether curves are dropped after extraction (by junction or box)."""
        return bool(self.junctions) or self.bbox is not None or self.curve_ids is not None

    @property
    def is_empty(self) -> bool:
        """Whether the selection keeps every curve a default extraction gives."""
        return not self.kinds and not self.narrows

    def effective_kinds(self) -> tuple[str, ...]:
        """The kinds extracted: those given, else :func:`extract_curves`' default ones.

        Examples
        --------
        >>> Selection(kinds=("ramp",)).effective_kinds()
        ('ramp',)
        >>> set(Selection().effective_kinds()) <= set(KINDS)
        True
        """
        if self.kinds:
            return self.kinds
        default = inspect.signature(extract_curves).parameters["kinds"].default
        return tuple(default)

    def describe(self) -> str:
        """A short text of the criteria, e.g. ``kind roundabout, junction J1``.

        Examples
        --------
        >>> Selection(kinds=("turn",), bbox=(0, 0, 10, 5)).describe()
        'kind turn, bbox 0,0,10,5'
        >>> Selection().describe()
        'every curve'
        """
        parts = []
        if self.kinds:
            parts.append("kind " + ", ".join(self.kinds))
        if self.junctions:
            parts.append("junction " + ", ".join(self.junctions))
        if self.bbox is not None:
            parts.append("bbox " + ",".join(f"{v:g}" for v in self.bbox))
        if self.curve_ids is not None:
            parts.append(f"{len(self.curve_ids)} curves of the routes")
        return ", ".join(parts) or "every curve"


def parse_bbox(text: str) -> BBox:
    """``XMIN,YMIN,XMAX,YMAX`` (metres, network coordinates) as four floats.

    Raises
    ------
    InputError
        Not four finite numbers, or a minimum above its maximum (a box of zero width or
        height, a line or a point, is allowed).

    Examples
    --------
    >>> parse_bbox("10,-5.5, 20,4")
    (10.0, -5.5, 20.0, 4.0)
    >>> parse_bbox("3,3,3,3")
    (3.0, 3.0, 3.0, 3.0)
    """
    parts = [p.strip() for p in text.split(",")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise OptionError(f"--bbox {text!r}: give four numbers XMIN,YMIN,XMAX,YMAX "
                         "(metres, network coordinates)")
    xmin, ymin, xmax, ymax = values
    if xmin > xmax or ymin > ymax:
        raise OptionError(f"--bbox {text!r}: XMIN must not exceed XMAX nor YMIN YMAX")
    return xmin, ymin, xmax, ymax


def check_junctions(junctions: Iterable[str], networks: Sequence[Network]) -> None:
    """Raise :class:`InputError` for a junction id that none of ``networks`` has.

    The message names the id, the network(s), and up to three close matches.
    """
    for jid in junctions:
        if any(jid in net.junctions for net in networks):
            continue
        known = [j for net in networks for j in net.junctions if not j.startswith(":")]
        close = difflib.get_close_matches(jid, known, n=3, cutoff=0.6)
        hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
        where = ", ".join(str(net.path) for net in networks)
        raise OptionError(f"--junction {jid!r}: no such junction in {where}{hint}")


def feature_line(curve: Curve) -> np.ndarray:
    """The plane (x, y) points of a curve's feature: its centre line from ``core_start_m``
    to ``core_end_m`` (one point when the feature has no length)."""
    return cut_polyline(curve.centerline, curve.core_start_m, curve.core_end_m)[:, :2]


def in_bbox(curve: Curve, bbox: BBox) -> bool:
    """Whether the curve's feature line meets the box (edges count).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> c = SimpleNamespace(centerline=np.array([[0.0, 0, 0], [10, 10, 0]]),
    ...                     core_start_m=0.0, core_end_m=math.hypot(10, 10))
    >>> in_bbox(c, (4, 0, 6, 1)), in_bbox(c, (0, 3, 4, 9)), in_bbox(c, (10, 10, 11, 11))
    (False, True, True)
    >>> p = SimpleNamespace(centerline=c.centerline, core_start_m=2.0, core_end_m=2.0)
    >>> in_bbox(p, (1, 1, 2, 2))   # a feature of no length: its one point
    True
    """
    xy = feature_line(curve)
    xmin, ymin, xmax, ymax = bbox
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    if lo[0] > xmax or hi[0] < xmin or lo[1] > ymax or hi[1] < ymin:
        return False  # the feature's own bounds miss the box
    inside = (xy[:, 0] >= xmin) & (xy[:, 0] <= xmax) & (xy[:, 1] >= ymin) & (xy[:, 1] <= ymax)
    if inside.any():
        return True
    from shapely import LineString, box

    return bool(LineString(xy).intersects(box(xmin, ymin, xmax, ymax)))


def select(curves: Iterable[Curve], selection: Selection) -> list[Curve]:
    """The curves that pass ``selection`` (kinds, junctions, box), in their order."""
    kinds = set(selection.kinds)
    junctions = set(selection.junctions)
    bbox = selection.bbox
    ids = selection.curve_ids
    return [c for c in curves
            if (ids is None or c.curve_id in ids)
            and (not kinds or c.kind in kinds)
            and (not junctions or c.junction in junctions)
            and (bbox is None or in_bbox(c, bbox))]


def load_selected(
    net: Network,
    selection: Selection | None = None,
    options: CurveOptions | None = None,
) -> list[Curve]:
    """The curves of ``net`` that pass ``selection``, with areas built on demand.

    Only the selected kinds are extracted. When the selection also drops curves by
    junction or box, the curves are extracted without areas, filtered, and only the kept
    ones get an :class:`~clearance.networks.area_book.AreaBook` (so no area of a dropped curve is
    ever built).
    """
    selection = selection or Selection()
    kinds = selection.effective_kinds()
    if not selection.narrows:
        return extract_curves(net, kinds, options=options)
    from clearance.networks.area_book import AreaBook

    kept = select(extract_curves(net, kinds, options=options, areas=False), selection)
    if kept:
        AreaBook(net, kept)
    return kept
