"""Output units: SI inside, metres or feet at the edge."""

from __future__ import annotations

import pandas as pd

from vehicles.errors import InputError
from vehicles.schema import UNITS_TO_M

__all__ = ["length_scale", "to_output_units"]


def length_scale(units: str) -> float:
    """Metres per output unit (``"m"`` or ``"ft"``)."""
    try:
        return UNITS_TO_M[units]
    except KeyError:
        raise InputError(f"unknown units {units!r}: use 'm' or 'ft'") from None


def to_output_units(frame: pd.DataFrame, units: str) -> pd.DataFrame:
    """Rename ``*_m`` columns (dropping the suffix) in ``units``; ``*_rad`` to ``*_deg``.

    Examples
    --------
    >>> f = pd.DataFrame({"ctr_m": [0.3048], "max_steer_rad": [3.141592653589793]})
    >>> to_output_units(f, "ft").round(6).to_dict("list")
    {'ctr': [1.0], 'max_steer_deg': [180.0]}
    """
    scale = length_scale(units)
    out = pd.DataFrame(index=frame.index)
    for col in frame.columns:
        if col.endswith("_m"):
            out[col[:-2]] = frame[col] / scale
        elif col.endswith("_rad"):
            out[col[:-4] + "_deg"] = frame[col] * (180.0 / 3.141592653589793)
        else:
            out[col] = frame[col]
    return out
