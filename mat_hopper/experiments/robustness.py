"""The robustness study's runs: the settings of
:mod:`mat_hopper.analysis.robustness` (its variants, designs and
behaviours) as runs of the result cache and process pool
(:func:`tasks`, through :mod:`mat_hopper.experiments.runner`), or on a
batch backend (:func:`batch_runs`, :mod:`mat_hopper.batch`: MuJoCo Warp, or
the CPU rollouts as the reference). The analysis of what they give
(quantities, keeps / moves / flips) stays in
:mod:`mat_hopper.analysis.robustness`.

>>> from mat_hopper.experiments.profiles import get_profile
>>> specs = tasks(get_profile("quick"), variants(replicates=0))
>>> len(specs) == len(variants(replicates=0)) * len(designs_and_behaviours())
True
>>> [v.label for v in batch_variants()][:3]
['authors', 'fresh', 'latency-2']
"""

from __future__ import annotations

from dataclasses import replace

import pandas as pd

from ..analysis.robustness import DEFAULT, Variant, designs_and_behaviours, variants
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import parse_design
from .profiles import get_profile, resolve_profile
from .runner import RunSpec


def tasks(profile, variant_list=None) -> list:
    """RunSpecs of every run of the study under ``profile``; labels: study, profile, variant, variant_kind, convention,
    sensor_timing, timestep_s, substeps, replicate. Runs the default shares
    with experiments 1 and 3 (and replicates with the claims' replicates)
    have the same settings, hence the same cache keys: computed once.

    Args:
        profile: a :class:`~mat_hopper.experiments.profiles.Profile` or its
            name, any case (:func:`~mat_hopper.experiments.profiles.get_profile`;
            the entry points, e.g. :func:`batch_runs`, resolve $MAT_HOPPER_PROFILE).
        variant_list: the variants (:class:`~mat_hopper.analysis.robustness.Variant`)
            to run; None: :func:`~mat_hopper.analysis.robustness.variants`.

    Returns:
        list of RunSpec, variant-major, one per variant and (design,
        behaviour) of :func:`~mat_hopper.analysis.robustness.designs_and_behaviours`.
        timestep_s (s) and substeps are the run's physics step and substeps
        per control period; replicate is -1 for an unperturbed variant. The
        design and behaviour columns come from the runner's default labels.

    Raises:
        ValueError: an unknown profile, an empty `variant_list`, an entry
            that is not a Variant, a variant's unknown convention or sensor
            timing, or invalid settings.
    """
    profile = get_profile(profile)  # a name or a Profile
    given = variants() if variant_list is None else list(variant_list)
    if not given:
        raise ValueError("tasks: no variants to run (None runs variants())")
    bad = [v for v in given if not isinstance(v, Variant)]
    if bad:
        raise ValueError(f"variants must be Variant objects (robustness.variants()), got {bad[0]!r}")
    out = []
    for v in given:
        prof = profile.for_convention(v.convention).for_sensor_timing(v.sensor_timing)
        pert = None if v.replicate is None else profile.replicate(v.replicate)
        for d, b in designs_and_behaviours():
            design = parse_design(d)
            settings = prof.sim_settings(pert, design=design)
            if v.timestep_s is not None:
                settings = replace(settings, timestep_s=v.timestep_s, substeps=v.substeps)
            if (v.contact, v.apex_reference) != (settings.contact, settings.apex_reference):
                settings = replace(settings, contact=v.contact, apex_reference=v.apex_reference)
            labels = {
                "study": "robustness",
                "profile": profile.name,
                "variant": v.label,
                "variant_kind": v.kind,
                "convention": settings.convention,
                "sensor_timing": settings.sensor_timing.name,
                "timestep_s": settings.timestep_s,
                "substeps": settings.substeps,
                "replicate": -1 if v.replicate is None else v.replicate,
            }
            out.append(RunSpec(design, get_behaviour(b), settings, labels))
    return out


def batch_variants(variant_list=None) -> list[Variant]:
    """The variants a batch backend (:mod:`mat_hopper.batch`) runs: those
    with no perturbation, no physics substeps, the paper convention (its
    axial runs need substeps), and the default contact and apex reference
    (the batch model takes neither): the sensor latencies and the plain
    ``2e-5 s step``. The default comes first, as in :func:`variants`.
    variant_list: None for :func:`variants`; raises ValueError for an entry
    that is not a :class:`Variant`.

    Args:
        variant_list: the variants to filter (any iterable); None:
            :func:`~mat_hopper.analysis.robustness.variants`.

    Returns:
        list of the given variants, in their order, that have no replicate,
        one substep, the default (``paper``) convention, contact and apex reference.

    Raises:
        ValueError: an entry that is not a :class:`Variant`.
    """
    given = variants() if variant_list is None else list(variant_list)
    bad = [v for v in given if not isinstance(v, Variant)]
    if bad:
        raise ValueError(f"variants must be Variant objects (robustness.variants()), got {bad[0]!r}")
    return [
        v
        for v in given
        if v.replicate is None
        and v.substeps == 1
        and v.convention == DEFAULT.convention
        and (v.contact, v.apex_reference) == (DEFAULT.contact, DEFAULT.apex_reference)
    ]


