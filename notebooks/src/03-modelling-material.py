# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Modelling material in MuJoCo
#
# How does a rigid-body simulator hopping a leg know what the leg is made
# of? Before a simulator can use a material, a designer has to choose one.
# This chapter starts where the paper does, with the materials on an
# Ashby chart, their catalogue and what porosity does to a density, and
# then builds the models: how a rigid-body simulator is given a density
# and a modulus, and what that costs.
#
# ## Materials
#
# Material scientists compare materials on an **Ashby chart**: one
# property against another on log-log axes, where materials of one class
# (metals, ceramics, polymers, natural materials) gather in a region of
# their own. The paper uses the density-modulus chart to choose the range
# of its designs: the class of metals and ceramics, and the class of
# polymers and natural composites. The chart ({numref}`fig-ashby`) is
# drawn from our catalogue: the paper's four materials (bold), a few
# natural and technical ones for context {cite:p}`ashby2011materials,wegst2004mechanical`,
# the two class regions and the bounds of the design space.

# %%
import pandas as pd
from myst_nb import glue

from mat_hopper import book
from mat_hopper.core import materials
from mat_hopper.viz import maps

b = book.setup()
glue("fig-ashby", maps.ashby_figure(), display=False)

# %% [markdown]
# ```{glue:figure} fig-ashby
# :name: fig-ashby
# :alt: Log-log chart of elastic modulus (GPa) against density (g/cm³) with the catalogue's materials as labelled points, shaded regions for metals and ceramics and for polymers and natural materials, and the paper's design box.
#
# {term}`Ashby chart` of the catalogue: modulus against density, log-log.
# The paper's materials in bold, the two material classes shaded, the
# bounds of the design space outlined.
# ```

# %% [markdown]
# The paper's materials sit in two clusters: PVC among the polymers (light
# and soft, 4 GPa), aluminium, titanium and stainless steel among the
# metals (70-193 GPa). Natural materials span the gap between them:
# cortical bone is a little denser than PVC and several times stiffer;
# tendon is lighter and softer still.
#
# ### The catalogue
#
# Every material the library knows, with the source of its numbers. The
# paper's five come from the authors' code; the others are typical
# mid-range values from Ashby's handbook {cite:p}`ashby2011materials` and
# from Wegst & Ashby's survey of natural materials
# {cite:p}`wegst2004mechanical`. A rigid material (MD, the simulator's default) has no
# modulus.

# %%
book.show(maps.catalogue_table())

# %% [markdown]
# ### Porosity and density
#
# A porous material is a solid with holes ({term}`porosity`). Its bulk density ρ_b is what
# the leg weighs per volume; its porosity is the fraction of the volume
# that is empty:
#
# > Φ = 1 − ρ_b / ρ_s,
#
# with ρ_s the density of the solid itself. For a segment of fixed size,
# mass scales with bulk density, so in the simulation porosity enters only
# through mass (below). Bone is the model: trabecular (spongy) bone is
# cortical bone with most of its volume empty. With our catalogue's
# numbers:

# %%
trabecular = materials.material("TrabecularBone").density_g_cm3
cortical = materials.material("CorticalBone").density_g_cm3
phi = materials.porosity(trabecular, cortical)
print(f"trabecular bone ({trabecular} g/cm³) as porous cortical bone ({cortical} g/cm³): porosity {phi:.0%}")
print(f"titanium at 50 % porosity: {materials.bulk_density(0.5, materials.material('Ti').density_g_cm3):.2f} g/cm³")

# %% [markdown]
# Experiment 2 (chapter 7) varies density around each base material while
# keeping its modulus. Read as porosity of that material, only the sweep
# points below the solid's own density are reachable by making it porous;
# the points above it (negative porosity) stand for a denser material of
# the same stiffness, not for a porous one.

# %%
from mat_hopper.core import reference as ref

