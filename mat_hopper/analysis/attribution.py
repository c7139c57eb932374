"""What leg mass and hip inertia explain, and what the moduli add.

:func:`attribution` regresses the log of each metric on the log leg mass,
the log hip inertia, the axial time step and the springs over the
factorial of :func:`mat_hopper.experiments.controls.attribution_tasks`
(statsmodels OLS, seed fixed effects, errors clustered by mass
distribution): R^2 of mass and inertia alone, R^2 with springs added, each
partial effect with its interval, and the VIF of log mass and log inertia.

:func:`modulus_at_equal_mass` re-reads the one-property sweeps and the
"moduli <= 9 GPa track worse" claim at equal mass: a density-adjusted
pooled indicator, and each base material's modulus sweep (density, so
mass, fixed).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["attribution", "modulus_at_equal_mass"]


def _attribution_frame(means, m):
    d = means[means[m] > 0].copy()
    d["y"] = np.log(d[m])
    d["log_mass"], d["log_inertia"] = np.log(d["leg_mass_kg"]), np.log(d["hip_inertia_kg_m2"])
    # indicators: the axial runs' time step (rigid and axial legs at it), and each kind of springs
    # against a rigid leg at the same step; one indicator pools every modulus (4-193 GPa)
    d["axial_step"] = d["springs"].isin(["axial", "rigid, axial step"]).astype(float)
    d["springs_paper"] = (d["springs"] == "paper").astype(float)
    d["springs_axial"] = (d["springs"] == "axial").astype(float)
    return d


def attribution(hops: pd.DataFrame, metrics=("tracking_error_m", "power_w", "power_total_w", "jerk_m_s3")):
    """How much of each metric's variation across designs leg mass and hip
    inertia explain, and what the springs add (statsmodels OLS on logs).

    Per behaviour and metric, over the run means of the factorial
    (:func:`mat_hopper.experiments.controls.attribution_tasks`), with seed
    fixed effects (the replicates are shared): model A, log y ~ log
    leg_mass + log hip_inertia; model B, A + the axial runs' time step
    (``axial_step``, rigid legs at it included) + ``springs_paper`` +
    ``springs_axial`` (each against a rigid leg at its own step; one
    indicator pools every modulus of the designs, 4-193 GPa: no springs x
    design interaction is fitted). Errors clustered by mass distribution
    (``mass_of``; few clusters: intervals are rough). Log mass and log
    inertia are nearly collinear across these designs: ``vif`` (1 / (1 -
    r^2) of the two) says how far their separate elasticities can be read.

    Args:
        hops: the factorial's per-hop rows (springs, mass_of, leg_mass_kg,
            hip_inertia_kg_m2, replicate, design, behaviour, metric columns).
        metrics: metric columns (positive values; non-positive runs dropped).

    Returns:
        tidy DataFrame: behaviour, metric, term, estimate, ci_low, ci_high,
        p, r2_mass_inertia, r2_with_springs, n_runs, n_clusters,
        corr_mass_inertia, vif. Estimates on log y: for log regressors an
        elasticity, for an indicator the log ratio at equal mass and inertia.

    Raises:
        ValueError: columns missing.
    """
    import statsmodels.formula.api as smf

    need = {"springs", "leg_mass_kg", "hip_inertia_kg_m2", "replicate", "design", "behaviour"}
    if not need <= set(hops.columns):
        raise ValueError(f"hops needs columns {sorted(need)}")
    hops = hops if "mass_of" in hops.columns else hops.assign(mass_of=hops["design"])
    keys = ["design", "mass_of", "springs", "behaviour", "replicate"]
    means = hops.groupby(keys, sort=False)[[*metrics, "leg_mass_kg", "hip_inertia_kg_m2"]].mean().reset_index()
    rows = []
    for beh in means["behaviour"].unique():
        for m in metrics:
            d = _attribution_frame(means[means["behaviour"] == beh], m)
            if len(d) < 6:
                continue
            groups = pd.factorize(d["mass_of"])[0]
            fe = " + C(replicate)" if d["replicate"].nunique() > 1 else ""
            terms = [t for t in ("axial_step", "springs_paper", "springs_axial") if d[t].nunique() > 1]
            # few clusters (the mass distributions, about 7): t with G - 1 degrees of freedom, not the normal
            cov = {"cov_type": "cluster", "cov_kwds": {"groups": groups}, "use_t": True}
            a = smf.ols(f"y ~ log_mass + log_inertia{fe}", d).fit(**cov)
            b = smf.ols(f"y ~ log_mass + log_inertia{fe} + " + " + ".join(terms or ["0"]), d).fit(**cov)
            r = float(np.corrcoef(d["log_mass"], d["log_inertia"])[0, 1])
            ci = b.conf_int()
            for term in ["Intercept", "log_mass", "log_inertia", *terms]:
                rows.append(
                    {
                        "behaviour": beh,
                        "metric": m,
                        "term": term,
                        "estimate": float(b.params[term]),
                        "ci_low": float(ci.loc[term, 0]),
                        "ci_high": float(ci.loc[term, 1]),
                        "p": float(b.pvalues[term]),
                        "r2_mass_inertia": float(a.rsquared),
                        "r2_with_springs": float(b.rsquared),
                        "n_runs": int(b.nobs),
                        "n_clusters": int(groups.max() + 1),
                        "corr_mass_inertia": r,
                        "vif": float(1.0 / (1.0 - r**2)) if abs(r) < 1 else np.inf,
                    }
                )
    return pd.DataFrame(rows)


def modulus_at_equal_mass(hops: pd.DataFrame, metric: str = "tracking_error_m", low_gpa=None, high_gpa=None):
    """The one-property sweeps and the "moduli <= 9 GPa track worse" claim,
    re-read at equal mass.

    The claim pools the sweep points with E <= 9 GPa (all on the light PVC
    leg) against those with E >= 20 GPa (the metals): density differs with
    modulus. Here, over the sweep points (run means, replicates when there
    are), an OLS of log metric on log density and a low-modulus indicator
    (``low``: E <= low_gpa; points between the thresholds left out), and
    per base material's modulus sweep (density fixed, so mass fixed) the
    slope of log metric on log modulus: these within-material slopes are
    the equal-mass test. The low and high groups share few densities (the
    book's sweeps: 2.0-2.5 g/cm^3), so the pooled indicator rests on an
    extrapolation along log density (``density_overlap_g_cm3``). Errors
    clustered by replicate seed where there are seeds, else HC3
    (statsmodels).

    Args:
        hops: experiment 2's per-hop rows (sweep_base, sweep_property,
            density_g_cm3, modulus_gpa, metric; replicate optional).
        metric: the metric column.
        low_gpa, high_gpa: the claim's thresholds (default the paper's 9 and 20 GPa).

    Returns:
        tidy DataFrame: scope (``pooled, density-adjusted`` or ``<base>
        (equal mass)``), term, estimate, ci_low, ci_high, p, n_points,
        density_overlap_g_cm3. For the
        indicator, exp(estimate) is the ratio of low- to high-modulus legs
        at equal density.

    Raises:
        ValueError: columns missing.
    """
    import statsmodels.formula.api as smf

    from ..core import reference as ref

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

    def add(scope, fit, term, n, overlap=""):
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
                "density_overlap_g_cm3": overlap,
            }
        )

    def fit(formula, g):
        # the sweep points share their replicate seeds: errors clustered by seed where there are seeds
        if "replicate" in g.columns and g["replicate"].nunique() >= 2:
            groups = pd.factorize(g["replicate"])[0]
            # few clusters (the seeds, 3 to 10): t with G - 1 degrees of freedom, not the normal
            return smf.ols(formula, g).fit(cov_type="cluster", cov_kwds={"groups": groups}, use_t=True)
        return smf.ols(formula, g).fit(cov_type="HC3")

    split = d[(d["modulus_gpa"] <= low_gpa) | (d["modulus_gpa"] >= high_gpa)].copy()
    split["low"] = (split["modulus_gpa"] <= low_gpa).astype(float)
    if split["low"].nunique() == 2 and len(split) > 3:
        lo_d, hi_d = (split.loc[split["low"] == v, "density_g_cm3"] for v in (1.0, 0.0))
        a, b = max(lo_d.min(), hi_d.min()), min(lo_d.max(), hi_d.max())
        # outside the densities both groups cover, the indicator is an extrapolation along log density
        overlap = f"{a:.3g}-{b:.3g} (extrapolation outside it)" if a <= b else "none (extrapolation)"
        f = fit("y ~ log_density + low", split)
        add("pooled, density-adjusted", f, "low", len(split), overlap)
        add("pooled, density-adjusted", f, "log_density", len(split), overlap)
    for base, g in d[d["sweep_property"] == "modulus"].groupby("sweep_base", sort=False):
        if g["log_modulus"].nunique() >= 2 and len(g) > 2:
            add(f"{base} (equal mass)", fit("y ~ log_modulus", g), "log_modulus", len(g))
    return pd.DataFrame(rows)
