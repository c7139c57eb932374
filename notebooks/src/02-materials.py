# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Materials
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
# ## The catalogue
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
# ## Porosity and density
#
# A porous material is a solid with holes ({term}`porosity`). Its bulk density ρ_b is what
# the leg weighs per volume; its porosity is the fraction of the volume
# that is empty:
#
# > Φ = 1 − ρ_b / ρ_s,
#
# with ρ_s the density of the solid itself. For a segment of fixed size,
# mass scales with bulk density, so in the simulation porosity enters only
# through mass (chapter 3). Bone is the model: trabecular (spongy) bone is
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
