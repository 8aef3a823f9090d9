"""The gate of ``clearance check`` without a golden file: which runs are not allowed.

A run passes when its verdict is allowed (``clear`` and those given with ``--allow``) or
it is waived (:mod:`clearance.reports.results.waivers`); a vertical finding (``scrapes``,
``too-steep``, :mod:`clearance.reports.results.vertical`) fails unless allowed too.
"""

from __future__ import annotations

from typing import Any

import pandas as pd

from clearance.reports.results.records import VERDICT_ORDER
from clearance.reports.results.vertical import FINDINGS
from clearance.reports.results.waivers import Waived

__all__ = ["not_allowed", "vertical_not_allowed"]


def not_allowed(frame: pd.DataFrame, allowed: set[str], waived: Waived) -> pd.DataFrame:
    """The runs of ``frame`` (rows of ``clearance.csv``) whose verdict is not in
    ``allowed`` and that no waiver covers, worst first (verdict, margin, then ids).

    >>> f = pd.DataFrame({"network": ["n", "n"], "vehicle": ["P", "P"],
    ...                   "curve_id": ["a", "b"], "verdict": ["clear", "fails"],
    ...                   "margin_m": [0.5, -1.0]})
    >>> list(not_allowed(f, {"clear"}, Waived({}, {}, {}, [])).curve_id)
    ['b']
    """
    failing = frame[~frame.verdict.isin(allowed)]
    unwaived = [(n, v, c) not in waived.by for n, v, c in
                zip(failing.network, failing.vehicle, failing.curve_id, strict=True)]
    failing = failing[pd.Series(unwaived, index=failing.index, dtype=bool)]
    return failing.assign(_o=failing.verdict.map(VERDICT_ORDER)).sort_values(
        ["_o", "margin_m", "network", "curve_id", "vehicle"], kind="stable").drop(columns="_o")


def vertical_not_allowed(frame: pd.DataFrame, allowed: set[str]) -> list[Any]:
    """The runs (``frame.itertuples()`` rows) whose vertical finding is not in ``allowed``,
    the deepest first."""
    def findings(text: str) -> set[str]:
        return {x.strip() for x in text.split(",")} & set(FINDINGS)

    bad = [r for r in frame.itertuples() if findings(str(r.vertical)) - allowed]
    bad.sort(key=lambda r: (r.vertical_margin_m, r.network, r.curve_id, r.vehicle))
    return bad
