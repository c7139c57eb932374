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
# How small must the time step be for a leg of a given density and
# modulus, and is the largest stable step log-linear in the two, as the
# paper says? A stiff spring between light masses vibrates fast, and an
# integrator that steps over a vibration blows up. The paper maps this
# over the whole design space: for a grid of mono-material legs, 20
# densities from 1.39 to 8 g/cm³ by 20 moduli from 4 to 340 GPa
# (log-spaced), it searches the largest time step at which the hopper can
# hop in place without numerical blow-up, and draws the answer as a heat
# map. Its reading: the stable step is log-linear in density and modulus,
# light or stiff materials need smaller steps, and PVC runs at a step ten
# times larger than aluminium and steel need (the paper's numbers are in
# the claims table of {doc}`10-reproduction-report`; MuJoCo's default
# step is 2e-3 s). This chapter gives two estimates of the limit,
# measures it for the paper's materials under both stiffness conventions
# of {doc}`03-modelling-material`, and then over the paper's grid.
#
# ## Two estimates
#
# MuJoCo's default (semi-implicit Euler) integrator treats joint damping
# implicitly but springs explicitly; for a mass-spring chain it is stable
# while ω Δt < 2, with ω the chain's highest natural frequency. The leg
# along its axis is such a chain: the body with the top half of segment
# 1, the halves of adjacent segments joined, the foot below the foot
# spring. Its highest frequency ω_max comes from the generalized
# eigenproblem K v = ω² M v with the masses and stiffnesses of the
# compiled model, and gives the estimate Δt < 2 / ω_max (`spring`).
#
# A second limit has nothing to do with the material: in stance the
# controller damps the body's pitch and roll through the hips, a damper
# of c = 1 × 600 N m s/rad acting on the body's inertia I about the hip
# (I ≈ 0.127 kg m²). Explicit damping computed from the current state is
# stable for Δt < 2 I / c; the authors' controller reads the body's gyro
# one physics step old (their {term}`sensor timing`), and a rate feedback
# read L steps late, ω[n+1] = ω[n] − a h ω[n−L], is stable only for
# Δt < c(L) I / c with c(L) = 2 cos(Lπ / (2L + 1))
# {cite:p}`levin1976note`: c(1) = 1, half the undelayed limit, the same
# for every leg (`controller`; `mat_hopper/physics/modes.py`,
# `mat_hopper/physics/stability.py`). The smaller of the two estimates is
# the `combined` one. The controller's limit for the sensor delays that
# {doc}`11-robustness` tries:

# %%
import pandas as pd

from mat_hopper import book
from mat_hopper.analysis import robustness
from mat_hopper.core.materials import parse_design
from mat_hopper.core.stable_step import controller_timestep

b = book.setup()
limits = pd.DataFrame(
    {
        "latency_steps": lat,
        "largest stable step (s)": controller_timestep(parse_design("SS"), sensor_timing=lat),
    }
    for lat in robustness.DEFAULT_LATENCIES
)
limits["stable at 1e-4 s"] = limits["largest stable step (s)"] > 1e-4
book.show(limits, precision=6)

# %% [markdown]
# Latencies of 5 and 10 steps put the paper's 1e-4 s step above the
# controller's limit: the controller itself goes unstable in the first
# stance, whatever the leg. The authors' controller tolerates at most
# about two steps (0.2 ms) of sensor delay at its own rate.
#
# ## The paper's materials, under both stiffness conventions
#
# We also measure the largest stable step: static hopping at a given step
# counts as stable when it ends without NaN, without any acceleration
# above 1e6 and with the body above 0.1 m (the paper's criterion). The
# search starts at the estimate, steps by factors of 1.5 until the outcome
# changes, then bisects (the protocol below). Every mono-material, under
# the authors' `paper` springs and the physical `axial` ones
# ({doc}`03-modelling-material`):

# %%
from mat_hopper.core import reference as ref
from mat_hopper.experiments import paper
from mat_hopper.viz import chapters

steps = paper.convention_stability(profile=b.profile, cache_dir=b.cache_dir)
book.show(steps, precision=3)

# %%
from myst_nb import glue

glue("fig-conventions", chapters.convention_figure(steps), display=False)

