"""The paper's quantitative claims beside ours, with a verdict computed
from the results (never typed in).

:func:`claims_table` takes the result tables of a reproduction (per-hop
table, run summaries, stable-time-step map) and returns one row per claim
and stiffness convention: the claim, the paper's figure, ours, a verdict
and the rule that gave it. :func:`write_claims` writes ``claims.md`` and
``claims.csv`` (atomically).

Verdicts:

- ``holds``, ``partly``, ``does not hold``: by the claim's rule (below, and
  in the table's ``rule`` column);
- ``not run``: the convention's results needed for the claim are missing;
- ``not testable``: the runs exist but none of the needed ones is usable:
  they diverged numerically (e.g. the explicit spring limit of stiff
  metals under the ``axial`` convention at dt = 1e-4 s), fell over, or
  failed. Where only some of the needed runs are unusable the claim is
  judged on the others and its verdict is at best ``partly``.

Rules (thresholds are module constants):

- a number of the paper (a percent change) is matched when ours has the
  same sign and lies within ``MATCH_REL_TOL`` (25 %) of it, or within
  ``MATCH_ABS_TOL_PCT`` (10 percentage points), whichever is wider:
  ``holds``; same sign and at least ``PARTLY_MIN_FRACTION`` (a quarter) of
  its size: ``partly``; otherwise ``does not hold``;
- "every ... significantly" claims count the comparisons that go the
  claimed way with Holm-adjusted p < ``ALPHA``: all ``holds``, at least
  half ``partly``, fewer ``does not hold``;
- hop height: every design and behaviour's mean within
  ``HOP_HEIGHT_TOL_M`` (0.05 m) of 1 m ``holds``, at least half ``partly``;
- stable time steps: within ``TIMESTEP_TOL_DECADES`` (0.3 decade, a factor 2) of
  the paper's value for every material ``holds``; for some, or in the
  paper's order (PVC's step the largest), ``partly``;
- the log-linear trend: a least-squares plane log10 dt = a + b log10 rho +
  c log10 E with b > 0 and c < 0 and R^2 >= ``TREND_MIN_R2`` (0.8)
  ``holds``; the right signs with a poorer fit, or one right sign,
  ``partly``.

Comparisons are those of :mod:`mat_hopper.analysis.stats` on the ``basis`` chosen
(``auto``: replicate means where every design and behaviour has
replicates, else the paper's hop cycles of the unperturbed run; the
``basis`` column says which); the Holm family of a claim is its own
comparisons (one metric), and on the replicate basis a comparison is
significant only where an exact sign-flip test on its n paired seeds
could reach Holm's threshold in that family (:func:`mat_hopper.analysis.paired.reachable`). Hop
cycles of runs that diverged, fell over or failed are never used
(:func:`mat_hopper.analysis.stats.drop_unusable`).
"""

from __future__ import annotations

import math
import os

import pandas as pd

from ..core import reference as ref
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.controller import DEFAULT_SENSOR_TIMING
from ..core.materials import REPRODUCTION_CONVENTIONS, check_convention
from ..core.replicates import DEFAULT_REPLICATE_PROTOCOL
from ..util.atomic import write_text
from ..util.change import percent_change
from ..util.parsing import parse_name
from . import beyond_mass as _beyond
from . import stats as _stats
from ._claim_checks import (  # noqa: F401 (public names of this module)
    ALPHA,
    COLUMNS,
    FAILS,
    HOLDS,
    HOP_HEIGHT_TOL_M,
    MATCH_ABS_TOL_PCT,
    MATCH_REL_TOL,
    MONO,
    NOT_RUN,
    NOT_TESTABLE,
    PARTLY,
    PARTLY_MIN_FRACTION,
    TIMESTEP_MOVE_TOL,
    TIMESTEP_TOL_DECADES,
    TREND_MIN_R2,
    VERDICTS,
    Claim,
    Outcome,
    _claim_count_significant,
    _claim_density_over_modulus,
    _claim_hop_height,
    _claim_low_modulus,
    _claim_pct,
    _claim_ss_power,
    _claim_ss_power_for,
    _claim_ss_tracking,
    _claim_timestep_materials,
    _claim_timestep_trend,
    _Context,
    _pct,
    fraction_verdict,
    match_percent,
    smallest_p,
)
from .stationarity import NOT_CHECKED, stationarity, window_halves
from .stats import seconds

