"""mat-hopper: materials matter, in a simulated one-legged hopper.

The executable companion to Schulz, Ahmad & Tucker, "Materials Matter:
Investigating Functional Advantages of Bio-Inspired Materials via Simulated
Robotic Hopping" (ICRA 2025).
"""

__version__ = "0.1.0"

from .behaviours import Behaviour, behaviour  # noqa: E402
from .control import ControllerSettings  # noqa: E402
from .controls import inertia_matched, mass_matched, mass_properties, rigid_twin  # noqa: E402
from .materials import CATALOGUE, LegDesign, Material, material, parse_design  # noqa: E402
from .rollout import Rollout  # noqa: E402
from .sim import SimSettings, simulate  # noqa: E402

__all__ = [
    "CATALOGUE",
    "LegDesign",
    "Material",
    "material",
    "parse_design",
    "Behaviour",
    "behaviour",
    "ControllerSettings",
    "rigid_twin",
    "mass_matched",
    "inertia_matched",
    "mass_properties",
    "Rollout",
    "SimSettings",
    "simulate",
    "__version__",
]
