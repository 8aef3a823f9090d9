"""Errors shared by every package: bad input is reported, never asserted."""

from __future__ import annotations

__all__ = ["InputError", "LimitError", "TableError"]


class InputError(Exception):
    """Bad user input: a missing file, a malformed table or network, an unknown name.

    The command-line interface prints the message and exits with status 2, without a
    traceback. The message must name the file, row or element and what is wrong.
    """


class TableError(InputError):
    """One or more bad rows in a vehicle table; ``problems`` lists each of them."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__(
            f"{len(self.problems)} problem(s) in the vehicle table(s):\n  "
            + "\n  ".join(self.problems)
        )


class LimitError(InputError):
    """An input over one of the tool's own size caps (bytes, elements, rows): refused by the
    tool before anything else is asked of it; the message names the cap and how to raise
    it."""