_PCT_RULE = (
    f"same sign and within max({MATCH_REL_TOL:.0%} of the paper's, {MATCH_ABS_TOL_PCT:g} points): holds; "
    f"same sign and >= {PARTLY_MIN_FRACTION:.0%} of its size: partly"
)
_COUNT_RULE = f"all comparisons the claimed way with Holm p < {ALPHA:g}: holds; at least half: partly"

CLAIMS: tuple[Claim, ...] = (
    Claim(
        "hop_height",
        "Every design holds a mean hop height of 1 m",
        f"{ref.CLAIM_HOP_HEIGHT_M:g} m, every design and behaviour",
        f"every design-behaviour mean within {HOP_HEIGHT_TOL_M:g} m of 1 m: holds; at least half: partly",
        _claim_hop_height,
    ),
    Claim(
        "tracking_all_beat_md",
        "Tracking error: every physical material beats MD significantly",
        "PVC, Al, Ti, SS lower than MD, p < 0.05, all four behaviours",
        _COUNT_RULE,
        _claim_count_significant("tracking_error_m", list(MONO), list(BEHAVIOUR_NAMES), -1),
    ),
    Claim(
        "tracking_ss_55",
        "Tracking error: SS lower than MD by at least 55 % on every behaviour",
        f"<= {ref.CLAIM_SS_TRACKING_PCT:+.0f} % on every behaviour",
        f"every behaviour <= {ref.CLAIM_SS_TRACKING_PCT:+.0f} %: holds; every behaviour lower, or half of them "
        f"<= {ref.CLAIM_SS_TRACKING_PCT:+.0f} %: partly",
        _claim_ss_tracking,
    ),
    Claim(
        "power_higher_dynamic",
        "Power: higher for materials than MD on the dynamic behaviours (2-4)",
        "PVC, Al, Ti, SS higher than MD on forward, ramp, circle",
        _COUNT_RULE,
        _claim_count_significant("power_w", list(MONO), list(ref.DYNAMIC_BEHAVIOURS), +1),
    ),
    Claim(
        "power_ss_max",
        "Power: up to +193 % for SS against MD",
        f"{ref.CLAIM_SS_POWER_MAX_PCT:+.0f} % (largest, SS)",
        _PCT_RULE + " (on our largest increase)",
        _claim_ss_power,
    ),
    Claim(
        "density_over_modulus",
        "Density moves tracking error more than modulus",
        "density sweeps change tracking error more than modulus sweeps",
        "span of mean tracking error over the density sweep larger than over the modulus sweep for every "
        "base material: holds; for at least half: partly",
        _claim_density_over_modulus,
    ),
    Claim(
        "low_modulus_tracks_worse",
        "Moduli <= 9 GPa track worse than moduli >= 20 GPa",
        f"E <= {ref.CLAIM_LOW_MODULUS_GPA:g} GPa much higher tracking error than E >= {ref.CLAIM_HIGH_MODULUS_GPA:g} GPa",
        "every low-modulus sweep point above every high-modulus one: holds; medians in that order: partly",
        _claim_low_modulus,
    ),
    Claim(
        "ramp_rho_inc_tracking",
        "Ramp: rho-inc against MD, tracking error",
        _pct(ref.CLAIM_RAMP_RHO_INC_TRACKING_PCT),
        _PCT_RULE,
        _claim_pct("rho-inc", "tracking_error_m", ref.CLAIM_RAMP_RHO_INC_TRACKING_PCT),
    ),
    Claim(
        "ramp_rho_inc_power",
        "Ramp: rho-inc against MD, power",
        _pct(ref.CLAIM_RAMP_RHO_INC_POWER_PCT),
        _PCT_RULE,
        _claim_pct("rho-inc", "power_w", ref.CLAIM_RAMP_RHO_INC_POWER_PCT),
    ),
    Claim(
        "ramp_ss_tracking",
        "Ramp: SS against MD, tracking error",
        _pct(ref.CLAIM_RAMP_SS_TRACKING_PCT),
        _PCT_RULE,
        _claim_pct("SS", "tracking_error_m", ref.CLAIM_RAMP_SS_TRACKING_PCT),
    ),
    Claim(
        "ramp_ss_power",
        "Ramp: SS against MD, power",
        _pct(ref.CLAIM_RAMP_SS_POWER_PCT),
        _PCT_RULE,
        _claim_pct("SS", "power_w", ref.CLAIM_RAMP_SS_POWER_PCT),
    ),
    Claim(
        "headline_tracking",
        "Ramp: rho-inc against SS, tracking error (abstract)",
        _pct(ref.CLAIM_HEADLINE_TRACKING_PCT),
        _PCT_RULE,
        _claim_pct("rho-inc", "tracking_error_m", ref.CLAIM_HEADLINE_TRACKING_PCT, baseline="SS"),
    ),
    Claim(
        "headline_power",
        "Ramp: rho-inc against SS, power (abstract)",
        _pct(ref.CLAIM_HEADLINE_POWER_PCT),
        _PCT_RULE,
        _claim_pct("rho-inc", "power_w", ref.CLAIM_HEADLINE_POWER_PCT, baseline="SS"),
    ),
    Claim(
        "jerk_gradient",
        "Jerk: the increasing-density gradient lower than SS",
        "rho-inc lower jerk than SS (the paper's Fig. 5C and conclusion)",
        _COUNT_RULE,
        _claim_count_significant(
            "jerk_m_s3", ["rho-inc"], list(BEHAVIOUR_NAMES), -1, exps=("exp1", "exp3"), baseline="SS"
        ),
    ),
    Claim(
        "timestep_materials",
        "Stable time step: PVC about 1e-3 s, Al and SS about 1e-4 s",
        ", ".join(f"{k} {seconds(v)} s" for k, v in ref.CLAIM_STABLE_TIMESTEP_S.items()),
        f"every material within a factor {10**TIMESTEP_TOL_DECADES:.0f} of the paper's: holds; some, or PVC's the largest: "
        "partly",
        _claim_timestep_materials,
    ),
    Claim(
        "timestep_trend",
        "Stable time step log-linear in density and modulus; light or stiff need smaller steps",
        "log-linear; grows with density, shrinks with modulus",
        f"plane fit in log-log with density slope > 0, modulus slope < 0 and R² >= {TREND_MIN_R2:g}: holds; "
        "right signs with a poorer fit, or one right sign: partly",
        _claim_timestep_trend,
    ),
)


