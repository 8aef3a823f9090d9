"""Documents and drawings: what a designer reads and prints.

- ``plotting``, ``drawing``, ``figures``, ``profile_figure``, ``html_images``: figures.
- ``sheets``, ``templates``: A3 swept-path sheets and turning templates.
- ``report``, ``markdown``: report.html and report.md.
- ``drawings``: the report's drawings made in the study's workers.
- ``writer``: a report's folder written as a whole.
- ``compare``: the side-by-side comparison of vehicle models.
"""
