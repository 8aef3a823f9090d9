"""Output units: SI inside, metres or feet at the edge.

One output uses one unit system (docs/design.md §9, *Output units*): with ``ft`` every
length of a document is in feet, the numbers of its columns (:func:`to_output_units`) and
the lengths written into its sentences (:func:`text_in_units`) alike. Network coordinates
(``x``, ``y``, the ``overreach_x``/``overreach_y`` columns) stay the network's own
(metres), angles are degrees, grades percent and speeds what the text says.
"""

from __future__ import annotations

import math
import re

import pandas as pd

from clearance.vehicles.errors import OptionError
from clearance.vehicles.schema import UNITS_TO_M

__all__ = ["TEXT_COLUMNS", "length_scale", "text_in_units", "to_output_units"]

#: Free-text columns whose lengths :func:`to_output_units` converts (the reasons the
#: analysis writes in metres, and the suspect-height notes of the network reader).
TEXT_COLUMNS = ("reason", "suspect_elevation", "geometry", "conflict_at")

#: Metres per unit of the length units a text may use.
_LENGTH_UNITS = {"mm": 1e-3, "cm": 1e-2, "m": 1.0, "km": 1e3}

# A number (a sign only where it starts a word: not the ``+07`` of ``1e+07``, not the
# ``-3`` of ``E2-3``), optionally a range to a second one (``10.0-20.0 m``, ``1.5 to 3 m``),
# one space, and a length unit as a word of its own, optionally squared (an area). A unit
# followed by ``/`` is a speed's (``m/s``, ``km/h``) and is left alone.
_NUMBER = r"(?:(?<![\w.])[+-]|(?<![\w.+-]))\d+(?:\.\d+)?"
_LENGTH = re.compile(
    rf"(?P<a>{_NUMBER})(?:(?P<sep>-|–| to )(?P<b>[+-]?\d+(?:\.\d+)?))?"
    rf" (?P<unit>{'|'.join(sorted(_LENGTH_UNITS, key=len, reverse=True))})(?P<sq>²)?"
    r"(?![\w/²³])")


def length_scale(units: str) -> float:
    """Metres per output unit (``"m"`` or ``"ft"``)."""
    try:
        return UNITS_TO_M[units]
    except KeyError:
        raise OptionError(f"unknown units {units!r}: use 'm' or 'ft'") from None


def _converted(number: str, factor: float) -> str:
    """``number`` (text) times ``factor``, with as many decimals as it had, and its ``+``."""
    decimals = len(number.partition(".")[2])
    text = f"{float(number) * factor:.{decimals}f}"
    return "+" + text if number.startswith("+") and not text.startswith("-") else text


def text_in_units(text: str, units: str) -> str:
    """``text`` with each length it gives in metric units (``0.53 m``, ``10.0-20.0 m``,
    ``1.2 km``) in ``units``, and each area (``m²``) in square ``units``.

    A length is a number, or a range of two (``a-b``, ``a to b``), then one space and
    ``mm``, ``cm``, ``m`` or ``km`` as a word of its own. Each number keeps its decimals
    (so ``0.53 m`` becomes ``1.74 ft``: the metre figure was rounded to the centimetre,
    and the feet are within that rounding of the length, ``0.005 m / 0.3048`` plus half
    a last digit) and its explicit ``+``. Everything else is left as written: numbers
    without a unit (network coordinates such as ``(x 405.11, y -10.65)``, counts),
    percentages, degrees, times (``2.00 s``) and speeds (``m/s``, ``km/h``). With
    ``units="m"`` the text is returned as it is.

    Examples
    --------
    >>> print(text_in_units("leaves the paved area by 0.53 m; worst at station 52.1 m of "
    ...                     "the curve (x 405.11, y -10.65): 50% at 2 m/s, 12 deg", "ft"))
    ... # doctest: +NORMALIZE_WHITESPACE
    leaves the paved area by 1.74 ft; worst at station 170.9 ft of the curve
    (x 405.11, y -10.65): 50% at 2 m/s, 12 deg
    >>> text_in_units("on the level at 3.0 m, stations 10.0-20.0 m; +0.25 m; 2 m² hole", "ft")
    'on the level at 9.8 ft, stations 32.8-65.6 ft; +0.82 ft; 22 ft² hole'
    >>> text_in_units("swung 1.5 to 3 m, -0.30 m, 1.2 km", "ft")
    'swung 4.9 to 10 ft, -0.98 ft, 3937.0 ft'
    >>> text_in_units("no lengths: 3 minutes, 1e+07 m/s, lane E2-3 m", "ft")
    'no lengths: 3 minutes, 1e+07 m/s, lane E2-3 m'
    >>> text_in_units("", "ft"), text_in_units("0.53 m", "m")
    ('', '0.53 m')
    """
    scale = length_scale(units)
    if scale == 1.0 or not text:
        return text

    def convert(match: re.Match[str]) -> str:
        squared = match["sq"] is not None
        factor = _LENGTH_UNITS[match["unit"]] / scale
        factor = factor ** 2 if squared else factor
        out = _converted(match["a"], factor)
        if match["b"] is not None:
            out += match["sep"] + _converted(match["b"], factor)
        return f"{out} {units}{'²' if squared else ''}"

    return _LENGTH.sub(convert, text)


def to_output_units(frame: pd.DataFrame, units: str, suffix: bool = False) -> pd.DataFrame:
    """Rename ``*_m`` columns (dropping the suffix) in ``units``; ``*_rad`` to ``*_deg``;
    the lengths in the text of :data:`TEXT_COLUMNS` in ``units`` (:func:`text_in_units`).

    With ``suffix`` a ``*_m`` column keeps a unit suffix, that of ``units`` (``margin_m``
    becomes ``margin_ft``; in metres the names stay as they are).

    Examples
    --------
    >>> f = pd.DataFrame({"ctr_m": [0.3048], "max_steer_rad": [3.141592653589793]})
    >>> to_output_units(f, "ft").round(6).to_dict("list")
    {'ctr': [1.0], 'max_steer_deg': [180.0]}
    >>> g = pd.DataFrame({"margin_m": [-0.6096], "x": [405.11], "reason": ["by 0.61 m"]})
    >>> to_output_units(g, "ft", suffix=True).round(6).to_dict("list")
    {'margin_ft': [-2.0], 'x': [405.11], 'reason': ['by 2.00 ft']}
    >>> to_output_units(g.iloc[:0], "ft", suffix=True).columns.tolist()
    ['margin_ft', 'x', 'reason']
    """
    scale = length_scale(units)
    out = pd.DataFrame(index=frame.index)
    for col in frame.columns:
        if col.endswith("_m"):
            out[col[:-2] + (f"_{units}" if suffix else "")] = frame[col] / scale
        elif col.endswith("_rad"):
            out[col[:-4] + "_deg"] = frame[col] * (180.0 / math.pi)
        elif col in TEXT_COLUMNS:
            out[col] = [text_in_units(t, units) if isinstance(t, str) else t
                        for t in frame[col]]
        else:
            out[col] = frame[col]
    return out