# %% [markdown]
# ```{glue:figure} fig-conventions
# :name: fig-conventions
# :alt: Per mono-material leg, the paper and axial stiffness conventions compared: spring stiffness in N/m on a log axis, and the measured largest stable time step beside its spring-chain estimate, with the paper's 1e-4 s step and the controller's limit drawn as lines.
#
# The two {term}`stiffness conventions <stiffness convention>` for every
# mono-material: the springs they give, and the largest stable time step,
# measured and estimated. Dotted: the paper's time step of 1e-4 s;
# dashed: the controller's limit.
# ```

# %%
paper_conv = steps[steps["convention"] == "paper"].set_index("design")
for name, claimed in ref.CLAIM_STABLE_TIMESTEP_S.items():
    print(
        f"{name:>3} (paper convention): stable up to {paper_conv.loc[name, 'max_stable_timestep_s']:.1e} s, "
        f"spring-chain estimate {paper_conv.loc[name, 'analytic_timestep_s']:.1e} s; "
        f"the paper: about {claimed:.0e} s"
    )
print(f"controller limit c(1) I / c: {steps['controller_timestep_s'].min():.1e} s, for every leg")

# %% [markdown]
# Under the paper's convention the measured limits of the metals lie near
# the paper's own time step of 1e-4 s (dotted line), and PVC, the softest,
# allows the largest step of the four sprung legs (the numbers are printed
# above). Wherever a material spring sets the limit, the chain estimate
# lands close to the measurement; where it does not, the delayed stance
# damping does (dashed line), and it caps every leg, MD included, whose
# chain estimate only sees the soft foot spring. The physical `axial`
# springs are about twenty times stiffer, so the stable step shrinks by
# roughly the square root of that: the metals then need steps well below
# 1e-4 s, and the paper's time step makes them diverge.
#
# ## The map over the design space
#
# A try is 2 s of static hopping at one time step (the `quick` profile:
# 1 s). It **fails** when any acceleration becomes NaN, infinite or larger
# than 1e6, or when the body ends below 0.1 m. For each design of the grid
# we run two searches:
#
# - the paper's: 20 steps log-spaced from 1e-3 s down to 1e-5 s, the first
#   that survives;
# - ours: from the combined estimate, in steps of a factor 1.5 up while a
#   try survives or down while it fails, until the outcome changes; then
#   bisection (in log scale) between the last failure and the first
#   survivor, down to a bracket of a factor 1.25 (the `quick` profile:
#   1.5). It finds steps above 1e-3 s too, and the bracket says how sharp
#   the answer is.

# %%
from mat_hopper.experiments import reproduce
from mat_hopper.physics.stability import agreement
from mat_hopper.viz import maps

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
#
# The paper's two claims about the time step, its numbers beside ours
# with their verdicts, are rows of the claims table of
# {doc}`10-reproduction-report`, judged by the rules of
# `mat_hopper/analysis/claims.py` that chapter lists. A time step is only
# "about" right within 0.3 decade (a factor of 2, the rule's
# `TIMESTEP_TOL_DECADES`); the trend holds when a plane fitted to log Δt
# over log ρ and log E has a positive density slope, a negative modulus
# slope and R² ≥ 0.8. This build's plane:

# %%
from mat_hopper.analysis import tables as tab

fits = tab.claims_for(tables, "stability", columns=("claim_id", "ours")).set_index("claim_id")
print(f"fitted plane over the stable grid points: {fits.loc['timestep_trend', 'ours']}")

# %% [markdown]
# Why log-linear? For one spring between two equal masses m, ω = √(2k/m),
# so Δt ∝ √(m/k) ∝ √ρ / √E under the paper's convention, where k ∝ E and
# m ∝ ρ: a plane of slopes +½ and −½ in log-log axes. The fitted slopes
# above are to be compared with these; the foot spring and the foot's mass,
# the same in every design, pull them toward zero.

# %% [markdown]
# ## Answer
#
# The stable step is set by the fastest of two modes: the leg's axial
# spring chain, whose limit 2 / ω_max grows with density and shrinks with
# modulus, and the controller's delayed stance damping, the same for
# every leg, which caps soft, heavy legs. Where the springs set it, the
# measured map is close to log-linear in density and modulus, as the
# paper says, with slopes pulled toward zero from the ±½ of a single
# spring by the foot spring and foot mass shared by every design. Under
# the paper's stiffness convention the metals are stable near the paper's
# 1e-4 s step and PVC at a larger one, though not as large as the paper
# reports; the physical axial springs need steps well below 1e-4 s. The
# verdicts on the paper's numbers are in {doc}`10-reproduction-report`.
