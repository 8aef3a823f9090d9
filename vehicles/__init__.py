"""The vehicle table: what each vehicle is, read from CSV and checked (imports nothing of ours).

Modules, in the order data flows:

- ``errors``: the tool's error tree (used by every package).
- ``files``: opening the files a user names, safely.
- ``schema``: the table's columns, kinds, units and defaults.
- ``lock``, ``steering``, ``sensor``, ``underside``: steering lock forms, steering
  mechanisms, a steering-angle sensor, the underside in side view.
- ``derive``: the columns a row does not give, derived from those it does.
- ``vehicle``: one vehicle's geometry in SI units.
- ``table``: loading and validating tables (bundled ones under ``tables/``).
"""
