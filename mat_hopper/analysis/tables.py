"""Small tables of results, for reading: one call per question a chapter
asks (how did each run end, percent change against a baseline, what
claims hold), from the tidy tables of :mod:`mat_hopper.experiments`.
Every percent change is :func:`mat_hopper.util.change.percent_change`.

Units: SI in the column names (``_m``, ``_w``, ``_s``); densities g/cm^3,
moduli GPa.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.behaviours import order_behaviours
from ..core.materials import CONVENTIONS, LegDesign, order_designs, paper_designs
from ..util.change import percent_change


def _need(table: pd.DataFrame, columns, what: str) -> None:
    """ValueError naming the `columns` `table` lacks (the caller `what`)."""
    missing = [c for c in dict.fromkeys(columns) if c not in table.columns]
    if missing:
        raise ValueError(f"{what} needs columns {missing}")


def design_table(designs: dict[str, LegDesign] | None = None) -> pd.DataFrame:
    """One row per design and segment (1 nearest the base): design,
    segment, material, density_g_cm3, modulus_gpa (nan: rigid).

    Args:
        designs: designs by name; None: :func:`mat_hopper.core.materials.paper_designs`.

    Returns:
        DataFrame with columns design, segment (1, 2, ...), material (name), density_g_cm3 (g/cm^3),
        modulus_gpa (GPa, nan: rigid).
    """
    designs = paper_designs() if designs is None else designs
    rows = []
    for name, d in designs.items():
        for i, m in enumerate(d.segments, start=1):
            rows.append(
                {
                    "design": name,
                    "segment": i,
                    "material": m.name,
                    "density_g_cm3": m.density_g_cm3,
                    "modulus_gpa": np.nan if m.modulus_gpa is None else m.modulus_gpa,
                }
            )
    return pd.DataFrame(rows)


_JOINT_TYPES = {0: "free", 1: "ball", 2: "slide", 3: "hinge"}


def joint_table(design: LegDesign | str = "SS", convention: str = "paper") -> pd.DataFrame:
    """Every joint of the compiled hopper, from the base down: name, type
    (slide m, hinge rad), stiffness (N/m or N m/rad), damping, range (nan:
    unlimited), the body it moves.

    Args:
        design: the leg, or its name (:func:`mat_hopper.core.materials.parse_design`).
        convention: the stiffness convention the model is built with (:func:`mat_hopper.core.model.build_model`).

    Returns:
        DataFrame, one row per joint in MuJoCo's order. Columns: joint (name), type (free, ball, slide
        or hinge), body, stiffness (N/m or N m/rad), damping (N s/m or N m s/rad, of the joint's first
        degree of freedom), range_low, range_high (m or rad; nan: unlimited).

    Raises:
        ValueError: an unknown design name, or invalid arguments to :func:`mat_hopper.core.model.build_model`
            (e.g. an unknown convention).
    """
    from ..core.materials import parse_design
    from ..core.model import build_model

    d = parse_design(design) if isinstance(design, str) else design
    m = build_model(d, convention=convention).model
    rows = []
    for j in range(m.njnt):
        jt = m.joint(j)
        limited = bool(m.jnt_limited[j])
        lo, hi = (float(m.jnt_range[j, 0]), float(m.jnt_range[j, 1])) if limited else (np.nan, np.nan)
        rows.append(
            {
                "joint": jt.name,
                "type": _JOINT_TYPES.get(int(m.jnt_type[j]), str(m.jnt_type[j])),
                "body": m.body(int(m.jnt_bodyid[j])).name,
                "stiffness": float(m.jnt_stiffness[j]),
                "damping": float(m.dof_damping[m.jnt_dofadr[j]]),
                "range_low": lo,
                "range_high": hi,
            }
        )
    return pd.DataFrame(rows)


def replicate_table(comparison: pd.DataFrame, metrics=("tracking_error_m", "power_w")) -> pd.DataFrame:
    """A compare_replicates table for reading: one row per design and
    metric, percent change of the mean with its 95 % bootstrap interval,
    the Holm-adjusted p and a star where p < 0.05.

    Args:
        comparison: :func:`mat_hopper.analysis.stats.compare_replicates`'s table (design, metric, n,
            pct_change, ci_low, ci_high, p_holm, significant).
        metrics: the metrics kept.

    Returns:
        DataFrame, one row per row of `comparison` with a kept metric (no behaviour column). Columns:
        design, metric, n, change ("+12 % [+3, +20]": pct_change with ci_low, ci_high), "p (Holm)"
        (three significant digits), "" ("*" where the ``significant`` column is true).

    Raises:
        ValueError: `comparison` lacks one of the columns above.
    """
    need = ("design", "metric", "n", "pct_change", "ci_low", "ci_high", "p_holm", "significant")
    _need(comparison, need, "replicate_table")
    c = comparison[comparison["metric"].isin(metrics)]
    return pd.DataFrame(
        {
            "design": c["design"],
            "metric": c["metric"],
            "n": c["n"],
            "change": [
                f"{p:+.0f} % [{lo:+.0f}, {hi:+.0f}]" for p, lo, hi in zip(c["pct_change"], c["ci_low"], c["ci_high"])
            ],
            "p (Holm)": c["p_holm"].map(lambda p: f"{p:.3g}"),
            "": np.where(c["significant"], "*", ""),
        }
    ).reset_index(drop=True)


def pct_change_table(
    hops: pd.DataFrame, metric: str, baseline: str = "MD", *, designs=None, behaviours=None
) -> pd.DataFrame:
    """Percent change of the mean of `metric` against `baseline` (same
    behaviour, unperturbed runs), designs as rows and behaviours as
    columns (from :func:`mat_hopper.analysis.stats.summary_table`). Where the
    baseline's mean is round-off (:func:`~mat_hopper.util.change.percent_change`;
    e.g. the tracking error of hopping in place) the change is nan: a
    percentage of nothing means nothing.

    Args:
        hops: a per-hop table (design, behaviour, `metric`; the unperturbed run, replicate -1, is used).
        metric: the metric column.
        baseline: the baseline design.
        designs: the designs shown (rows, in the paper's order); None: those of the table.
        behaviours: the behaviours shown (columns, in the paper's order); None: those of the table.

    Returns:
        DataFrame of percent changes (%), designs as index (the baseline left out unless named in
        `designs`, then all nan), behaviours as columns; the columns' name is "<metric>: % vs <baseline>".

    Raises:
        ValueError: `metric` is not a column of `hops` (:func:`mat_hopper.analysis.stats.summary_table`).
    """
    from . import stats

    s = stats.summary_table(hops, metrics=(metric,), baseline=baseline)
    if designs is not None:
        s = s[s["design"].isin(designs)]
    if behaviours is not None:
        s = s[s["behaviour"].isin(behaviours)]
    s = s[s["design"] != baseline]
    t = s.pivot_table(index="design", columns="behaviour", values="pct_change_mean", aggfunc="first")
    t = t.reindex(index=order_designs(designs or t.index), columns=order_behaviours(behaviours or t.columns))
    t.columns.name = f"{metric}: % vs {baseline}"
    return t


def outcome_table(runs: pd.DataFrame) -> pd.DataFrame:
    """How each run ended, designs as rows and behaviours as columns: "ok,
    N hops" (N scored hop cycles), "fell" (the body ended below 0.1 m),
    "diverged at T s" (numerical blow-up, simulated time) or "failed"
    (an error; see the runs table). Unperturbed runs only.

    Args:
        runs: a run-summary table (design, behaviour, status; n_hops, diverged_at_s and replicate where
            present).

    Returns:
        DataFrame of str, designs as index and behaviours as columns, each in the paper's order: "ok, N
        hops" ("ok" without an n_hops value), "diverged at T s" (T to two significant digits) or the
        run's status as written (e.g. "fallen", "failed", "diverged" without a time); nan where no run.

    Raises:
        ValueError: `runs` lacks a column design, behaviour or status.
    """
    need = ("design", "behaviour", "status")
    missing = [c for c in need if c not in runs.columns]
    if missing:
        raise ValueError(f"outcome_table needs columns {missing}")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs

    def cell(row) -> str:
        st = row["status"]
        if st == "ok":
            return f"ok, {int(row['n_hops'])} hops" if "n_hops" in row and pd.notna(row["n_hops"]) else "ok"
        if st == "diverged" and pd.notna(row.get("diverged_at_s", np.nan)):
            return f"diverged at {row['diverged_at_s']:.2g} s"
        return str(st)

    t = r.assign(outcome=r.apply(cell, axis=1)).pivot_table(
        index="design", columns="behaviour", values="outcome", aggfunc="first"
    )
    t = t.reindex(index=order_designs(t.index), columns=order_behaviours(t.columns))
    t.columns.name = None
    return t


def outcome_summary(runs: pd.DataFrame) -> str:
    """One paragraph on how the (unperturbed) runs ended: how many ended
    upright, then each design and behaviour that did not, with how
    (diverged at T s, fell, failed).

    Args:
        runs: a run-summary table, as for :func:`outcome_table`.

    Returns:
        str: "K of N runs ended upright." or "K of N runs ended upright; not: <design> <behaviour>:
        <outcome>; ...." (the behaviour left out where the table has only one), outcomes as in
        :func:`outcome_table`; N counts the design-behaviour cells that have a run.

    Raises:
        ValueError: `runs` lacks a column design, behaviour or status.
    """
    t = outcome_table(runs)
    cells = [(d, b, v) for d in t.index for b in t.columns if isinstance(v := t.loc[d, b], str)]
    bad = [(d, b, v) for d, b, v in cells if not v.startswith("ok")]
    one_behaviour = len(t.columns) == 1
    text = f"{len(cells) - len(bad)} of {len(cells)} runs ended upright"
    if not bad:
        return text + "."
    items = [f"{d}{'' if one_behaviour else ' ' + b}: {v}" for d, b, v in bad]
    return text + "; not: " + "; ".join(items) + "."


def metric_table(hops: pd.DataFrame, metric: str, stat: str = "mean", *, scale: float = 1.0) -> pd.DataFrame:
    """`stat` (mean or median) of `metric` over the scored hop cycles of
    the unperturbed runs, times `scale` (e.g. 1e3 for mm), designs as rows
    and behaviours as columns.

    Args:
        hops: a per-hop table (design, behaviour, `metric`).
        metric: the metric column.
        stat: ``mean`` or ``median``.
        scale: factor on every value.

    Returns:
        DataFrame, designs as index and behaviours as columns, each in the paper's order.

    Raises:
        ValueError: `stat` not mean or median; `metric` not a column of `hops`.
    """
    from . import stats

    if stat not in ("mean", "median"):
        raise ValueError(f"stat must be mean or median, got {stat!r}")
    s = stats.summary_table(hops, metrics=(metric,), baseline=None)
    t = s.pivot_table(index="design", columns="behaviour", values=stat, aggfunc="first") * scale
    t = t.reindex(index=order_designs(t.index), columns=order_behaviours(t.columns))
    t.columns.name = None
    return t


def sweep_spans(hops: pd.DataFrame, metric: str = "tracking_error_m") -> pd.DataFrame:
    """Experiment 2, one row per base material and swept property: the
    smallest and largest mean of `metric` over the sweep's points (mean
    over each point's scored hop cycles, unperturbed runs), their span,
    and the property values where they occur. Columns sweep_base,
    sweep_property, n_points, min, at_min, max, at_max, span.

    Args:
        hops: experiment 2's per-hop rows (sweep_base, sweep_property, density_g_cm3, modulus_gpa,
            `metric`; replicate -1 only where a ``replicate`` column exists).
        metric: the metric column.

    Returns:
        DataFrame, one row per (sweep_base, sweep_property) in order of appearance. min, max and span
        in the metric's unit; at_min, at_max the swept property's value (density_g_cm3 in g/cm^3 for a
        ``density`` sweep, else modulus_gpa in GPa).

    Raises:
        ValueError: `hops` lacks one of the needed columns.
    """
    need = ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa", metric)
    missing = [c for c in need if c not in hops.columns]
    if missing:
        raise ValueError(f"sweep_spans needs columns {missing}")
    h = hops[hops["replicate"] == -1] if "replicate" in hops.columns else hops
    rows = []
    for (base, prop), g in h.groupby(["sweep_base", "sweep_property"], sort=False):
        col = "density_g_cm3" if prop == "density" else "modulus_gpa"
        means = g.groupby(col)[metric].mean()
        rows.append(
            {
                "sweep_base": base,
                "sweep_property": prop,
                "n_points": len(means),
                "min": means.min(),
                "at_min": means.idxmin(),
                "max": means.max(),
                "at_max": means.idxmax(),
                "span": means.max() - means.min(),
            }
        )
    return pd.DataFrame(rows)


ORDER_PAIRS = (("rho-inc", "rho-dec"), ("PVC-Ti-SS", "SS-Ti-PVC"))


def order_effect(
    hops: pd.DataFrame, pairs=ORDER_PAIRS, metrics=("tracking_error_m", "power_w", "jerk_m_s3"), alpha: float = 0.05
) -> pd.DataFrame:
    """Does segment order matter? For each pair of designs made of the same
    segments in opposite orders: the percent change of the second's mean
    against the first's, per behaviour and metric, with the Mann-Whitney U
    test on hop cycles (unperturbed runs; Holm over each pair's
    behaviours and metrics). Columns pair, behaviour, metric, pct_change,
    p_holm, significant.

    Args:
        hops: a per-hop table holding both designs of every pair (their experiments are merged into
            one family).
        pairs: (first, second) design names; the second is compared against the first.
        metrics: metric columns.
        alpha: significance level.

    Returns:
        DataFrame, one row per pair, behaviour and metric; pair is "<second> vs <first>", pct_change in
        %. The Holm correction is :func:`mat_hopper.analysis.stats.compare_hops`'s: one family per metric
        (and profile and convention) within each pair.

    Raises:
        ValueError: a pair's design missing from `hops`; a metric not a column of `hops`.
    """
    from . import stats

    frames = []
    for first, second in pairs:
        sub = hops[hops["design"].isin([first, second])]
        if not {first, second} <= set(sub["design"]):
            raise ValueError(f"order_effect: designs {first} and {second} must both be in the table")
        if "experiment" in sub.columns:
            sub = sub.assign(experiment="+".join(sorted(set(sub["experiment"].astype(str)))))
        res = stats.compare_hops(sub, baseline=first, metrics=metrics, alpha=alpha)
        res = res[res["design"] == second].assign(pair=f"{second} vs {first}")
        frames.append(res[["pair", "behaviour", "metric", "pct_change", "p_holm", "significant"]])
    return pd.concat(frames, ignore_index=True)


def starred(
    table: pd.DataFrame,
    rows=("pair", "metric"),
    column: str = "behaviour",
    value: str = "pct_change",
    flag: str = "significant",
) -> pd.DataFrame:
    """A tidy comparison as a wide table for the page: `value` (a percent
    change) as "+12 %" with a star where `flag` is true, `rows` as the
    index and `column` values as columns ("–" where nan).

    Args:
        table: a tidy comparison (e.g. :func:`order_effect`'s).
        rows: the columns that make the index.
        column: the column whose values become columns (behaviours in the paper's order).
        value: the percent-change column.
        flag: the boolean column that earns a star.

    Returns:
        DataFrame of str: "+12 %", "+12 % *" where `flag` is true, "–" where `value` is not finite.

    Raises:
        ValueError: `table` lacks one of the columns `rows`, `column`, `value`, `flag`.
    """
    _need(table, (*rows, column, value, flag), "starred")

    def cell(r) -> str:
        v = r[value]
        if not np.isfinite(v):
            return "–"
        return f"{v:+.0f} %" + (" *" if bool(r[flag]) else "")

    t = table.assign(_cell=table.apply(cell, axis=1))
    out = t.pivot_table(index=list(rows), columns=column, values="_cell", aggfunc="first", sort=False)
    if column == "behaviour":
        out = out[order_behaviours(out.columns)]
    out.columns.name = None
    return out


CHAPTER_CLAIMS = {
    "mono": ("hop_height", "tracking_all_beat_md", "tracking_ss_55", "power_higher_dynamic", "power_ss_max"),
    "one_property": ("density_over_modulus", "low_modulus_tracks_worse"),
    "gradients": (
        "ramp_rho_inc_tracking",
        "ramp_rho_inc_power",
        "ramp_ss_tracking",
        "ramp_ss_power",
        "headline_tracking",
        "headline_power",
    ),
    "stability": ("timestep_materials", "timestep_trend"),
}


def _concat(tables: dict, suffix: str) -> pd.DataFrame | None:
    frames = [
        t
        for name, t in sorted(tables.items())
        if name.startswith("exp") and name.endswith(suffix) and t is not None and len(t)
    ]
    return pd.concat(frames, ignore_index=True) if frames else None


def claims_for(
    tables: dict, chapter: str | None = None, *, conventions=None, columns=("claim", "paper", "ours", "verdict")
) -> pd.DataFrame:
    """The paper's claims beside ours (:func:`mat_hopper.analysis.claims.claims_table`)
    from a reproduction's tables (``exp*_hops``, ``exp*_runs``,
    ``stability``, ``controls_hops`` where present), for one chapter (a key of :data:`CHAPTER_CLAIMS`) or all
    (None). conventions: default those present in the tables. columns:
    which to keep (None: all).

    Args:
        tables: result tables by name (``exp1_hops``, ``exp1_runs``, ..., ``stability``,
            ``robustness_hops`` for the time-step check, ``controls_hops``, ``controls_runs``); the
            ``exp*_hops`` and ``exp*_runs`` tables are concatenated.
        chapter: a key of :data:`CHAPTER_CLAIMS`, or None: every claim.
        conventions: the stiffness conventions; None: those present in the tables (``paper`` where
            none is).
        columns: the columns kept; None: all.

    Returns:
        DataFrame, one row per claim and convention (a chapter's claims in :data:`CHAPTER_CLAIMS`'s
        order), index reset.

    Raises:
        ValueError: an unknown chapter; or from :func:`mat_hopper.analysis.claims.claims_table`.
    """
    from . import claims

    if chapter is not None and chapter not in CHAPTER_CLAIMS:
        raise ValueError(f"chapter must be one of {', '.join(CHAPTER_CLAIMS)} or None, got {chapter!r}")
    hops, runs, stab = _concat(tables, "_hops"), _concat(tables, "_runs"), tables.get("stability")
    if conventions is None:
        present = set()
        for t in (hops, runs, stab):
            if t is not None and "convention" in t.columns:
                present |= set(t["convention"].dropna().astype(str))
        conventions = [c for c in CONVENTIONS if c in present] or ["paper"]
    from .robustness import FINE_LABEL, fine_step_hops

    fine = fine_step_hops(tables.get("robustness_hops"))
    table = claims.claims_table(
        hops,
        runs,
        stab,
        conventions=tuple(conventions),
        fine_hops=fine,
        fine_label=FINE_LABEL,
        controls=tables.get("controls_hops"),  # the beyond-mass columns, where the controls ran
        control_runs=tables.get("controls_runs"),  # their unusable runs dropped
    )
    if chapter is not None:
        ids = CHAPTER_CLAIMS[chapter]
        table = table[table["claim_id"].isin(ids)]
        table = (
            table.assign(_o=table["claim_id"].map({c: i for i, c in enumerate(ids)}))
            .sort_values(["_o", "convention"], kind="stable")
            .drop(columns="_o")
        )
    table = table.reset_index(drop=True)
    return table if columns is None else table[[c for c in columns if c in table.columns]]


def claim_rules() -> pd.DataFrame:
    """The rule behind each claim's verdict (:data:`mat_hopper.analysis.claims.CLAIMS`):
    columns claim, rule.

    Returns:
        DataFrame, one row per claim in :data:`mat_hopper.analysis.claims.CLAIMS`'s order.
    """
    from . import claims

    return pd.DataFrame([{"claim": c.claim, "rule": c.rule} for c in claims.CLAIMS])


def _subsampling_steps(rates_hz, record_hz: float, n_samples: int) -> list[int]:
    """Every-k-th-sample steps k that emulate `rates_hz` from a record at
    `record_hz` (:func:`jerk_by_rate`), all checked before any is used."""
    try:
        rates = [float(r) for r in rates_hz]
    except (TypeError, ValueError):
        raise ValueError(f"rates_hz must be numbers (Hz), got {rates_hz!r}") from None
    if not rates:
        raise ValueError("jerk_by_rate needs at least one rate")
    possible = f"possible rates: {record_hz:g} Hz divided by a whole number ({record_hz:g}, {record_hz / 2:g}, ...)"
    steps = []
    for rate in rates:
        if not (np.isfinite(rate) and rate > 0):
            raise ValueError(f"rate {rate} Hz must be a finite number > 0; {possible}")
        if rate > record_hz * (1 + 1e-6):  # 1e-6: the record rate is read off the samples' times
            raise ValueError(f"rate {rate:g} Hz exceeds the record rate {record_hz:g} Hz; {possible}")
        ratio = record_hz / rate
        k = max(1, int(round(ratio))) if ratio < n_samples else n_samples
        if (n_samples - 1) // k + 1 < 3:
            raise ValueError(f"rate {rate:g} Hz leaves fewer than 3 samples")
        steps.append(k)
    return steps


def jerk_by_rate(rollout, rates_hz=(1000.0, 100.0, 10.0)) -> pd.DataFrame:
    """Mean |jerk| (m/s^3) of the body's vertical motion after the
    transient, as it would be recorded at each rate (every k-th recorded
    sample), two ways:

    - ``raw_jerk_m_s3``: the vertical acceleration at that rate
      differentiated by finite differences (``np.gradient``), the old
      metric and the authors' way (they logged at about 10 Hz of wall
      time). The leg's axial modes (kHz, barely damped) lie above the
      Nyquist frequency of any record rate, so this number measures the
      sampling (aliased ringing), not the hop: kept as an illustration.
    - ``metric_jerk_m_s3``: the book's metric, :mod:`mat_hopper.physics.metrics`'
      ``jerk_z`` channel (computed at the physics rate from the
      acceleration low-passed at 50 Hz) averaged over the samples at that
      rate: what ``hop_table`` reports for a run recorded at that rate.

    ``mean_jerk_m_s3`` repeats ``raw_jerk_m_s3`` (the column's name before
    the metric changed). Columns rate_hz, raw_jerk_m_s3, metric_jerk_m_s3,
    mean_jerk_m_s3.

    Args:
        rollout: a :class:`mat_hopper.core.rollout.Rollout`; averaged from ``rollout.settings.transient_s`` on.
        rates_hz: the record rates to emulate, Hz (one or more, each finite and > 0). Subsampling can
            only emulate the record rate R divided by a whole number k (R, R/2, R/3, ...): a rate at or
            below R is rounded to the nearest of these (the ``rate_hz`` column says which); a rate above
            R cannot be honoured and is refused, never lowered to R.

    Returns:
        DataFrame, one row per rate: rate_hz (the emulated rate, Hz), raw_jerk_m_s3, metric_jerk_m_s3,
        mean_jerk_m_s3 (m/s^3).

    Raises:
        ValueError: no rate; a rate that is not a finite number > 0; a rate above the record rate (the
            message gives the record rate and the possible rates); fewer than 4 recorded samples; a
            rate that leaves fewer than 3 samples. Every rate is checked before any is computed.
    """
    from ..core.sim import C

    d = rollout.data
    t, az, jz = d[:, C["t"]], d[:, C["az"]], d[:, C["jerk_z"]]
    if len(t) < 4:
        raise ValueError("jerk_by_rate: the rollout recorded fewer than 4 samples")
    dt = float(np.median(np.diff(t)))
    steps = _subsampling_steps(rates_hz, 1.0 / dt, len(t))
    rows = []
    for k in steps:
        ts, a, j = t[::k], az[::k], jz[::k]
        raw = np.abs(np.gradient(a, ts))
        keep = ts >= rollout.settings.transient_s
        rows.append(
            {
                "rate_hz": 1.0 / (k * dt),
                "raw_jerk_m_s3": float(raw[keep].mean()),
                "metric_jerk_m_s3": float(np.abs(j[keep]).mean()),
            }
        )
    out = pd.DataFrame(rows)
    out["mean_jerk_m_s3"] = out["raw_jerk_m_s3"]
    return out


def setting_comparison(
    hops: pd.DataFrame,
    pairs=(("rho-inc", "MD"), ("SS", "MD"), ("rho-inc", "SS")),
    metrics=("tracking_error_m", "power_w"),
) -> pd.DataFrame:
    """Percent change of the mean of each metric for each (design,
    baseline) pair, per ``setting`` of the table (e.g. from
    :func:`axial_check`): rows setting, columns "<metric>: <design> vs
    <baseline>"; nan where either is missing or the baseline's mean is
    round-off (:func:`~mat_hopper.util.change.percent_change`).

    Args:
        hops: a per-hop table with columns setting, design and the metrics.
        pairs: (design, baseline) names.
        metrics: metric columns.

    Returns:
        DataFrame, one row per setting (in order of appearance, index named ``setting``), percent
        changes (%) of the means over all rows of each design and setting.

    Raises:
        ValueError: `hops` lacks the ``setting`` or ``design`` column or a metric's (the message names
            them).
    """
    _need(hops, ("setting", "design", *metrics), "setting_comparison")
    means = hops.groupby(["setting", "design"])[list(metrics)].mean()
    rows = {}
    for setting in dict.fromkeys(hops["setting"]):
        row = {}
        for design, baseline in pairs:
            for m in metrics:
                try:
                    a, b = means.loc[(setting, design), m], means.loc[(setting, baseline), m]
                except KeyError:
                    a, b = np.nan, np.nan
                row[f"{m}: {design} vs {baseline}"] = percent_change(a, b)
        rows[setting] = row
    out = pd.DataFrame.from_dict(rows, orient="index")
    out.index.name = "setting"
    return out


def power_formula_table(hops: pd.DataFrame, design: str = "SS", baseline: str = "MD") -> pd.DataFrame:
    """Percent change of `design`'s mean hip power against `baseline`'s, per
    behaviour, measured two ways: the real mechanical power of the hip
    motors (``power_w``, ours) and the authors' formula
    (``power_paper_w``). Rows: the two measures; columns: behaviours.

    Args:
        hops: a per-hop table (design, behaviour, power_w, power_paper_w; the unperturbed run is used,
            :func:`pct_change_table`).
        design: the design.
        baseline: the baseline design.

    Returns:
        DataFrame of percent changes (%): rows "real hip power (ours)" and "the authors' formula",
        behaviours as columns (nan where `design` has no value); the columns' name is
        "power: <design> vs <baseline> (%)".

    Raises:
        ValueError: `hops` lacks power_w or power_paper_w.
    """
    rows = {}
    for metric, label in (("power_w", "real hip power (ours)"), ("power_paper_w", "the authors' formula")):
        t = pct_change_table(hops, metric, baseline, designs=[baseline, design])
        rows[label] = t.loc[design] if design in t.index else pd.Series(dtype=float)
    out = pd.DataFrame(rows).T
    out.columns.name = f"power: {design} vs {baseline} (%)"
    return out


def leg_mass_table(runs: pd.DataFrame) -> pd.DataFrame:
    """The runs of a sweep with the mass of the leg's material (the sum of
    :func:`mat_hopper.core.materials.segment_masses`, kg, from the runs'
    per-segment ``densities_g_cm3`` "a/b/c" and ``segment_mass``
    convention) as ``leg_mass_kg``; unperturbed runs only. Columns: those of
    `runs` plus leg_mass_kg.

    Args:
        runs: a run-summary table with ``densities_g_cm3`` ("a/b/c", g/cm^3 per segment, hip to foot)
            and, optionally, ``segment_mass`` (default ``leg``) and ``replicate`` (-1 kept).

    Returns:
        DataFrame: the kept rows, index reset, with leg_mass_kg (kg).

    Raises:
        ValueError: no ``densities_g_cm3`` column; a density out of range
            (:meth:`mat_hopper.core.materials.LegDesign.from_properties`); an unknown segment-mass convention
            (:func:`mat_hopper.core.materials.segment_masses`).
    """
    from ..core.materials import LegDesign, segment_masses

    _need(runs, ("densities_g_cm3",), "leg_mass_table")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs
    masses = []
    for text, conv in zip(r["densities_g_cm3"].astype(str), r.get("segment_mass", pd.Series("leg", index=r.index))):
        rho = [float(x) for x in text.split("/")]
        d = LegDesign.from_properties(rho, [None] * len(rho))
        masses.append(sum(segment_masses(d, conv)))
    return r.assign(leg_mass_kg=masses).reset_index(drop=True)


def failure_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Every unperturbed run that did not end upright, told apart:
    ``numerical`` (the numbers blew up while the body was still up: a time
    step above the design's stable step, chapter 5), ``fell, then
    diverged`` (the body was already below 0.1 m, the paper's criterion,
    when the numbers blew up: the hopper failed first), ``fell`` (ended
    below 0.1 m without blowing up) or ``failed`` (an error). Columns:
    design, behaviour, kind, at_s (time of the blow-up, s; nan for a plain
    fall), final_base_z_m (the last recorded body height), n_hops.

    Args:
        runs: a run-summary table (design, behaviour, status, final_base_z_m; upright, diverged_at_s,
            n_hops and replicate where present; without ``upright`` a run is upright when its status is
            "ok").

    Returns:
        DataFrame, one row per unperturbed run whose status is not "ok" or that is not upright, with
        the columns above (at_s and final_base_z_m in s and m; n_hops 0 where missing). "Below 0.1 m"
        is not at or above :data:`mat_hopper.core.reference.STABLE_MIN_BASE_Z` (a nan height counts as
        below).

    Raises:
        ValueError: `runs` lacks a column design, behaviour, status or final_base_z_m, or lacks
            diverged_at_s while one of its unperturbed runs diverged (the message names the columns).
    """
    from ..core import reference as ref

    _need(runs, ("design", "behaviour", "status", "final_base_z_m"), "failure_table")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs
    upright = r["upright"].astype(bool) if "upright" in r.columns else r["status"] == "ok"
    bad = r[(r["status"] != "ok") | ~upright]
    if (bad["status"] == "diverged").any():  # the time of a blow-up: checked before any row is made
        _need(runs, ("diverged_at_s",), "failure_table (a run diverged)")
    rows = []
    for row in bad.itertuples(index=False):
        z = float(row.final_base_z_m)
        low = not (z >= ref.STABLE_MIN_BASE_Z)
        if row.status == "diverged":
            kind = "fell, then diverged" if low else "numerical"
            at = float(row.diverged_at_s)
        elif row.status == "failed":
            kind, at = "failed", np.nan
        else:
            kind, at = "fell", np.nan
        rows.append(
            {
                "design": row.design,
                "behaviour": row.behaviour,
                "kind": kind,
                "at_s": at,
                "final_base_z_m": z,
                "n_hops": int(row.n_hops) if pd.notna(getattr(row, "n_hops", np.nan)) else 0,
            }
        )
    return pd.DataFrame(rows, columns=["design", "behaviour", "kind", "at_s", "final_base_z_m", "n_hops"])
