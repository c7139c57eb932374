"""Optuna's samplers as the optimizer uses them (private): which ones,
checked before any work, and seeded per worker so that resumed runs and
parallel workers never repeat each other's proposals.
"""

from __future__ import annotations

import importlib.util
import warnings

import numpy as np
import optuna

SAMPLERS = ("tpe", "nsga2", "gp")


def check_sampler(name: str) -> str:
    """A sampler name, checked.

    Args:
        name: one of :data:`SAMPLERS` (``"tpe"``, ``"nsga2"``, ...; any case).

    Returns:
        The name in lower case.

    Raises:
        ValueError: an unknown sampler, or ``"gp"`` without PyTorch.
    """
    name = str(name).strip().lower()
    if name not in SAMPLERS:
        raise ValueError(f"unknown sampler {name!r}; accepted: {', '.join(SAMPLERS)}")
    if name == "gp" and importlib.util.find_spec("torch") is None:
        raise ValueError(
            "--sampler gp needs PyTorch, which is not installed "
            "(pip install torch, the CPU build is enough); use tpe or nsga2"
        )
    return name


def make_sampler(name: str, seed: int):
    """A seeded multi-objective sampler. Constraints reach it through
    ``Trial.set_constraint`` (Optuna 5 deprecated ``constraints_func``)."""
    name = check_sampler(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        if name == "tpe":
            return optuna.samplers.TPESampler(seed=seed, multivariate=True, constant_liar=True)
        if name == "nsga2":
            return optuna.samplers.NSGAIISampler(seed=seed)
        return optuna.samplers.GPSampler(seed=seed)


def worker_seed(seed: int, n_existing: int, index: int) -> int:
    """Sampler seed of one worker: from the run's seed, the study's size
    when the run started and the worker's index (so resumed runs and
    parallel workers do not repeat each other's random proposals)."""
    return int(np.random.SeedSequence([seed, n_existing, index]).generate_state(1)[0])
