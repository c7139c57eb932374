"""Warm start for the runner's worker processes (private).

The runner's forkserver imports this module once before it forks any
worker: the heavy imports (MuJoCo, numba's compiled rollout loop from its
on-disk cache, scipy, pyarrow) and one tiny rollout happen here, and every
worker forked afterwards starts with them loaded. Nothing here may raise:
a failed warm-up only means colder workers.
"""

try:
    import pyarrow.parquet  # noqa: F401

    from .. import metrics, stability  # noqa: F401
    from ..sim import SimSettings, simulate

    simulate("MD", "static", settings=SimSettings(duration_s=0.002, timestep_s=1e-3, transient_s=0.0))
except Exception:  # pragma: no cover
    pass
