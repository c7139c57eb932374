"""Material or mass? Each design against its controls, and the attribution.

:func:`control_effects` compares every design with each of its controls
(:mod:`mat_hopper.core.control_legs`; runs of
:func:`mat_hopper.experiments.controls.control_tasks`) on shared seeds,
paired (:func:`mat_hopper.analysis.paired.paired_effect`): the design
against its rigid twin is what its moduli add at the same mass
distribution; against its mass-matched leg, what it adds beyond its leg
mass (the distribution of mass and of modulus along the leg).

:func:`beyond_mass_columns` adds to each material or gradient claim of the
claims table its comparisons (:func:`comparison_frame`), each with its
interval and the share of the claim's effect it leaves, and a verdict
``beyond mass``, per formula of the claim's quantity (power: paper
formula, hip, total; jerk: the body's zero-phase jerk and the causal one):

- the comparisons: the design against its mass-matched leg, a
  homogeneous leg of its own mass (left out where that leg is the design
  itself, same physics key): does the design beat it, as it beats the
  baseline? And for a rigid baseline (MD) the design against its rigid
  twin; for an elastic baseline (SS) the per-seed difference in
  differences ln[(d/d_rigid)/(b/b_rigid)], the springs' effect in the
  design beyond the springs' effect in the baseline;
- a comparison counts only where the claim's own effect (design vs
  baseline, paired, Holm over the claim's) holds in the claimed direction;
  it votes yes (Holm p < alpha in the claimed direction), equivalent
  (inside the ±10 % margin), the other way, or no evidence; the verdict
  names how many of each;
- ``yes``: every counted comparison yes; ``partly``: at least half;
  ``no``: fewer, with a no among them; ``untestable``: otherwise, or where
  the family cannot reach Holm p < alpha with an exact sign-flip test at
  this n (n = 3: p >= 0.25 each), or the claim's own effect holds in
  fewer than half of its comparisons (nothing much to attribute);
  ``not run``: the controls or the design's runs are missing.

The regressions (what leg mass and hip inertia explain, the sweeps at
equal mass) are in :mod:`mat_hopper.analysis.attribution`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.control_legs import CONTROLS, MASS_PROPERTY_COLUMNS, mass_matched
from ..core.materials import parse_design
from ..physics.metrics import holm
from ..util.keys import design_key
from .attribution import modulus_at_equal_mass
from .paired import DIFFERENCE, EQUIVALENCE_MARGIN, NO_DIFFERENCE, conclusion, paired_effect, reachable, share_left

YES, PARTLY, NO, UNTESTABLE = "yes", "partly", "no", "untestable"
NOT_RUN = "not run"
CONTROL_COLUMNS = ("vs_rigid_twin", "vs_mass_matched", "beyond_mass")
# Claims about materials or gradients: (designs, baseline, behaviours (None: all four), metrics
# ((label, column), ...: one beyond-mass verdict each), the claimed direction: -1 lower, +1 higher).
_DYN = ("forward", "ramp", "circle")
_TRACK = (("", "tracking_error_m"),)
_POWER = (("paper formula", "power_paper_w"), ("hip", "power_w"), ("total", "power_total_w"))
_JERK = (("body, zero-phase", "jerk_body_m_s3"), ("causal 50 Hz", "jerk_m_s3"))
MATERIAL_CLAIMS = {
    "tracking_all_beat_md": (("PVC", "Al", "Ti", "SS"), "MD", None, _TRACK, -1),
    "tracking_ss_55": (("SS",), "MD", None, _TRACK, -1),
    "power_higher_dynamic": (("PVC", "Al", "Ti", "SS"), "MD", _DYN, _POWER, +1),
    "power_ss_max": (("SS",), "MD", _DYN, _POWER, +1),
    "ramp_rho_inc_tracking": (("rho-inc",), "MD", ("ramp",), _TRACK, -1),
    "ramp_rho_inc_power": (("rho-inc",), "MD", ("ramp",), _POWER, +1),
    "ramp_ss_tracking": (("SS",), "MD", ("ramp",), _TRACK, -1),
    "ramp_ss_power": (("SS",), "MD", ("ramp",), _POWER, +1),
    "headline_tracking": (("rho-inc",), "SS", ("ramp",), _TRACK, -1),
    "headline_power": (("rho-inc",), "SS", ("ramp",), _POWER, -1),
    "jerk_gradient": (("rho-inc",), "SS", None, _JERK, -1),
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


def _is_rigid(name: str) -> bool:
    return all(e is None for e in parse_design(name).moduli_gpa)


def _is_own_mass_leg(name: str) -> bool:
    """Whether the design's mass-matched leg is the design itself (same physics key)."""
    d = parse_design(name)
    try:
        return design_key(mass_matched(d)) == design_key(d)
    except ValueError:
        return False


