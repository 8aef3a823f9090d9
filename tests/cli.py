"""The ``clearance`` command as a subprocess runs it: this interpreter, the installed package."""

import sys

#: ``[*CLI, "report", ...]`` runs ``clearance report ...``.
CLI = (sys.executable, "-m", "clearance.reports.cli")
