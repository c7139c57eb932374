# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # One property at a time
#
# A real material comes with both properties tied together: steel is dense
# *and* stiff. To tell which one matters, the paper's second experiment
# varies one at a time around each base material, keeping the other at
# the material's own value, and hops forward. The sweep values are the
# authors' (`reference.SWEEPS`):

# %%
from mat_hopper import book
from mat_hopper import reference as ref
from mat_hopper.analysis import tables as tab
from mat_hopper.experiments import reproduce
from mat_hopper.viz import figures as plots

b = book.setup()
for base, sweep in ref.SWEEPS.items():
    rho, e = ref.MONO_MATERIALS[base]
    print(
        f"{base:>3}: density {sweep['density']} g/cm³ at {e:g} GPa\n     modulus {sweep['modulus']} GPa at {rho:g} g/cm³"
    )

# %% [markdown]
# Each sweep includes the base material itself (added where the paper's
# list leaves it out), so that every point can be read against it.
# Chapter 2 showed which of the density points a porous version of the
# material could reach.

# %%
tables = reproduce.run_experiments(b.profile, "2", out_dir=b.out_dir, cache_dir=b.cache_dir)
mono = reproduce.run_experiments(
    b.profile, "1", out_dir=b.out_dir, cache_dir=b.cache_dir, quiet=True
)  # MD's forward hopping: the reference line
tables.update(mono)
sweeps = tables["exp2_hops"]

# %%
from IPython.display import Markdown

Markdown(tab.outcome_summary(tables["exp2_runs"]))

# %% [markdown]
# A sweep point that diverges in its first steps is a light or stiff leg
# whose stable time step (chapter 5) lies below the paper's 1e-4 s: it has
# no hop cycles and drops out of the figure below.

# %% [markdown]
# ## Tracking error against density and against modulus
#
# Mean tracking error per sweep point (bars: interquartile range over hop
# cycles) against density (left) and modulus (right), one line per base
# material; the dashed line and band are the rigid MD leg's forward
# hopping. Filled markers differ from MD significantly (Mann-Whitney U on
# hop cycles, Holm over all points), open ones do not.

# %%
plots.figure4_sweeps(sweeps, tables["exp1_hops"])

# %% [markdown]
# How far each sweep moves the tracking error: the smallest and largest
# mean over its points (mm) and where they occur.

# %%
spans = tab.sweep_spans(sweeps)
spans[["min", "max", "span"]] *= 1e3
book.show(spans.rename(columns={"min": "min (mm)", "max": "max (mm)", "span": "span (mm)"}), precision=3)

# %% [markdown]
# ## Beside the paper
#
# The paper reads two things off its version of this figure: density moves
# tracking error more than modulus does, and the soft moduli (at most
# 9 GPa, polymers and natural materials) track worse than the stiff ones
# (at least 20 GPa, metals and ceramics).

# %%
book.show(tab.claims_for(tables, "one_property"))

# %% [markdown]
# The first claim compares, per base material, the span of the density
# sweep with the span of the modulus sweep above; the second compares
# every low-modulus point with every high-modulus one. One reading of why
# density should matter more: density acts through mass, and a heavier leg
# is a larger share of the robot's mass below the hip, which changes how
# the body swings over the foot in every hop. Modulus acts only through
# the material springs, and under the paper's conversion these are much
# stiffer than the foot spring (8000 N/m) that sits in series with them,
# so the leg's compliance is mostly the foot spring's, except at the soft
# end of the sweeps:

# %%
from mat_hopper.materials import spring_stiffness

softest = min(min(s["modulus"]) for s in ref.SWEEPS.values())
k = spring_stiffness(softest)
print(
    f"softest swept modulus {softest:g} GPa: material spring {k:.3g} N/m, "
    f"{k / ref.FOOT_SPRING_STIFFNESS:.0f} times the foot spring ({ref.FOOT_SPRING_STIFFNESS:g} N/m)"
)
