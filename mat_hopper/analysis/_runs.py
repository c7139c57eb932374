"""The runs of a per-hop table: the columns that make families and runs,
the runs that are not results, one replicate or several experiments, and
the mean of each run.

These are the rows that :mod:`mat_hopper.analysis.stats` compares: a family
(one Holm correction, one baseline) is one experiment, profile and stiffness
convention; a run is one design and behaviour of a family and one replicate
(-1: the unperturbed run). Units: SI in the column names (``_m``, ``_w``,
``_s``); densities g/cm^3, moduli GPa.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..physics.metrics import ALL_METRICS

# Columns that split results into independent families (one Holm correction,
# one baseline each) when they are present in a table.
FAMILY_COLUMNS = ("experiment", "profile", "convention")
# Columns that identify one run in a per-hop table.
RUN_COLUMNS = FAMILY_COLUMNS + ("design", "behaviour", "replicate")
SWEEP_COLUMNS = ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa")
UNPERTURBED = -1  # replicate id of the unperturbed run


def _present(table: pd.DataFrame, columns) -> list[str]:
    return [c for c in columns if c in table.columns]


def _check_metrics(table: pd.DataFrame, metrics) -> tuple[str, ...]:
    metrics = tuple(metrics)
    missing = [m for m in metrics if m not in table.columns]
    if missing:
        raise ValueError(
            f"metrics {missing} are not columns of the table; accepted: "
            f"{[m for m in ALL_METRICS if m in table.columns]}"
        )
    return metrics


def _families(table: pd.DataFrame):
    """(dict of family values, sub-table) for each family in the table."""
    fam = _present(table, FAMILY_COLUMNS)
    if not fam:
        yield {}, table
        return
    for key, g in table.groupby(fam, sort=True, dropna=False):
        key = key if isinstance(key, tuple) else (key,)
        yield dict(zip(fam, key)), g


def seconds(x: float) -> str:
    """A duration in s, short: 0.5, 12.9, 1e-4, 2.5e-3.

    Args:
        x: the duration, s.

    Returns:
        str: three significant digits for 0.01 <= |x| < 1e4, else two significant digits (a trailing
        zero dropped) and an unpadded exponent ("2.5e-3", "1e-4"); 0, nan and inf as ``format(x, "g")``.
    """
    if not np.isfinite(x) or x == 0:
        return f"{x:g}"
    if 0.01 <= abs(x) < 1e4:
        return f"{x:.3g}"
    mant, exp = f"{x:.1e}".split("e")
    mant = mant.rstrip("0").rstrip(".")
    return f"{mant}e{int(exp)}"


def _fell_at(runs: pd.DataFrame, i) -> float | None:
    """The run's fall time (s) from a ``fell_at_s`` column, or None."""
    if "fell_at_s" not in runs.columns:
        return None
    v = runs.at[i, "fell_at_s"]
    return float(v) if v is not None and pd.notna(v) else None


def _suspect_why(runs: pd.DataFrame, i, timestep_s: float | None) -> str:
    """``numerically suspect at dt=1e-4 s, hop apex 7.45 m at t=1.82 s``: a
    run whose numbers are corrupted without diverging."""
    dt = runs.at[i, "timestep_s"] if "timestep_s" in runs.columns else timestep_s
    text = "numerically suspect" + (
        f" at dt={seconds(float(dt))} s" if dt is not None and np.isfinite(float(dt)) else ""
    )
    apex = runs.at[i, "suspect_apex_m"] if "suspect_apex_m" in runs.columns else None
    at = runs.at[i, "suspect_at_s"] if "suspect_at_s" in runs.columns else None
    if apex is not None and pd.notna(apex) and at is not None and pd.notna(at):
        text += f", hop apex {float(apex):.3g} m at t={seconds(float(at))} s"
    return text


