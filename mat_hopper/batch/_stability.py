"""The reference protocol's stable-time-step scan for many designs at once.

docs/reference-hopper.md (experiment 4): for each design, try time steps
log-spaced from 1e-3 down to 1e-5 s (20 values) on static hopping until a
run ends upright (no NaN or inf, every |qacc| <= 1e6, the base above
0.1 m); that step is the design's stable time step (nan if none is).
:func:`mat_hopper.physics.stability.spec_scan` does this one design at a time.

:func:`spec_scan_batch` turns the loops inside out: each rung of the
ladder is one call of :func:`mat_hopper.batch.evaluate` (static hopping,
transient 0) over every design that has not yet ended upright, so that on
the warp backend a rung of the paper's 400-design map is one MuJoCo Warp
batch. The answer per design is the same rule as ``spec_scan``'s; with
``backend="mujoco"`` it is the CPU rollouts themselves (the reference).

Only the scan is batched. The map's bisection
(:func:`mat_hopper.physics.stability.largest_stable_timestep`) adapts each design's
next step to its last outcome, so it stays one design at a time on the CPU
(``mat-hopper reproduce``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from ..core import reference as ref
from ..core.controller import SensorTiming
from ..core.materials import DEFAULT_CONVENTION, as_design
from ..core.model import MAX_TIMESTEP_S
from ..physics.stability import SPEC_SCAN_N, spec_ladder
from ._evaluate import evaluate
from ._settings import BatchSettings

SCAN_COLUMNS = ("design", "density_g_cm3", "modulus_gpa", "spec_timestep_s", "n_spec_tries", "backend")
TRY_COLUMNS = ("design", "dt_s", "stable", "upright", "diverged_at_s")


def spec_scan_batch(
    designs: Sequence,
    *,
    duration_s: float = ref.STABILITY_TEST_DURATION_S,
    convention: str = DEFAULT_CONVENTION,
    sensor_timing: SensorTiming | str | int = SensorTiming(),
    first_s: float = ref.STABILITY_TIMESTEP_RANGE[0],
    last_s: float = ref.STABILITY_TIMESTEP_RANGE[1],
    n: int = SPEC_SCAN_N,
    backend: str = "mujoco",
    device: str | None = None,
    workers: int | None = None,
    max_batch: int | None = None,
    progress: bool = False,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The reference stable-time-step scan of many designs on a batch backend.

    Args:
        designs: LegDesigns or names.
        duration_s: static hopping per try, s.
        convention: the stiffness convention.
        sensor_timing: the controller's (:class:`~mat_hopper.core.controller.SensorTiming`;
            a name or a latency in physics steps).
        first_s, last_s, n: the ladder of :func:`mat_hopper.physics.stability.spec_ladder`
            (s, from first_s down to last_s, n rungs).
        backend, device, workers, max_batch, progress: as :func:`mat_hopper.batch.evaluate`.

    Returns:
        (one row per design, :data:`SCAN_COLUMNS`: spec_timestep_s, the first
        rung at which the design ends upright, nan if none; density_g_cm3 and
        modulus_gpa of the first segment (the map's designs are mono-material);
        one row per try, :data:`TRY_COLUMNS`).

    Raises:
        ValueError: an empty design list, n < 1, or a ladder outside (0, 0.1] s.
    """
    designs = [as_design(d) for d in designs]
    if not designs:
        raise ValueError("no designs to scan")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"the ladder needs n >= 1 time steps, got {n!r}")
    if not (0 < last_s <= first_s <= MAX_TIMESTEP_S):
        raise ValueError(
            f"the ladder must run from first_s down to last_s within (0, {MAX_TIMESTEP_S:g}] s, "
            f"got {first_s!r}, {last_s!r}"
        )
    ladder = spec_ladder(first_s, last_s, n)
    found = [math.nan] * len(designs)
    n_tries = [0] * len(designs)
    tries = []
    todo = list(range(len(designs)))
    for dt in ladder:
        if not todo:
            break
        settings = BatchSettings(
            duration_s=duration_s,
            timestep_s=float(dt),
            transient_s=0.0,
            convention=convention,
            sensor_timing=sensor_timing,
        )
        table = evaluate(
            [designs[i] for i in todo],
            "static",
            settings,
            backend=backend,
            device=device,
            workers=workers,
            max_batch=max_batch,
            progress=progress,
        )
        todo = _record_rung(float(dt), todo, table, designs, found, n_tries, tries)
    summary = pd.DataFrame(
        [
            {
                "design": d.name,
                "density_g_cm3": d.densities_g_cm3[0],
                "modulus_gpa": d.moduli_gpa[0],
                "spec_timestep_s": found[i],
                "n_spec_tries": n_tries[i],
                "backend": backend,
            }
            for i, d in enumerate(designs)
        ],
        columns=list(SCAN_COLUMNS),
    )
    return summary, pd.DataFrame(tries, columns=list(TRY_COLUMNS))


def _record_rung(dt: float, todo: list, table, designs, found: list, n_tries: list, tries: list) -> list:
    """One rung of the ladder: each try recorded, the step noted for the
    designs that ended upright; returns the designs still to try."""
    left = []
    for i, row in zip(todo, table.to_dict("records")):
        n_tries[i] += 1
        tries.append(
            {
                "design": designs[i].name,
                "dt_s": dt,
                "stable": bool(row["stable"]),
                "upright": bool(row["upright"]),
                "diverged_at_s": math.nan if row["diverged_at_s"] is None else float(row["diverged_at_s"]),
            }
        )
        if row["upright"]:
            found[i] = dt
        else:
            left.append(i)
    return left
