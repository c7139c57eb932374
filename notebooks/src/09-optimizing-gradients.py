# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Designing gradients with Optuna
#
# The paper picks four gradients by hand. A three-segment leg whose every
# segment has its own density and modulus is a point in a six-dimensional
# space, and the hand-picked legs are four points in it. This chapter goes
# past the paper: it lets an optimizer search that space for legs that
# track their path well *and* spend little hip power, hopping up the ramp
# of the paper's headline.
#
# The search (`mat_hopper/optimize.py`, built on Optuna):
#
# - **Design space**: per segment a density from 0.9 to 20 g/cm³ and a
#   modulus from 0.1 to 1000 GPa, both on log scales: the hull of the two
#   Ashby classes the paper draws from (chapter 2).
# - **Objectives**, both minimized: mean tracking error (m) and mean hip
#   power (W) over the scored hop cycles. There is no single best leg
#   when the two conflict, only a **Pareto front**: the legs that no other
#   leg beats on both.
# - **Constraints**: the mean hop height must stay within 5 cm of the 1 m
#   target, and the run must neither diverge nor fall. Parts of the space
#   (light and very stiff) diverge at the paper's time step (chapter 5);
#   they come out as infeasible trials.
# - **Start**: every study first evaluates the paper's SS, ρ-inc and
#   PVC-Ti-SS legs, so that the front is read against them.
#
# ## A study
#
# The book runs a small study: one worker process (so a fresh study gives
# the same trials every time), a few dozen trials with this build's
# profile, stored in `studies/` and resumed, not rerun, by the next build.

# %%
from IPython.display import Image

from mat_hopper import book, optimize
from mat_hopper.viz import maps

b = book.setup()
study = optimize.book_study(b.profile, studies_dir=b.root / "studies", out_dir=b.out_dir / "study")
trials = study["trials"]
print(
    f"study {study['name']}: {len(trials)} trials, "
    f"{int(trials['feasible'].sum())} feasible, {len(study['pareto'])} on the Pareto front"
)

# %% [markdown]
# Every trial: hip power against tracking error, feasible and infeasible,
# the front in red, the paper's designs starred.

# %%
Image(filename=study["paths"]["pareto_plot"], width=600)

# %% [markdown]
# ## The front against SS and ρ-inc
#
# The designs on the front, best tracking first, with the percent change
# of each objective against the paper's steel leg and its increasing-
# density gradient (as evaluated in this study, with its settings):

# %%
front = study["pareto"]
book.show(optimize.front_table(front), precision=3)

# %% [markdown]
# What the front's legs are made of (the first six by tracking error,
# leaving out the paper's own designs), beside the paper's SS and ρ-inc;
# segment 1 at the hip:

# %%
from mat_hopper.materials import paper_designs

paper = paper_designs()
legs = {"SS": paper["SS"], "rho-inc": paper["rho-inc"], **optimize.front_designs(front, k=6)}
maps.designs_figure(legs)

# %% [markdown]
# How the front grew, trial by trial (the hypervolume the feasible front
# dominates, up to a reference point just beyond its worst values):

# %%
Image(filename=study["paths"]["hypervolume_plot"], width=600)

# %% [markdown]
# A few dozen trials only sketch the front: the first ones are random
# samples, and a study needs hundreds before its front settles. Read the
# book's study as a demonstration of the method, not as the best legs.
#
# ## Bigger studies
#
# The same study runs from the command line, on as many cores and
# machines as there are:
#
# ```bash
# # 500 trials on this machine, two worker processes, resumable (rerun to continue)
# .venv/bin/mat-hopper optimize --study ramp-500 --trials 500 --workers 2 --behaviour ramp
#
# # several behaviours at once, a catalogue material at the hip and two free segments
# .venv/bin/mat-hopper optimize --study mixed --trials 300 --behaviour forward,ramp \
#     --space catalogue,continuous,continuous
#
# # many machines: one PostgreSQL database, the same command on each (its own --seed)
# .venv/bin/mat-hopper optimize --study ramp-big --trials 5000 --workers 16 --seed 1 \
#     --storage postgresql://USER@HOST:5432/DB
#
# # the report (Pareto front, hypervolume, importances, CSV) and one trial replayed
# .venv/bin/mat-hopper optimize --report ramp-500
# .venv/bin/mat-hopper optimize --study ramp-500 --replay 42
# ```
#
# A study holds every trial in its storage (`studies/<name>.db` by
# default); killed workers' trials are retried, and rerunning the command
# resumes where it stopped. `--profile quick` gives first looks in
# minutes. The study's parameter importances tell which segment's density
# or modulus moves each objective most:

# %%
book.show(study["importances"], precision=3)
