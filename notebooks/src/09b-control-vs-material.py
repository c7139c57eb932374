# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Does control erase material?
#
# Every comparison so far ran every leg under one controller, with the
# authors' gains, tuned for none of the legs in particular. A steel leg
# and a PVC leg may differ because the material differs, or because the
# gains happen to suit one of them better. The paper leaves this
# co-design question open; this chapter asks it directly: give each of
# the five mono-materials (MD, PVC, Al, Ti, SS) its own controller gains,
# then compare the materials again.
#
# **Tuning** (`mat_hopper.optimize.codesign`). For each material, a small
# seeded Optuna study (TPE, 24 trials, the authors' gains first) searches
# the controller's foot-placement gain (0.01 to 0.25 s; authors 0.05) and
# its stance attitude gains, kp (0.5 to 40; authors 4) and kd (0.1 to 4;
# authors 1), on log scales, hopping forward under this build's profile.
# The score is the sum of tracking error and hip power, each relative to
# the same leg's at the authors' gains: 2 at the authors' gains, lower is
# better on the two together. A trial counts only if the hopper stays up,
# does not diverge and hops within 5 cm of its 1 m target (or no farther
# from it than at the authors' gains).
#
# **Comparing.** Each material, at the authors' gains and at its own best
# gains, runs on perturbed replicates (chapter 6's method); each is
# compared with MD on replicate means: the percent change with its 95 %
# bootstrap interval. A material difference **survives** tuning when its
# interval is clear of zero at the authors' gains and stays clear of zero,
# with the same sign, at the materials' own gains.

# %%
from mat_hopper import book
from mat_hopper.optimize import codesign

b = book.setup()
result = codesign.codesign(profile=b.profile)

# %% [markdown]
# The gains each material chose, its score (2 = the authors' gains), and
# its tracking error and hip power at both (one unperturbed run each):

# %%
book.show(result["gains"], precision=3)

# %% [markdown]
# Where each material moved ({numref}`fig-codesign`): its mean over
# replicates of tracking error and hip power at the authors' gains (open)
# and at its own (filled).

# %%
from myst_nb import glue

from mat_hopper.viz import chapters

fig = chapters.codesign_figure(
    result["hops"],
    result["gains"]["design"],
    codesign.DEFAULT,
    codesign.TUNED,
    title=f"forward, {b.profile.name} profile: authors' gains (open) to own gains (filled)",
)
glue("fig-codesign", fig, display=False)

# %% [markdown]
# ```{glue:figure} fig-codesign
# :name: fig-codesign
# :alt: Scatter plot of hip power in W against tracking error in mm for the five mono-material legs, each drawn twice: an open circle at the authors' controller gains and a filled circle at its own tuned gains, joined by an arrow.
#
# Each mono-material's mean over perturbed replicates of tracking error
# and hip power, forward hopping, at the authors' gains (open) and at its
# own tuned foot-placement and stance gains (filled).
# ```

# %% [markdown]
# Every material against MD, on replicates, at the authors' gains and at
# each material's own (percent change and 95 % interval; Holm-adjusted
# Mann-Whitney p over one family per gain setting):

# %%
cols = ["experiment", "design", "metric", "n", "pct_change", "ci_low", "ci_high", "p_holm"]
comparison = result["comparison"]
book.show(comparison[[c for c in cols if c in comparison.columns]], precision=3)

# %% [markdown]
# Which differences survive tuning:

# %%
book.show(result["survival"], precision=1)

# %% [markdown]
# ## The answer

# %%
print(result["answer"])
