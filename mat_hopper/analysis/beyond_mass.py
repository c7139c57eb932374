"""Material or mass? Each design against its controls, and the attribution.

:func:`control_effects` compares every design with each of its controls
(:mod:`mat_hopper.controls`; runs of
:func:`mat_hopper.experiments.controls.control_tasks`) on shared seeds,
paired (:func:`mat_hopper.analysis.paired.paired_effect`): the design
against its rigid twin is what its moduli add at the same mass
distribution; against its mass-matched leg, what it adds beyond its leg
mass (the distribution of mass and of modulus along the leg).

:func:`beyond_mass_columns` adds to each material or gradient claim of the
claims table its comparisons' effects against the rigid twin and the
mass-matched leg, each with its interval, and a verdict ``beyond mass``:

- ``yes``: against at least one control, the design differs in the
  claimed direction (the paper's: lower tracking error, higher power
  against MD, ...), Holm p < alpha within the claim's control
  comparisons: something of the claimed effect is not its mass;
- ``no``: against every control the difference is inside the equivalence
  margin (``no difference``) or goes the other way: at equal mass (and
  mass distribution, for the twin) the claimed effect is gone;
- ``untestable``: not enough evidence either way, or the controls or the
  design's runs are missing.

:func:`attribution` regresses the log of each metric on the log leg mass,
the log hip inertia and the springs (rigid, ``paper``, ``axial``) over
the factorial of :func:`mat_hopper.experiments.controls.attribution_tasks`
(statsmodels OLS): R^2 of mass and inertia alone, R^2 with springs added,
and each partial effect with its interval.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..controls import CONTROLS, MASS_PROPERTY_COLUMNS
from ..metrics import holm
from .paired import DIFFERENCE, NO_DIFFERENCE, conclusion, paired_effect

YES, NO, UNTESTABLE = "yes", "no", "untestable"
CONTROL_COLUMNS = ("vs_rigid_twin", "vs_mass_matched", "beyond_mass")
# Claims about materials or gradients: (designs, baseline, behaviours (None: all four), metric,
# the claimed direction of the design's effect: -1 lower, +1 higher); the others get "".
_DYN = ("forward", "ramp", "circle")
MATERIAL_CLAIMS = {
    "tracking_all_beat_md": (("PVC", "Al", "Ti", "SS"), "MD", None, "tracking_error_m", -1),
    "tracking_ss_55": (("SS",), "MD", None, "tracking_error_m", -1),
    "power_higher_dynamic": (("PVC", "Al", "Ti", "SS"), "MD", _DYN, "power_w", +1),
    "power_ss_max": (("SS",), "MD", _DYN, "power_w", +1),
    "ramp_rho_inc_tracking": (("rho-inc",), "MD", ("ramp",), "tracking_error_m", -1),
    "ramp_rho_inc_power": (("rho-inc",), "MD", ("ramp",), "power_w", +1),
    "ramp_ss_tracking": (("SS",), "MD", ("ramp",), "tracking_error_m", -1),
    "ramp_ss_power": (("SS",), "MD", ("ramp",), "power_w", +1),
    "headline_tracking": (("rho-inc",), "SS", ("ramp",), "tracking_error_m", -1),
    "headline_power": (("rho-inc",), "SS", ("ramp",), "power_w", -1),
    "jerk_gradient": (("rho-inc",), "SS", None, "jerk_m_s3", -1),
}
SWEEP_CLAIMS = ("density_over_modulus", "low_modulus_tracks_worse")


def _run_means(hops: pd.DataFrame, metrics) -> pd.DataFrame:
    keys = [
        c for c in ("profile", "convention", "design", "behaviour", "replicate", "control_of", "control") if c in hops
    ]
    return hops.groupby(keys, sort=False, dropna=False)[list(metrics)].mean().reset_index()


def control_effects(hops: pd.DataFrame, metrics=("tracking_error_m", "power_w", "jerk_m_s3"), confidence=0.95):
    """Every design against each of its controls, paired on replicate seeds.

    Args:
        hops: per-hop rows with design, behaviour, replicate, control_of and
            control columns (:func:`mat_hopper.experiments.controls.run_controls`).
        metrics: metric columns.
        confidence: of the t intervals.

    Returns:
        DataFrame: design, control, control_design, behaviour, metric, the
        paired effect (n_pairs, pct_change, ci_low, ci_high, p, p_wilcoxon,
        p_min_wilcoxon, method) of the design against the control, and the
        mass properties of both (``leg_mass_kg`` ..., ``control_`` prefixed).

    Raises:
        ValueError: columns missing.
    """
    need = {"design", "behaviour", "replicate", "control_of", "control"}
    if not need <= set(hops.columns):
        raise ValueError(f"hops needs columns {sorted(need)}; has {sorted(hops.columns)}")
    means = _run_means(hops, [*metrics, *[c for c in MASS_PROPERTY_COLUMNS if c in hops]])
    rows = []
    for (of, beh), g in means.groupby(["control_of", "behaviour"], sort=False):
        own = g[g["control"] == "none"]
        if len(own) == 0:
            continue
        for kind in CONTROLS:
            ctl = g[g["control"] == kind]
            if len(ctl) == 0:
                continue
            for m in metrics:
                pair = own[["replicate", m]].merge(ctl[["replicate", m]], on="replicate", suffixes=("", "_c"))
                row = {
                    "design": of,
                    "control": kind,
                    "control_design": ctl["design"].iloc[0],
                    "behaviour": beh,
                    "metric": m,
                    **paired_effect(pair[m], pair[f"{m}_c"], confidence=confidence),
                }
                for c in MASS_PROPERTY_COLUMNS:
                    if c in g:
                        row[c], row[f"control_{c}"] = float(own[c].iloc[0]), float(ctl[c].iloc[0])
                rows.append(row)
    return pd.DataFrame(rows)


def _main_effects(hops, designs, baseline, behaviours, metric):
    """The claim's own effect (design vs baseline), paired, on the control runs' seeds."""
    means = _run_means(hops[hops["control"] == "none"], [metric])
    out = {}
    for beh, g in means.groupby("behaviour", sort=False):
        if behaviours is not None and beh not in behaviours:
            continue
        base = g[g["design"] == baseline]
        for d in designs:
            own = g[g["design"] == d]
            pair = own[["replicate", metric]].merge(base[["replicate", metric]], on="replicate", suffixes=("", "_b"))
            out[(d, beh)] = paired_effect(pair[metric], pair[f"{metric}_b"])
    return out


def _fmt(rows: pd.DataFrame) -> str:
    if len(rows) == 0:
        return "not run"
    return "; ".join(
        f"{r.behaviour} {r.design} {r.pct_change:+.1f} % [{r.ci_low:+.1f}, {r.ci_high:+.1f}] ({r.conclusion})"
        for r in rows.itertuples()
    )


def claim_controls(claim_id: str, hops: pd.DataFrame | None, effects: pd.DataFrame | None, alpha=0.05) -> dict:
    """The beyond-mass columns of one claim (module doc).

    Args:
        claim_id: a claim of :data:`mat_hopper.analysis.claims.CLAIMS`.
        hops: the control runs' per-hop rows (or None: not run).
        effects: :func:`control_effects` of them (computed when None).
        alpha: significance level.

    Returns:
        dict of :data:`CONTROL_COLUMNS` (text); empty strings for claims
        that are not about materials.
    """
    if claim_id in SWEEP_CLAIMS:
        return dict(zip(CONTROL_COLUMNS, ("", "", "untestable here: see the attribution at equal mass")))
    if claim_id not in MATERIAL_CLAIMS:
        return dict.fromkeys(CONTROL_COLUMNS, "")
    if hops is None or len(hops) == 0:
        return dict(zip(CONTROL_COLUMNS, ("not run", "not run", UNTESTABLE)))
    designs, baseline, behaviours, metric, sign = MATERIAL_CLAIMS[claim_id]
    effects = control_effects(hops, metrics=(metric,)) if effects is None else effects
    e = effects[(effects["metric"] == metric) & effects["design"].isin(designs)]
    if behaviours is not None:
        e = e[e["behaviour"].isin(behaviours)]
    inertia = e[e["control"] == "inertia"]
    e = e[e["control"].isin(("rigid", "mass"))].copy()
    if len(e) == 0:
        return dict(zip(CONTROL_COLUMNS, ("not run", "not run", UNTESTABLE)))
    # A mass-matched leg that is the design itself (a homogeneous design) tests nothing.
    same = e["control"].eq("mass") & np.isclose(e["leg_com_m"], e["control_leg_com_m"]) if "leg_com_m" in e else False
    e = e[~same] if isinstance(same, pd.Series) else e
    e["p_holm"] = holm(e["p"].to_numpy(float))  # the claim's control comparisons: one family
    e["conclusion"] = [conclusion(p, lo, hi, alpha=alpha) for p, lo, hi in zip(e.p_holm, e.ci_low, e.ci_high)]
    votes = []
    for r in e.itertuples():
        if r.conclusion == DIFFERENCE and np.sign(r.pct_change) == sign:
            votes.append(YES)
        elif r.conclusion == NO_DIFFERENCE or (r.conclusion == DIFFERENCE and np.sign(r.pct_change) == -sign):
            votes.append(NO)
        else:
            votes.append(UNTESTABLE)
    verdict = YES if YES in votes else NO if votes and all(v == NO for v in votes) else UNTESTABLE
    mass_rows = e[e["control"] == "mass"]
    text = f"{verdict} ({votes.count(YES)}/{len(votes)} control comparisons beyond mass)"
    by_mass = [v == YES and c == "mass" for v, c in zip(votes, e["control"])]
    if verdict == YES and all(c == "mass" for v, c in zip(votes, e["control"]) if v == YES) and any(by_mass):
        # beyond the leg's mass, through the mass-matched leg only: does the mass distribution explain it?
        d_rows = mass_rows[[b for b, c in zip(by_mass, e["control"]) if c == "mass"]]
        ii = inertia.merge(d_rows[["design", "behaviour"]], on=["design", "behaviour"])
        if len(ii):
            ok = [conclusion(p, lo, hi, alpha=alpha) == NO_DIFFERENCE for p, lo, hi in zip(ii.p, ii.ci_low, ii.ci_high)]
            if all(ok):
                text += "; an inertia-matched leg reproduces it: the distribution of mass, not the material"
    return {
        "vs_rigid_twin": _fmt(e[e["control"] == "rigid"]),
        "vs_mass_matched": _fmt(mass_rows) if len(mass_rows) else "homogeneous: the design is its own mass-matched leg",
        "beyond_mass": text,
    }


def beyond_mass_columns(claims: pd.DataFrame, control_hops: pd.DataFrame | None, alpha: float = 0.05):
    """The claims table with :data:`CONTROL_COLUMNS` added (module doc).

    Args:
        claims: :func:`mat_hopper.analysis.claims.claims_table`.
        control_hops: per-hop rows of the control runs (one profile and
            convention; rows of other conventions get "not run").
        alpha: significance level.

    Returns:
        DataFrame, a copy with the three columns.
    """
    out = claims.copy()
    cache: dict = {}
    cols = {c: [] for c in CONTROL_COLUMNS}
    for r in out.to_dict("records"):
        h = control_hops
        if h is not None and "convention" in h.columns:
            h = h[h["convention"] == r.get("convention", "paper")]
        key = (r["claim_id"], r.get("convention"))
        if key not in cache:
            cache[key] = claim_controls(r["claim_id"], h, None, alpha)
        for c in CONTROL_COLUMNS:
            cols[c].append(cache[key][c])
    for c in CONTROL_COLUMNS:
        out[c] = cols[c]
    return out


def attribution(hops: pd.DataFrame, metrics=("tracking_error_m", "power_w", "power_total_w", "jerk_m_s3")):
    """How much of each metric's variation across designs leg mass and hip
    inertia explain, and what the springs add (statsmodels OLS on logs).

    Per behaviour and metric, over the run means of the factorial
    (:func:`mat_hopper.experiments.controls.attribution_tasks`): model A,
    log y ~ log leg_mass + log hip_inertia; model B, A + springs (rigid as
    the reference level; ``paper``, ``axial``). HC3 standard errors.

    Args:
        hops: the factorial's per-hop rows (springs, leg_mass_kg,
            hip_inertia_kg_m2, replicate, design, behaviour, metric columns).
        metrics: metric columns (positive values; non-positive runs dropped).

    Returns:
        tidy DataFrame: behaviour, metric, term, estimate, ci_low, ci_high,
        p, r2_mass_inertia, r2_with_springs, n_runs. Estimates on log y:
        for log regressors an elasticity, for a springs level the log
        ratio against the rigid leg at equal mass and inertia.

    Raises:
        ValueError: columns missing.
    """
    import statsmodels.formula.api as smf

    need = {"springs", "leg_mass_kg", "hip_inertia_kg_m2", "replicate", "design", "behaviour"}
    if not need <= set(hops.columns):
        raise ValueError(f"hops needs columns {sorted(need)}")
    keys = ["design", "springs", "behaviour", "replicate"]
    means = hops.groupby(keys, sort=False)[[*metrics, "leg_mass_kg", "hip_inertia_kg_m2"]].mean().reset_index()
    rows = []
    for (beh, m), _ in [((b, m), None) for b in means["behaviour"].unique() for m in metrics]:
        d = means[(means["behaviour"] == beh) & (means[m] > 0)].copy()
        if len(d) < 6:
            continue
        d["y"] = np.log(d[m])
        d["log_mass"], d["log_inertia"] = np.log(d["leg_mass_kg"]), np.log(d["hip_inertia_kg_m2"])
        d["springs"] = pd.Categorical(d["springs"], categories=["rigid", "paper", "axial"])
        a = smf.ols("y ~ log_mass + log_inertia", d).fit(cov_type="HC3")
        b = smf.ols("y ~ log_mass + log_inertia + C(springs)", d).fit(cov_type="HC3")
        ci = b.conf_int()
        for term in b.params.index:
            rows.append(
                {
                    "behaviour": beh,
                    "metric": m,
                    "term": term.replace("C(springs)[T.", "springs=").rstrip("]"),
                    "estimate": float(b.params[term]),
                    "ci_low": float(ci.loc[term, 0]),
                    "ci_high": float(ci.loc[term, 1]),
                    "p": float(b.pvalues[term]),
                    "r2_mass_inertia": float(a.rsquared),
                    "r2_with_springs": float(b.rsquared),
                    "n_runs": int(b.nobs),
                }
            )
    return pd.DataFrame(rows)


def headline_sentence(hops: pd.DataFrame, metric: str = "tracking_error_m", behaviour: str = "ramp") -> str:
    """The abstract's claim (rho-inc against SS on the ramp) in one plain
    sentence, with the robots' masses and rho-inc against its controls.

    Args:
        hops: the control runs' per-hop rows (control_of, control,
            replicate, total mass from the run summaries is not needed: the
            leg mass columns are used, the base is the same 15 kg).
        metric: the claim's metric.
        behaviour: the claim's behaviour.

    Returns:
        str.
    """
    if hops is None or len(hops) == 0 or not {"SS", "rho-inc"} <= set(hops["design"]):
        return "The abstract's claim cannot be read: the control runs of rho-inc and SS are missing."
    main = _main_effects(hops, ["rho-inc"], "SS", [behaviour], metric).get(("rho-inc", behaviour))
    eff = control_effects(hops[hops["behaviour"] == behaviour], metrics=(metric,))
    eff = eff[eff["design"] == "rho-inc"].set_index("control")
    legs = hops.groupby("design")["leg_mass_kg"].first()
    word = metric.replace("_m", "").replace("_w", "").replace("_", " ")

    def part(kind, label):
        if kind not in eff.index:
            return f"against {label}: not run"
        r = eff.loc[kind]
        return f"against {label} {r['pct_change']:+.1f} % [{r['ci_low']:+.1f}, {r['ci_high']:+.1f}]"

    return (
        f"On the {behaviour}, rho-inc (leg {legs['rho-inc']:.2f} kg) changes the {word} by "
        f"{main['pct_change']:+.1f} % [{main['ci_low']:+.1f}, {main['ci_high']:+.1f}] against SS (leg "
        f"{legs['SS']:.2f} kg, {legs['SS'] - legs['rho-inc']:.2f} kg heavier), n = {main['n_pairs']} paired seeds; "
        f"{part('mass', 'a homogeneous leg of its own mass')}, {part('inertia', 'a leg of its mass and hip inertia')}, "
        f"{part('rigid', 'its rigid twin')} (95 % t intervals)."
    )


def modulus_at_equal_mass(hops: pd.DataFrame, metric: str = "tracking_error_m", low_gpa=None, high_gpa=None):
    """The one-property sweeps and the "moduli <= 9 GPa track worse" claim,
    re-read at equal mass.

    The claim pools the sweep points with E <= 9 GPa (all on the light PVC
    leg) against those with E >= 20 GPa (the metals): density differs with
    modulus. Here, over the sweep points (run means, replicates when there
    are), an OLS of log metric on log density and a low-modulus indicator
    (``low``: E <= low_gpa; points between the thresholds left out), and
    per base material's modulus sweep (density fixed, so mass fixed) the
    slope of log metric on log modulus. HC3 intervals (statsmodels).

    Args:
        hops: experiment 2's per-hop rows (sweep_base, sweep_property,
            density_g_cm3, modulus_gpa, metric; replicate optional).
        metric: the metric column.
        low_gpa, high_gpa: the claim's thresholds (default the paper's 9 and 20 GPa).

    Returns:
        tidy DataFrame: scope (``pooled, density-adjusted`` or the base
        material), term, estimate, ci_low, ci_high, p, n_points. For the
        indicator, exp(estimate) is the ratio of low- to high-modulus legs
        at equal density.

    Raises:
        ValueError: columns missing.
    """
    import statsmodels.formula.api as smf

    from .. import reference as ref

    low_gpa = ref.CLAIM_LOW_MODULUS_GPA if low_gpa is None else low_gpa
    high_gpa = ref.CLAIM_HIGH_MODULUS_GPA if high_gpa is None else high_gpa
    need = {"sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa", metric}
    if not need <= set(hops.columns):
        raise ValueError(f"hops needs columns {sorted(need)}")
    keys = ["sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa"]
    keys += ["replicate"] if "replicate" in hops.columns else []
    d = hops.groupby(keys, sort=False)[metric].mean().reset_index()
    d = d[(d[metric] > 0) & d["modulus_gpa"].notna()].copy()
    d["y"], d["log_density"] = np.log(d[metric]), np.log(d["density_g_cm3"])
    d["log_modulus"] = np.log(d["modulus_gpa"])
    rows = []

    def add(scope, fit, term, n):
        ci = fit.conf_int()
        rows.append(
            {
                "scope": scope,
                "term": term,
                "estimate": float(fit.params[term]),
                "ci_low": float(ci.loc[term, 0]),
                "ci_high": float(ci.loc[term, 1]),
                "p": float(fit.pvalues[term]),
                "n_points": int(n),
            }
        )

    split = d[(d["modulus_gpa"] <= low_gpa) | (d["modulus_gpa"] >= high_gpa)].copy()
    split["low"] = (split["modulus_gpa"] <= low_gpa).astype(float)
    if split["low"].nunique() == 2 and len(split) > 3:
        fit = smf.ols("y ~ log_density + low", split).fit(cov_type="HC3")
        add("pooled, density-adjusted", fit, "low", len(split))
        add("pooled, density-adjusted", fit, "log_density", len(split))
    for base, g in d[d["sweep_property"] == "modulus"].groupby("sweep_base", sort=False):
        if g["log_modulus"].nunique() >= 2 and len(g) > 2:
            add(str(base), smf.ols("y ~ log_modulus", g).fit(cov_type="HC3"), "log_modulus", len(g))
    return pd.DataFrame(rows)
