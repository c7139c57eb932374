# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Material or mass?
#
# A leg's density sets its segments' masses; its modulus sets the springs
# between them. Chapters 6-8 compare legs that differ in both, and in the
# robot's total mass: the SS robot weighs 23.8 kg, the ρ-inc robot 20.4 kg.
# A claim about a *material* holds only against a control that differs
# from the design in that material alone. This chapter builds three
# controls for every design of the paper's claims
# ({mod}`mat_hopper.controls`):
#
# - the **rigid twin**: the same segment densities, no springs (same mass,
#   centre of mass and hip inertia): what the moduli add;
# - the **mass-matched** leg: a homogeneous leg of the same leg mass (mean
#   density, series-equivalent modulus): what the distribution of mass and
#   modulus along the leg adds beyond the leg's mass;
# - the **inertia-matched** leg: the same leg mass *and* hip inertia (a
#   linear density profile): what is left beyond the first two moments of
#   the mass.
#
# Every design and its controls run the same replicate seeds (start
# offset, tilt, one push inside the scored window, sensor noise), so the
# comparisons are paired: log ratios of run means per seed, a paired t
# test with its t interval, Holm's correction within each claim, and an
# equivalence margin of ±10 % that separates "no difference" from "not
# enough evidence" ({mod}`mat_hopper.analysis.paired`).

# %%
from mat_hopper import book

b = book.setup()
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from mat_hopper import mass_matched, mass_properties, parse_design, rigid_twin, simulate
from mat_hopper.analysis import beyond_mass, claims, paired
from mat_hopper.controls import inertia_matched
from mat_hopper.experiments import controls as control_runs
from mat_hopper.experiments import reproduce
from mat_hopper.jerk import jerk_sensitivity

# %% [markdown]
# ## The controls, built
#
# Each control is an ordinary {class}`~mat_hopper.materials.LegDesign`. Its
# leg mass, centre of mass (below the hip) and hip inertia come from the
# compiled MuJoCo model (tested against a hand calculation of capsule
# volumes and the parallel-axis theorem):

# %%
rows = []
for name in ("SS", "rho-inc", "rho-dec"):
    d = parse_design(name)
    for leg in (d, rigid_twin(d), mass_matched(d), inertia_matched(d)):
        rows.append(
            {
                "leg": leg.name,
                "densities_g_cm3": ", ".join(f"{x:.2f}" for x in leg.densities_g_cm3),
                "moduli_gpa": ", ".join("rigid" if e is None else f"{e:.0f}" for e in leg.moduli_gpa),
                **mass_properties(leg).as_dict(),
            }
        )
book.show(pd.DataFrame(rows), pattern="{:.4g}")

# %% [markdown]
# For a homogeneous leg (SS) the mass- and inertia-matched legs are the
# design itself: only its rigid twin tests its material. For a
# three-segment gradient, matching the mass and the hip inertia leaves
# little freedom: the inertia-matched leg is close to the gradient, with
# one modulus throughout.
#
# ## The designs beside their controls, on shared seeds

# %%
res = control_runs.run_controls(b.profile, cache_dir=b.cache_dir)
hops = res.tables
print(
    f"{res.n_tasks} runs ({res.n_unique} distinct), {b.profile.replicates} seeds per design and behaviour; "
    f"{res.n_cached} cached, {res.n_computed} computed"
)
effects = beyond_mass.control_effects(hops, metrics=("tracking_error_m", "power_w", "power_total_w", "jerk_body_m_s3"))
b.downloads({"controls_hops": hops, "control_effects": effects})
book.show(
    effects[effects["control"] != "inertia"][
        ["design", "control", "behaviour", "metric", "n_pairs", "pct_change", "ci_low", "ci_high", "p"]
    ].head(40),
    pattern="{:.3g}",
)

# %% [markdown]
# Each design against its rigid twin and its mass-matched leg, tracking
# error and total power (all actuators, thrust included): a point is the
# paired effect, the bar its 95 % t interval, the band the ±10 %
# equivalence margin.

