"""Per-hop metrics, run summaries and comparisons against a baseline.

A hop cycle runs from one lift-off (the state machine's stance-to-flight
switch) to the next. Cycles that start before the transient (20 s by
default) are not scored. Per cycle, from the rollout's samples (1 kHz):

- ``hop_height_m``: max base z (m);
- ``tracking_error_m``: mean planar distance base - desired path (m);
- ``hop_height_ground_m``: max over the cycle of base z above the terrain
  under the base (m). On flat ground the same as ``hop_height_m``; on the
  ramp the ground rises about 0.1 m over a run while the controller keeps
  regulating the world-z apex to 1 m, so this height falls;
- ``jerk_m_s3``: mean |d^3 z / dt^3| of the base (m/s^3): the base's z
  acceleration low-passed at the physics rate (2nd-order Butterworth,
  50 Hz, :data:`mat_hopper.core.sim.JERK_CUTOFF_HZ`), differentiated step by step
  (channel ``jerk_z``), averaged over the cycle's recorded samples. It does
  not depend on the record rate (an unfiltered derivative of the recorded
  acceleration measures the aliased ringing of the leg's kHz axial modes);
- ``jerk_body_m_s3``: the same with a zero-phase 4th-order 20 Hz
  Butterworth after an anti-aliasing box mean (:mod:`mat_hopper.physics.jerk`):
  the body's jerk without the leg's ringing;
- ``power_w``: mean norm of the hip actuators' real mechanical power,
  ||(tau_y qdot_y, tau_x qdot_x)|| (W), tau the joint torque MuJoCo applies
  (``qfrc_actuator``: gear 600 x control, joint space);
- ``power_paper_w``: the authors' formula, labelled as such: the hip_y
  *flight* PD command (before the gear, also in stance) times each hip rate;
- ``energy_j``: integral of |tau qdot| of all three actuators (J), joint
  space;
- ``peak_stress_pa``, ``peak_stress_segment``, ``damage``,
  ``yield_exceeded``: the leg's peak section stress over the
  hop (Pa, physics rate) and its segment, the worst segment's Miner damage
  of the hop, and whether any segment's peak exceeded its yield strength
  (:mod:`mat_hopper.physics.fatigue`); beside the ``damping`` setting.
- ``touch_toggles_per_switch``: the toe's touch-sensor on/off switches
  (touch > 0 N is on, counted at the physics rate on the reading the
  controller gets, so in step with its switches) over the hop, divided by
  the controller's phase switches in it (its lift-off and touchdown): 1.0
  is a clean contact, more is chatter; ``peak_penetration_m``: the foot's
  deepest penetration into the terrain over the hop (m, positive into the
  ground; 0 if it never touched; MuJoCo's foot-terrain distance at the
  physics rate); beside the ``contact`` setting
  (:mod:`mat_hopper.core.contact`). Both are read from the records of the
  hop, each covering the physics steps since the record before.
- the energetics of :mod:`mat_hopper.physics.energetics` (total actuator work
  including thrust, absolute and positive, hip work, total power, Joule
  proxies): ``work_abs_j`` ... ``joule_thrust_n2s``.

Every row also carries the design's leg mass properties (constant per run,
:func:`mat_hopper.core.control_legs.mass_properties`): ``leg_mass_kg``,
``leg_com_m`` (m below the hip) and ``hip_inertia_kg_m2``; and the
``apex_reference`` setting, what the controller's hop height is measured
from (``world`` z or the ``ground`` under the foot at lift-off,
:mod:`mat_hopper.core.controller`).

:func:`compare` sets each design's hop cycles beside a baseline's: the
percent change of means, the rank-biserial effect size and a Mann-Whitney
U, descriptive only (its columns say so, and it draws no verdict): hop
cycles of one deterministic run are not independent samples. Inference
uses replicate runs: paired on shared seeds
(:func:`mat_hopper.analysis.paired.compare_paired`), or independent run
means (:func:`compare_independent`, Mann-Whitney U with Holm's correction).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from ..core import reference as ref
from ..core.control_legs import MASS_PROPERTY_COLUMNS, mass_properties
from ..core.controller import LIFTOFF, TOUCHDOWN
from ..core.model import terrain_height_m
from ..core.rollout import Rollout, check_transient_within, hop_cycles
from ..core.sim import C
from ..util.change import percent_change
from . import energetics as _energetics
from .fatigue import fatigue_summary, hop_stress_columns

METRICS = ("hop_height_m", "tracking_error_m", "jerk_m_s3", "power_w")
ALL_METRICS = METRICS + (
    "hop_height_ground_m",
    "power_paper_w",
    "energy_j",
    *_energetics.HOP_COLUMNS,
    "jerk_body_m_s3",
)
GRAVITY = ref.GRAVITY_M_S2
# the damping setting, then each hop's stress and fatigue (mat_hopper.physics.fatigue)
STRESS_COLUMNS = ("damping", "peak_stress_pa", "peak_stress_segment", "damage", "yield_exceeded")
# the contact setting, then each hop's contact chatter and penetration (module doc)
CONTACT_COLUMNS = ("contact", "touch_toggles_per_switch", "peak_penetration_m")
ROUNDOFF = 1e-12  # relative spread below which a metric's values count as equal


def _segment_means(values: np.ndarray, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    csum = np.concatenate([[0.0], np.cumsum(values)])
    return (csum[ends] - csum[starts]) / np.maximum(ends - starts, 1)


def _body_jerk(rollout: Rollout, i0: np.ndarray, i1: np.ndarray) -> np.ndarray:
    """mat_hopper.physics.jerk.hop_body_jerk; nan for a run too short to filter."""
    from .jerk import hop_body_jerk

    try:
        return hop_body_jerk(rollout, i0, i1)
    except ValueError:
        return np.full(len(i0), np.nan)


def _hop_contact(rollout: Rollout, cycles: np.ndarray, i0: np.ndarray, i1: np.ndarray) -> dict:
    """Per hop: touch toggles per phase switch and peak penetration, m (module doc)."""
    d = rollout.data
    toggles = np.concatenate([[0.0], np.cumsum(d[:, C["touch_toggles"]])])
    ev = rollout.events
    switch_t = np.sort(ev[np.isin(ev[:, 1], (TOUCHDOWN, LIFTOFF)), 0])
    switches = np.searchsorted(switch_t, cycles[:, 1], "left") - np.searchsorted(switch_t, cycles[:, 0], "left")
    gap = d[:, C["foot_clearance_min"]]
    return {
        "touch_toggles_per_switch": (toggles[i1] - toggles[i0]) / np.maximum(switches, 1),
        "peak_penetration_m": np.array([max(0.0, -float(gap[a:b].min())) for a, b in zip(i0, i1)]),
    }


def _check_rollout(rollout) -> None:
    if not isinstance(rollout, Rollout):
        raise ValueError(f"rollout must be a mat_hopper.Rollout (from simulate), got {type(rollout).__name__}")


def _scored_cycles(rollout: Rollout, transient_s, warn: bool) -> np.ndarray:
    """hop_cycles, with a DivergenceWarning (at hop_table's caller) for a
    diverged run when `warn`: never a silently short or empty table."""
    cycles = hop_cycles(rollout, transient_s)
    if warn:
        rollout.warn_if_diverged(f"hop_table holds the {len(cycles)} hop cycles scored before it", stacklevel=3)
        rollout.warn_if_suspect(f"hop_table holds its {len(cycles)} scored hop cycles", stacklevel=3)
    return cycles


def hop_table(rollout: Rollout, transient_s: float | None = None, *, warn: bool = True) -> pd.DataFrame:
    """One row per scored hop cycle, with every metric (see module doc).
    Raises ValueError when `rollout` is not a Rollout.

    Args:
        rollout: the :class:`~mat_hopper.core.rollout.Rollout` of a run.
        transient_s: hop cycles starting before it (s) are not scored, a
            finite number >= 0; None: the rollout's own ``settings.transient_s``.
        warn: a DivergenceWarning (its table holds only the cycles before it),
            SuspectWarning or FallWarning (:meth:`Rollout.warn_if_suspect`) as it applies; False: none.

    Returns:
        DataFrame, one row per scored hop cycle (lift-off to lift-off), columns
        ``design``, ``behaviour``, ``convention``, ``sensor_timing``,
        ``segment_mass``, ``hop`` (0, 1, ...), ``t_start_s``, ``t_end_s``, every
        metric of :data:`ALL_METRICS`, the leg's mass properties
        (``leg_mass_kg``, ``leg_com_m``, ``hip_inertia_kg_m2``), ``apex_reference``,
        :data:`STRESS_COLUMNS` and :data:`CONTACT_COLUMNS`. Empty (same columns) without scored cycles or
        with fewer than 4 recorded samples.

    Raises:
        ValueError: `rollout` is not a Rollout, or `transient_s` is not None
            nor a finite number >= 0 s (:func:`mat_hopper.core.rollout.check_transient`),
            or at or beyond the run's duration
            (:func:`mat_hopper.core.rollout.check_transient_within`).
    """
    _check_rollout(rollout)
    transient_s = check_transient_within(rollout, transient_s)
    cycles = _scored_cycles(rollout, transient_s, warn)
    d = rollout.data
    t = d[:, C["t"]]
    cols = [
        "design",
        "behaviour",
        "convention",
        "sensor_timing",
        "segment_mass",
        "hop",
        "t_start_s",
        "t_end_s",
        *ALL_METRICS,
        *MASS_PROPERTY_COLUMNS,
        "apex_reference",
        *STRESS_COLUMNS,
        *CONTACT_COLUMNS,
    ]
    if len(cycles) == 0 or len(t) < 4:
        return pd.DataFrame(columns=cols)
    dt_rec = float(np.median(np.diff(t)))
    i0 = np.searchsorted(t, cycles[:, 0])
    i1 = np.searchsorted(t, cycles[:, 1])
    keep = i1 > i0
    cycles, i0, i1 = cycles[keep], i0[keep], i1[keep]

    z = d[:, C["z"]]
    err = np.hypot(d[:, C["x"]] - d[:, C["x_des"]], d[:, C["y"]] - d[:, C["y_des"]])
    jerk = np.abs(d[:, C["jerk_z"]])
    ground = terrain_height_m(d[:, C["x"]], d[:, C["y"]], rollout.behaviour.ramp_grade_deg)
    above = z - ground
    p_y, p_x = rollout.hip_power.T
    power = np.hypot(p_y, p_x)
    g = rollout.settings.controller
    u_flight = -g.flight_kp * (d[:, C["hip_y"]] - d[:, C["hip_y_target"]]) - g.flight_kd * (
        d[:, C["hip_y_rate"]] - d[:, C["hip_y_target_rate"]]
    )
    power_paper = np.hypot(u_flight * d[:, C["hip_y_rate"]], u_flight * d[:, C["hip_x_rate"]])
    p_abs = np.abs(p_y) + np.abs(p_x) + np.abs(rollout.thrust_force * d[:, C["foot_spring_rate"]])

    heights = np.array([z[a:b].max() for a, b in zip(i0, i1)])
    heights_ground = np.array([above[a:b].max() for a, b in zip(i0, i1)])
    out = pd.DataFrame(
        {
            "design": rollout.design.name,
            "behaviour": rollout.behaviour.name,
            "convention": rollout.settings.convention,
            "sensor_timing": rollout.settings.sensor_timing.name,
            "segment_mass": rollout.settings.segment_mass,
            "hop": np.arange(len(cycles)),
            "t_start_s": cycles[:, 0],
            "t_end_s": cycles[:, 1],
            "hop_height_m": heights,
            "hop_height_ground_m": heights_ground,
            "tracking_error_m": _segment_means(err, i0, i1),
            "jerk_m_s3": _segment_means(jerk, i0, i1),
            "power_w": _segment_means(power, i0, i1),
            "power_paper_w": _segment_means(power_paper, i0, i1),
            "energy_j": _segment_means(p_abs, i0, i1) * (i1 - i0) * dt_rec,
            **_energetics.hop_energetics(rollout, i0, i1, dt_rec),
            "jerk_body_m_s3": _body_jerk(rollout, i0, i1),
            **mass_properties(rollout.design, rollout.settings.segment_mass).as_dict(),
        }
    )
    out["apex_reference"], out["damping"] = rollout.settings.apex_reference, rollout.settings.damping
    stress = hop_stress_columns(rollout, cycles)
    for c in STRESS_COLUMNS[1:]:
        out[c] = stress[c].to_numpy()
    out["contact"] = rollout.settings.contact
    for c, v in _hop_contact(rollout, cycles, i0, i1).items():
        out[c] = v
    return out[cols]


def run_summary(rollout: Rollout, transient_s: float | None = None, *, hops: pd.DataFrame | None = None) -> dict:
    """One run in a line: outcome, the leg's mass properties, means of the
    per-hop metrics, energy (J) and the run energetics of
    :func:`mat_hopper.physics.energetics.run_energetics` (cost of transport over the
    path length travelled, nan without travel). Raises ValueError when
    `rollout` is not a Rollout.

    Args:
        rollout: the :class:`~mat_hopper.core.rollout.Rollout` of a run.
        transient_s: hop cycles starting before it (s) are not scored, a
            finite number >= 0; None: the rollout's own ``settings.transient_s``.
        hops: the run's hop table (:func:`hop_table` of `rollout` with the
            same `transient_s`), when the caller has it already: each run's
            hop table is computed once. None: computed here.

    Returns:
        dict: ``design``, ``behaviour``, ``convention``, ``sensor_timing``,
        ``segment_mass``, ``stable``, ``diverged_at_s``, ``fell_at_s``,
        ``suspect_at_s`` and ``suspect_apex_m`` (when, s, and how high, m,
        the first scored apex of a numerically suspect run:
        :attr:`mat_hopper.core.rollout.Rollout.suspect_apex`; None if not), ``n_hops``,
        ``total_mass_kg``, the mass properties (``leg_mass_kg``, ``leg_com_m``,
        ``hip_inertia_kg_m2``), ``apex_reference``, ``mean_<metric>`` for every metric of
        :data:`ALL_METRICS` (nan without hops), ``damping``, the stress and
        fatigue of :func:`mat_hopper.physics.fatigue.fatigue_summary`, ``energy_j``
        (sum over the hops, J; nan without hops), the keys of
        :func:`mat_hopper.physics.energetics.run_energetics`, ``contact``,
        ``mean_touch_toggles_per_switch`` and ``peak_penetration_m`` (the
        deepest over the hops, m; both nan without hops), ``replicate_protocol``.

    Raises:
        ValueError: `rollout` is not a Rollout, or `transient_s` is not None
            nor a finite number >= 0 s (:func:`mat_hopper.core.rollout.check_transient`),
            or at or beyond the run's duration
            (:func:`mat_hopper.core.rollout.check_transient_within`).
    """
    _check_rollout(rollout)
    transient_s = check_transient_within(rollout, transient_s)
    if hops is None:  # the summary says it diverged (stable, diverged_at_s)
        hops = hop_table(rollout, transient_s, warn=False)
    apex = rollout.suspect_apex  # numerically corrupted without diverging: when (s) and how high (m)
    out = {
        "design": rollout.design.name,
        "behaviour": rollout.behaviour.name,
        "convention": rollout.settings.convention,
        "sensor_timing": rollout.settings.sensor_timing.name,
        "segment_mass": rollout.settings.segment_mass,
        "stable": rollout.stable,
        "diverged_at_s": rollout.diverged_at_s,
        "fell_at_s": rollout.fell_at_s,
        "suspect_at_s": None if apex is None else apex[0],
        "suspect_apex_m": None if apex is None else apex[1],
        "n_hops": len(hops),
        "total_mass_kg": rollout.total_mass_kg,
        **mass_properties(rollout.design, rollout.settings.segment_mass).as_dict(),
        "apex_reference": rollout.settings.apex_reference,
    }
    for m in ALL_METRICS:
        out[f"mean_{m}"] = float(hops[m].mean()) if len(hops) else np.nan
    out["damping"] = rollout.settings.damping
    out.update(fatigue_summary(rollout, hop_cycles(rollout, transient_s)))
    out["energy_j"] = float(hops["energy_j"].sum()) if len(hops) else np.nan
    out.update(_energetics.run_energetics(hops, rollout))
    out["contact"] = rollout.settings.contact
    out["mean_touch_toggles_per_switch"] = float(hops["touch_toggles_per_switch"].mean()) if len(hops) else np.nan
    out["peak_penetration_m"] = float(hops["peak_penetration_m"].max()) if len(hops) else np.nan
    out["replicate_protocol"] = rollout.settings.replicate_protocol
    return out


def summarize(hops: pd.DataFrame, by=("design", "behaviour"), metrics=METRICS) -> pd.DataFrame:
    """Mean, median and IQR of each metric per group, tidy (one row per
    group and metric).

    Args:
        hops: a hop table (:func:`hop_table`, or several concatenated).
        by: the column names to group by (a sequence, not a single string),
            groups in order of appearance.
        metrics: the metric columns to summarize.

    Returns:
        DataFrame with one column per name in `by`, then ``metric``, ``n``
        (hops in the group), ``mean``, ``median`` and ``iqr`` (75th minus
        25th percentile), in the metric's unit.
    """
    rows = []
    for key, g in hops.groupby(list(by), sort=False):
        key = key if isinstance(key, tuple) else (key,)
        for m in metrics:
            v = g[m].to_numpy(float)
            q1, q3 = np.percentile(v, [25, 75]) if len(v) else (np.nan, np.nan)
            rows.append(
                {
                    **dict(zip(by, key)),
                    "metric": m,
                    "n": len(v),
                    "mean": v.mean() if len(v) else np.nan,
                    "median": np.median(v) if len(v) else np.nan,
                    "iqr": q3 - q1,
                }
            )
    return pd.DataFrame(rows)


def holm(pvalues) -> np.ndarray:
    """Holm-Bonferroni adjusted p-values (same order as given).

    A non-finite p (nan: a comparison that could not be tested, e.g. no
    usable pairs) stays a member of the family: it counts in the family's
    size m as a hypothesis that can never be rejected (as p = 1, so it
    ranks last), and comes back nan. Leaving it out would shrink m and
    make every other adjustment less strict.

    Args:
        pvalues: raw p-values, array-like (nan where untested).

    Returns:
        float array of the input's shape: the adjusted p-values, capped at 1
        and made monotone in the order of the raw ones; nan where the input is
        not finite.
    """
    p = np.asarray(pvalues, dtype=float)
    ok = np.isfinite(p)
    filled = np.where(ok, p, 1.0).ravel()  # untested: in the family, never rejected
    m = filled.size
    idx = np.argsort(filled, kind="stable")
    adj = np.maximum.accumulate((m - np.arange(m)) * filled[idx])
    out = np.empty(m)
    out[idx] = np.minimum(adj, 1.0)
    out = out.reshape(p.shape)
    out[~ok] = np.nan
    return out


DESCRIPTIVE = "descriptive: hop cycles of one run are not independent"


def _check_compare_args(table, baseline: str, by: str, metrics, what: str) -> None:
    """The checks :func:`compare` and :func:`compare_independent` share
    (`what`: the argument's name in messages)."""
    if not isinstance(table, pd.DataFrame):
        raise ValueError(f"{what} must be a pandas DataFrame (a hop table), got {type(table).__name__}")
    if isinstance(metrics, str) or not list(metrics):
        raise ValueError(f"metrics must be a non-empty sequence of column names, got {metrics!r}")
    missing = [c for c in ("design", by) if c not in table.columns]
    if missing:
        raise ValueError(f"{what} has no column {', '.join(map(repr, missing))} (by={by!r})")
    if baseline not in set(table["design"]):
        raise ValueError(f"baseline {baseline!r} not among the designs: {sorted(set(table['design']))}")
    missing = [c for c in metrics if c not in table.columns]
    if missing:
        raise ValueError(f"{what} has no column {', '.join(map(repr, missing))} (metrics={list(metrics)})")


def _rank_rows(table: pd.DataFrame, baseline: str, by: str, metrics) -> list[dict]:
    """Per group, design and metric: sizes, means, percent change of means,
    Mann-Whitney U (two-sided), its p and the rank-biserial effect size."""
    rows = []
    for group, g in table.groupby(by, sort=False):
        base = g[g["design"] == baseline]
        for design, dg in g.groupby("design", sort=False):
            if design == baseline:
                continue
            for m in metrics:
                a, b = dg[m].to_numpy(float), base[m].to_numpy(float)
                mean_a, mean_b = (a.mean() if len(a) else np.nan), (b.mean() if len(b) else np.nan)
                pct = percent_change(mean_a, mean_b)
                pooled = np.concatenate([a, b])
                # Round-off spread (e.g. 1e-17 m of lateral drift in symmetric
                # in-place hopping) is no difference: treat it as ties.
                tied = len(pooled) == 0 or np.ptp(pooled) <= ROUNDOFF * max(np.abs(pooled).max(), 1.0)
                if len(a) and len(b) and not tied:
                    u, p = stats.mannwhitneyu(a, b, alternative="two-sided")
                    effect = 2.0 * u / (len(a) * len(b)) - 1.0
                else:
                    u, p, effect = np.nan, np.nan if not (len(a) and len(b)) else 1.0, 0.0
                rows.append(
                    {
                        by: group,
                        "design": design,
                        "baseline": baseline,
                        "metric": m,
                        "n": len(a),
                        "n_baseline": len(b),
                        "mean": mean_a,
                        "mean_baseline": mean_b,
                        "pct_change": pct,
                        "u": u,
                        "p": p,
                        "effect_size": effect,
                    }
                )
    return rows


def compare(hops: pd.DataFrame, baseline: str, *, by: str = "behaviour", metrics=METRICS, alpha=None) -> pd.DataFrame:
    """Every design's hop cycles beside `baseline`'s, per `by` group and
    metric: descriptive, hop cycles of one run are not independent.

    Each cycle starts from the state the previous one left and the
    controller adapts its thrust from the last hop, so a run's cycles are
    one sample, not many: a rank test over them gets a smaller p from a
    longer run, not from more evidence, and this table draws no verdict
    (no significance column). The Mann-Whitney U and its p are kept as a
    description of how far apart two runs' cycle distributions lie, in
    columns that say so. For inference compare replicate runs on shared
    seeds (:func:`mat_hopper.analysis.paired.compare_paired`, through
    :func:`mat_hopper.analysis.stats.compare_replicates`), or independent
    run means with :func:`compare_independent`.

    Args:
        hops: a hop table (:func:`hop_table` rows of several designs).
        baseline: the design name (column ``design``) described against.
        by: the column to group by (default ``"behaviour"``); designs are
            set beside the baseline within each group.
        metrics: the metric columns (a non-empty sequence of names).
        alpha: not accepted (None): a description has no significance
            level; a value is refused with a pointer to the tests.

    Returns:
        DataFrame, one row per group, design (other than the baseline) and
        metric: `by`, ``design``, ``baseline``, ``metric``, ``n_hops``,
        ``n_hops_baseline`` (hop cycles), ``mean``, ``mean_baseline``,
        ``pct_change`` (%, nan where the baseline mean is not finite or below
        1e-12 in magnitude), ``u_descriptive`` (Mann-Whitney U of the
        design's cycles), ``p_descriptive`` (its two-sided p over hop cycles,
        not a test), ``effect_size`` (rank-biserial, 2 U / (n n_baseline) - 1,
        in [-1, 1], positive: the design's cycles tend to be larger) and
        ``basis`` (:data:`DESCRIPTIVE`). Where all values tie (within
        round-off) u is nan, p 1 and the effect 0; where either side has no
        hops u and p are nan. Empty (no columns) when no design but the
        baseline is present.

    Raises:
        ValueError: hops not a DataFrame; metrics a string or empty; `alpha`
            given; hops without a ``design`` or `by` column; a baseline not
            among the designs; a metric not among the columns.
    """
    if alpha is not None:
        raise ValueError(
            f"alpha={alpha!r}: metrics.compare is descriptive (hop cycles of one run are not independent) and draws "
            "no verdict; test replicate runs instead: mat_hopper.analysis.paired.compare_paired on shared seeds, or "
            "metrics.compare_independent on independent run means"
        )
    _check_compare_args(hops, baseline, by, metrics, "hops")
    out = pd.DataFrame(_rank_rows(hops, baseline, by, metrics))
    if len(out):
        out = out.rename(
            columns={"n": "n_hops", "n_baseline": "n_hops_baseline", "u": "u_descriptive", "p": "p_descriptive"}
        )
        out["basis"] = DESCRIPTIVE
    return out


def compare_independent(
    samples: pd.DataFrame, baseline: str, *, by: str = "behaviour", metrics=METRICS, alpha: float = 0.05
) -> pd.DataFrame:
    """Every design against `baseline` on independent samples, per `by`
    group and metric: a two-sided Mann-Whitney U test with Holm's
    correction over all rows.

    The samples must be independent: one value per run, e.g. the means of
    replicate runs with their own seeds
    (:func:`mat_hopper.analysis.stats.replicate_means`); runs on shared
    seeds are better compared paired
    (:func:`mat_hopper.analysis.paired.compare_paired`). The hop cycles of
    one run are not independent: on them the p-values describe the run
    (:func:`compare`), they test nothing. The paper's comparison does
    this on hop cycles; :func:`mat_hopper.analysis.stats.compare_hops`
    reproduces it and labels it ``basis = "hops"``.

    Args:
        samples: one row per independent sample: columns ``design``, `by`
            and the metrics.
        baseline: the design name (column ``design``) compared against.
        by: the column to group by (default ``"behaviour"``).
        metrics: the metric columns compared (a non-empty sequence of names).
        alpha: significance level for the Holm-adjusted p (default 0.05).

    Returns:
        DataFrame, one row per group, design (other than the baseline) and
        metric: `by`, ``design``, ``baseline``, ``metric``, ``n``,
        ``n_baseline``, ``mean``, ``mean_baseline``, ``pct_change`` (%, nan
        where the baseline mean is not finite or below 1e-12 in magnitude),
        ``u``, ``p``, ``effect_size`` (rank-biserial), ``p_holm`` and
        ``significant`` (``p_holm < alpha``). Ties and empty sides as
        :func:`compare`. Empty (no columns) when no design but the baseline
        is present.

    Raises:
        ValueError: samples not a DataFrame; metrics a string or empty; alpha
            not a number in (0, 1); no ``design`` or `by` column; a baseline
            not among the designs; a metric not among the columns.
    """
    if isinstance(alpha, bool) or not isinstance(alpha, int | float) or not 0 < alpha < 1:
        raise ValueError(f"alpha must be a significance level in (0, 1), got {alpha!r}")
    _check_compare_args(samples, baseline, by, metrics, "samples")
    out = pd.DataFrame(_rank_rows(samples, baseline, by, metrics))
    if len(out):
        out["p_holm"] = holm(out["p"].to_numpy())
        out["significant"] = out["p_holm"] < alpha
    return out