# Claims that quote power, re-judged under each power: the paper's
# formula, the hips' mechanical power, and all actuators' (thrust included).
POWER_FORMULAS = (("paper formula", "power_paper_w"), ("hip", "power_w"), ("total", "power_total_w"))
POWER_VARIANTS = {
    "power_higher_dynamic": lambda m: _claim_count_significant(m, list(MONO), list(ref.DYNAMIC_BEHAVIOURS), +1),
    "power_ss_max": _claim_ss_power_for,
    "ramp_rho_inc_power": lambda m: _claim_pct("rho-inc", m, ref.CLAIM_RAMP_RHO_INC_POWER_PCT),
    "ramp_ss_power": lambda m: _claim_pct("SS", m, ref.CLAIM_RAMP_SS_POWER_PCT),
    "headline_power": lambda m: _claim_pct("rho-inc", m, ref.CLAIM_HEADLINE_POWER_PCT, baseline="SS"),
}


# The jerk claim under the loop's causal jerk and the body's zero-phase jerk (mat_hopper.physics.jerk).
JERK_FORMULAS = (("causal 50 Hz", "jerk_m_s3"), ("body, zero-phase 20 Hz", "jerk_body_m_s3"))
JERK_VARIANTS = {
    "jerk_gradient": lambda m: _claim_count_significant(
        m, ["rho-inc"], list(BEHAVIOUR_NAMES), -1, exps=("exp1", "exp3"), baseline="SS"
    ),
}


