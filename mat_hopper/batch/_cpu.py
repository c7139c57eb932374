"""The CPU reference backend: one ``mat_hopper.core.sim`` rollout per design.

Each design runs through :func:`mat_hopper.core.sim.simulate` and is summarised
by :func:`mat_hopper.physics.metrics.run_summary`, the package's own definitions;
designs run in parallel over processes.
"""

from __future__ import annotations

import math
import multiprocessing
import os
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd

from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import as_design
from ..util.pool import stop_pool
from ._settings import BatchSettings, design_settings, finite_mean, result_frame


def _row(design, beh, settings) -> dict:
    from ..core.sim import C, simulate
    from ..physics.metrics import run_summary

    r = simulate(design, beh, settings=settings, warn=False)  # the row says it: stable, diverged_at_s
    s = run_summary(r)
    err = np.hypot(*(r.base_pos[:, :2] - r.data[:, [C["x_des"], C["y_des"]]]).T)
    power = np.hypot(*r.hip_power.T)
    return {
        "design": design.name,
        "n_hops": int(s["n_hops"]),
        "hop_height_m": s["mean_hop_height_m"],
        "tracking_error_m": s["mean_tracking_error_m"],
        "power_w": s["mean_power_w"],
        "stable": bool(s["stable"]),
        "behaviour": beh.name,
        "sensor_timing": s["sensor_timing"],
        "diverged_at_s": s["diverged_at_s"],
        "total_mass_kg": s["total_mass_kg"],
        "backend": "mujoco",
        "upright": bool(r.upright),
        "fell_at_s": math.nan if r.fell_at_s is None else r.fell_at_s,
        "suspect_at_s": math.nan if s["suspect_at_s"] is None else s["suspect_at_s"],
        "run_tracking_error_m": finite_mean(err),
        "run_power_w": finite_mean(power),
    }


def _row_star(args):
    return _row(*args)


def evaluate_cpu(
    designs: Sequence,
    behaviour,
    settings: BatchSettings | None = None,
    *,
    workers: int | None = None,
    progress: bool = False,
    auto_timestep: bool = False,
) -> pd.DataFrame:
    """The mujoco backend: one CPU rollout (:func:`mat_hopper.core.sim.simulate`) per design.

    Args:
        designs: LegDesigns or names.
        behaviour: a Behaviour or a name.
        settings: the run's :class:`BatchSettings` (None: the paper's protocol).
        workers: processes (default: every core; 1 runs in this process).
        progress: show a progress bar.
        auto_timestep: run each design at its own ``timestep_s="auto"``
            (physics substeps of its control period, :func:`design_settings`);
            False: every design at ``settings.timestep_s``.

    Returns:
        One row per design, in input order: :data:`RESULT_COLUMNS` (n_hops,
        hop_height_m in m, tracking_error_m in m, power_w in W, stable) and
        :data:`EXTRA_COLUMNS`.

    Raises:
        ValueError: invalid designs, behaviour or workers.
    """
    settings = settings or BatchSettings()
    designs = [as_design(d) for d in designs]
    beh = get_behaviour(behaviour)
    workers = min(len(designs), workers or os.cpu_count() or 1)
    tasks = [(d, beh, design_settings(d, settings, auto_timestep)) for d in designs]
    if progress:
        from ..util.progress import progress_bar

        bar = progress_bar(total=len(tasks), unit="design", desc="mujoco")
    else:
        bar = None
    rows = []
    try:
        if workers <= 1:
            for t in tasks:
                rows.append(_row_star(t))
                if bar:
                    bar.update(1)
        else:
            ctx = multiprocessing.get_context(
                "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
            )
            pool = ProcessPoolExecutor(workers, mp_context=ctx)
            try:
                # submit and read in order, not pool.map: its iterator cancels the futures
                # left (Future.cancel()) when an interrupt stops it, which then races the
                # pool's manager thread into InvalidStateError (CPython < 3.12) as the
                # workers are stopped (mat_hopper.experiments.runner.stop_pool)
                futures = [pool.submit(_row_star, t) for t in tasks]
                for fut in futures:
                    rows.append(fut.result())
                    if bar:
                        bar.update(1)
            except BaseException:  # Ctrl-C, SIGTERM (mat_hopper.cli: KeyboardInterrupt), a failed row
                stop_pool(pool, terminate=True)  # the pool cancels the rest, the workers stop now
                raise
            pool.shutdown(wait=True)
    finally:
        if bar:
            bar.close()
    return result_frame(rows)
