"""Driving a run: the path a vehicle takes through a curve, and how it is judged.

Modules, in the order data flows:

- ``runs``: what a drive is asked and what it returns.
- ``shapes``, ``room``, ``candidates``, ``refine``: swung paths: offset profiles and corner
  cuts, the room the pavement gives, the family of candidates, the local refinement.
- ``judging``: which of a run's paths a driver would take.
- ``swing``: the second pass: a swung path for every run not clear on its lane.
- ``drive``: the simulated method: the kinematic model placed in SUMO
  (:mod:`clearance.networks.sumo.session`), then the swung pass.
- ``analytic``: the analytic method, beside it: steady state at every station.
"""
