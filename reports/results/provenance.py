"""What each run's verdict rests on, and where its worst conflict lies.

:func:`set_provenance` fills two columns of ``clearance.csv`` after a study: ``geometry``
(the netconvert defaults among the inputs the verdict rests on, or ``data``:
:mod:`clearance.networks.provenance`) and ``conflict_at`` (where along the curve the worst
conflict of a run that is not clear lies: :mod:`clearance.networks.places`).
:func:`provenance_summary` splits each network's runs that are not clear into those resting on
data and those resting on defaults, with the assumptions that carry most of them.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence
from typing import Protocol

import pandas as pd

from clearance.networks.curves import Curve
from clearance.networks.model import DEFAULT_LANE_WIDTH_M, Network
from clearance.networks.places import place_of
from clearance.networks.provenance import (
    BuildHeader,
    assumption_key,
    curve_assumptions,
    geometry_words,
    read_header,
)
from clearance.reports.results.records import RunRecord

__all__ = ["NOT_CLEAR", "header_summary", "provenance_summary", "set_provenance"]

#: The verdicts a designer has to look at (an ``error`` is the tool's, not the geometry's).
NOT_CLEAR = ("encroaches", "fails", "cannot-turn")


class _NetworkCurves(Protocol):
    name: str
    network: Network
    curves: list[Curve]


def set_provenance(records: Iterable[RunRecord], nets: Sequence[_NetworkCurves]) -> None:
    """Fill ``geometry`` of every record and ``conflict_at`` of those not clear."""
    words: dict[tuple[str, str], str] = {}
    by_name = {n.name: n for n in nets}
    headers = {n.name: read_header(n.network.path) for n in nets}
    curves = {(n.name, c.curve_id): c for n in nets for c in n.curves}
    for rec in records:
        key = (rec.network, rec.curve_id)
        curve = curves.get(key)
        if curve is None:
            continue
        net = by_name[rec.network].network
        if key not in words:
            words[key] = geometry_words(curve_assumptions(net, curve, headers[rec.network]))
        rec.geometry = words[key]
        if rec.verdict in NOT_CLEAR:
            place = place_of(net, curve, rec.overreach_station_m)
            rec.conflict_at = place.words if place is not None else ""


def provenance_summary(frame: pd.DataFrame) -> dict[str, dict[str, dict[str, int]]]:
    """Per network: its runs not clear (``encroaches``, ``fails``, ``cannot-turn``) split by
    what they rest on, and the default assumptions that carry most of them (runs per
    assumption, most first; a run may rest on several).

    Examples
    --------
    >>> f = pd.DataFrame({"network": ["n"] * 3, "verdict": ["fails", "fails", "clear"],
    ...                   "geometry": ["data",
    ...                                "lane width default 3.2 m; corner computed (r 2.0 m)",
    ...                                "lane width default 3.2 m"]})
    >>> provenance_summary(f)["n"]["not_clear"]
    {'runs': 2, 'on_data': 1, 'on_defaults': 1}
    >>> provenance_summary(f)["n"]["defaults_carrying"]
    {'corner computed': 1, 'lane width default 3.2 m': 1}
    """
    out: dict[str, dict[str, dict[str, int]]] = {}
    for name, group in frame.groupby("network", sort=True):
        bad = group[group.verdict.isin(NOT_CLEAR)]
        on_data = int((bad.geometry == "data").sum())
        carrying: Counter[str] = Counter()
        for g in bad.geometry:
            if g and g != "data":
                carrying.update({assumption_key(a) for a in g.split("; ")})
        out[str(name)] = {
            "not_clear": {"runs": len(bad), "on_data": on_data,
                          "on_defaults": len(bad) - on_data},
            "defaults_carrying": dict(sorted(carrying.items(), key=lambda kv: (-kv[1], kv[0]))),
        }
    return out


def header_summary(header: BuildHeader) -> dict[str, object]:
    """What a network's header says of its build, for ``summary.json``.

    >>> header_summary(BuildHeader("netconvert 1.21.0", {"osm-files": "a.osm"}))
    ... # doctest: +NORMALIZE_WHITESPACE
    {'built_by': 'netconvert 1.21.0', 'inputs': ['a.osm'], 'default_lane_width_m': 3.2,
     'corner_radius_m': 4.0}
    """
    return {"built_by": header.tool, "inputs": header.inputs,
            "default_lane_width_m": header.default_lane_width_m or DEFAULT_LANE_WIDTH_M,
            "corner_radius_m": header.corner_radius_m}
