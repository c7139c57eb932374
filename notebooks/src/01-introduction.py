# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Introduction
#
# Do the materials a robot's leg is made of change how well it hops?
# Most robots are built from aluminium, stainless steel and 3D-printed
# plastic, and simulated as rigid bodies. Nature builds differently: bone
# has a porous core inside a dense shell, and the tissue between bone,
# tendon and muscle is graded, its stiffness and density changing
# gradually along the limb. The paper this book reproduces, *Materials
# Matter* (Schulz, Ahmad & Tucker, ICRA 2025), asks whether such material
# properties change how well a robot does its job, and answers it with a
# simulated one-legged hopper whose leg is made of three material
# segments {cite:p}`schulz2025materials`. The authors published their code
# (<https://github.com/dynamicmobility/mat-hopper>; we read its commit
# `c213300`) and a video (<https://youtu.be/SEuEXRi80XU>); the page
# {doc}`../book/cite` says how to cite the paper and this book, and the
# {doc}`../book/glossary` defines the words used here in a sense of their
# own.
#
# Two properties of a segment are varied:
#
# - its **density** (g/cm³), which a designer can lower by making the
#   material porous; in the simulation it sets the segment's mass;
# - its **elastic modulus** (GPa), which sets the stiffness of an axial
#   spring inside the segment.
#
# The hopper hops in place, forward, up a ramp and around a circle, and
# every hop cycle is scored by hip power, tracking error (how far the
# body is from where it should be), jerk and hop height. The paper's
# headline: hopping up a ramp, a leg whose density increases from hip to
# foot tracks its path better, and with less hip power, than a leg of
# stainless steel (the numbers are printed below, from
# `mat_hopper/core/reference.py`).
#
# This book rebuilds the study from the authors' published numbers, runs
# it, and sets our results beside the paper's claims. Where the authors'
# code has defects we say so, follow a documented convention, and measure
# what the defect changes (chapter 10). The simulator is MuJoCo
# {cite:p}`todorov2012mujoco`.

# %% [markdown]
# ## How to read this book
#
# Every chapter is a notebook: a few sentences, then a call into the
# `mat_hopper` library, then what it returned. Nothing in the text is
# typed-in data: tables and figures are computed when the book is built,
# from simulations run for the build or loaded from the cache of an earlier
# one. The paper's numbers (its model, controller, protocol and claims)
# live in one module, `mat_hopper/core/reference.py`, and the chapters read
# them from there.
#
# Each chapter starts by calling `book.setup()`: it finds the repository
# (so a notebook runs from wherever Jupyter was started), chooses the
# profile of the build and points the result cache at `results/cache`.

# %%
from mat_hopper import book
from mat_hopper.core import reference as ref
from mat_hopper.experiments import profiles
from mat_hopper.viz import maps

b = book.setup()
print(b.describe())
print(
    f"the paper's headline (ramp, density increasing toward the foot, against stainless steel): "
    f"tracking error {ref.CLAIM_HEADLINE_TRACKING_PCT:+.0f} %, power {ref.CLAIM_HEADLINE_POWER_PCT:+.0f} %"
)
book.show(book.environment_table())

# %% [markdown]
# ## Profiles: the paper's protocol, or a quick look
#
# One setting, the environment variable `MAT_HOPPER_PROFILE`, chooses the
# run lengths for the whole book:
#
# - `paper` (the default): the paper's protocol, 60 s of simulated time per
#   run at a 1e-4 s time step, hop cycles after the first 20 s scored, and
#   a 20 x 20 stable-time-step map;
# - `quick`: the same model, controller and designs with 12 s runs (cycles
#   after 4 s scored), a 4 x 4 map, 2 replicate seeds, and none of the
#   checks that need physics substeps (the axial and 2e-5 s robustness
#   settings, the factorial's axial arms). CI builds this one. Its numbers
#   are noisier and closer to the start-up transient; they are not the
#   paper's protocol, and the claims table of
#   {doc}`10-reproduction-report` says which profile it was computed on.
#
# This build's profile beside the paper's protocol:

# %%
book.show(profiles.profile_table(b.profile))

# %% [markdown]
# ## Rerunning it
#
# From a fresh clone, one command sets everything up and builds the book:
#
# ```bash
# make book                  # the paper's protocol, into _build/html/index.html
# make book PROFILE=quick    # the short version (what CI builds)
# ```
#
# which runs, after the setup,
#
# ```bash
# MAT_HOPPER_PROFILE=paper .venv/bin/jupyter-book build . -W -n --keep-going
# ```
#
# Every notebook is executed on every build; a cell that raises fails the
# build. The simulations themselves are cached: one file per run in
# `results/cache/`, named by a hash of every setting that changes the
# result (design, behaviour, duration, time step, stiffness convention,
# controller gains, the versions of mat-hopper and MuJoCo). A second build
# therefore only re-reads results and redraws figures. Delete
# `results/cache/` to recompute everything. The page {doc}`../book/runtime`
# says how long each chapter took to execute, for this build's profile and
# for the other one.
#
# To work with one chapter, open it in Jupyter with the repository's
# environment (the kernel is `Python 3 (ipykernel)` of `.venv`) and run it
# top to bottom:
#
# ```bash
# .venv/bin/jupyter lab notebooks/06-mono-materials.ipynb
# ```
#
# The experiments also run without the book, from the command line
# (`.venv/bin/mat-hopper reproduce --profile quick`), and every function
# the chapters call is importable from Python. The notebooks are stored
# without outputs and paired with `notebooks/src/*.py` by jupytext
# (`make notebooks`): edit those sources.

# %% [markdown]
# ## The designs
#
# The paper compares nine legs ({numref}`fig-designs`). Five are
# {term}`mono-materials <mono-material>`: the rigid *MuJoCo default* leg
# ({term}`MD`: density 1 g/cm³ and no springs at all, the usual rigid-body
# model), PVC, aluminium (Al), titanium (Ti) and stainless steel (SS).
# Four are {term}`functional gradients <functional gradient>`: density
# increasing from hip to foot ({term}`ρ-inc`) or decreasing
# ({term}`ρ-dec`), both at 70 GPa throughout, and the three materials PVC,
# Ti and SS stacked in either order ({term}`PVC-Ti-SS`). Segment 1 is the
# one nearest the body.

# %%
from myst_nb import glue

glue("fig-designs", maps.designs_figure(), display=False)

# %% [markdown]
# ```{glue:figure} fig-designs
# :name: fig-designs
# :alt: The nine leg designs drawn as three stacked segments each, coloured by density and labelled with each segment's density and modulus; the rigid MD leg has no modulus.
#
# The paper's nine legs, segment 1 (at the hip) on top: five mono-materials
# and four functional gradients, each segment's density (g/cm³) and
# modulus (GPa).
# ```

# %% [markdown]
# ## Answer
#
# The question this book asks with the paper is whether a leg's material,
# its density and its modulus, changes how well a simulated hopper hops;
# the short answer, from the paper profile's records, is on the
# {doc}`00-findings` page. The chapters give the evidence in the paper's
# order: what the materials are and how a density and a modulus become a
# MuJoCo model (chapter 3), the hopper and its controller (chapter 4), the
# numerical price of stiff springs (chapter 5), the paper's three
# experiments (chapters 6 to 8), then three studies past the paper: the
# stress in graded legs (chapter 8b), a design optimizer (chapter 9) and
# the controls that separate material from mass (chapter 9c). The
# reproduction report (chapter 10) tables every claim with its verdict,
# and chapter 11 asks how robust the paper's numbers are; the appendix
# checks the number of segments (chapter 12) and the batch backend
# (chapter 13).
