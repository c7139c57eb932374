"""Analysis of result tables: statistics, tables for reading, the paper's claims.

- :mod:`~mat_hopper.analysis.change`: the one percent change against a
  baseline and the one round-off floor (a leaf module: the core's
  :mod:`mat_hopper.metrics` uses it too);
- :mod:`~mat_hopper.analysis.stats`: comparisons (Mann-Whitney U with
  Holm's correction, bootstrap intervals of replicate means);
- :mod:`~mat_hopper.analysis.tables`: small tables of results for the page;
- :mod:`~mat_hopper.analysis.claims`: the paper's claims beside ours.

This package's ``__init__`` imports nothing, so importing one module never
drags in the others.
"""
