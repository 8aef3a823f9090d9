"""A study and what comes of it: running it, its results, documents, exports, the command line.

Subpackages, in the order data flows:

- :mod:`clearance.reports.output`: output safety (atomic files, whole output folders, file
  names from ids).
- :mod:`clearance.reports.results`: the run records and what is derived from them (design
  feedback, vertical checks, tables, golden files, waivers, units).
- :mod:`clearance.reports.study`: running a study (batches through an executor, the life
  of its processes).
- :mod:`clearance.reports.exports`: GeoJSON, DXF and SUMO additional files, one module per
  format.
- :mod:`clearance.reports.documents`: report.html and report.md, figures, sheets, templates.
- :mod:`clearance.reports.cli`: the ``clearance`` command, one module per sub-command: each
  parses its options and calls the packages above.
"""
