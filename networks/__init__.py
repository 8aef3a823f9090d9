"""SUMO networks: reading, curves, areas, and driving a run (imports vehicles, analysis).

Modules, in the order data flows:

- ``safe_xml``, ``shapes``, ``reader``, ``model``, ``integrity``, ``elevation``,
  ``loading``: reading a network as SUMO loads it (:func:`loading.load_network`).
- ``geometry``, ``profiles``, ``profile_kernel``, ``paths``: plane geometry and the
  curvature of lane sequences.
- ``curves``, ``selection``, ``permissions``: the curves of a network, a scheme's
  selection, which classes may drive them.
- ``stacking``, ``area_groups``, ``areas``, ``area_book``, ``collector``: each curve's
  three areas, storey by storey.
- ``routes``, ``passages``: SUMO route files, and the passages a route drives.
- ``plot``: plan figures.
- :mod:`clearance.networks.driving`: choosing and driving a vehicle's path through a curve.
- :mod:`clearance.networks.sumo`: SUMO itself (the only code that imports libsumo).
- :mod:`clearance.networks.samples`: the bundled sample networks.
"""
