"""The tool's errors, one tree (docs/design.md §3).

::

    ClearanceError                 anything the tool itself refuses or cannot do
    ├── InputError                 bad input: exit 2, the message and no traceback
    │   ├── TableError             a vehicle table (file, row)
    │   ├── NetworkError           a SUMO network (file, element)
    │   ├── RouteError             a route or additional file (file, route, element)
    │   ├── OptionError            a command-line option or an output path
    │   └── LimitError             an input over one of the tool's own size caps
    └── GeometryError              one curve's areas or paths cannot be built: that curve's
                                   run gets an ``error`` row with the reason; the study goes on

Everything else raised inside the tool (``ValueError`` for a function called with arguments
it does not take, ``TypeError``, ...) is a bug: the command line exits 3 with a one-line
message, and the traceback under ``-v``.

Each input error says where the problem is, in its message and as attributes a script can
read (``file``, ``row``, ``element``; ``None`` when not known):

>>> e = NetworkError("lane 'a_0' has no shape", file="city.net.xml", element="lane 'a_0'")
>>> str(e), e.file, e.element
("city.net.xml: lane 'a_0' has no shape", 'city.net.xml', "lane 'a_0'")
>>> isinstance(e, InputError) and not isinstance(e, GeometryError)
True
"""

from __future__ import annotations

from os import PathLike

__all__ = ["ClearanceError", "GeometryError", "InputError", "LimitError", "NetworkError",
           "OptionError", "RouteError", "TableError"]


class ClearanceError(Exception):
    """The base of every error the tool raises on purpose."""


class InputError(ClearanceError):
    """Bad user input: a missing file, a malformed table or network, an unknown name.

    The command-line interface prints the message and exits with status 2, without a
    traceback. The message names the file, row or element and what is wrong; given
    ``file``, the message is prefixed with it (unless it already starts with it).

    Parameters
    ----------
    message
        What is wrong.
    file, row, element
        Where: the input file, the row of a table (1-based line), the element of a network
        or route file (``"lane 'a_0'"``).
    """

    def __init__(self, message: str = "", *, file: str | PathLike[str] | None = None,
                 row: int | None = None, element: str | None = None) -> None:
        self.file = None if file is None else str(file)
        self.row = row
        self.element = element
        if self.file is not None and not message.startswith(self.file):
            message = f"{self.file}: {message}"
        super().__init__(message)


class TableError(InputError):
    """A vehicle table that cannot be read, or bad rows in it: ``problems`` lists each of
    them (each naming its file, line and column); one problem is the message itself."""

    def __init__(self, problems: list[str] | str, *, file: str | PathLike[str] | None = None,
                 row: int | None = None) -> None:
        self.problems = [problems] if isinstance(problems, str) else list(problems)
        if isinstance(problems, str):
            super().__init__(problems, file=file, row=row)
            return
        super().__init__(
            f"{len(self.problems)} problem(s) in the vehicle table(s):\n  "
            + "\n  ".join(self.problems), file=file, row=row)


class NetworkError(InputError):
    """A SUMO network the tool cannot read, or one SUMO itself refuses."""


class RouteError(InputError):
    """A route or additional file: malformed, or naming what the network does not have."""


class OptionError(InputError):
    """A command-line option's value (a bad ``--bbox``, an unknown method, an output path
    that cannot be written)."""


class LimitError(InputError):
    """An input over one of the tool's own size caps (bytes, elements, rows): refused by the
    tool before anything else is asked of it; the message names the cap and how to raise
    it."""


class GeometryError(ClearanceError):
    """A curve's areas or a vehicle's path through it cannot be built (a centre line that
    turns back on itself, an area that is not a polygon): that run gets an ``error`` row
    with this message, and the study goes on. Not bad input: the network loads in SUMO."""