def _series(means, of, kind, beh, metric):
    g = means[(means["control_of"] == of) & (means["control"] == kind) & (means["behaviour"] == beh)]
    return g.set_index("replicate")[metric]


def comparison_frame(hops: pd.DataFrame, claim_id: str, metric: str | None = None, confidence=0.95) -> pd.DataFrame:
    """The per-seed comparisons behind one claim's beyond-mass verdict.

    Per design and behaviour: the claim's own effect ln(d/base); for a
    rigid baseline (MD), the design against its rigid twin ln(d/d_rigid)
    and against its mass-matched leg ln(d/d_mass) (left out where that leg
    is the design itself, same physics key); for an elastic baseline (SS),
    the difference in differences ln[(d/d_rigid)/(b/b_rigid)]: what the
    design's springs do beyond what the baseline's springs do, the mass
    distributions held by the rigid twins (the mass-matched leg still
    differs from SS in modulus, so it isolates nothing there), and for
    either baseline the design against its mass-matched leg (a
    homogeneous leg of its own mass: what its distribution of mass and
    modulus adds). Each with
    its paired effect (t interval, paired t p, exact sign-flip p and its
    smallest reachable p) and the share of the claim's effect it leaves.

    Args:
        hops: control runs' per-hop rows (design, behaviour, replicate, control_of, control, metric).
        claim_id: a key of :data:`MATERIAL_CLAIMS`.
        metric: the metric column (default the claim's first).
        confidence: of the intervals.

    Returns:
        DataFrame: design, behaviour, comparison (``rigid twin``,
        ``mass-matched``, ``springs vs both rigid twins``), the paired
        effect columns, share, share_low, share_high, and the claim's own
        effect (claim_pct, claim_p).

    Raises:
        ValueError: unknown claim.
    """
    if claim_id not in MATERIAL_CLAIMS:
        raise ValueError(f"claim_id must be one of {sorted(MATERIAL_CLAIMS)}, got {claim_id!r}")
    designs, baseline, behaviours, metrics, _ = MATERIAL_CLAIMS[claim_id]
    metric = metrics[0][1] if metric is None else metric
    if metric not in hops.columns:
        return pd.DataFrame()
    means = _run_means(hops, [metric])
    elastic = not _is_rigid(baseline)
    rows = []
    for beh in means["behaviour"].unique():
        if behaviours is not None and beh not in behaviours:
            continue
        b = _series(means, baseline, "none", beh, metric)
        b_rigid = _series(means, baseline, "rigid", beh, metric)
        for d in designs:
            own = _series(means, d, "none", beh, metric)
            x_claim = np.log(own / b)
            comps = []
            rigid = np.log(own / _series(means, d, "rigid", beh, metric))
            comps.append(
                ("springs vs both rigid twins", rigid - np.log(b / b_rigid)) if elastic else ("rigid twin", rigid)
            )
            if not _is_own_mass_leg(d):  # a homogeneous leg of the design's own mass: what the distribution adds
                comps.append(("mass-matched", np.log(own / _series(means, d, "mass", beh, metric))))
            main = paired_effect(np.exp(x_claim.dropna()), np.ones(int(x_claim.notna().sum())))
            for label, x in comps:
                x = x.dropna()
                if len(x) == 0:
                    continue
                pair = pd.concat([x, x_claim], axis=1, join="inner").dropna()
                rows.append(
                    {
                        "design": d,
                        "behaviour": beh,
                        "metric": metric,
                        "comparison": label,
                        **paired_effect(np.exp(x.to_numpy()), np.ones(len(x)), confidence=confidence),
                        **share_left(pair.iloc[:, 0], pair.iloc[:, 1], confidence),
                        "claim_pct": main["pct_change"],
                        "claim_p": main["p"],
                    }
                )
    return pd.DataFrame(rows)


def _fmt(rows: pd.DataFrame) -> str:
    if len(rows) == 0:
        return NOT_RUN

    def share(r):
        lo, hi = r.share_low, r.share_high
        ci = f" [{lo:.2f}, {hi:.2f}]" if np.isfinite(lo) else " [unbounded]"
        return f"share left {r.share:.2f}{ci}"

    return "; ".join(
        f"{r.behaviour} {r.design} {r.pct_change:+.1f} % [{r.ci_low:+.1f}, {r.ci_high:+.1f}] ({r.conclusion}, "
        f"p_holm {r.p_holm:.2g}, p_min {r.p_min:.2g}, {share(r)})"
        for r in rows.itertuples()
    )