rows = []
for base, sweeps in ref.SWEEPS.items():
    rho_s = materials.material(base).density_g_cm3  # the solid's own density
    for rho in sweeps["density"]:
        phi = 1.0 - rho / rho_s  # Φ = 1 - ρ_b / ρ_s; < 0: denser than the solid
        rows.append({"base": base, "density_g_cm3": rho, "porosity": phi, "reachable_by_porosity": phi >= 0})
book.show(pd.DataFrame(rows), {"porosity": "{:+.0%}"})

# %% [markdown]
# ## From materials to a model
#
# MuJoCo {cite:p}`todorov2012mujoco` simulates rigid bodies. The paper gives a rigid-body simulator
# two material properties with two simple devices: **density becomes
# mass**, and **modulus becomes a spring**. Each of the leg's material
# segments is a capsule of radius 2.5 cm and length 10 cm, cut in two
# halves with an axial spring between them, so that half of the segment's
# mass sits above its spring and half below. The rest of this chapter
# builds the models and looks at what the two devices do.

# %%
import math

from mat_hopper.core.materials import parse_design
from mat_hopper.core.model import build_model, build_spec


def segment_xml(design: str, i: int = 1) -> str:
    """The MJCF lines of material segment i, as MuJoCo writes the model."""
    keys = (f'name="seg{i}_upper"', f'<body name="seg{i}"', f'name="mat_spring_{i}"', f'name="seg{i}_lower"')
    return "\n".join(
        ln.strip() for ln in build_spec(parse_design(design)).to_xml().splitlines() if any(k in ln for k in keys)
    )


print(segment_xml("SS"))

# %% [markdown]
# Above: one stainless-steel segment as MuJoCo sees it. The upper half
# capsule belongs to the body above; the child body `seg1` holds the
# axial slide joint `mat_spring_1` (its stiffness from the modulus) and
# the lower half capsule. The rigid MD leg has the same capsules and no
# spring joints at all:

# %%
print(segment_xml("MD"))

# %% [markdown]
# ## Mass from density
#
# Given a density, MuJoCo computes each capsule's mass as m = ρV, end caps
# included. The material segments' masses, and the whole robot's mass as
# the compiled model reports it (15 kg of it is the body):

# %%
rows = []
for name, design in materials.paper_designs().items():
    seg = materials.segment_masses(design)  # m = ρ V per segment, kg
    rows.append(
        {
            "design": name,
            "densities_g_cm3": "/".join(f"{x:g}" for x in design.densities_g_cm3),
            "segment_masses_kg": "/".join(f"{x:.3f}" for x in seg),
            "leg_material_kg": sum(seg),
            "total_mass_kg": build_model(design).total_mass_kg,
        }
    )  # MuJoCo's own total
masses = pd.DataFrame(rows)
book.show(masses, {"leg_material_kg": "{:.3f}", "total_mass_kg": "{:.2f}"})

# %%
by_name = masses.set_index("design")["total_mass_kg"]
print(
    f"MD: {by_name['MD']:.2f} kg (the authors' model: {ref.MASS_MD_KG} kg); "
    f"SS: {by_name['SS']:.2f} kg (theirs: {ref.MASS_SS_KG} kg)"
)

# %% [markdown]
# The gradients all weigh the same: they use the same three densities in
# different orders. Whatever separates them in chapter 8 is the order, not
# the amount, of material.
#
# ## Springs from modulus: two conventions
#
# The paper converts a modulus E into a spring stiffness with the
# cantilever formula k = 3EI/L³ {cite:p}`schulz2025materials`. Its code
# evaluates it with E as the bare number of GPa (193 for steel, not
# 193e9 Pa), the second moment of area as I = π r · 4 (for I = π r⁴ / 4)
# and L = 0.01 m (the segments are 0.1 m long). The result is one constant
# per GPa, whatever the segment's size. Those slips look like a unit
# defect, but they nearly cancel: the paper's own formula done in SI units
# for its segment (r = 2.5 cm, L = 10 cm) lands within a few percent of
# the code's constant.

# %%
from mat_hopper.core.materials import segment_length

