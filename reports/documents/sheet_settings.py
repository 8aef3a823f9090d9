"""What a report's sheets are asked for: which runs get one, the ghost, the title block.

The title block of a sheet carries what a firm fills in and signs: the project, the
drawing number, who drew and who checked it, the revision and the date
(:class:`Project`). They come from a small project file (:func:`read_project`), by default
``clearance.toml`` beside the study (the folder the command runs in), or ``--project
FILE``, and from options, which win over the file::

    [project]
    name = "Harbour Road junction improvements"
    drawing_number = "HRJ-SP"    # the sheets are HRJ-SP-001, HRJ-SP-002, ...
    drawn = "A. Designer"
    checked = "B. Engineer"
    revision = "P01"
    date = "2026-12-06"

A field left out is left blank on the sheet, for a person to write in; the signature
boxes are always blank.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path

from clearance.vehicles.errors import InputError

__all__ = ["DEFAULT_SHEETS", "MAX_SHEETS", "PROJECT_FILE", "SHEET_CHOICES", "Project",
           "SheetSettings", "read_project"]

#: The project file a study reads when it lies in the folder the command runs in.
PROJECT_FILE = "clearance.toml"
#: ``--sheets``: a sheet for every run that is not clear (the default), for every run, or
#: for none.
SHEET_CHOICES = ("not-clear", "all", "none")
#: Sheets per network at most unless asked otherwise (``--max-sheets``), worst first: every
#: vehicle of the 20 or so worst curves (a sheet takes half a second to draw and 30 kB).
MAX_SHEETS = 60


@dataclass(frozen=True)
class Project:
    """The title block's fields a firm fills in (blank: left for a person to write in).

    Examples
    --------
    >>> p = Project(name="Ring road", drawing_number="RR-SP")
    >>> p.sheet_number(7), Project().sheet_number(7)
    ('RR-SP-007', '007')
    """

    name: str = ""
    drawing_number: str = ""
    drawn: str = ""
    checked: str = ""
    revision: str = ""
    date: str = ""

    def sheet_number(self, number: int) -> str:
        """The drawing number of sheet ``number``: the project's prefix and three digits."""
        return f"{self.drawing_number}-{number:03d}" if self.drawing_number else f"{number:03d}"

    def merged(self, **given: str | None) -> Project:
        """This project with the fields ``given`` (options) set where they are not None.

        >>> Project(name="A", drawn="X").merged(drawn="Y", checked=None).drawn
        'Y'
        """
        values: dict[str, str] = {}
        for f in fields(self):
            value = given.get(f.name)
            values[f.name] = value if value is not None else getattr(self, f.name)
        return Project(**values)


@dataclass(frozen=True)
class SheetSettings:
    """Which runs of a report get a sheet, the vehicle shown beside them, the title block.

    Attributes
    ----------
    which
        One of :data:`SHEET_CHOICES`.
    limit
        Sheets per network at most (None: every run chosen), worst first; by default
        :data:`MAX_SHEETS`: a town's hundreds of runs not clear are its report's, the worst
        curves' its sheets.
    ghost
        A vehicle drawn faintly on every other vehicle's sheet of a curve, for comparison
        (a route study's baseline), or "".
    project
        The title block's fields.
    """

    which: str = "not-clear"
    limit: int | None = MAX_SHEETS
    ghost: str = ""
    project: Project = field(default_factory=Project)

    def __post_init__(self) -> None:
        if self.which not in SHEET_CHOICES:
            raise ValueError(f"sheets: {self.which!r} is not one of {', '.join(SHEET_CHOICES)}")
        if self.limit is not None and self.limit < 0:
            raise ValueError(f"sheets: the limit must be >= 0, got {self.limit}")


#: The sheets of a report when nothing else is asked: every run that is not clear.
DEFAULT_SHEETS = SheetSettings()


def read_project(path: str | Path) -> Project:
    """The :class:`Project` of a project file's ``[project]`` table.

    Raises :class:`~clearance.vehicles.errors.InputError` naming the file (and the key) on
    a missing or malformed file, an unknown key or a value that is not text.

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> p = os.path.join(d, "clearance.toml")
    >>> _ = open(p, "w").write('[project]\\nname = "Ring road"\\nrevision = "P02"\\n')
    >>> read_project(p).revision
    'P02'
    >>> _ = open(p, "w").write('[project]\\nnmae = "Ring road"\\n')
    >>> read_project(p)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    clearance.vehicles.errors.InputError: ...: [project] has no key 'nmae' (known: name, ...)
    """
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError("no such project file", file=path) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the project file: {exc}", file=path) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not a TOML file: {exc}", file=path) from None
    table = data.get("project")
    if not isinstance(table, dict):
        raise InputError("no [project] table (the title block's fields go under it)",
                         file=path)
    known = [f.name for f in fields(Project)]
    values: dict[str, str] = {}
    for key, value in table.items():
        if key not in known:
            raise InputError(f"[project] has no key {key!r} (known: {', '.join(known)})",
                             file=path)
        if hasattr(value, "isoformat"):  # a TOML date: as written
            value = value.isoformat()
        if not isinstance(value, str):
            raise InputError(f"[project] {key} must be text, got {value!r}", file=path)
        values[key] = value
    return Project(**values)
