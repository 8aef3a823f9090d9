"""Exports, one module per format (as sumolib's ``output/convert``).

- ``envelopes``: the record every writer takes, and the checks they share.
- ``geojson``, ``dxf``, ``sumo``: GIS, CAD and sumo-gui files.
- ``study``: a study's records and each network's export files.
"""