def _power_verdicts(claim_id: str, ctx: _Context, variants=None, formulas=POWER_FORMULAS) -> str:
    """The claim's verdict under each formula of a quantity: "paper formula:
    ours (verdict); hip: ...; total: ..." for a power claim (or the jerk
    formulas with JERK_VARIANTS), "" for other claims."""
    variants = POWER_VARIANTS if variants is None else variants
    if claim_id not in variants:
        return ""
    parts = []
    for label, metric in formulas:
        if len(ctx.hops) == 0 or metric not in ctx.hops.columns:
            parts.append(f"{label}: not recorded")
            continue
        out = variants[claim_id](metric)(ctx)
        parts.append(f"{label}: {out.ours} ({out.verdict})")
    return "; ".join(parts)


# What each hopping claim reads: experiments (None: all), designs and behaviours (None: all), metrics.
# The time-step check compares exactly these runs at the finer step.
_ALL4 = tuple(BEHAVIOUR_NAMES)
_DYN = tuple(ref.DYNAMIC_BEHAVIOURS)
USES = {
    "hop_height": (None, None, None, ("hop_height_m",)),
    "tracking_all_beat_md": (("exp1",), ("MD", *MONO), _ALL4, ("tracking_error_m",)),
    "tracking_ss_55": (("exp1",), ("MD", "SS"), _ALL4, ("tracking_error_m",)),
    "power_higher_dynamic": (("exp1",), ("MD", *MONO), _DYN, ("power_w",)),
    "power_ss_max": (("exp1",), ("MD", "SS"), _DYN, ("power_w",)),
    "density_over_modulus": (("exp2",), None, ("forward",), ("tracking_error_m",)),
    "low_modulus_tracks_worse": (("exp2",), None, ("forward",), ("tracking_error_m",)),
    "ramp_rho_inc_tracking": (("exp1", "exp3"), ("MD", "rho-inc"), ("ramp",), ("tracking_error_m",)),
    "ramp_rho_inc_power": (("exp1", "exp3"), ("MD", "rho-inc"), ("ramp",), ("power_w",)),
    "ramp_ss_tracking": (("exp1",), ("MD", "SS"), ("ramp",), ("tracking_error_m",)),
    "ramp_ss_power": (("exp1",), ("MD", "SS"), ("ramp",), ("power_w",)),
    "headline_tracking": (("exp1", "exp3"), ("SS", "rho-inc"), ("ramp",), ("tracking_error_m",)),
    "headline_power": (("exp1", "exp3"), ("SS", "rho-inc"), ("ramp",), ("power_w",)),
    "jerk_gradient": (("exp1", "exp3"), ("SS", "rho-inc"), _ALL4, ("jerk_m_s3",)),
}


def _unperturbed_means(hops: pd.DataFrame, metrics) -> pd.DataFrame:
    t = hops
    if "replicate" in t.columns:
        t = t[t["replicate"] == _stats.UNPERTURBED]
    return t.groupby(["design", "behaviour"])[list(metrics)].mean()


