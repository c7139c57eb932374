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
# of the paper's headline, then checks whether what it found holds up.
#
# The search (`mat_hopper.optimize`, built on Optuna):
#
# - **Design space**: per segment a density from 0.9 to 20 g/cm³ and a
#   modulus from 0.1 to 1000 GPa, both on log scales. This box *bounds* the
#   two Ashby classes the paper draws from (chapter 2); it is not their
#   hull, and it holds materials no class holds (a leg at 11.9 g/cm³ and
#   1 GPa, say). `--ashby-classes metal,polymer` (or
#   `SearchSpace(ashby_classes=...)`) restricts every segment to the convex
#   hulls, in log density and log modulus, of the catalogue's members of
#   those classes.
# - **Objectives**, both minimized: mean tracking error (m) and mean hip
#   power (W) over the scored hop cycles. There is no single best leg when
#   the two conflict, only a **Pareto front**: the legs that no other leg
#   beats on both.
# - **Constraints**: the mean hop height must stay within 5 cm of the 1 m
#   target, and the run must neither diverge nor fall.
# - **Start**: every study first evaluates the paper's designs: SS,
#   ρ-inc, PVC-Ti-SS, SS-Ti-PVC, ρ-dec, PVC, Al and Ti. The ninth, the
#   rigid MD, has no modulus, so no point of the space is MD; it enters the
#   comparison below as a baseline run.
# - **Equal legs**: every leg has 0.3 m of material and the `leg` mass
#   convention (a leg's mass does not depend on its number of segments);
#   the study records both and refuses to mix trials of other settings.
#
# ## The study
#
# The sampler is Optuna's multi-objective TPE: in a side-by-side run of
# TPE, NSGA-II and random search on this objective
# (`benchmarks/sampler.py`, same seeds and budget, hypervolume after
# every trial), TPE reached the largest hypervolume soonest in the region
# that competes with the paper's designs. The study asks for trials in
# batches of eight, simulates each batch as one grid through the result
# cache on every core, and tells the results in order, so it is the same
# study on any machine, and a rebuild reruns nothing.

# %%
from IPython.display import Image, display
from myst_nb import glue

from mat_hopper import book, optimize
from mat_hopper.optimize import validate
from mat_hopper.viz import maps

b = book.setup()
study = optimize.book_study(b.profile, studies_dir=b.root / "studies", out_dir=b.out_dir / "study")
trials = study["trials"]
print(
    f"study {study['name']}: {len(trials)} trials, "
    f"{int(trials['feasible'].sum())} feasible, {len(study['pareto'])} on the Pareto front"
)

# %% [markdown]
# Every trial ({numref}`fig-pareto`): hip power against tracking error,
# feasible and infeasible, the front in red, the paper's designs starred.

# %%
glue("fig-pareto", Image(filename=study["paths"]["pareto_plot"], width=600), display=False)

# %% [markdown]
# ```{glue:figure} fig-pareto
# :name: fig-pareto
# :alt: Scatter plot of hip power in W against tracking error in m for every trial of the study, feasible and infeasible, with the Pareto front in red and the paper's designs starred.
#
# The study's trials: hip power against tracking error; the Pareto front
# of the feasible trials in red, the paper's seeded designs starred
# (Optuna's own Pareto-front plot).
# ```

# %% [markdown]
# How the front grew, trial by trial ({numref}`fig-hypervolume`: the
# hypervolume the feasible front dominates, up to a reference point just
# beyond its worst values). A flat tail says the budget was enough for
# this sampler to stop finding better legs; a rising one says more trials
# would still pay.

# %%
glue("fig-hypervolume", Image(filename=study["paths"]["hypervolume_plot"], width=600), display=False)

# %% [markdown]
# ```{glue:figure} fig-hypervolume
# :name: fig-hypervolume
# :alt: Line plot of the hypervolume dominated by the feasible Pareto front against the trial number.
#
# Hypervolume of the feasible front after each trial.
# ```

