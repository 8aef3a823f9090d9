"""Running a study: every vehicle through every curve, in parallel.

- ``run``: :func:`run.run_study`, the study as a whole.
- ``batch``: one batch of runs as a worker runs it.
- ``routes``: a route study: the passages of SUMO routes only.
- ``drives``: chosen vehicle x curve pairs driven in workers (``clearance simulate``).
- ``executor``: local worker processes or a Dask cluster.
- ``lifetime``: every process of a run ends when the command is stopped.
"""
