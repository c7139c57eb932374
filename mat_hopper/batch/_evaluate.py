"""The batch evaluator's one entry point: the backend by name."""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd

from ._cpu import evaluate_cpu
from ._settings import BACKENDS, BatchSettings


def evaluate(
    designs: Sequence,
    behaviour,
    settings: BatchSettings | None = None,
    *,
    backend: str = "mujoco",
    device: str | None = None,
    workers: int | None = None,
    max_batch: int | None = None,
    progress: bool = False,
) -> pd.DataFrame:
    """One row per design, in input order (see :mod:`mat_hopper.batch`).

    designs: LegDesigns or names; behaviour: a Behaviour or a name;
    device: Warp device for the warp backend ("cpu", "cuda"); workers:
    processes for the mujoco backend; max_batch: most worlds in one warp
    batch."""
    if backend == "mujoco":
        return evaluate_cpu(designs, behaviour, settings, workers=workers, progress=progress)
    if backend == "warp":
        from ._warp import evaluate_warp

        return evaluate_warp(designs, behaviour, settings, device=device, max_batch=max_batch, progress=progress)
    raise ValueError(f"unknown backend {backend!r}; accepted: {', '.join(BACKENDS)}")
