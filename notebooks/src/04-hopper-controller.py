# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # The hopper and its controller
#
# What robot and controller do the paper's results come from, and what
# does one run of them look like? The robot is a 3D version of Raibert's one-legged hopping machine
# {cite:p}`raibert1984experiments,raibert1986legged`:
# a 15 kg body free to move and turn in space, a leg on a two-axis hip,
# and a sprung foot whose spring a linear actuator can push. Between hip
# and foot sit the three material segments of chapter 3. The numbers are
# those of the authors' published code (`mat_hopper/core/reference.py`); the
# model is built in memory from them.

# %%
import pandas as pd

from mat_hopper import book, simulate
from mat_hopper.analysis import tables
from mat_hopper.physics.metrics import hop_table, run_summary
from mat_hopper.viz import chapters

b = book.setup()

# %% [markdown]
# ## The model
#
# The body's six joints (three slides, three hinges) are unactuated. The
# hip has two motorized hinges (pitch `hip_y`, then roll `hip_x`, ±70°,
# 600:1 gear). The material springs `mat_spring_1..3` follow, then the
# foot spring (8000 N/m, ±0.1 m), the only spring the thrust actuator
# drives. Only the foot touches the ground. Rendered off-screen, the
# hopper with the ρ-inc leg standing at the foot of the ramp, its segments
# coloured by density (light at the hip, dense at the foot); the dotted
# line is the desired path ({numref}`fig-model`):

# %%
from myst_nb import glue
from PIL import Image

from mat_hopper.viz import render

glue("fig-model", Image.fromarray(render.render_still("rho-inc", "ramp", size=(720, 480))), display=False)

# %% [markdown]
# ```{glue:figure} fig-model
# :name: fig-model
# :alt: Off-screen rendering of the hopper standing at the foot of the ramp: a cross-shaped body, the leg below it with segments shaded from light at the hip to dark at the foot, and a dotted line marking the desired path up the ramp.
#
# The hopper with the {term}`ρ-inc` leg at the foot of the 3.5 % ramp,
# rendered off-screen by MuJoCo: segments coloured by density, the
# desired path dotted.
# ```

# %% [markdown]
# The joints of the stainless-steel leg:

# %%
book.show(tables.joint_table("SS"), precision=3)

# %% [markdown]
# ## The controller
#
# Every physics step, the controller reads the touch sensor, the body's
# position, orientation, angular rate and velocity, and the hip angles,
# and decides three commands.
#
# - **Phase.** Flight switches to stance when the foot touches down while
#   the body falls; stance switches to flight when the foot leaves the
#   ground while the body rises. A switch may only follow the previous one
#   after 0.1 s.
# - **Hop height.** During stance, while the body rises, the actuator
#   pushes the foot spring with a constant force F. At each touchdown F
#   adapts to the last hop's apex h: F ← F + 100 (1 - h). The target apex
#   is 1 m, for every leg.
# - **Foot placement and attitude.** In flight, the hips swing the leg to
#   place the foot where Raibert's rule puts it, half the stance's travel
#   ahead plus a correction proportional to the velocity error (a PD law on
#   the hip angles). In stance, the hips instead level the body (a PD law on
#   pitch and roll).
#
# The desired velocity comes from the desired path (chapter 1's
# behaviours) and is clamped at 0.1 m/s. The gains, from the authors'
# code:

# %%
from dataclasses import asdict

from mat_hopper import ControllerSettings

book.show(pd.DataFrame(asdict(ControllerSettings()).items(), columns=["setting", "value"]))

# %% [markdown]
# ## One rollout
#
# The stainless-steel leg hopping forward, for one run of this build's
# {term}`profile` ({numref}`fig-rollout`). Left, the whole run: the hop apexes approach the 1 m target as
# the thrust adapts; the shaded start is the transient, whose hop cycles
# are not scored. Right, a short window (marked orange on the left): the
# body's height with stance shaded, the thrust pushing the foot spring
# only while the body rises in stance, the hip swinging the leg toward
# its flight target, and the body following its desired x.

# %%
rollout = simulate("SS", "forward", settings=b.profile.sim_settings())
glue("fig-rollout", chapters.controller_figure(rollout), display=False)

