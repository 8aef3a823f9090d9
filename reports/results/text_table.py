"""Aligned plain-text tables for the terminal."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

__all__ = ["counted", "format_table"]


def format_table(rows: Sequence[Mapping[str, str]], columns: Sequence[str],
                 heads: Sequence[str], text_columns: int) -> list[str]:
    """Lines of a table: the first ``text_columns`` left-aligned, the rest (numbers) right.

    Examples
    --------
    >>> rows = [{"a": "x", "n": "1.5"}, {"a": "long", "n": "10.25"}]
    >>> print("\\n".join(format_table(rows, ["a", "n"], ["name", "value"], 1)))
    name  value
    x       1.5
    long  10.25
    """
    widths = [max(len(h), *(len(r[c]) for r in rows)) if rows else len(h)
              for h, c in zip(heads, columns, strict=True)]

    def line(cells: Sequence[str]) -> str:
        parts = [v.ljust(w) if i < text_columns else v.rjust(w)
                 for i, (v, w) in enumerate(zip(cells, widths, strict=True))]
        return "  ".join(parts).rstrip()

    return [line(heads)] + [line([r[c] for c in columns]) for r in rows]


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and the noun, singular for one.

    >>> counted(1, "vehicle"), counted(2, "vehicle"), counted(0, "run")
    ('1 vehicle', '2 vehicles', '0 runs')
    >>> counted(2, "batch", "batches")
    '2 batches'
    """
    return f"{n} {noun if n == 1 else (plural or noun + 's')}"
