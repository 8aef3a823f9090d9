"""What one run's geometry may fail with: the failures a study turns into an ``error`` row.

A curve whose areas or paths cannot be built fails that curve's runs only: our own
:class:`~clearance.vehicles.errors.GeometryError`, or shapely's (GEOS) error on geometry
it cannot compute. Nothing else is caught: any other exception is a bug and stops the
command (exit 3).

>>> import shapely
>>> try:
...     shapely.from_wkt("POLYGON ((0 0, 1 1")
... except GEOMETRY_FAILURES as exc:
...     print(type(exc).__name__)
GEOSException
"""

from __future__ import annotations

import shapely.errors

from clearance.vehicles.errors import GeometryError

__all__ = ["GEOMETRY_FAILURES"]

#: ``except GEOMETRY_FAILURES`` where one run's geometry may fail and the others go on.
GEOMETRY_FAILURES: tuple[type[Exception], ...] = (GeometryError, shapely.errors.ShapelyError)