EQUIVALENT, OPPOSITE, NO_EVIDENCE, NO_OWN = "equivalent", "the other way", "no evidence", "no own effect"


def _votes(e: pd.DataFrame, sign: int, alpha: float) -> list[str]:
    """One vote per comparison: yes (beyond mass, the claimed way), equivalent
    (inside the margin: the control reproduces the design), the other way
    (significant, against the claim), no evidence, or no own effect."""
    votes = []
    for r in e.itertuples():
        if not r.own_effect:
            votes.append(NO_OWN)
        elif r.conclusion == DIFFERENCE:
            votes.append(YES if np.sign(r.pct_change) == sign else OPPOSITE)
        elif r.conclusion == NO_DIFFERENCE:
            votes.append(EQUIVALENT)
        else:
            votes.append(NO_EVIDENCE)
    return votes


def _tally(votes: list[str]) -> str:
    kinds = (YES, EQUIVALENT, OPPOSITE, NO_EVIDENCE, NO_OWN)
    return ", ".join(f"{votes.count(k)} {k}" for k in kinds if votes.count(k))


def _verdict(e: pd.DataFrame, sign: int, alpha: float) -> str:
    """The fraction rule of the main verdicts over the comparisons where the
    claim's own effect holds, with every vote counted by kind; where that
    effect holds in fewer than half of the claim's comparisons, the claim
    itself mostly fails and there is too little effect to attribute:
    ``untestable``, however those few vote (one yes among sixteen is not
    a claim surviving its controls). Where n seeds cannot reach Holm's
    threshold, no comparison can be significant, but an interval inside
    the ±10 % margin still says the control reproduces the design: where
    every comparison is so and the claim's own effect is larger than the
    margin in each (so that the control reproducing the design says
    something), ``no``, otherwise ``untestable``."""
    family = len(e)
    n = int(e["n_pairs"].min())
    if not reachable(n, family, alpha):
        floor = min(1.0, family * float(e["p_min"].max()))
        claim_large = bool((np.abs(e["claim_pct"].to_numpy(float)) > 100 * EQUIVALENCE_MARGIN).all())
        if (e["conclusion"] == NO_DIFFERENCE).all() and claim_large:
            return (
                f"{NO} (every one of {family} comparisons within the ±10 % margin of a claimed effect larger than it: "
                f"the controls reproduce the design; n = {n} seeds cannot test a difference, Holm p >= {floor:.2g})"
            )
        return f"{UNTESTABLE} (n = {n} seeds can reach Holm p >= {floor:.2g} with an exact sign-flip test, family {family})"
    votes = _votes(e, sign, alpha)
    live = [v for v in votes if v != NO_OWN]
    if not live:
        return f"{UNTESTABLE} (the claim's own effect is not significant in any of its {family} comparisons)"
    if len(live) < family / 2:
        return (
            f"{UNTESTABLE} (the claim's own effect holds in only {len(live)} of its {family} comparisons, "
            f"too few to attribute: {_tally(votes)})"
        )
    k = live.count(YES)
    if k == len(live):
        verdict = YES
    elif k >= len(live) / 2:
        verdict = PARTLY
    elif EQUIVALENT in live or OPPOSITE in live:
        verdict = NO
    else:
        verdict = UNTESTABLE
    return f"{verdict} ({_tally(votes)})"


def _one_metric(claim_id, hops, metric, alpha) -> dict:
    designs, baseline, _, _, sign = MATERIAL_CLAIMS[claim_id]
    e = comparison_frame(hops, claim_id, metric)
    if len(e) == 0:
        return dict(zip(CONTROL_COLUMNS, (NOT_RUN, NOT_RUN, NOT_RUN)))
    e["p_holm"] = holm(e["p"].to_numpy(float))  # the claim's control comparisons: one family
    e["conclusion"] = [conclusion(p, lo, hi, alpha=alpha) for p, lo, hi in zip(e.p_holm, e.ci_low, e.ci_high)]
    claim_holm = holm(e.drop_duplicates(["design", "behaviour"])["claim_p"].to_numpy(float))
    own = dict(zip(zip(*e.drop_duplicates(["design", "behaviour"])[["design", "behaviour"]].T.values), claim_holm))
    e["own_effect"] = [own[(r.design, r.behaviour)] < alpha and np.sign(r.claim_pct) == sign for r in e.itertuples()]
    verdict = _verdict(e, sign, alpha)
    mass_rows = e[e["comparison"] == "mass-matched"]
    vs_mass = _fmt(mass_rows) if len(mass_rows) else "homogeneous: the design is its own mass-matched leg"
    if _is_rigid(baseline):
        vs_rigid = _fmt(e[e["comparison"] == "rigid twin"])
    else:
        vs_rigid = "springs beyond the baseline's springs: " + _fmt(e[e["comparison"] == "springs vs both rigid twins"])
    return {"vs_rigid_twin": vs_rigid, "vs_mass_matched": vs_mass, "beyond_mass": verdict}