def unusable_runs(runs: pd.DataFrame | None, timestep_s: float | None = None) -> pd.DataFrame:
    """The runs of a run-summary table that diverged numerically, are
    numerically suspect (corrupted without diverging:
    :attr:`mat_hopper.core.rollout.Rollout.suspect`), fell over (not upright
    at the end) or failed, with a reason in ``why`` ("unstable at dt=1e-4 s,
    diverged at t=2.5e-3 s", "fell at t=9.39 s, then unstable ...",
    "numerically suspect at dt=1e-4 s, hop apex 7.45 m at t=1.82 s", "fell
    over at t=9.39 s", "failed"). Uses the columns status, stable, upright,
    diverged_at_s, fell_at_s, suspect_at_s, suspect_apex_m and timestep_s
    where present (else the `timestep_s` argument, s).

    Args:
        runs: a run-summary table (one row per run), or None.
        timestep_s: the runs' physics step, s, named in ``why`` where `runs` has no ``timestep_s``
            column; None: not named.

    Returns:
        DataFrame, one row per unusable run. Columns: design, behaviour, experiment, profile,
        convention, replicate, key, the sweep columns (:data:`SWEEP_COLUMNS`), why; columns `runs`
        lacks are nan. A run is diverged where status is "diverged" or ``stable`` is false, fallen
        where status is "fallen" or ``upright`` is false (a missing stable or upright value counts as
        false), suspect where status is "suspect" or ``suspect_at_s`` is set (and not diverged),
        failed where status is "failed". Empty (those columns) for None or an empty table.
    """
    cols = ["design", "behaviour", "experiment", "profile", "convention", "replicate", "key", *SWEEP_COLUMNS, "why"]
    if runs is None or len(runs) == 0:
        return pd.DataFrame(columns=cols)
    status = runs["status"].astype(str) if "status" in runs.columns else pd.Series("", index=runs.index)
    stable = (
        runs["stable"].fillna(False).astype(bool) if "stable" in runs.columns else pd.Series(True, index=runs.index)
    )
    upright = (
        runs["upright"].fillna(False).astype(bool) if "upright" in runs.columns else pd.Series(True, index=runs.index)
    )
    diverged = (status == "diverged") | ~stable
    failed = status == "failed"
    at_suspect = runs["suspect_at_s"] if "suspect_at_s" in runs.columns else pd.Series(np.nan, index=runs.index)
    suspect = ~diverged & ~failed & ((status == "suspect") | pd.to_numeric(at_suspect, errors="coerce").notna())
    fallen = ~diverged & ~failed & ~suspect & ((status == "fallen") | ~upright)
    why = pd.Series("", index=runs.index, dtype=object)
    for i in runs.index[diverged]:
        dt = runs.at[i, "timestep_s"] if "timestep_s" in runs.columns else timestep_s
        at = runs.at[i, "diverged_at_s"] if "diverged_at_s" in runs.columns else None
        text = "unstable" + (f" at dt={seconds(float(dt))} s" if dt is not None and np.isfinite(float(dt)) else "")
        if at is not None and pd.notna(at):
            text += f", diverged at t={seconds(float(at))} s"
        fell = _fell_at(runs, i)
        why[i] = text if fell is None else f"fell at t={seconds(fell)} s, then {text}"
    for i in runs.index[suspect]:
        why[i] = _suspect_why(runs, i, timestep_s)
    for i in runs.index[fallen]:
        fell = _fell_at(runs, i)
        why[i] = "fell over" + ("" if fell is None else f" at t={seconds(fell)} s")
    why[failed] = "failed"
    out = diverged | suspect | fallen | failed
    bad = runs[out].assign(why=why[out])
    for c in cols:
        if c not in bad.columns:
            bad[c] = np.nan
    return bad[cols].reset_index(drop=True)


def drop_unusable(hops: pd.DataFrame, bad: pd.DataFrame | None) -> pd.DataFrame:
    """The per-hop rows of usable runs only: rows of the runs in `bad` (from
    :func:`unusable_runs`) are dropped, matched by the runner's ``key``
    column where both have it, else by experiment, profile, convention,
    design, behaviour, replicate and sweep point. A diverged run keeps the hop cycles it
    scored before diverging; they are not results.

    Args:
        hops: a per-hop table.
        bad: :func:`unusable_runs`'s table, or None. Only the matching columns that `hops` has and
            that are filled in every row of `bad` are used.

    Returns:
        DataFrame: the rows of `hops` not in a run of `bad` (original index kept); `hops` itself where
        `bad` is None or either table is empty.
    """
    if bad is None:
        return hops
    if len(bad) == 0 or len(hops) == 0:
        return hops
    if "key" in hops.columns and bad["key"].notna().all():
        return hops[~hops["key"].isin(set(bad["key"]))]
    keys = [
        c
        for c in (
            "experiment",
            "profile",
            "convention",
            "design",
            "behaviour",
            "replicate",
            "density_g_cm3",
            "modulus_gpa",
        )
        if c in hops.columns and bad[c].notna().all()
    ]
    marker = bad[keys].drop_duplicates().assign(_bad=True)
    m = hops.merge(marker, on=keys, how="left")
    return hops[~m["_bad"].fillna(False).to_numpy(bool)]


