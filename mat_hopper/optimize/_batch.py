"""The optimizer's objective on the batch backend (MuJoCo Warp): many designs at once.

:func:`evaluate_batch` scores designs as :func:`~mat_hopper.optimize.evaluate`
does on the CPU, with the designs simulated together by :mod:`mat_hopper.batch`
(MuJoCo Warp, on a GPU or, slowly, on Warp's CPU device): one batch per
behaviour (grouped by topology inside :func:`mat_hopper.batch.evaluate`).
:class:`~mat_hopper.optimize._evaluators.WarpEvaluator` hands it the
batches of the optimizer's one loop (:func:`~mat_hopper.optimize.run_batch_study`).

The objective is the CPU path's, definition for definition
(:mod:`mat_hopper.optimize._objective`): per behaviour, the per-hop means
of tracking error and hip power when the run scored hop cycles and ended
upright, else the whole-run means over every finite recorded sample; the
objectives are the means over the behaviours, the constraints the worst
hop-height violation and instability (:func:`~._objective.aggregate`, the
same function the CPU path calls). The batch computes tracking error, hip
power and (from the design) leg mass, no energetics and no stress: an
objective that asks for another metric is refused in one line
(:func:`check_unperturbed`). Only the simulator differs: MJWarp in
float32 against MuJoCo's CPU engine in float64 (the batch agreement tests
bound the difference: hop count +-1, height +-0.01 m, tracking error and
power within 10 %).

A study holds trials of one backend only: a warp study is marked (study
user attr ``mat_hopper_backend`` = ``"warp"``) and each of its trials
carries ``backend`` = ``"warp"``; the CPU path refuses a warp study and
the warp path refuses a study the CPU path created
(:func:`~._study.create_or_load`). Replaying a warp trial
(:func:`~mat_hopper.optimize.replay`) re-simulates it on the CPU, so its
values agree within the batch tolerance, not exactly.

The CPU path (:func:`~mat_hopper.optimize.run_study`) stays the default and
the reference.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Sequence

from ..core.materials import LegDesign
from ..physics.run_metrics import check_warp
from ._objective import Evaluation, Objective, aggregate, scored_by_hops, whole_run_value
from ._scoring import leg_mass_kg

BACKEND = "warp"
DEFAULT_BATCH_SIZE = 64  # trials asked per round (a GPU takes thousands: raise it there)


def check_unperturbed(objective: Objective) -> None:
    """ValueError unless the batch can score `objective`: unperturbed runs
    (replicates 0: the batch kernels have no perturbations,
    :mod:`mat_hopper.core.perturbations`) and objectives it computes (tracking
    error, hip power, leg mass: no energetics, no stress, so no stress
    constraint; :func:`~mat_hopper.physics.run_metrics.check_warp`), each
    refused in one line."""
    check_warp(objective.objectives)
    stress = [f for f in ("max_yield_fraction", "min_hops_to_failure") if getattr(objective, f) is not None]
    if stress:
        raise ValueError(
            f"the warp backend computes no stress: the constraints {', '.join(stress)} need the CPU path "
            "(use --backend mujoco)"
        )
    if objective.replicates:
        raise ValueError(
            f"the warp backend runs unperturbed rollouts only: give --replicates 0 (this objective asks for "
            f"{objective.replicates} perturbed replicates), or use --backend mujoco"
        )


def batch_settings(objective: Objective, design: LegDesign):
    """The :class:`~mat_hopper.batch.BatchSettings` of one design's runs
    under `objective`: the profile's SimSettings (the CPU path's) as a batch.
    ValueError where the batch cannot run them (physics substeps, i.e. the
    ``axial`` convention's automatic time step)."""
    from ..batch import BatchSettings

    check_unperturbed(objective)
    sim = objective.profile.for_convention(objective.convention).sim_settings(design=design)
    if sim.substeps != 1:
        raise ValueError(
            f"the warp backend runs the controller every physics step; under this profile design "
            f"{design.name!r} needs {sim.substeps} physics substeps (automatic time step): give the "
            "profile a fixed axial_timestep_s, or use --backend mujoco"
        )
    return BatchSettings.of(sim)


def behaviour_row(summary: dict, behaviour: str, duration_s: float) -> dict:
    """One behaviour's row of an Evaluation (the keys of
    ``_objective.run_behaviour``) from a batch result row."""
    n_hops = int(summary["n_hops"])
    upright = bool(summary["upright"])
    if scored_by_hops(n_hops, upright):
        tracking, power = float(summary["tracking_error_m"]), float(summary["power_w"])
    else:
        tracking = whole_run_value(float(summary["run_tracking_error_m"]))
        power = whole_run_value(float(summary["run_power_w"]))
    diverged = summary["diverged_at_s"]
    diverged = None if diverged is None or (isinstance(diverged, float) and math.isnan(diverged)) else float(diverged)
    return {
        "behaviour": behaviour,
        "tracking_error_m": tracking,
        "power_w": power,
        "hop_height_m": float(summary["hop_height_m"]),
        "n_hops": n_hops,
        "stable": bool(summary["stable"]),
        "upright": upright,
        "diverged_at_s": diverged,
        # the batch runs every world to the end; a diverged world stops counting at its divergence
        "simulated_s": float(duration_s if diverged is None else diverged),
        "total_mass_kg": float(summary["total_mass_kg"]),
        "backend": BACKEND,
    }


def evaluate_batch(
    designs: Sequence[LegDesign],
    objective: Objective,
    *,
    device: str | None = None,
    max_batch: int | None = None,
    progress: bool = False,
) -> list[Evaluation]:
    """Each design scored as :func:`~mat_hopper.optimize.evaluate` scores it on
    the CPU, all of them simulated together by the warp backend (one batch per
    behaviour, topology and set of run settings).

    Args:
        designs: the legs.
        objective: what to run and score.
        device: the Warp device (``"cpu"``, ``"cuda"``).
        max_batch: most worlds in one batch.
        progress: show a progress bar.

    Returns:
        One :class:`Evaluation` per design, in order.

    Raises:
        ValueError: a design that needs physics substeps under the profile,
            a perturbed objective, or an objective the batch cannot compute
            (energetics, stress: one line naming them).
        mat_hopper.batch.WarpUnavailable: without mujoco-warp.
    """
    from ..batch import evaluate as batch_evaluate

    check_unperturbed(objective)
    designs = list(designs)
    if not designs:
        return []
    groups: OrderedDict = OrderedDict()
    for i, d in enumerate(designs):
        groups.setdefault(batch_settings(objective, d), []).append(i)
    rows: list[list[dict]] = [[] for _ in designs]
    for settings, idx in groups.items():
        for b in objective.behaviours:
            table = batch_evaluate(
                [designs[i] for i in idx],
                b,
                settings,
                backend=BACKEND,
                device=device,
                max_batch=max_batch,
                progress=progress,
            )
            for i, summary in zip(idx, table.to_dict("records")):
                row = behaviour_row(summary, b, settings.duration_s)
                row["leg_mass_kg"] = leg_mass_kg(designs[i], objective.segment_mass)
                rows[i].append(row)
    return [aggregate(r, objective, d) for r, d in zip(rows, designs)]


def default_device() -> str:
    """ "cuda" where Warp sees a GPU, else "cpu"."""
    from ..batch import require_warp

    wp, _ = require_warp()
    return "cuda" if wp.get_cuda_device_count() > 0 else "cpu"
