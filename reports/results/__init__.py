"""A study's results: the run records and what is derived from them.

- ``records``: one :class:`records.RunRecord` per network x vehicle x curve, the columns of
  clearance.csv and the verdict order.
- ``feedback``, ``vertical``: design feedback and the vertical checks of each run.
- ``units``, ``text_table``, ``tables``: output units, terminal tables, clearance.csv and
  summary.json.
- ``csv_rows``, ``golden``, ``waivers``, ``gate``: the small CSV files ``check`` reads, and
  its gate.
- ``routes``: a route study's rows (``routes.csv``) and the comparison with a baseline.
- ``curve_rows``, ``vehicle_metrics``, ``simulate_files``: the tables of ``curves``,
  ``vehicles`` and ``simulate``.
"""
