"""Cache keys: what a result depends on (a core leaf module).

- :func:`design_key` and :func:`settings_key` say what a result depends
  on; :func:`versions` adds mat-hopper's version, a digest of the source
  that makes results (:data:`RESULT_MODULES`) and MuJoCo's version;
  :func:`hash_key` names the file (:mod:`mat_hopper.experiments.cache`
  stores it). Conventions enter a key by their names (a sensor timing as
  ``"authors"``, ``"latency-5"``).
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
from dataclasses import asdict, fields, is_dataclass

import numpy as np

__all__ = ["RESULT_MODULES", "design_key", "hash_key", "json_default", "settings_key", "source_digest", "versions"]


def json_default(o):
    """JSON for numpy scalars and arrays, and tuples (as lists), in keys and metadata.

    The ``default`` hook of :func:`json.dumps`.

    Args:
        o: the object json cannot encode itself.

    Returns:
        int for a numpy integer, float for a numpy floating, bool for a numpy
        bool, a list for a tuple or a numpy array.

    Raises:
        TypeError: any other object (``not JSON serialisable``).
    """
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, (np.bool_,)):
        return bool(o)
    if isinstance(o, (tuple, np.ndarray)):
        return list(o)
    raise TypeError(f"not JSON serialisable: {o!r}")


# Modules whose code makes or summarises a result: their source is part of every key.
# Paths relative to the package folder, "/"-separated.
RESULT_MODULES = (
    "core/reference",
    "core/materials",
    "core/ranges",
    "core/conventions",
    "core/catalogue",
    "core/damping",
    "core/contact",
    "core/replicates",
    "physics/porosity",
    "core/model",
    "core/terrain",
    "core/mjcf",
    "core/controller",
    "core/behaviours",
    "core/_loop",
    "core/sim",
    "core/timestep",
    "core/rollout",
    "core/perturbations",
    "physics/metrics",
    "physics/run_metrics",
    "physics/fatigue",
    "physics/energetics",
    "core/control_legs",
    "physics/jerk",
    "core/lumped",
    "core/stable_step",
    "core/flight_loop",
    "physics/modes",
    "physics/stability",
    "util/keys",
    "experiments/cache",
    "experiments/runner",
    "experiments/groups",
)


@functools.lru_cache(maxsize=1)
def source_digest() -> str:
    """SHA-256 (short) of the source of :data:`RESULT_MODULES`: any edit to
    the physics, controller, metrics, these keys or the runner invalidates
    the cache."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    h = hashlib.sha256()
    for name in RESULT_MODULES:
        with open(os.path.join(package, *f"{name}.py".split("/")), "rb") as f:
            h.update(name.encode() + b"\0" + f.read())
    return h.hexdigest()[:16]


def versions() -> dict:
    """What besides the settings changes results: mat-hopper's version and
    source, and MuJoCo's version.

    Returns:
        A dict with keys ``mat_hopper`` (the package's ``__version__``),
        ``source`` (:func:`source_digest`, 16 hex characters) and
        ``mujoco`` (``mujoco.__version__``).
    """
    import mujoco

    from .version import __version__

    return {"mat_hopper": __version__, "source": source_digest(), "mujoco": mujoco.__version__}


def design_key(design) -> dict:
    """A design as the physics sees it: per-segment density (g/cm^3) and
    modulus (GPa, None = rigid). The name is a label, not physics.

    Args:
        design: the LegDesign.

    Returns:
        A dict with keys ``n_segments`` (int), ``densities_g_cm3`` (list
        of float, g/cm^3) and ``moduli_gpa`` (list of float GPa, or None
        where rigid), base to foot.
    """
    return {
        "n_segments": design.n_segments,
        "densities_g_cm3": list(design.densities_g_cm3),
        "moduli_gpa": list(design.moduli_gpa),
    }


def settings_key(settings) -> dict:
    """Every field of SimSettings, by name: a setting added to SimSettings is
    in every key without another edit. Nested settings (controller gains,
    perturbation) as dicts, a sensor timing by its name.

    Args:
        settings: the SimSettings.

    Returns:
        A dict {field name: value}: a SensorTiming as its name (str), any
        other dataclass as ``dataclasses.asdict`` gives it, other values as
        they are.
    """
    return {f.name: _key_value(getattr(settings, f.name)) for f in fields(settings)}


def _key_value(value):
    # A value that names itself in keys (the controller's SensorTiming, an
    # int latency carrying its name) is keyed by that name. Duck-typed, so
    # that this leaf imports nothing of the physics.
    if callable(getattr(value, "key_value", None)):
        return value.key_value()
    if is_dataclass(value):
        return asdict(value)
    return value


def hash_key(key: dict) -> str:
    """Stable short hash (hex) of a key dict.

    Args:
        key: the key: JSON-encodable with :func:`json_default` (numpy
            scalars and arrays, tuples); encoded with sorted keys, NaN
            allowed.

    Returns:
        The first 24 hex characters of the SHA-256 of the key's JSON text.

    Raises:
        TypeError: a value that neither json nor :func:`json_default` can
            encode.
    """
    text = json.dumps(key, sort_keys=True, default=json_default, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]