def claim_controls(claim_id: str, hops: pd.DataFrame | None, effects=None, alpha=0.05, sweep_hops=None) -> dict:
    """The beyond-mass columns of one claim (module doc), one verdict per
    formula of the claim's quantity (power: paper formula, hip, total;
    jerk: body zero-phase, causal), joined as ``label: text | ...``.

    Args:
        claim_id: a claim of :data:`mat_hopper.analysis.claims.CLAIMS`.
        hops: the control runs' per-hop rows, unusable runs dropped (or None: not run).
        effects: unused; accepted and ignored.
        alpha: significance level.
        sweep_hops: experiment 2's per-hop rows, for the sweep claims
            (:func:`sweep_controls`).

    Returns:
        dict of :data:`CONTROL_COLUMNS` (text); empty strings for claims
        that are not about materials.
    """
    if claim_id in SWEEP_CLAIMS:
        return sweep_controls(claim_id, sweep_hops, alpha)
    if claim_id not in MATERIAL_CLAIMS:
        return dict.fromkeys(CONTROL_COLUMNS, "")
    if hops is None or len(hops) == 0:
        return dict(zip(CONTROL_COLUMNS, (NOT_RUN, NOT_RUN, NOT_RUN)))
    metrics = MATERIAL_CLAIMS[claim_id][3]
    parts = [(label, _one_metric(claim_id, hops, m, alpha)) for label, m in metrics]
    if len(parts) == 1:
        return parts[0][1]
    return {c: " | ".join(f"{label}: {p[c]}" for label, p in parts) for c in CONTROL_COLUMNS}


def sweep_controls(claim_id: str, sweep_hops: pd.DataFrame | None, alpha: float = 0.05) -> dict:
    """The beyond-mass columns of the one-property sweep claims.

    ``density_over_modulus`` compares density (the leg's mass) with
    modulus: a claim about mass itself, which no mass control can test.
    ``low_modulus_tracks_worse`` pools light polymer points against heavy
    metal points; at equal mass it is read from each base material's
    modulus sweep (density, and so mass, fixed; :func:`modulus_at_equal_mass`):
    ``yes`` where every sweep's slope of log tracking error on log modulus
    is negative with Holm p < alpha, ``partly`` where at least half are,
    ``no`` otherwise.

    Args:
        claim_id: one of :data:`SWEEP_CLAIMS`.
        sweep_hops: experiment 2's per-hop rows (or None: not run).
        alpha: significance level.

    Returns:
        dict of :data:`CONTROL_COLUMNS`.
    """
    if claim_id == "density_over_modulus":
        return dict(zip(CONTROL_COLUMNS, ("", "", "n/a: density is the leg's mass; the claim is about mass itself")))
    if sweep_hops is None or len(sweep_hops) == 0 or "sweep_base" not in sweep_hops.columns:
        return dict(zip(CONTROL_COLUMNS, ("", NOT_RUN, NOT_RUN)))
    t = modulus_at_equal_mass(sweep_hops)
    slopes = t[t["term"] == "log_modulus"].copy() if len(t) else t
    if len(slopes) == 0:
        return dict(zip(CONTROL_COLUMNS, ("", NOT_RUN, NOT_RUN)))
    slopes["p_holm"] = holm(slopes["p"].to_numpy(float))
    k = int(((slopes["p_holm"] < alpha) & (slopes["estimate"] < 0)).sum())
    m = len(slopes)
    verdict = YES if k == m else PARTLY if k >= m / 2 else NO
    text = "; ".join(
        f"{r.scope}: error ~ E^{r.estimate:+.3f} [{r.ci_low:+.3f}, {r.ci_high:+.3f}], p_holm {r.p_holm:.2g}"
        for r in slopes.itertuples()
    )
    why = f"{verdict} ({k}/{m} modulus sweeps at equal mass: tracking error falls with modulus, Holm p < {alpha:g})"
    return {"vs_rigid_twin": "", "vs_mass_matched": text, "beyond_mass": why}


