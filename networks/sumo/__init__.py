"""SUMO itself: the only subpackage that imports libsumo or runs SUMO's programs.

- ``tools``: finding and running the programs the eclipse-sumo package ships.
- ``load_check``: does SUMO load this network? (``sumo -n NET``, once per file).
- ``placement``: what SUMO is told about a run (vTypes, routes, lane hints, replay), free of
  libsumo.
- ``session``: the libsumo session a drive places its vehicles in.
"""
