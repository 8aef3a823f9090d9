"""Geometry and kinematics without SUMO (imports :mod:`clearance.vehicles` only).

Modules, in the order data flows:

- ``turning``, ``control_law``, ``design_turn``: steady-state turning geometry, the paper's
  control law, the Green Book's design turn.
- ``kinematics``, ``trailer``: the bicycle model and a towed unit.
- ``polyline``: centre lines prepared for tracking.
- ``tracking``, ``tracking_loop``: a vehicle following a centre line (the compiled loop).
- ``envelope``, ``kernels``: the swept path of a run (compiled measures).
- ``feature``, ``levels``, ``margins``, ``overreach``, ``clearance``: judging a sweep
  against the three areas: the feature window, storeys, signed margins, where it
  overreaches, the verdict.
- ``vertical``: the underside against the profile.
- ``failures``: what one run's geometry may fail with.
"""