r_m, length_m = ref.MATERIAL_RADIUS, segment_length(ref.REFERENCE_SEGMENTS)
i_m4 = math.pi * r_m**4 / 4  # second moment of area of the round section
k_bending_si = 3 * 1e9 * i_m4 / length_m**3  # 3 E I / L^3 for E = 1 GPa, in N/m
k_code = materials.spring_stiffness(1.0, "paper")  # the authors' constant, N/m per GPa
k_rod = materials.spring_stiffness(1.0, "axial")  # E A / L, N/m per GPa
print(f"the authors' code:           {k_code:.3e} N/m per GPa")
print(
    f"3EI/L^3 in SI (r = {r_m * 100:g} cm, L = {length_m * 100:g} cm): {k_bending_si:.3e} N/m per GPa "
    f"({(k_code / k_bending_si - 1) * 100:+.1f} %)"
)
print(f"E A / L, a rod in tension:   {k_rod:.3e} N/m per GPa ({k_rod / k_bending_si:.1f} times the bending stiffness)")

# %% [markdown]
# So the authors' number is, to a few percent, what their formula says.
# The real modelling choice is the formula itself: 3EI/L³ is the
# stiffness of a cantilever *bent* sideways at its tip, and it sets a
# spring that the leg compresses *along its axis*, which a rod resists
# with E A / L. For a round rod the ratio of the two is 4L²/(3r²), about
# 21 for these segments: the paper's legs are about twenty times softer
# along their axis than rods of their materials would be. We keep the
# authors' constant as the **paper** {term}`stiffness convention`, so that
# our results can be compared with the paper's, and offer the rod beside
# it:
#
# - `paper`: k = 9.42e5 N/m per GPa (the authors' constant, a bending
#   stiffness);
# - `axial`: k = E A / L, the axial stiffness of a rod of cross-section
#   A = π r² and length L (0.1 m for three segments).
#
# Both are linear in E, so they differ by one factor:

# %%
springs = pd.DataFrame(
    [
        {
            "material": n,
            "modulus_gpa": materials.material(n).modulus_gpa,
            "k_paper_n_m": materials.spring_stiffness(materials.material(n).modulus_gpa, "paper"),
            "k_axial_n_m": materials.spring_stiffness(materials.material(n).modulus_gpa, "axial"),
        }
        for n in ("PVC", "Al", "Ti", "SS")
    ]
)
springs["axial_over_paper"] = springs["k_axial_n_m"] / springs["k_paper_n_m"]
print(f"axial / paper: {springs['axial_over_paper'].iloc[0]:.1f} times stiffer, for every material")
book.show(springs, {"axial_over_paper": "{:.1f}"}, precision=3)

# %% [markdown]
# What the stiffer springs cost is the time step: a stiff spring between
# small masses vibrates fast, and an explicit integrator that steps over a
# vibration blows up. {doc}`05-numerical-stability` estimates and measures
# the largest stable step under both conventions, and over the paper's
# whole design space.
#
# The experiments of chapters 6 to 9 use the `paper` convention, as the
# paper's results do, except where a chapter names another: chapter 8b's
# stress study needs legs that bend (`bending`, `axial+bending`), and
# chapter 9c's attribution factorial adds axial springs. Chapters 10 and
# 11 measure what the `axial` convention changes, at steps where it is
# stable, and the appendix's convergence study uses it throughout.

# %% [markdown]
# ## Answer
#
# The paper gives a rigid-body simulator a material through two devices:
# density becomes the mass of each segment's two half capsules (m = ρV),
# and modulus becomes the stiffness of an axial spring between them. Its
# materials sit in two clusters of the Ashby chart, PVC among the
# polymers and the three metals together, and porosity reaches only the
# densities below a solid's own. The authors' modulus-to-stiffness
# constant is, to a few percent, their cantilever formula 3EI/L³: a
# bending stiffness, about twenty times softer than the axial rod of the
# same material. We keep it as the `paper` convention and offer the rod as
# `axial`; what the stiffer rod costs in time step is chapter 5's answer.