# %%
sel = effects[effects["metric"].isin(["tracking_error_m", "power_total_w"]) & (effects["control"] != "inertia")]
sel = sel[~((sel["control"] == "mass") & np.isclose(sel["leg_com_m"], sel["control_leg_com_m"]))]
fig, axes = plt.subplots(1, 2, figsize=(11, 0.28 * len(sel) / 2 + 1.5), sharey=True)
labels = sorted(set(sel["design"] + " vs " + sel["control"] + ", " + sel["behaviour"]))
for ax, metric in zip(axes, ["tracking_error_m", "power_total_w"]):
    s = sel[sel["metric"] == metric]
    y = [labels.index(lbl) for lbl in s["design"] + " vs " + s["control"] + ", " + s["behaviour"]]
    ax.axvspan(-100 * paired.EQUIVALENCE_MARGIN, 100 * paired.EQUIVALENCE_MARGIN, color="0.9")
    ax.errorbar(s["pct_change"], y, xerr=[s["pct_change"] - s["ci_low"], s["ci_high"] - s["pct_change"]], fmt="o")
    ax.axvline(0, color="k", lw=0.8)
    ax.set_xlabel(f"{metric}: design vs control (%)")
axes[0].set_yticks(range(len(labels)), labels)
fig.tight_layout()

# %% [markdown]
# ## The claims, re-read with the controls
#
# The claims table of the reproduction (chapter 10) gains three columns:
# each material or gradient claim's effect against the rigid twins and the
# mass-matched legs, and a verdict *beyond mass* (yes: some of the effect
# is not the leg's mass; no: at equal mass it is gone; untestable: not
# enough evidence either way). Claims that quote power are judged under
# the paper's formula, the hips' power and the total power side by side.

# %%
tables = reproduce.run_experiments(b.profile, "1,3", out_dir=b.out_dir, cache_dir=b.cache_dir)
exp_hops = pd.concat([tables["exp1_hops"], tables["exp3_hops"]], ignore_index=True)
exp_runs = pd.concat([tables["exp1_runs"], tables["exp3_runs"]], ignore_index=True)
table = claims.claims_table(exp_hops, exp_runs, None, conventions=("paper",), controls=hops)
material = table[table["claim_id"].isin(beyond_mass.MATERIAL_CLAIMS)]
b.downloads({"claims_beyond_mass": table})
book.show(material[["claim", "ours", "verdict", "beyond_mass", "power_verdicts"]])

# %% [markdown]
# The abstract's claim in one sentence:

# %%
print(beyond_mass.headline_sentence(hops, "tracking_error_m"))
print(beyond_mass.headline_sentence(hops, "power_total_w"))

# %% [markdown]
# How the abstract's comparison moves with the size of the replicates'
# push (0: none; 1: the book's 5 N for 0.1 s; 2: twice it), paired on the
# same seeds:

# %%
pushes = control_runs.run_push_scale(b.profile, cache_dir=b.cache_dir)
means = pushes.tables.groupby(["push_scale", "design", "replicate"])[["tracking_error_m", "power_total_w"]].mean()
moves = pd.DataFrame(
    [
        {
            "push_scale": s,
            "metric": m,
            **paired.paired_effect(g.xs("rho-inc", level="design")[m], g.xs("SS", level="design")[m]),
        }
        for s, g in means.groupby(level="push_scale")
        for m in ("tracking_error_m", "power_total_w")
    ]
)
fig, ax = plt.subplots(figsize=(6, 3))
for m, g in moves.groupby("metric"):
    ax.errorbar(
        g["push_scale"],
        g["pct_change"],
        yerr=[g["pct_change"] - g["ci_low"], g["ci_high"] - g["pct_change"]],
        marker="o",
        capsize=3,
        label=m,
    )
ax.axhline(0, color="k", lw=0.8)
ax.set_xlabel("push scale (x 5 N for 0.1 s)")
ax.set_ylabel("rho-inc vs SS, ramp (%)")
ax.legend(fontsize=8)
plt.tight_layout()

