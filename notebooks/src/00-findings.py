# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Findings
#
# **What leg should I build?** The paper's answer is a functional gradient:
# hopping up a ramp, a leg whose density increases from hip to foot tracks
# its path better, for less hip power, than a leg of stainless steel. This
# page gives this book's answer first, and the chapters after it give the
# evidence.
#
# The answer rests on the paper profile (60 s runs scored after 20 s, at
# the authors' 1e-4 s time step, 10 paired replicate seeds per design, for
# most records; each record's README entry gives its own basis: the
# crossed legs run at finer steps, the robustness variants one run each).
# Those runs take hours on a small machine, so their results are kept as
# records in `book/records/`, each with the command, commit and machine
# that made it (the folder's README). This page reads those records and
# runs no simulation: every number below is read from them when the book
# is built, none is typed into the text.

# %%
from mat_hopper import book
from mat_hopper.viz import findings

b = book.setup()
records = findings.read_records(b.root / "book" / "records")
print("records read from book/records/: " + ", ".join(findings.RECORD_FILES.values()))
import pandas as pd

made = pd.read_csv(b.root / "book" / "records" / "provenance.csv")  # written by `mat-hopper records`
print(f"provenance.csv: {len(made)} record files rebuilt from one paper-book build at commit "
      f"{', '.join(made['commit'].unique())} (how each was made, its SHA-256); the bending records are "
      "benchmarks', each with its commit in the folder's README")  # fmt: skip

# %% [markdown]
# ## The paper's claims, reproduced or not
#
# One row per quantitative claim of the paper, as recorded: the paper's
# number, ours, and the verdict by the rule stated in
# {doc}`10-reproduction-report` (holds, partly, does not hold), where the
# claims table of this build stands beside these records. The next two columns ask whether the effect is the material's:
# against the **rigid twin** (the same segment masses without springs: what
# the moduli add) and against the **mass-matched leg** (a homogeneous leg
# of the same mass: what the gradient adds beyond the leg's mass), as
# chapter 9c builds them. The last two are checks of the numerics: the
# claim's runs rerun at a finer time step ("not checked" where the record
# has no such rerun; chapter 11's robustness study reruns the main claims
# at 2e-5 s) and whether the claim's verdict is the same on the first and
# the second half of the scoring window ("stationary") or differs
# ("window-dependent").

# %%
book.show(findings.findings_table(records))

# %% [markdown]
# ## Every paired effect, against the ±10 % margin
#
# {numref}`fig-findings-forest` draws every numeric paired effect of the
# records: a design against its comparator on the same replicate seeds,
# its percent change (dot) and 95 % paired t interval (line). Inside the
# shaded band (±10 %) a difference counts as none. The groups: the crossed
# legs of chapter 9c (the modulus or the densities changed alone), the
# stress study of chapter 8b (each gradient against its mass-matched leg
# and titanium), and the optimizer's validated designs of chapter 9
# against their controls (their 122 comparisons with the paper's designs
# are in chapter 9).

# %%
from myst_nb import glue

controls = [g for g in findings.paired_effects(records)["group"].unique() if g != "optimizer: vs paper designs"]
glue("fig-findings-forest", findings.forest_plot(records, kinds=controls), display=False)

# %% [markdown]
# ```{glue:figure} fig-findings-forest
# :name: fig-findings-forest
# :alt: A forest plot: one horizontal interval per paired comparison of the recorded paper-profile results, grouped by comparison kind, over a shaded band from minus to plus ten percent; the modulus-only contrasts sit inside the band, the density contrasts far outside it.
#
# Every recorded paired effect of a design against a control (percent change,
# 95 % paired t interval), grouped by comparison kind, on an axis linear
# inside ±10 % (shaded: the equivalence margin) and logarithmic beyond.
# ```

# %% [markdown]
# ## Where the evidence is
#
# - {doc}`09c-material-or-mass`: the controls (rigid twin, mass-matched and
#   inertia-matched legs) and the crossed legs, the modulus and the
#   densities changed one at a time;
# - {doc}`09-optimizing-gradients`: the design study on the ramp, its front
#   validated on fresh seeds against the paper's designs and the uniform
#   legs of each design's mass;
# - {doc}`10-reproduction-report`: every claim with its rule, where and why
#   our numbers differ, the authors' code defects;
# - {doc}`08b-gradients-stress`: the stress study behind the stress
#   effects above, and the same pairs where the leg bends;
# - {doc}`07-one-property`: the modulus sweeps at equal mass, also where
#   the leg bends;
# - the records themselves, in `book/records/` (CSV files, with how each
#   was made in the folder's README).
#
# ## The records' answer
#
# Generated from the same records (`findings.design_answer`), with its
# limits:

# %%
print(findings.design_answer(records))

# %% [markdown]
# ## Answer
#
# The answer is the generated text above, with its limits; this cell only
# says how to read it. How many of the paper's material effects remain
# against a leg of the same mass is counted there, per kind of control,
# and "not enough evidence" is not "no effect". A uniform modulus changed
# between 70 and 193 GPa at fixed densities (the crossed legs, on the
# ramp) is the only modulus contrast tested at equal mass against the
# margin; at the soft end of the one-property sweeps the equal-mass slopes
# of tracking error on modulus are in the claims table's "beyond the
# mass-matched leg" column. Whether a graded leg beats the uniform leg of
# its mass depends on the margin and the domination rule (chapter 9), and
# the ramp's answers depend on the contact model and the time step: one
# lumped model's answers, on one contact.