def select_replicates(hops: pd.DataFrame, replicate: int | None = UNPERTURBED) -> pd.DataFrame:
    """Rows of one replicate id (default: the unperturbed run, -1); all rows
    when `replicate` is None or the table has no ``replicate`` column.

    Args:
        hops: a per-hop table.
        replicate: the replicate id to keep (-1: the unperturbed run), or None.

    Returns:
        DataFrame: the rows whose ``replicate`` equals `replicate`, or `hops` itself.
    """
    if replicate is None or "replicate" not in hops.columns:
        return hops
    return hops[hops["replicate"] == replicate]


def combine_experiments(hops: pd.DataFrame, experiments=None) -> pd.DataFrame:
    """Rows of several experiments as one comparison family (e.g. the
    gradients of experiment 3 beside MD and SS of experiment 1): every
    design and behaviour (per profile and convention) is taken from the
    first experiment in `experiments` (default: sorted) that has it, and the
    ``experiment`` column becomes their names joined by "+".

    Args:
        hops: a per-hop table with an ``experiment`` column.
        experiments: experiment names in order of precedence (compared as str); None: every
            experiment of the table, sorted.

    Returns:
        DataFrame: a copy of the kept rows (rows of experiments not named dropped), ``experiment`` set
        to e.g. "exp1+exp3"; `hops` itself where it has no ``experiment`` column or is empty.
    """
    if "experiment" not in hops.columns or len(hops) == 0:
        return hops
    exps = [
        str(e) for e in (experiments if experiments is not None else sorted(hops["experiment"].astype(str).unique()))
    ]
    t = hops[hops["experiment"].astype(str).isin(exps)]
    rank = t["experiment"].astype(str).map({e: i for i, e in enumerate(exps)})
    keys = _present(t, ("profile", "convention", "design", "behaviour"))
    first = rank.groupby([t[k] for k in keys], dropna=False).transform("min")
    out = t[rank == first].copy()
    out["experiment"] = "+".join(exps)
    return out


def replicate_means(hops: pd.DataFrame, *, metrics=ALL_METRICS, include_unperturbed: bool = False) -> pd.DataFrame:
    """One row per run: the mean of each metric over its scored hop cycles
    and ``n_hops``. Run keys: the family columns, design, behaviour,
    replicate and, where present, the sweep columns. The unperturbed run
    (replicate -1) is left out unless `include_unperturbed`.

    Args:
        hops: a per-hop table with a ``replicate`` column.
        metrics: metric columns to average; those not in `hops` are skipped.
        include_unperturbed: keep the unperturbed run (replicate -1).

    Returns:
        DataFrame, one row per run: the run keys, n_hops, the mean of each metric. Empty (those
        columns) when no row is left.

    Raises:
        ValueError: `hops` has no ``replicate`` column.
    """
    if "replicate" not in hops.columns:
        raise ValueError("replicate_means needs a 'replicate' column (int, -1 for the unperturbed run)")
    metrics = tuple(m for m in metrics if m in hops.columns)
    if not include_unperturbed:
        hops = hops[hops["replicate"] != UNPERTURBED]
    keys = _present(hops, RUN_COLUMNS + SWEEP_COLUMNS)
    if len(hops) == 0:
        return pd.DataFrame(columns=[*keys, "n_hops", *metrics])
    grouped = hops.groupby(keys, sort=True, dropna=False)
    out = grouped[list(metrics)].mean()
    out.insert(0, "n_hops", grouped.size())
    return out.reset_index()


def has_replicates(hops: pd.DataFrame, min_replicates: int = 2) -> bool:
    """True when every run key of the table has at least `min_replicates`
    perturbed replicates (replicate >= 0).

    Args:
        hops: a per-hop table.
        min_replicates: the fewest replicates each run key needs.

    Returns:
        bool: True where every combination of the family columns, design and behaviour present has at
        least `min_replicates` distinct replicate ids other than -1; False without a ``replicate``
        column, for an empty table, or without perturbed rows.
    """
    if "replicate" not in hops.columns or len(hops) == 0:
        return False
    reps = hops[hops["replicate"] != UNPERTURBED]
    if len(reps) == 0:
        return False
    keys = _present(hops, FAMILY_COLUMNS + ("design", "behaviour"))
    counts = reps.groupby(keys)["replicate"].nunique()
    all_keys = hops.groupby(keys).size().index
    return len(counts) == len(all_keys) and int(counts.min()) >= min_replicates
