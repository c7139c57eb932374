"""The paper's experiments and how they run.

- :mod:`~mat_hopper.experiments.profiles`: run profiles (``paper``, ``quick``);
- :mod:`~mat_hopper.experiments.paper`: experiments 1-3, the stable-time-step
  map and the book's extra checks, as data;
- :mod:`~mat_hopper.experiments.runner`: the one result cache and the one
  process pool (every grid of runs, whole rollouts included);
- :mod:`~mat_hopper.experiments.reproduce`: the reproduction pipeline
  (tables, figures, claims).

This package's ``__init__`` imports nothing. The cache keys are the core's
:mod:`mat_hopper.util.keys` (the core module :mod:`mat_hopper.physics.stability` uses them too).
"""
