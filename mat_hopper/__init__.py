"""mat-hopper: materials matter, in a simulated one-legged hopper.

The executable companion to Schulz, Ahmad & Tucker, "Materials Matter:
Investigating Functional Advantages of Bio-Inspired Materials via Simulated
Robotic Hopping" (ICRA 2025).
"""

from .util.version import __version__

# The public names load on first use (PEP 562): `import mat_hopper` and
# `mat-hopper --help` stay fast; MuJoCo and numba load with the first
# name that needs them.
_LAZY = {
    "Behaviour": "core.behaviours",
    "behaviour": "core.behaviours",
    "ControllerSettings": "core.controller",
    "inertia_matched": "core.control_legs",
    "mass_matched": "core.control_legs",
    "mass_properties": "core.control_legs",
    "rigid_twin": "core.control_legs",
    "CATALOGUE": "core.materials",
    "LegDesign": "core.materials",
    "Material": "core.materials",
    "material": "core.materials",
    "parse_design": "core.materials",
    "DivergenceWarning": "core.rollout",
    "SuspectWarning": "core.rollout",
    "FallWarning": "core.rollout",
    "Rollout": "core.rollout",
    "StableStepWarning": "core.timestep",
    "SimSettings": "core.sim",
    "simulate": "core.sim",
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


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
    "DivergenceWarning",
    "SuspectWarning",
    "FallWarning",
    "StableStepWarning",
    "SimSettings",
    "simulate",
    "__version__",
]
