"""The batch evaluator's one entry point: the backend by name."""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd

from ..util.parsing import parse_name
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
    auto_timestep: bool = False,
) -> pd.DataFrame:
    """Many designs on one behaviour under one settings, on a batch backend.

    Args:
        designs: a list of LegDesigns or design names (``"SS"``, ``"PVC-Ti-SS"``).
        behaviour: a Behaviour or a name (``"forward"``, ...).
        settings: the run's :class:`BatchSettings` (None: the paper's 60 s at
            1e-4 s, 20 s transient).
        backend: ``"mujoco"`` (CPU rollouts, the reference) or ``"warp"`` (MuJoCo Warp),
            any case (:func:`mat_hopper.util.parsing.parse_name`).
        device: the Warp device for the warp backend (``"cpu"``, ``"cuda"``).
        workers: processes for the mujoco backend (default: every core).
        max_batch: most worlds in one warp batch.
        progress: show a progress bar.
        auto_timestep: backend ``"mujoco"`` only: each design at its own
            ``timestep_s="auto"`` (physics substeps of its control period,
            :func:`mat_hopper.batch.design_settings`), ``settings.timestep_s``
            unused; False: every design at ``settings.timestep_s``.

    Returns:
        One row per design, in input order (see :mod:`mat_hopper.batch`):
        :data:`~mat_hopper.batch.RESULT_COLUMNS` (n_hops; hop_height_m in m,
        tracking_error_m in m and power_w in W, means over the scored hop
        cycles; stable) and :data:`~mat_hopper.batch.EXTRA_COLUMNS`.

    Raises:
        ValueError: a string of designs, options of the other backend, counts
            < 1, settings that are not BatchSettings, an unknown backend, or
            auto_timestep on the warp backend (one physics step for every world).
        WarpUnavailable: the warp backend without mujoco-warp installed.
    """
    if isinstance(designs, str):
        raise ValueError(
            f"designs must be a list of designs (names or LegDesigns), got the string {designs!r}; "
            "mat_hopper.batch.parse_design_list splits 'A,B,C'"
        )
    if settings is not None and not isinstance(settings, BatchSettings):
        raise ValueError(
            f"settings must be a BatchSettings (or None: the paper's 60 s runs), got {type(settings).__name__}"
        )
    backend = parse_name(backend, BACKENDS, "backend")
    for name, value in (("workers", workers), ("max_batch", max_batch)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 1):
            raise ValueError(f"{name} must be an integer >= 1 (or None), got {value!r}")
    if backend == "mujoco" and (device is not None or max_batch is not None):
        raise ValueError("device and max_batch are for backend='warp'")
    if backend == "warp" and workers is not None:
        raise ValueError("workers is for backend='mujoco' (a warp batch is one process)")
    if backend == "warp" and auto_timestep:
        raise ValueError(
            "auto_timestep is for backend='mujoco': a warp batch runs every world at one physics step, "
            "the controller every step; give settings a timestep_s"
        )
    if backend == "mujoco":
        return evaluate_cpu(
            designs, behaviour, settings, workers=workers, progress=progress, auto_timestep=auto_timestep
        )
    if backend == "warp":
        from ._warp import evaluate_warp

        return evaluate_warp(designs, behaviour, settings, device=device, max_batch=max_batch, progress=progress)
    raise ValueError(f"unknown backend {backend!r}; accepted: {', '.join(BACKENDS)}")
