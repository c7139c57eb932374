"""Many designs at once: batch evaluation on MuJoCo Warp, with the CPU path as reference.

:func:`evaluate` runs designs of one behaviour and gives one row per design
(:data:`RESULT_COLUMNS`: n_hops, hop_height_m, tracking_error_m, power_w,
stable, the definitions of :mod:`mat_hopper.physics.metrics`):

- ``backend="mujoco"``: one CPU rollout per design (:mod:`mat_hopper.core.sim`),
  in parallel over processes. The reference.
- ``backend="warp"``: designs grouped by topology, each group one batched
  MuJoCo Warp simulation (per-world masses, inertias and spring
  stiffnesses), the controller and the per-hop metrics as Warp kernels.
  Needs the optional ``gpu`` extra (``mujoco-warp``, ``warp-lang``); runs
  on a GPU or, slowly, on Warp's CPU device.

:func:`spec_scan_batch` runs the reference protocol's stable-time-step
scan (experiment 4) of many designs, one batch per time step of its ladder.

Example::

    from mat_hopper.batch import BatchSettings, evaluate
    table = evaluate(["SS", "rho-inc", "PVC-Ti-SS"], "forward",
                     BatchSettings(duration_s=60, transient_s=20), backend="warp", device="cuda")
"""

from __future__ import annotations

from ..core.materials import as_design
from ._agreement import AGREEMENT_COLUMNS, RELATIVE_TOLERANCE, agreement
from ._cpu import evaluate_cpu
from ._designs import (
    design_columns,
    designs_from_csv,
    designs_from_frame,
    designs_to_frame,
    group_by_topology,
    parse_design_list,
    topology_key,
)
from ._evaluate import evaluate
from ._settings import BACKENDS, EXTRA_COLUMNS, RESULT_COLUMNS, BatchSettings, design_settings
from ._stability import SCAN_COLUMNS, TRY_COLUMNS, spec_scan_batch


def __getattr__(name):
    # The warp side imports lazily: mujoco-warp is an optional dependency.
    if name in ("WarpBatch", "WarpUnavailable", "evaluate_warp", "require_warp", "warp_available", "design_fields"):
        from . import _warp

        return getattr(_warp, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "AGREEMENT_COLUMNS",
    "RELATIVE_TOLERANCE",
    "agreement",
    "BACKENDS",
    "EXTRA_COLUMNS",
    "RESULT_COLUMNS",
    "SCAN_COLUMNS",
    "TRY_COLUMNS",
    "BatchSettings",
    "WarpBatch",
    "WarpUnavailable",
    "as_design",
    "design_fields",
    "design_columns",
    "design_settings",
    "designs_from_csv",
    "designs_from_frame",
    "designs_to_frame",
    "evaluate",
    "evaluate_cpu",
    "evaluate_warp",
    "group_by_topology",
    "parse_design_list",
    "require_warp",
    "spec_scan_batch",
    "topology_key",
    "warp_available",
]