def timestep_check(claim_id: str, hops: pd.DataFrame, fine_hops: pd.DataFrame | None, label: str) -> str:
    """Which of the claim's runs move by more than TIMESTEP_MOVE_TOL (10 %)
    between ``hops`` and ``fine_hops`` (the same runs at a finer step), in
    words: "converged (n runs)", "moves > 10 %: MD ramp tracking_error_m
    +410 %; ..." (a moving baseline named first), "not checked".

    Args:
        claim_id: a claim of :data:`CLAIMS`; the runs and metrics compared are its entry in :data:`USES`.
        hops: the per-hop rows of the claim's runs at the runs' own step (design, behaviour, the claim's
            metric columns; only the unperturbed run, replicate -1, is read where a ``replicate`` column
            exists).
        fine_hops: the same runs at the finer step (same columns), or None.
        label: names the finer step in the text.

    Returns:
        str: "converged at <label> (n runs within 10 %)", "moves > 10 % at <label>: <design> <behaviour>
        <metric> <change> %; ..." (percent change of the run's mean at the finer step against its mean in
        ``hops``; a change that is nan, e.g. a diverged fine run, counts as moving; runs of MD sorted
        first), or "not checked" where the claim has no entry in :data:`USES`, either table is None or
        empty, or no (design, behaviour) of the claim is in both.
    """
    use = USES.get(claim_id)
    if use is None or fine_hops is None or len(fine_hops) == 0 or len(hops) == 0:
        return "not checked"
    exps, designs, behaviours, metrics = use
    base = _unperturbed_means(hops, metrics)
    fine = _unperturbed_means(fine_hops, metrics)
    moved, n = [], 0
    for (d, b), row in base.iterrows():
        if (designs is not None and d not in designs) or (behaviours is not None and b not in behaviours):
            continue
        if (d, b) not in fine.index:
            continue
        n += 1
        for m in metrics:
            change = percent_change(fine.loc[(d, b), m], row[m])
            if not abs(change) <= 100 * TIMESTEP_MOVE_TOL:  # nan (a diverged fine run) counts as moving
                moved.append((d != "MD", f"{d} {b} {m} {change:+.0f} %"))
    if n == 0:
        return "not checked"
    if not moved:
        return f"converged at {label} ({n} runs within {100 * TIMESTEP_MOVE_TOL:.0f} %)"
    return f"moves > {100 * TIMESTEP_MOVE_TOL:.0f} % at {label}: " + "; ".join(t for _, t in sorted(moved))


# --- the table -----------------------------------------------------------------------------


def _by_convention(table: pd.DataFrame | None, convention: str) -> pd.DataFrame | None:
    if table is None:
        return None
    if "convention" not in table.columns:
        return table if convention == "paper" else table.iloc[0:0]
    return table[table["convention"] == convention]


