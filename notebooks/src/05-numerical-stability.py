# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Numerical stability
#
# Chapter 3 showed that a stiff spring between light masses forces a small
# time step. The paper maps this over the whole design space: for a grid
# of mono-material legs, 20 densities from 1.39 to 8 g/cm³ by 20 moduli
# from 4 to 340 GPa (log-spaced), it searches the largest time step at
# which the hopper can hop in place without numerical blow-up, and draws
# the answer as a heat map. Its reading: the stable step is log-linear in
# density and modulus, light or stiff materials need smaller steps, and
# PVC runs at a step ten times larger than aluminium and steel need (the
# paper's numbers are in the table at the end of this chapter; MuJoCo's
# default step is 2e-3 s).
#
# ## Protocol
#
# A try is 2 s of static hopping at one time step (the `quick` profile:
# 1 s). It **fails** when any acceleration becomes NaN, infinite or larger
# than 1e6, or when the body ends below 0.1 m. For each design of the grid
# we run two searches:
#
# - the paper's: 20 steps log-spaced from 1e-3 s down to 1e-5 s, the first
#   that survives;
# - ours: from the estimate below, in steps of a factor 1.5 up while a
#   try survives or down while it fails, until the outcome changes; then
#   bisection (in log scale) between the last failure and the first
#   survivor, down to a bracket of a factor 1.25 (the `quick` profile:
#   1.5). It finds steps above 1e-3 s too, and the bracket says how sharp
#   the answer is.
#
# Beside the measurement, the two estimates of chapter 3: the leg's axial
# mass-spring chain has a highest natural frequency ω_max, and the
# explicit spring update is stable while Δt < 2 / ω_max (`spring`); the
# controller's explicit attitude damping, read one step late (the
# authors' {term}`sensor timing`), is stable while Δt < I / c
# {cite:p}`levin1976note`, the same for every leg (`controller`); the
# smaller of the two is the `combined` estimate.

# %%
from mat_hopper import book
from mat_hopper.analysis import tables as tab
from mat_hopper.experiments import reproduce
from mat_hopper.physics.stability import agreement
from mat_hopper.viz import maps

b = book.setup()
tables = reproduce.run_experiments(b.profile, "stability", out_dir=b.out_dir, cache_dir=b.cache_dir)
stab = tables["stability"]

# %%
from myst_nb import glue

glue("fig-stability", maps.stability_figure(stab, convention=b.profile.convention), display=False)
b.downloads({"stability": stab, "stability_agreement": tables["stability_agreement"]})

# %% [markdown]
# ```{glue:figure} fig-stability
# :name: fig-stability
# :alt: Left, a heat map of the measured largest stable time step over density (g/cm³) and modulus (GPa) on log axes, with dashed contours of the analytic estimate and the paper's materials marked; right, a scatter of measured against estimated stable time step on log axes with the line of equality.
#
# The {term}`stable time step` over the design space. Left: measured
# (colour) with the estimate's contours (dashed) and the paper's materials
# marked. Right: measured against estimated, one point per design.
# ```
#
# How close the estimate is, over the whole map
# ({numref}`fig-stability`):

# %%
book.show(agreement(stab), precision=3)

# %% [markdown]
# The spring estimate follows the trend: stiffer springs and lighter
# segments mean a higher ω_max and a smaller step. Soft, heavy legs, whose
# spring limit lies above the controller's, meet the controller's limit
# instead, and there the measured map levels off. The median ratio says
# how far off an estimate is; a ratio below 1 means the measured step is
# smaller than the estimate, as expected from models that leave out
# contact, and from tries that fail because the body falls rather than
# because the integration blows up. The `fraction_scan_consistent` row
# checks the paper's 20-step scan against our bisection: where both agree,
# the stable region is a simple threshold in the time step, as both
# searches assume.
#
# ## Beside the paper

# %%
book.show(tab.claims_for(tables, "stability"))

# %% [markdown]
# The verdicts follow the rules of `mat_hopper/analysis/claims.py` (chapter 10
# lists them). A time step is only "about" right within 0.3 decade (a
# factor of 2, the rule's `TIMESTEP_TOL_DECADES`); the
# trend holds when a plane fitted to log Δt over log ρ and log E has a
# positive density slope, a negative modulus slope and R² ≥ 0.8.
#
# Why log-linear? For one spring between two equal masses m, ω = √(2k/m),
# so Δt ∝ √(m/k) ∝ √ρ / √E under the paper's convention, where k ∝ E and
# m ∝ ρ: a plane of slopes +½ and −½ in log-log axes. The fitted slopes
# above are to be compared with these; the foot spring and the foot's mass,
# the same in every design, pull them toward zero.
