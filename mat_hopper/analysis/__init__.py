"""Analysis of result tables: statistics, tables for reading, the paper's claims.

- :mod:`~mat_hopper.analysis.stats`: comparisons (Mann-Whitney U with
  Holm's correction, bootstrap intervals of replicate means);
- :mod:`~mat_hopper.analysis.tables`: small tables of results for the page;
- :mod:`~mat_hopper.analysis.claims`: the paper's claims beside ours;
- :mod:`~mat_hopper.analysis.growth`: the growth rate of an oscillation's envelope.

The one percent change against a baseline is the core's
:func:`mat_hopper.util.change.percent_change`.

This package's ``__init__`` imports nothing, so importing one module never
drags in the others.
"""