# %% [markdown]
# ## The front against SS and ρ-inc
#
# The designs on the front, best tracking first, with the percent change
# of each objective against the paper's steel leg and its increasing-
# density gradient (one unperturbed run each, as the study scores them):

# %%
front = study["pareto"]
book.show(optimize.front_table(front), precision=3)

# %% [markdown]
# ## Does the front survive a harder look?
#
# One deterministic run per design at one time step is how the study
# scores; it is not how a result is checked. Every design of the front
# that is not one of the paper's own is simulated again
# (`mat_hopper.optimize.validate`):
#
# - on seeded, perturbed **replicates** (a few mm of start offset, half a
#   degree of tilt, a gentle push, sensor noise: chapter 6's method), as
#   are the paper's nine designs;
# - on the **other behaviours** (static, forward, circle);
# - at a **smaller time step**: physics at 2e-5 s with the controller still
#   every 1e-4 s and the authors' 1e-4 s sensor delay (5 substeps), and a
#   plain 2e-5 s step (controller every step);
# - under the **axial** stiffness convention (k = E A / L) with automatic
#   physics substeps.
#
# A design **survives** when every one of those runs stays upright without
# numerical divergence, and no paper design dominates it: each design's
# objectives are read as 95 % bootstrap intervals of the mean over
# replicates; a paper design beats it on an objective only when its
# interval lies wholly below, and dominates it when it is no worse on both
# (overlapping intervals are ties) and better on one.

# %%
legs = optimize.front_designs(front)
checked = validate.validate_front(legs, study["config"].objective)
book.show(checked["verdicts"])

# %% [markdown]
# The replicate intervals of every design (front and paper), each
# objective's mean over replicates with its 95 % interval:

# %%
book.show(checked["intervals"], precision=4)

# %% [markdown]
# What the surviving legs are made of ({numref}`fig-survivors`), beside
# the paper's SS and ρ-inc; segment 1 at the hip:

# %%
from mat_hopper.materials import paper_designs

paper = paper_designs()
glue(
    "fig-survivors",
    maps.designs_figure({"SS": paper["SS"], "rho-inc": paper["rho-inc"], **checked["survivors"]}),
    display=False,
)

# %% [markdown]
# ```{glue:figure} fig-survivors
# :name: fig-survivors
# :alt: Per-segment density and modulus of the paper's SS and rho-inc legs and of every front design that survived validation, segment 1 at the hip.
#
# The legs that survived validation beside the paper's SS and ρ-inc:
# density and modulus of each segment, segment 1 at the hip.
# ```

# %% [markdown]
# ## Does a gradient beat the paper's best?
#
# The paper's best designs are those of the nine that no other paper
# design dominates under the same interval logic. Each surviving design
# against each of them: the percent change of the replicate means with
# its 95 % bootstrap interval (negative: lower, i.e. better), and whether
# both intervals lie wholly below zero.

# %%
beats = validate.beats_paper(checked)
display(book.show(beats, precision=1))
print(validate.answer(checked, beats))

# %% [markdown]
# ## Bigger studies
#
# The same search runs from the command line, on as many cores and
# machines as there are:
#
# ```bash
# # 500 trials on this machine, two worker processes, resumable (rerun to continue)
# .venv/bin/mat-hopper optimize --study ramp-500 --trials 500 --workers 2 --behaviour ramp
#
# # only legs whose every segment is a metal or a polymer (the catalogue's class hulls)
# .venv/bin/mat-hopper optimize --study ramp-ashby --trials 300 --ashby-classes metal,polymer
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
# The study's parameter importances (Optuna's PED-ANOVA) tell which
# segment's density or modulus moves each objective most. Read them with
# the number of feasible trials in mind: importances from a few dozen
# points are a sketch.

# %%
print(f"importances from {int(trials['feasible'].sum())} feasible trials")
book.show(study["importances"], precision=3)