def batch_runs(
    profile, variant_list=None, *, backend: str = "warp", device=None, workers=None, progress: bool = False
) -> pd.DataFrame:
    """The study's runs on a batch backend (:func:`mat_hopper.batch.evaluate`):
    one row per variant, design and behaviour with the means over scored hop
    cycles (``tracking_error_m``, ``power_w``, ``hop_height_m``, the CPU
    path's per-hop means) and ``status`` ("ok", "diverged", "suspect", "fallen", as
    the runner's). Each variant and behaviour is one batch of its designs.
    ``quantity_values(runs, runs)`` reads it as it reads per-hop tables.

    profile: a Profile or its name (run length, step, record rate,
    segment mass); variant_list: None for :func:`batch_variants`; an empty
    list, a non-Variant, or a variant no batch can run raises ValueError
    naming it, before any work; backend, device, workers: as
    :func:`mat_hopper.batch.evaluate` (checked there, before its first
    batch).

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        variant_list: the variants to run; None: :func:`batch_variants`.
        backend: ``"warp"`` (MuJoCo Warp, the default here) or ``"mujoco"``
            (the CPU rollouts).
        device: the Warp device (``"cpu"``, ``"cuda"``) for the warp backend.
        workers: processes for the mujoco backend (default: every core).
        progress: show a progress bar per batch.

    Returns:
        DataFrame, one row per variant, behaviour and design: variant,
        variant_kind, design, behaviour, sensor_timing, timestep_s (s),
        n_hops, tracking_error_m (m), power_w (W), hop_height_m (m), status
        and backend.

    Raises:
        ValueError: an empty `variant_list`, a non-Variant entry, a variant no
            batch can run (named), an unknown profile, or what
            :func:`mat_hopper.batch.evaluate` refuses (options of the other
            backend, an unknown backend, bad counts).
        WarpUnavailable: the warp backend without mujoco-warp installed (an
            ImportError).
    """
    from ..batch import BatchSettings, evaluate  # MuJoCo Warp, imported only when a batch runs

    profile = resolve_profile(profile)  # a name, a Profile or None ($MAT_HOPPER_PROFILE)
    wanted = batch_variants() if variant_list is None else list(variant_list)
    if not wanted:
        raise ValueError("batch_runs: no variants to run (None runs batch_variants())")
    runnable = batch_variants(wanted)
    refused = [v.label for v in wanted if v not in runnable]
    if refused:
        raise ValueError(
            f"a batch backend cannot run these variants (perturbed replicates, physics substeps, the axial "
            f"convention's substeps): {', '.join(refused)}"
        )
    pairs = designs_and_behaviours()
    rows = []
    for v in runnable:
        settings = profile.for_convention(v.convention).for_sensor_timing(v.sensor_timing).sim_settings()
        if v.timestep_s is not None:
            settings = replace(settings, timestep_s=v.timestep_s)
        settings = BatchSettings.of(settings)
        for b in BEHAVIOUR_NAMES:
            names = [d for d, beh in pairs if beh == b]
            if not names:
                continue
            table = evaluate(names, b, settings, backend=backend, device=device, workers=workers, progress=progress)
            for r in table.to_dict("records"):
                status = "ok" if r["upright"] else ("diverged" if not r["stable"] else "fallen")
                if r["stable"] and pd.notna(r.get("suspect_at_s")):  # corrupted numbers (Rollout.suspect)
                    status = "suspect"
                rows.append(
                    {
                        "variant": v.label,
                        "variant_kind": v.kind,
                        "design": r["design"],
                        "behaviour": b,
                        "sensor_timing": r["sensor_timing"],
                        "timestep_s": settings.timestep_s,
                        "n_hops": r["n_hops"],
                        "tracking_error_m": r["tracking_error_m"],
                        "power_w": r["power_w"],
                        "hop_height_m": r["hop_height_m"],
                        "status": status,
                        "backend": r["backend"],
                    }
                )
    return pd.DataFrame(rows)