def claims_table(
    hops: pd.DataFrame | None,
    runs: pd.DataFrame | None = None,
    stability: pd.DataFrame | None = None,
    *,
    conventions=REPRODUCTION_CONVENTIONS,
    basis: str = "auto",
    alpha: float = ALPHA,
    timestep_s: float | None = None,
    fine_hops: pd.DataFrame | None = None,
    fine_label: str = "the finer step",
    controls: pd.DataFrame | None = None,
    control_runs: pd.DataFrame | None = None,
    check_window: bool = True,
) -> pd.DataFrame:
    """Every claim of the paper beside ours, per stiffness convention.

    The tables must hold one profile and one sensor timing (ValueError
    otherwise). Tables without a ``convention`` column are taken as the
    ``paper`` convention's.

    Args:
        hops: the per-hop table of experiments 1-3 (all conventions; columns of
            :func:`mat_hopper.physics.metrics.hop_table` plus experiment, convention,
            replicate and the sweep columns); None: no hopping results.
        runs: the run summaries (status, stable, upright, diverged_at_s, ...;
            optional, tells unstable runs apart from missing ones).
        stability: the stable-time-step map (one row per grid point; a
            ``convention`` column, else taken as ``paper``).
        conventions: the stiffness conventions to judge the claims under (names of
            :data:`mat_hopper.core.materials.CONVENTIONS`, any case; default ``paper`` and ``axial``).
        basis: ``hops``, ``replicates`` or ``auto``, any case (module doc).
        alpha: significance level of the Holm-adjusted comparisons (and of the beyond-mass columns).
        timestep_s: the runs' time step (s), named in "unstable at dt=..." when runs has no timestep_s
            column.
        fine_hops: the unperturbed runs the claims use (design, behaviour, metrics) at a finer step, for
            the ``timestep_check`` column (:func:`timestep_check`; "not checked" without them).
        fine_label: names that step.
        controls: the per-hop rows of :func:`mat_hopper.experiments.controls.run_controls`, for the
            beyond-mass columns ("not run" without them).
        control_runs: the control runs' summaries: their unusable runs are dropped from ``controls`` as
            the main claims' are.

    Returns:
        DataFrame, one row per claim and convention. Columns: claim_id, claim, paper, ours, verdict,
        convention, sensor_timing, replicate_protocol (the runs'), basis, n_replicates (per design and behaviour, 0 on the hop-cycle
        basis), timestep_check, stationarity (the verdicts on the scored window's two halves), detail, rule (and profile, when the tables have one), power_verdicts
        (claims that quote power: the verdict under the paper's formula, hip power and total power side
        by side), jerk_verdicts (the jerk claim under the causal and the body jerk), and the beyond-mass
        columns of :func:`mat_hopper.analysis.beyond_mass.beyond_mass_columns` (vs_rigid_twin,
        vs_mass_matched, beyond_mass, mass_properties; the sweep claims' from experiment 2's rows of
        ``hops``).

    Raises:
        ValueError: ``basis`` not hops, replicates or auto; an unknown convention; a non-empty ``hops``
            without a ``design`` column; tables holding several profiles (hops, runs, stability),
            several sensor timings (hops, runs) or several replicate protocols (runs).
    """
    basis = parse_name(basis, _stats.BASES + ("auto",), "basis")
    hops = pd.DataFrame() if hops is None else hops
    profiles = _one_value((hops, runs, stability), "profile", "profiles")
    timing = _one_value((hops, runs), "sensor_timing", "sensor timings") or str(DEFAULT_SENSOR_TIMING)
    protocol = _one_value((runs,), "replicate_protocol", "replicate protocols") or DEFAULT_REPLICATE_PROTOCOL
    rows = []
    for conv in conventions:
        conv = check_convention(conv)
        h = _by_convention(hops, conv)
        r = _by_convention(runs, conv)
        bad = _stats.unusable_runs(r, timestep_s)
        h = _stats.drop_unusable(h if h is not None else pd.DataFrame(), bad)
        if len(h) and "design" not in h.columns:
            raise ValueError("hops needs a 'design' column")
        ctx = _Context(conv, h, r, _by_convention(stability, conv), basis, alpha, timestep_s, bad)
        fine = _by_convention(fine_hops, conv)
        halves = window_halves(h) if check_window else None
        if halves is not None:
            halves = [_Context(conv, half, r, ctx.stability, basis, alpha, timestep_s, bad) for half in halves]
        rows += [
            {
                **_claim_row(claim, ctx, fine, fine_label, halves),
                "sensor_timing": timing,
                "replicate_protocol": protocol,
            }
            for claim in CLAIMS
        ]
    out = pd.DataFrame(rows, columns=[*COLUMNS, "power_verdicts", "jerk_verdicts"])
    bad_controls = _stats.unusable_runs(control_runs, timestep_s) if control_runs is not None else None
    sweeps = hops[hops["experiment"] == "exp2"] if len(hops) and "experiment" in hops.columns else None
    out = _beyond.beyond_mass_columns(out, controls, alpha, bad_controls, sweep_hops=sweeps)
    if profiles:
        out.insert(list(out.columns).index("detail"), "profile", profiles)
    return out


def _one_value(tables, column: str, what: str) -> str | None:
    """The one value of `column` across the tables that have it (None when
    none has); ValueError when they hold several."""
    values = set()
    for t in tables:
        if t is not None and column in t.columns:
            values |= set(t[column].dropna().astype(str))
    if len(values) > 1:
        raise ValueError(f"the tables hold several {what} {sorted(values)}; pass one's results")
    return values.pop() if values else None


