"""mat-hopper: materials matter, in a simulated one-legged hopper.

The executable companion to Schulz, Ahmad & Tucker, "Materials Matter:
Investigating Functional Advantages of Bio-Inspired Materials via Simulated
Robotic Hopping" (ICRA 2025).
"""

__version__ = "0.1.0"

# The public names load on first use (PEP 562): `import mat_hopper` and
# `mat-hopper --help` stay fast; MuJoCo and numba load with the first
# name that needs them.
_LAZY = {
    "Behaviour": "behaviours",
    "behaviour": "behaviours",
    "ControllerSettings": "control",
    "inertia_matched": "controls",
    "mass_matched": "controls",
    "mass_properties": "controls",
    "rigid_twin": "controls",
    "CATALOGUE": "materials",
    "LegDesign": "materials",
    "Material": "materials",
    "material": "materials",
    "parse_design": "materials",
    "Rollout": "rollout",
    "SimSettings": "sim",
    "simulate": "sim",
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
    "SimSettings",
    "simulate",
    "__version__",
]