# %% [markdown]
# ```{glue:figure} fig-rollout
# :name: fig-rollout
# :alt: Time series of one stainless-steel forward run: left, every hop apex approaching the 1 m target over the run with the transient shaded; right, a short window of body height with stance shaded, thrust, hip angle against its target, and body x against the desired x.
#
# One rollout of the SS leg hopping forward. Left: hop apexes over the
# run, the {term}`transient` shaded. Right: a short window (orange on the
# left) of the body's height, the thrust, the hip and the body's x.
# ```

# %% [markdown]
# Every {term}`hop cycle` (lift-off to the next lift-off) after the
# transient yields one row of metrics: {term}`hop height` (max body z in
# world coordinates, what the controller regulates, and beside it the
# apex above the ground under the body), {term}`tracking error` (mean
# planar distance between body and desired path), {term}`jerk` (mean
# |d³z/dt³| of the body, from its vertical acceleration low-passed at
# 50 Hz at the physics rate) and {term}`hip power` (mean norm of the hip
# motors' mechanical power). The first few scored cycles of this run, and
# the run in one line:

# %%
hops = hop_table(rollout)
book.show(hops.drop(columns=["design", "behaviour", "convention"]).head(), precision=3)

# %%
summary = run_summary(rollout)
keys = [
    "stable",
    "n_hops",
    "total_mass_kg",
    "mean_hop_height_m",
    "mean_tracking_error_m",
    "mean_jerk_m_s3",
    "mean_power_w",
    "distance_m",
]
book.show(pd.Series(summary)[keys].to_frame("value"), index=True, precision=3)

# %% [markdown]
# ## Try your own leg
#
# Everything above is a public call, so a leg of your own is one cell
# away. Change the densities (g/cm³, segment 1 at the hip), the moduli
# (GPa; `None` for a rigid segment) or the path (a function from time in
# s to the desired position (x, y) in m), and run the cell. Here: a
# bone-like leg, two segments of cortical bone above one of tendon (the
# catalogue's values, chapter 3), weaving 10 cm to each side while it
# moves forward at 5 cm/s; the SS run above beside it.

# %%
import math

from mat_hopper import Behaviour, LegDesign, material

bone, tendon = material("CorticalBone"), material("Tendon")
my_leg = LegDesign.from_properties(
    densities_g_cm3=[bone.density_g_cm3, bone.density_g_cm3, tendon.density_g_cm3],
    moduli_gpa=[bone.modulus_gpa, bone.modulus_gpa, tendon.modulus_gpa],
    name="bone-bone-tendon",
)
my_path = Behaviour.from_function(
    "weave", lambda t: (0.05 * t, 0.1 * math.sin(2 * math.pi * t / 20.0)), duration_s=b.profile.duration_s
)
mine = simulate(my_leg, my_path, settings=b.profile.sim_settings())
book.show(
    pd.DataFrame(
        {"SS, forward": pd.Series(summary)[keys], f"{my_leg.name}, {my_path.name}": pd.Series(run_summary(mine))[keys]}
    ),
    index=True,
    precision=3,
)

# %% [markdown]
# `simulate` takes the same settings as every run of this book
# (`b.profile.sim_settings()`: duration, time step, stiffness convention,
# sensor timing); `SimSettings` and `simulate`'s docstring list them. A
# leg whose springs are too stiff for the time step diverges rather than
# raising: `mine.stable` and `mine.diverged_at_s` say so
# ({doc}`05-numerical-stability` tells how to choose the step).

# %% [markdown]
# ## Answer
#
# The paper's results come from a 3D Raibert hopper rebuilt here from the
# authors' code: a 15 kg body on a two-axis hip, the three material
# segments, and a sprung foot pushed by a thrust actuator, under a
# controller that switches between flight and stance on the touch
# sensor, adapts its thrust toward a 1 m apex, places the foot by
# Raibert's rule in flight and levels the body in stance. In one run the
# apex settles toward its target after a transient that is not scored,
# and every hop cycle after it gives one row of hop height, tracking
# error, jerk and hip power. Any leg of one's own runs through the same
# call.
