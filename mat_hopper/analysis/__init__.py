"""Analysis of result tables: statistics, tables for reading, the paper's claims.

- :mod:`~mat_hopper.analysis.stats`: comparisons (Mann-Whitney U with
  Holm's correction, bootstrap intervals of replicate means);
- :mod:`~mat_hopper.analysis.tables`: small tables of results for the page;
- :mod:`~mat_hopper.analysis.claims`: the paper's claims beside ours;
- :mod:`~mat_hopper.analysis.growth`: the growth rate of an oscillation's envelope;
- :mod:`~mat_hopper.analysis.sequential`: sequential replication, paired
  seeds only where a verdict still needs them (its public names are
  handed on here, imported when first asked for).

The one percent change against a baseline is the core's
:func:`mat_hopper.util.change.percent_change`.

This package's ``__init__`` imports nothing, so importing one module never
drags in the others.
"""

_SEQUENTIAL = (
    "min_seeds",
    "sign_flip_floor",
    "narrowest_half_width",
    "family_verdicts",
    "sequential_family",
    "replay_family",
    "replay_families",
    "seeds_saved",
)


def __getattr__(name):
    # sequential's names, imported on first use so that importing the package stays free
    if name in _SEQUENTIAL:
        from . import sequential

        return getattr(sequential, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