# %% [markdown]
# ## What leg mass and hip inertia explain, and what the moduli add
#
# A factorial on forward hopping: the mass distributions of the paper's
# designs, each rigid, with the authors' springs (`paper`) and with
# physical axial springs (`axial`), on the same seeds. Per metric, an
# ordinary least-squares fit of the log metric on the log leg mass and log
# hip inertia (R² of mass and inertia alone), then with the springs added
# (statsmodels, HC3 intervals). A springs coefficient is the log ratio
# against the rigid leg at equal mass and inertia.

# %%
fact = control_runs.run_attribution(b.profile, behaviours=("forward",), cache_dir=b.cache_dir)
att = beyond_mass.attribution(fact.tables, metrics=("tracking_error_m", "power_w", "power_total_w", "jerk_body_m_s3"))
b.downloads({"attribution": att})
book.show(att, pattern="{:.3g}")

# %%
r2 = att.groupby("metric")[["r2_mass_inertia", "r2_with_springs"]].first()
ax = r2.plot.barh(figsize=(7, 3))
ax.set_xlabel("R² across the designs (forward hopping)")
ax.set_xlim(0, 1)
plt.tight_layout()

# %% [markdown]
# ### The one-property sweeps at equal mass
#
# Chapter 7's claim that moduli of at most 9 GPa track worse than moduli of
# at least 20 GPa pools the PVC leg's sweep points (light) against the
# metals' (heavy). Below: the low-modulus indicator with the log density
# as a covariate (a ratio exp(estimate) of low- to high-modulus legs at
# equal density), and per base material the slope of log tracking error
# on log modulus along its modulus sweep, where the density, and so the
# mass, is fixed.

# %%
sweeps = reproduce.run_experiments(b.profile, "2", out_dir=b.out_dir, cache_dir=b.cache_dir)["exp2_hops"]
equal_mass = beyond_mass.modulus_at_equal_mass(sweeps)
book.show(equal_mass, pattern="{:.3g}")

# %% [markdown]
# ## Jerk that measures the body
#
# The package's jerk (chapter 6) low-passes the base acceleration with a
# causal 2nd-order 50 Hz filter, which passes some of the leg's kHz
# ringing. The body jerk ({mod}`mat_hopper.jerk`) uses a zero-phase
# 4th-order Butterworth (Winter 2009) after an anti-aliasing mean. How the
# jerk claim (ρ-inc lower than SS) moves with the cut-off and the order:

# %%
settings = b.profile.sim_settings()
sens = pd.concat(
    [
        jerk_sensitivity(simulate(d, "forward", settings=settings))
        for d in (parse_design("SS"), parse_design("rho-inc"), rigid_twin(parse_design("rho-inc")))
    ],
    ignore_index=True,
)
fig, ax = plt.subplots(figsize=(7, 3.5))
for (design, order), g in sens.groupby(["design", "order"]):
    ax.plot(
        g["cutoff_hz"],
        g["jerk_body_m_s3"],
        marker="o",
        ls="-" if order == 4 else "--",
        label=f"{design}, order {order}",
    )
ax.set_xlabel("cut-off (Hz)")
ax.set_ylabel("mean body jerk (m/s³)")
ax.legend(fontsize=8)
plt.tight_layout()

# %%
book.show(
    sens.pivot_table(index=["order", "cutoff_hz"], columns="design", values="jerk_body_m_s3"),
    index=True,
    pattern="{:.0f}",
)

# %% [markdown]
# ## What survives
#
# The verdicts below are computed from the tables above, on this build's
# profile (the quick profile's 3 seeds give wide intervals; the paper
# profile runs 6).

# %%
for r in material.itertuples():
    print(f"- {r.claim}: {r.verdict}; beyond mass: {r.beyond_mass}")
low = equal_mass.set_index(["scope", "term"]).loc[("pooled, density-adjusted", "low")]
print(
    f"- Moduli <= 9 GPa at equal density: x{np.exp(low['estimate']):.2f} tracking error "
    f"[{np.exp(low['ci_low']):.2f}, {np.exp(low['ci_high']):.2f}], p = {low['p']:.2g}"
)