def mass_property_text(claim_id: str, segment_mass: str = "leg") -> str:
    """The mass properties of a material claim's designs, as text.

    Args:
        claim_id: a claim of :data:`MATERIAL_CLAIMS` (others give "").
        segment_mass: the segment mass convention of the runs.

    Returns:
        ``"<design> <leg mass> kg, <centre of mass below the hip> m, <hip
        inertia> kg m^2; ..."`` for each design and the baseline, from
        MuJoCo's compiled models (:func:`mat_hopper.core.control_legs.mass_properties`).
    """
    from ..core.control_legs import mass_properties

    if claim_id not in MATERIAL_CLAIMS:
        return ""
    designs, baseline = MATERIAL_CLAIMS[claim_id][:2]
    parts = []
    for name in dict.fromkeys([*designs, baseline]):
        mp = mass_properties(parse_design(name), segment_mass)
        parts.append(f"{name} {mp.leg_mass_kg:.2f} kg, {mp.leg_com_m:.3f} m, {mp.hip_inertia_kg_m2:.3f} kg m^2")
    return "; ".join(parts)


def beyond_mass_columns(
    claims: pd.DataFrame, control_hops: pd.DataFrame | None, alpha: float = 0.05, bad=None, sweep_hops=None
):
    """The claims table with :data:`CONTROL_COLUMNS` and ``mass_properties``
    (:func:`mass_property_text`) added (module doc).

    Args:
        claims: :func:`mat_hopper.analysis.claims.claims_table`.
        control_hops: per-hop rows of the control runs (one profile and
            convention; rows of other conventions get "not run").
        alpha: significance level.
        bad: unusable control runs (:func:`mat_hopper.analysis.stats.unusable_runs`
            of the control runs' summaries), dropped as the main claims drop theirs.
        sweep_hops: experiment 2's per-hop rows (the sweep claims, :func:`sweep_controls`).

    Returns:
        DataFrame, a copy with the four columns.
    """
    from .stats import drop_unusable

    if control_hops is not None and bad is not None:
        control_hops = drop_unusable(control_hops, bad)
    out = claims.copy()
    cache: dict = {}
    cols = {c: [] for c in CONTROL_COLUMNS}
    for r in out.to_dict("records"):
        h = control_hops
        if h is not None and "convention" in h.columns:
            h = h[h["convention"] == r.get("convention", "paper")]
        s = sweep_hops
        if s is not None and "convention" in s.columns:
            s = s[s["convention"] == r.get("convention", "paper")]
        key = (r["claim_id"], r.get("convention"))
        if key not in cache:
            cache[key] = claim_controls(r["claim_id"], h, None, alpha, sweep_hops=s)
        for c in CONTROL_COLUMNS:
            cols[c].append(cache[key][c])
    for c in CONTROL_COLUMNS:
        out[c] = cols[c]
    texts = {cid: mass_property_text(cid) for cid in out["claim_id"].unique()}
    out["mass_properties"] = out["claim_id"].map(texts)
    return out


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
    f = comparison_frame(hops[hops["behaviour"] == behaviour], "headline_tracking", metric)
    did = "its springs beyond SS's springs: not run"
    if len(f):
        r = f.iloc[0]
        did = (
            f"its springs beyond SS's springs (both against their rigid twins) {r['pct_change']:+.1f} % "
            f"[{r['ci_low']:+.1f}, {r['ci_high']:+.1f}], "
            + (
                f"{r['share']:.2f} [{r['share_low']:.2f}, {r['share_high']:.2f}] of the effect"
                if np.isfinite(r["share_low"])
                else "a share of the effect that is unbounded (the effect itself is not clear of zero)"
            )
        )

    def part(kind, label):
        if kind not in eff.index:
            return f"against {label}: not run"
        r = eff.loc[kind]
        seeds = "" if r["n_pairs"] == main["n_pairs"] else f" (n = {int(r['n_pairs'])})"
        return f"against {label} {r['pct_change']:+.1f} % [{r['ci_low']:+.1f}, {r['ci_high']:+.1f}]{seeds}"

    return (
        f"On the {behaviour}, rho-inc (leg {legs['rho-inc']:.2f} kg) changes the {word} by "
        f"{main['pct_change']:+.1f} % [{main['ci_low']:+.1f}, {main['ci_high']:+.1f}] against SS (leg "
        f"{legs['SS']:.2f} kg, {legs['SS'] - legs['rho-inc']:.2f} kg heavier), n = {main['n_pairs']} paired seeds; "
        f"{part('mass', 'a homogeneous leg of its own mass')}, {part('inertia', 'a leg of its mass and hip inertia')}, "
        f"{part('rigid', 'its rigid twin')}; {did} (95 % t intervals)."
    )
