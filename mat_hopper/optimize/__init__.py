"""Design optimization with Optuna: per-segment densities and moduli (or
catalogue materials) searched for low tracking error and low hip power
under a hop-height and a stability constraint.

The public names are re-exported here, as Optuna does: the search space
(:class:`SearchSpace`), the objective (:class:`Objective`,
:func:`evaluate`), the study (:class:`StudyConfig`, :class:`RunOptions`,
:func:`run_study` on the CPU process pool; :func:`run_batch_study`, the same
on the MuJoCo Warp batch backend), its storage and its report
(:func:`write_report`, :func:`replay`). The private modules ``_space``,
``_objective``, ``_samplers``, ``_storage`` and ``_study`` hold them;
``_driver`` is the one ask-and-tell loop that runs every study, and
``_evaluators`` what simulates a round of its trials (the CPU pool,
:class:`PoolEvaluator`; the Warp batch, :class:`WarpEvaluator`, scoring
with ``_batch``); ``_processes`` holds the signals;
:mod:`~mat_hopper.optimize.report` writes a study's tables and plots;
``_scoring`` holds the noise- and mass-aware scores (replicates on common
random numbers, mean or CVaR, the leg-mass constraint), ``_mass`` what a
study held to a leg mass does with its band (refuses a void or unmeetable
one, samples inside it, skips designs outside it before any run),
``_feasibility`` why trials are not feasible (the line a study ends
with) and why a run that fell is no baseline, ``_workers`` the worker
index that keeps concurrent runs' samplers apart; ``_stable_steps`` the warning
before a run above a queued design's stable step and the advice after a
divergence; ``_export`` writes a
trial's design as CSV and MJCF; ``_racing`` runs multi-fidelity racing
(successive halving on ask-and-tell, through the same evaluators);
``_book_study`` is chapter 9's study as the book runs it
(:func:`book_study`) and its record tables from a finished build
(:func:`book_record_tables`). The
named table of what an objective may minimize (:data:`METRICS`, with
units) is :mod:`mat_hopper.physics.run_metrics`'s, re-exported here. The
public module :mod:`~mat_hopper.optimize.validate` (a front judged on
fresh seeds against the paper's designs and its controls; its work in
``_validate_checks``, ``_validate_pairs`` and ``_validate_rules``) is
imported by name; the report's tables and hypervolume live in
``_report_tables`` and ``_hypervolume``. The command line is
:mod:`mat_hopper.cli.optimize`.
"""

from ..physics.run_metrics import METRICS, Metric, check_warp, parse_objectives
from ._ashby import check_classes
from ._batch import DEFAULT_BATCH_SIZE, evaluate_batch
from ._book_study import BookStudy, book_record_tables, book_study, validated_legs
from ._driver import RunResult, run_batch_study, run_loop, run_study
from ._evaluators import DEFAULT_BATCH, Evaluator, Lost, PoolEvaluator, WarpEvaluator
from ._export import design_frame, design_mjcf, export_trial
from ._feasibility import Feasibility, fall_reason, feasibility
from ._mass import LEG_MASS_SCOPE, check_mass_band, left_out_text, leg_mass_range_kg, queued_seeds
from ._objective import (
    CONSTRAINTS,
    HOPS_TO_FAILURE_RANGE,
    MAX_YIELD_FRACTION,
    OBJECTIVES,
    Evaluation,
    Objective,
    evaluate,
    scored_by_hops,
)
from ._processes import stop_signals
from ._racing import Racing, Rung, default_racing, promote, race_study, run_racing, simulated_seconds
from ._samplers import SAMPLERS, check_sampler
from ._scoring import (
    DEFAULT_CVAR_ALPHA,
    DEFAULT_LEG_MASS_TOLERANCE,
    DEFAULT_REPLICATES,
    MAX_LEG_MASS_KG,
    MAX_REPLICATES,
    RISKS,
    SEARCH_SEED_START,
    cvar,
    leg_mass_kg,
    leg_mass_model,
    replicate_seeds,
    score,
)
from ._space import (
    DENSITY_BOUNDS_G_CM3,
    KINDS,
    MASS_PARAM,
    MAX_SEGMENTS,
    MODULUS_BOUNDS_GPA,
    PAPER_SEEDS,
    MassHold,
    SearchSpace,
    describe,
    resample,
)
from ._stable_steps import diverged_run_message, divergence_advice, queued_step_warnings
from ._storage import check_study_name, default_url, dispose, open_storage, redact, storage_errors, storage_file
from ._study import (
    CONFIG_ATTR,
    DEFAULT_WORKERS,
    RunOptions,
    StudyConfig,
    StudyMismatch,
    check_objectives_vary,
    create_or_load,
    load_existing,
    stored_config,
    study_exists,
)
from .report import (
    front_designs,
    front_table,
    hypervolume,
    pareto_frame,
    replay,
    trials_frame,
    write_report,
)

__all__ = [
    "BookStudy",
    "book_record_tables",
    "book_study",
    "validated_legs",
    "HOPS_TO_FAILURE_RANGE",
    "MAX_LEG_MASS_KG",
    "LEG_MASS_SCOPE",
    "MAX_SEGMENTS",
    "MAX_YIELD_FRACTION",
    "check_classes",
    "DEFAULT_BATCH_SIZE",
    "evaluate_batch",
    "run_batch_study",
    "run_loop",
    "DEFAULT_BATCH",
    "Evaluator",
    "Lost",
    "PoolEvaluator",
    "WarpEvaluator",
    "design_frame",
    "design_mjcf",
    "export_trial",
    "Feasibility",
    "fall_reason",
    "feasibility",
    "check_mass_band",
    "leg_mass_range_kg",
    "left_out_text",
    "queued_seeds",
    "queued_step_warnings",
    "scored_by_hops",
    "divergence_advice",
    "diverged_run_message",
    "MASS_PARAM",
    "MassHold",
    "leg_mass_model",
    "METRICS",
    "Metric",
    "parse_objectives",
    "check_warp",
    "PAPER_SEEDS",
    "CONSTRAINTS",
    "OBJECTIVES",
    "Evaluation",
    "Objective",
    "evaluate",
    "Racing",
    "Rung",
    "default_racing",
    "promote",
    "race_study",
    "run_racing",
    "simulated_seconds",
    "DEFAULT_CVAR_ALPHA",
    "DEFAULT_LEG_MASS_TOLERANCE",
    "DEFAULT_REPLICATES",
    "MAX_REPLICATES",
    "RISKS",
    "SEARCH_SEED_START",
    "cvar",
    "leg_mass_kg",
    "replicate_seeds",
    "score",
    "DENSITY_BOUNDS_G_CM3",
    "KINDS",
    "MODULUS_BOUNDS_GPA",
    "SearchSpace",
    "describe",
    "resample",
    "check_study_name",
    "default_url",
    "dispose",
    "open_storage",
    "redact",
    "storage_errors",
    "storage_file",
    "stop_signals",
    "CONFIG_ATTR",
    "DEFAULT_WORKERS",
    "SAMPLERS",
    "RunOptions",
    "RunResult",
    "StudyConfig",
    "StudyMismatch",
    "load_existing",
    "check_sampler",
    "check_objectives_vary",
    "create_or_load",
    "run_study",
    "stored_config",
    "study_exists",
    "front_designs",
    "front_table",
    "hypervolume",
    "pareto_frame",
    "replay",
    "trials_frame",
    "write_report",
]