def _claim_row(claim: Claim, ctx: _Context, fine_hops, fine_label: str, halves=None) -> dict:
    """One claim under one convention: its outcome, basis, time-step check,
    its verdicts on the two halves of the scored window (`halves`: their
    contexts, or None) and the power and jerk verdicts side by side (a row
    of claims_table)."""
    conv, h = ctx.convention, ctx.hops
    is_stab = claim.claim_id.startswith("timestep")
    if not is_stab and len(h) == 0 and len(ctx.bad) == 0:
        out = Outcome("not run", NOT_RUN, f"no {conv}-convention hopping results")
    else:
        out = claim.evaluate(ctx)
    used, n_rep = ("", 0) if out.verdict == NOT_RUN else _basis_used(ctx, claim)
    if is_stab and out.verdict != NOT_RUN:
        used, n_rep = "stability map", 0
    exps = USES.get(claim.claim_id, (None,))[0]
    check = (
        ""
        if is_stab or out.verdict == NOT_RUN
        else timestep_check(claim.claim_id, h if exps is None else ctx.experiment(exps), fine_hops, fine_label)
    )
    run = out.verdict != NOT_RUN
    window = NOT_CHECKED
    if run and not is_stab and halves is not None:
        first, second = (claim.evaluate(half) for half in halves)
        window = stationarity(first.verdict, second.verdict, first.ours, second.ours)
    return {
        "claim_id": claim.claim_id,
        "claim": claim.claim,
        "paper": claim.paper,
        "ours": out.ours,
        "verdict": out.verdict,
        "convention": conv,
        "basis": used,
        "n_replicates": n_rep,
        "timestep_check": check,
        "stationarity": window if not is_stab else "",
        "detail": out.detail,
        "rule": claim.rule,
        "power_verdicts": _power_verdicts(claim.claim_id, ctx) if run else "",
        "jerk_verdicts": _power_verdicts(claim.claim_id, ctx, JERK_VARIANTS, JERK_FORMULAS) if run else "",
    }


def _basis_used(ctx: _Context, claim: Claim) -> tuple[str, int]:
    """("replicate means" or "hop cycles (description only)", replicates
    per design and behaviour, the fewest among the claim's runs)."""
    exps = USES.get(claim.claim_id, (None,))[0]
    t = ctx.hops if exps is None else ctx.experiment(exps)
    if ctx.basis_for(t) == "replicates":
        reps = t[t["replicate"] != _stats.UNPERTURBED] if "replicate" in t.columns else t
        n = int(reps.groupby(["design", "behaviour"])["replicate"].nunique().min()) if len(reps) else 0
        return "replicate means", n
    return "hop cycles (description only)", 0


# --- writers ---------------------------------------------------------------------------------


def _md_cell(x) -> str:
    s = "" if x is None or (isinstance(x, float) and math.isnan(x)) else str(x)
    return s.replace("|", "\\|").replace("\n", " ")


def to_markdown(
    table: pd.DataFrame,
    columns=(
        "claim",
        "convention",
        "paper",
        "ours",
        "verdict",
        "beyond_mass",
        "basis",
        "timestep_check",
        "stationarity",
    ),
) -> str:
    """The claims as a markdown table (one row per claim and convention),
    the rules listed below it.

    Args:
        table: :func:`claims_table`'s table (or some of its rows).
        columns: the columns to show, in order; those not in `table` are skipped.

    Returns:
        str: the markdown, ending in a newline; "|" in cells escaped, newlines and nan as spaces and
        empty cells. The "Verdict rules:" list (one item per claim_id) follows only where `table` has
        ``rule`` and ``claim_id`` columns.
    """
    cols = [c for c in columns if c in table.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" for _ in cols) + "|"]
    for r in table.to_dict("records"):
        lines.append("| " + " | ".join(_md_cell(r[c]) for c in cols) + " |")
    if "rule" in table.columns and "claim_id" in table.columns:
        lines += ["", "Verdict rules:", ""]
        for cid, rule in dict(zip(table["claim_id"], table["rule"])).items():
            claim = table.loc[table["claim_id"] == cid, "claim"].iloc[0]
            lines.append(f"- {_md_cell(claim)}: {_md_cell(rule)}.")
    return "\n".join(lines) + "\n"


def write_claims(table: pd.DataFrame, directory) -> tuple[str, str]:
    """Write ``claims.md`` (markdown table) and ``claims.csv`` (every
    column) into `directory`, each atomically. Returns their paths.

    Args:
        table: :func:`claims_table`'s table.
        directory: the folder (str or path-like); created if missing.

    Returns:
        tuple[str, str]: the paths of ``claims.md`` (:func:`to_markdown`, default columns) and
        ``claims.csv`` (no index).
    """
    directory = os.fspath(directory)
    md = os.path.join(directory, "claims.md")
    csv = os.path.join(directory, "claims.csv")
    write_text(to_markdown(table), md)
    write_text(table.to_csv(index=False), csv)
    return md, csv
