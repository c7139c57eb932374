"""Optuna's samplers as the optimizer uses them (private): which ones,
checked before any work, and seeded per run so that a resumed run does not
repeat the proposals of the run before it.
"""

from __future__ import annotations

import importlib.util
import warnings

import numpy as np
import optuna

from ..util.parsing import did_you_mean

SAMPLERS = ("tpe", "nsga2", "gp")


def sampler_name(name) -> str:
    """`name` as one of :data:`SAMPLERS` (any case, blanks trimmed);
    ValueError for an unknown one, listing them, with "did you mean ...?"
    where one is close (``tpee``: tpe)."""
    name = str(name).strip().lower()
    if name not in SAMPLERS:
        hint = did_you_mean(name, SAMPLERS)
        raise ValueError(f"unknown sampler {name!r}; accepted: {', '.join(SAMPLERS)}{f'; {hint}' if hint else ''}")
    return name


def check_sampler(name: str) -> str:
    """A sampler name, checked.

    Args:
        name: one of :data:`SAMPLERS` (``"tpe"``, ``"nsga2"``, ...; any case).

    Returns:
        The name in lower case.

    Raises:
        ValueError: an unknown sampler (with "did you mean ...?" where one
            is close), or ``"gp"`` without PyTorch.
    """
    name = sampler_name(name)
    if name == "gp" and importlib.util.find_spec("torch") is None:
        raise ValueError(
            "--sampler gp needs PyTorch, which is not installed: "
            "pip install mat-hopper[gp] (the CPU build of torch is enough), or use tpe or nsga2"
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


def sampler_seed(seed: int, n_existing: int, worker: int = 0) -> int:
    """The sampler seed of one run.

    Args:
        seed: the run's seed (``--seed``).
        n_existing: the study's trials when the run started.
        worker: the run's worker index on the study (0 when it runs alone;
            :mod:`mat_hopper.optimize._workers`).

    Returns:
        A seed from all three (a resumed run does not repeat the random
        proposals of the run before it, nor a run started beside it on the
        same study those of that run; a fresh study run by one command is
        fixed by `seed`).
    """
    return int(np.random.SeedSequence([seed, n_existing, worker]).generate_state(1)[0])
